// distance_along (level_set.hpp): plain sampling, no OpenVDB here.
#include "nodes/levelset/level_set.hpp"

#include <limits>

namespace cf {

double distance_along(const LevelSet& ls, const Vec3& p, const Vec3& direction, int max_steps) {
    // A sample at the band's half-width is clamped (the point may be farther); below it, it is the
    // distance. Inside (negative) values are returned as sampled: an inside point needs no march.
    const double clamp = 0.999 * ls.background();
    double t = 0;
    for (int k = 0; k < max_steps; ++k) {
        const double phi = sample(ls, p + t * direction);
        if (phi < clamp) return t + phi;
        t += phi;
    }
    return std::numeric_limits<double>::infinity();
}

}  // namespace cf
