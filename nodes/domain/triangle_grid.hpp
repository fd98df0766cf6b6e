#pragma once
// Closest-point queries against a triangle set: the coarse (BEM) mesh for the output-mesh
// deformation of thesis ch. 6.4 (cell size r_c), the fine mesh whose regions a remeshed BEM mesh
// takes over (nodes/simplify/carry_regions). A uniform grid, each cell listing the triangles whose bounding box
// overlaps it (the thesis uses a coarse OpenVDB grid the same way; a hash map of cells keeps
// OpenVDB out of this code). A query looks at the cell of x and then at shells of neighbouring
// cells until no unvisited triangle can be closer than the best one found.
#include "nodes/domain/triangle_closest_point.hpp"

#include <cstdint>
#include <limits>
#include <unordered_map>
#include <vector>

namespace cf {

using Triangle3 = std::array<Vec3, 3>;  // as nodes/levelset/crack_grids.hpp declares it

class TriangleGrid {
public:
    struct Hit {
        int triangle = -1;  // index into the triangles given to the constructor; -1: none
        Vec3 point = Vec3::Zero();
        Vec3 bary = Vec3::Zero();
        double distance = std::numeric_limits<double>::infinity();  // [m]
    };

    // Throws std::invalid_argument when cell_size is not positive and finite, when a vertex is not
    // finite, or when the triangles would fill more than max_cell_entries cell lists (triangles far
    // larger than the cells).
    TriangleGrid(std::vector<Triangle3> triangles, double cell_size, double max_cell_entries = 5e7);

    // The closest triangle to x; ties go to the lower triangle index, so the answer does not depend
    // on the order cells are visited in. No triangles: triangle == -1.
    Hit closest(const Vec3& x) const;
    // Every triangle within `radius` of x, once each, sorted by triangle index.
    std::vector<Hit> within(const Vec3& x, double radius) const;

    std::size_t size() const { return triangles_.size(); }
    double cell_size() const { return cell_; }
    const Triangle3& triangle(int t) const { return triangles_[std::size_t(t)]; }

private:
    using Cell = std::array<std::int64_t, 3>;
    Cell cell_of(const Vec3& x) const;
    static std::uint64_t key(const Cell& c);
    const std::vector<int>* cell_list(const Cell& c) const;
    void test(int t, const Vec3& x, Hit& best) const;

    std::vector<Triangle3> triangles_;
    double cell_ = 0;
    Cell lo_{}, hi_{};  // occupied cell index range (inclusive)
    std::unordered_map<std::uint64_t, std::vector<int>> cells_;
};

}  // namespace cf
