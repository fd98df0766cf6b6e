#pragma once
// Deforming the fragment output meshes (thesis ch. 6.4, App. B listing 2): every vertex x of a
// fine output mesh gets
//   - the continuous displacement, interpolated linearly in the closest coarse (BEM) triangle:
//     the nodal displacement u on an ordinary-surface triangle, the crack's average displacement
//     u_c (eq. 2.20 over the ordinary surface only) on a crack triangle;
//   - optionally the crack-opening displacement of every crack whose closest triangle y_f lies
//     within half_width * r_f of x: +-w [u](y_f), the sign chosen by the fine crack surface;
//   - optionally the gap closing: cut-face vertices move onto the recorded crack surface.
// Everything is evaluated at the undeformed x (the thickening gap is what tells the faces apart)
// and added at the end: x_new = x + s (u + cod) + closing (listing 2, lines 10-37).
// No OpenVDB here; crack grids are sampled through cf::LevelSet.
#include "nodes/levelset/crack_grids.hpp"
#include "nodes/domain/triangle_grid.hpp"

#include <memory>
#include <string>
#include <vector>

namespace cf {

namespace bem {
struct BemSolution;
}

// The coarse (BEM) data the output is interpolated from.
struct CoarseDisplacement {
    SurfaceMesh surface;                     // ordinary surface Gamma
    std::vector<Vec3> surface_displacement;  // u per surface vertex [m]
    SurfaceMesh cracks;                      // crack sheets; region r is crack r = CrackLevelSets::cracks[r]
    std::vector<Vec3> crack_average;         // u_c per crack vertex [m]
    std::vector<Vec3> crack_opening;         // [u] = u+ - u- per crack vertex [m]; triangle normals point from - to +
};

// From an SGBEM solution: copies meshes and nodal values and, when `with_crack_average`, evaluates
// u_c at every crack vertex (bem::crack_average_displacement, one surface integral per vertex).
CoarseDisplacement coarse_displacement_from(const bem::BemSolution& sol, bool with_crack_average = true);

enum class DisplacementMode { none, continuous, continuous_and_opening };
// "none", "continuous", "continuous_and_opening"; throws std::invalid_argument otherwise.
DisplacementMode displacement_mode_from_name(const std::string& name);

struct DeformationOptions {
    DisplacementMode mode = DisplacementMode::none;
    double scale = 1;                         // multiplies u and the opening (not the gap closing)
    bool remove_compressive_opening = true;   // drop the interpenetrating normal part of [u]
    bool close_gaps = false;                  // move cut-face vertices onto the recorded crack surface
    double opening_band = 3;                  // [voxels]: opening only where |x - y_f| <= opening_band r_f
    double gap_tolerance = 0.5;               // [voxels]: |Phi_f(x)| <= this r_f marks a cut-face vertex
};

struct DeformationStats {
    std::size_t vertices = 0;
    std::size_t on_crack = 0;         // closest coarse triangle is a crack triangle
    std::size_t opened = 0;           // got an opening from at least one crack
    std::size_t closed = 0;           // moved onto a recorded crack surface
    std::size_t sign_from_coarse = 0; // opening sign taken from the coarse triangle (no fine gradient at x)
    double max_displacement = 0;      // max |x_new - x| [m]
    void add(const DeformationStats& o);
};

// Removes the interpenetrating part of the opening at every crack vertex:
// [u] <- [u] - ([u].n) n where [u].n < 0, n the unit area-weighted vertex normal of the sheet
// (pointing from - to +; [u].n < 0 means the faces overlap). Returns the number of vertices changed.
std::size_t remove_compressive_opening(const SurfaceMesh& cracks, std::vector<Vec3>& opening);

class FragmentDeformation {
public:
    // `coarse` is needed unless mode == none; `cracks` (crack grids, voxel size r_f) for
    // continuous_and_opening (the opening's sign) and close_gaps. r_f [m] is the fragments' voxel
    // size. The acceleration grid's cell size r_c is the mean edge length of the coarse mesh.
    // Throws std::invalid_argument naming what is missing or inconsistent.
    FragmentDeformation(std::shared_ptr<const CoarseDisplacement> coarse, const CrackLevelSets* cracks, double r_f,
                        const DeformationOptions& options);
    ~FragmentDeformation();
    FragmentDeformation(FragmentDeformation&&) noexcept;
    FragmentDeformation& operator=(FragmentDeformation&&) noexcept;

    // New positions of undeformed output vertices (oneTBB over vertices; thread-count independent).
    std::vector<Vec3> deformed(const std::vector<Vec3>& x, DeformationStats* stats = nullptr) const;
    void apply(SurfaceMesh& mesh, DeformationStats* stats = nullptr) const;

    const DeformationOptions& options() const;
    double cell_size() const;                       // r_c [m] (0 without coarse data)
    const std::vector<Vec3>& opening() const;       // [u] per crack vertex after compressive removal
    std::size_t compressive_vertices() const;       // crack vertices whose opening was changed

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace cf
