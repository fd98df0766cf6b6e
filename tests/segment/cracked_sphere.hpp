#pragma once
// A sphere cut by random disk cracks and a bundle of three parallel ones 2.5 r_f apart (slivers
// thinner than a leaf: leaves hold pieces of several fragments), for the segmentation and cell
// equivalence tests.
#include "nodes/levelset/crack_grids.hpp"
#include "nodes/levelset/level_set.hpp"
#include "nodes/shape/icosphere.hpp"

#include <random>
#include <vector>

namespace cf::testing {

struct CrackedSphere {
    LevelSet sphere;  // uncut
    CrackLevelSets cracks;
};

// `random_cracks` disks of radius 1 m through the sphere (centres within `spread` [m] of its
// centre, seeded by `seed`), then the bundle normal to about y through (bundle_x, 0, 0).
inline CrackedSphere cracked_sphere(double radius, double r_f, int random_cracks, double spread, double bundle_x,
                                    unsigned seed) {
    SphereSpec spec;
    spec.radius = radius;
    spec.level = 4;
    CrackedSphere s{level_set_from_mesh(make_icosphere(spec), r_f), CrackLevelSets{r_f, 3, {}}};
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1, 1);
    for (int c = 0; c < random_cracks; ++c)
        s.cracks.cracks.push_back(planar_disk_crack(spread * Vec3(u(rng), u(rng), u(rng)), Vec3(u(rng), u(rng), u(rng)), 1, r_f));
    for (const double gap : {0.0, 2.5, 5.0})
        s.cracks.cracks.push_back(planar_disk_crack(Vec3(bundle_x, gap * r_f, 0), Vec3(0.05, 1, 0.02), 1, r_f));
    return s;
}

}  // namespace cf::testing
