#pragma once
// Fragments that keep the input surface (issue 14): fragment i's mesh is input ∩ C_i, the input
// surface intersected with the fragment's cell (fragment_cells.hpp) by CGAL's corefinement. Its
// outer faces are the input's own triangles, clipped where the cell's faces cut them, carrying the
// input's region (material / group), texture coordinates and normals (interpolated barycentrically
// on the input triangle where clipped); its fracture faces come from the cell and are tagged with
// the region "inside", with texture coordinates by box (triplanar) projection in object space, so
// they are continuous across pieces. No CGAL in this header.
#include "nodes/domain/surface_mesh.hpp"

#include <memory>
#include <string>

namespace cf {

inline constexpr const char* kInsideRegion = "inside";

// Box projection of the fracture faces: the face normal's dominant axis picks the plane,
// uv = (the two other coordinates - origin) / scale.
struct InsideUvProjection {
    Vec3 origin = Vec3::Zero();  // [m] the object's bounding-box minimum
    double scale = 1;            // [m] per UV unit, > 0 (the object's largest extent: UVs in [0, 1])
    Vec2 operator()(const Vec3& p, const Vec3& normal) const;
};

// The input surface prepared once (CGAL mesh, checks) and intersected with one cell per call.
class SurfaceClipper {
public:
    // Throws std::invalid_argument (naming the problem and the way out: mesher 'levelset') when the
    // input is not closed, manifold and free of self-intersections.
    explicit SurfaceClipper(const SurfaceMesh& input);
    ~SurfaceClipper();
    SurfaceClipper(const SurfaceClipper&) = delete;
    SurfaceClipper& operator=(const SurfaceClipper&) = delete;

    // input ∩ cell with attributes: regions of the input first (same ids and names), then
    // kInsideRegion; corner_uv on every face (input UVs, or the box projection where the input has
    // none), corner_normal likewise (input normals, or the flat face normal). Thread-safe. Returns
    // false with *problem set when the cell is not closed, manifold and free of self-intersections,
    // or the result is empty, open or non-manifold: the caller falls back to the level-set mesh.
    // With `folded`: where folds of the fracture faces cannot be mended, the result keeps them
    // (closed and manifold, its fracture faces crossing each other near the folds: fine to draw, not
    // to clip again) and *folded is set; without it, that is a failure too.
    bool clip(const SurfaceMesh& cell, SurfaceMesh& out, std::string* problem, bool* folded = nullptr) const;

    const SurfaceMesh& input() const;  // the surface it clips
    const InsideUvProjection& projection() const;
    int inside_region() const;  // the id of kInsideRegion in every clipped mesh

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace cf
