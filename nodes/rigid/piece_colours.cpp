#include "nodes/rigid/piece_colours.hpp"

#include "nodes/domain/fragment_palette.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>

namespace cf::rigid {

namespace {

std::uint64_t fnv1a(const std::string& s) {
    std::uint64_t h = 14695981039346656037ull;
    for (const char ch : s) {
        h ^= std::uint64_t(static_cast<unsigned char>(ch));
        h *= 1099511628211ull;
    }
    return h;
}

double fraction(double x) { return x - std::floor(x); }

}  // namespace

std::vector<Vec3> scene_piece_colours(const Animation& a) {
    const std::size_t n = a.pieces.size();
    // Each piece's original ancestor (bounded walk: a parent cycle is an error, not a hang).
    std::vector<std::size_t> root(n);
    for (std::size_t i = 0; i < n; ++i) {
        std::size_t r = i;
        for (std::size_t steps = 0; a.pieces[r].parent != -1; ++steps) {
            const int parent = a.pieces[r].parent;
            if (parent < 0 || std::size_t(parent) >= n || steps >= n)
                throw std::invalid_argument("piece " + std::to_string(r) + " ('" + a.pieces[r].name + "'): parent " +
                                            std::to_string(parent) + " is out of range or part of a cycle");
            r = std::size_t(parent);
        }
        root[i] = r;
    }
    // Originals in the order of their names' hashes take hues a golden angle apart: any few
    // bodies are well apart (2: 137.5 degrees, 5: >= 52, 8: >= 32), which hashing each name to a
    // hue independently would not give (6 bodies on 12 hues share one 78 % of the time).
    std::vector<std::pair<std::uint64_t, std::size_t>> originals;
    for (std::size_t i = 0; i < n; ++i)
        if (root[i] == i) originals.emplace_back(fnv1a(a.pieces[i].name), i);
    std::sort(originals.begin(), originals.end());
    std::vector<double> hue(n, 0);
    for (std::size_t r = 0; r < originals.size(); ++r)
        hue[originals[r].second] = 360 * fraction(0.07 + double(r) * 0.38196601125010515180);
    std::vector<Vec3> colours(n);
    std::vector<std::uint64_t> fragments_so_far(n, 0);  // per original
    constexpr double g = 1.32471795724474602596;  // plastic number, for the R2 sequence
    for (std::size_t i = 0; i < n; ++i) {
        const double h = hue[root[i]];
        if (root[i] == i) {
            colours[i] = hsv_to_rgb(h, 0.7, 0.9);
            continue;
        }
        // The k-th fragment of a body (in piece order, at any depth) takes the k-th point of the
        // R2 low-discrepancy sequence: consecutive points are well apart in hue shift, saturation
        // and value, so no two fragments of one body look alike.
        const double k = double(fragments_so_far[root[i]]++);
        const double u1 = fraction(0.5 + k / g), u2 = fraction(0.5 + k / (g * g));
        const double u3 = fraction(0.5 + k * 0.61803398874989484820);
        colours[i] = hsv_to_rgb(h + 6.0 * (2 * u1 - 1), 0.45 + 0.4 * u3, 0.55 + 0.45 * u2);
    }
    return colours;
}

}  // namespace cf::rigid
