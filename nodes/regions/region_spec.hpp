#pragma once
// Boundary regions as convex intersections of half-spaces (thesis App. A (10)): the text a user
// writes to name parts of a surface, e.g.
//
//   top: z >= 0.49; bottom: z <= -0.49; left_upper: x <= -0.49 & y >= 0;
//   slanted: 0.7071*x + 0.7071*z >= 0.3
//
// Grammar (whitespace and newlines are free between tokens):
//   spec      := region { ';' region } [';']
//   region    := name ':' condition { '&' condition }
//   name      := letter or '_', then letters, digits or '_'
//   condition := linear ( '>=' | '<=' | '>' | '<' ) linear
//   linear    := [ '+' | '-' ] term { ( '+' | '-' ) term }
//   term      := factor { ( '*' | '/' ) factor }, at most one of x, y, z; only numbers divide
//   factor    := number | x | y | z   (a number written right against its variable, 2x, means 2*x)
// Coordinates are in metres, in the mesh's frame.
#include "nodes/domain/surface_mesh.hpp"

#include <stdexcept>
#include <string>
#include <vector>

namespace cf {

// The set of points p with normal . p + offset >= 0 (> 0 when strict).
struct HalfSpace {
    Vec3 normal = Vec3::Zero();
    double offset = 0;
    bool strict = false;
    bool contains(const Vec3& p) const {
        const double s = normal.dot(p) + offset;
        return strict ? s > 0 : s >= 0;
    }
};

struct RegionDefinition {
    std::string name;
    std::vector<HalfSpace> conditions;  // all must hold
    bool contains(const Vec3& p) const {
        for (const HalfSpace& h : conditions)
            if (!h.contains(p)) return false;
        return true;
    }
};

// A mistake in the region text. what() names the region (when known) and the position, e.g.
// "region 'top', column 8: expected a comparison (>=, <=, >, <) after 'z', found '0.49'".
struct RegionSpecError : std::invalid_argument {
    using std::invalid_argument::invalid_argument;
};

// Regions in the order written (earlier regions win where they overlap). Throws RegionSpecError.
std::vector<RegionDefinition> parse_region_spec(const std::string& spec);

}  // namespace cf
