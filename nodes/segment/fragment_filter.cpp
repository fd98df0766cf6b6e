// Dropping speck fragments below a volume (segment.fragments' min_volume).
#include "nodes/segment/fragments.hpp"

#include "graph/diagnostics.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace cf {

std::size_t drop_small_fragments(Fragments& f, double min_volume, double* removed_volume) {
    if (!(min_volume >= 0) || !std::isfinite(min_volume))
        throw std::invalid_argument("minimum fragment volume " + graph::format_number(min_volume) +
                                    " m^3 must be finite and >= 0 (0 keeps every fragment)");
    std::size_t removed = 0;
    std::vector<Fragment> kept;
    kept.reserve(f.fragments.size());
    for (Fragment& g : f.fragments) {
        if (g.volume >= min_volume) {
            kept.push_back(std::move(g));
            continue;
        }
        ++removed;
        if (removed_volume) *removed_volume += g.volume;
    }
    f.fragments = std::move(kept);
    return removed;
}

}  // namespace cf
