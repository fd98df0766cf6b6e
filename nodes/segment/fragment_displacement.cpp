#include "nodes/segment/fragment_displacement.hpp"

#include "graph/diagnostics.hpp"
#include "nodes/bem/interior_evaluation.hpp"
#include "nodes/bem/solver.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace cf {

namespace {

// Gradients of a distance field have unit length inside the band; a much shorter one means x is
// outside the band (background value) or at its rim, where the direction is not reliable.
constexpr double kMinGradient = 0.25;

std::vector<Triangle3> triangles_of(const SurfaceMesh& m) {
    std::vector<Triangle3> t(m.num_triangles());
    for (std::size_t i = 0; i < t.size(); ++i)
        for (int k = 0; k < 3; ++k) t[i][k] = m.vertices[std::size_t(m.triangles[i][k])];
    return t;
}

Vec3 interpolate(const SurfaceMesh& m, const std::vector<Vec3>& nodal, int t, const Vec3& bary) {
    const Tri& tri = m.triangles[std::size_t(t)];
    return bary[0] * nodal[std::size_t(tri[0])] + bary[1] * nodal[std::size_t(tri[1])] + bary[2] * nodal[std::size_t(tri[2])];
}

double mean_edge_length(const SurfaceMesh& a, const SurfaceMesh& b) {
    double sum = 0;
    std::size_t n = 0;
    for (const SurfaceMesh* m : {&a, &b})
        for (const Tri& t : m->triangles)
            for (int k = 0; k < 3; ++k) {
                sum += (m->vertices[std::size_t(t[k])] - m->vertices[std::size_t(t[(k + 1) % 3])]).norm();
                ++n;
            }
    return n ? sum / double(n) : 0.0;
}

bool inside(const Box3& b, const Vec3& x, double margin) {
    return (x.array() >= b.min.array() - margin).all() && (x.array() <= b.max.array() + margin).all();
}

void check_mesh(const SurfaceMesh& m, const char* what) {
    for (std::size_t t = 0; t < m.num_triangles(); ++t)
        for (int v : m.triangles[t])
            if (v < 0 || std::size_t(v) >= m.num_vertices())
                throw std::invalid_argument(std::string(what) + " triangle " + std::to_string(t) + " refers to vertex " +
                                            std::to_string(v) + " of " + std::to_string(m.num_vertices()));
}

void check_size(std::size_t have, std::size_t want, const std::string& what) {
    if (have != want)
        throw std::invalid_argument(what + " has " + std::to_string(have) + " values for " + std::to_string(want) +
                                    " vertices");
}

}  // namespace

CoarseDisplacement coarse_displacement_from(const bem::BemSolution& sol, bool with_crack_average) {
    if (!sol.surface) throw std::invalid_argument("the BEM solution has no surface operators");
    CoarseDisplacement c;
    c.surface = sol.surface->mesh;
    c.surface_displacement = sol.displacement;
    if (sol.cracks) {
        c.cracks = sol.cracks->cracks;
        c.crack_opening = sol.crack_opening;
        // A solve without crack unknowns (every crack node on a front) leaves the opening empty: it is zero.
        if (c.crack_opening.empty()) c.crack_opening.assign(c.cracks.num_vertices(), Vec3::Zero());
        if (with_crack_average && c.cracks.num_vertices() > 0) c.crack_average = bem::crack_average_displacement(sol);
    }
    return c;
}

DisplacementMode displacement_mode_from_name(const std::string& name) {
    if (name == "none") return DisplacementMode::none;
    if (name == "continuous") return DisplacementMode::continuous;
    if (name == "continuous_and_opening") return DisplacementMode::continuous_and_opening;
    throw std::invalid_argument("unknown displacement mode '" + name + "' (none, continuous, continuous_and_opening)");
}

void DeformationStats::add(const DeformationStats& o) {
    vertices += o.vertices;
    on_crack += o.on_crack;
    opened += o.opened;
    closed += o.closed;
    sign_from_coarse += o.sign_from_coarse;
    max_displacement = std::max(max_displacement, o.max_displacement);
}

std::size_t remove_compressive_opening(const SurfaceMesh& cracks, std::vector<Vec3>& opening) {
    check_size(opening.size(), cracks.num_vertices(), "crack opening");
    std::vector<Vec3> normal(cracks.num_vertices(), Vec3::Zero());
    for (std::size_t t = 0; t < cracks.num_triangles(); ++t)
        for (int v : cracks.triangles[t]) normal[std::size_t(v)] += triangle_normal_unnormalised(cracks, t);  // area-weighted
    std::size_t changed = 0;
    for (std::size_t v = 0; v < opening.size(); ++v) {
        const double len = normal[v].norm();
        if (!(len > 0)) continue;
        const Vec3 n = normal[v] / len;
        const double un = opening[v].dot(n);
        if (un < 0) {
            opening[v] -= un * n;
            ++changed;
        }
    }
    return changed;
}

struct FragmentDeformation::Impl {
    DeformationOptions opt;
    std::shared_ptr<const CoarseDisplacement> coarse;
    const CrackLevelSets* cracks = nullptr;
    double r_f = 0, r_c = 0, h = 0;
    std::unique_ptr<TriangleGrid> surface_grid, crack_grid;
    std::vector<Vec3> crack_normal;  // unit triangle normals of the crack sheets (- to +)
    std::vector<Vec3> opening;       // after compressive removal
    std::size_t compressive = 0;
    std::vector<Box3> crack_boxes;   // active voxels of each crack grid

    Vec3 deform(const Vec3& x, DeformationStats& s) const;
    Vec3 opening_offset(const Vec3& x, const TriangleGrid::Hit& closest_crack, bool closest_is_crack,
                        DeformationStats& s) const;
    Vec3 closing_offset(const Vec3& x, DeformationStats& s) const;
};

FragmentDeformation::FragmentDeformation(std::shared_ptr<const CoarseDisplacement> coarse, const CrackLevelSets* cracks,
                                         double r_f, const DeformationOptions& options)
    : impl_(std::make_unique<Impl>()) {
    Impl& m = *impl_;
    m.opt = options;
    m.coarse = std::move(coarse);
    m.cracks = cracks;
    m.r_f = r_f;
    m.h = crack_half_thickness(r_f);
    if (!(r_f > 0)) throw std::invalid_argument("fragment deformation: voxel size r_f = " + graph::format_number(r_f) + " m must be positive");
    if (!(options.scale >= 0) || !std::isfinite(options.scale))
        throw std::invalid_argument("displacement scale " + graph::format_number(options.scale) + " must be finite and >= 0");
    const bool displace = options.mode != DisplacementMode::none;
    const bool open = options.mode == DisplacementMode::continuous_and_opening;
    if (displace && !m.coarse)
        throw std::invalid_argument("displacement needs the coarse BEM displacement (a BEM solution)");
    if ((open || options.close_gaps) && !cracks)
        throw std::invalid_argument(std::string(open ? "the crack opening" : "closing gaps") +
                                    " needs the recorded crack grids (CrackLevelSets)");
    if (cracks) {
        if (std::abs(cracks->voxel_size - r_f) > 1e-9 * r_f)
            throw std::invalid_argument("crack grids have voxel size " + graph::format_number(cracks->voxel_size) +
                                        " m but the fragments " + graph::format_number(r_f) + " m; record the cracks at the fragments' r_f");
        for (std::size_t c = 0; c < cracks->cracks.size(); ++c) {
            if (cracks->cracks[c].empty()) throw std::invalid_argument("crack grid " + std::to_string(c) + " is empty");
            m.crack_boxes.push_back(active_bounding_box(cracks->cracks[c]));
        }
    }
    if (open && !(options.opening_band > 1))
        throw std::invalid_argument("opening band " + graph::format_number(options.opening_band) +
                                    " voxels must exceed 1 voxel (the crack's half thickness is 0.87 voxels)");
    if (!(options.gap_tolerance > 0)) throw std::invalid_argument("gap tolerance must be positive");
    if (!displace) return;

    const CoarseDisplacement& c = *m.coarse;
    check_mesh(c.surface, "surface");
    check_mesh(c.cracks, "crack");
    check_size(c.surface_displacement.size(), c.surface.num_vertices(), "surface displacement");
    if (c.cracks.num_triangles() > 0) check_size(c.crack_average.size(), c.cracks.num_vertices(), "crack average displacement u_c");
    if (c.surface.num_triangles() + c.cracks.num_triangles() == 0)
        throw std::invalid_argument("the coarse BEM mesh has no triangles to interpolate from");
    m.r_c = mean_edge_length(c.surface, c.cracks);
    m.surface_grid = std::make_unique<TriangleGrid>(triangles_of(c.surface), m.r_c);
    m.crack_grid = std::make_unique<TriangleGrid>(triangles_of(c.cracks), m.r_c);
    if (!open) return;
    check_size(c.crack_opening.size(), c.cracks.num_vertices(), "crack opening [u]");
    for (std::size_t t = 0; t < c.cracks.num_triangles(); ++t) {
        const int r = c.cracks.region_of(t);
        if (r < 0 || std::size_t(r) >= cracks->cracks.size())
            throw std::invalid_argument("crack triangle " + std::to_string(t) + " belongs to crack " + std::to_string(r) +
                                        " but there are " + std::to_string(cracks->cracks.size()) +
                                        " crack grids; pass the crack grids of the same fracture run");
        m.crack_normal.push_back(triangle_normal(c.cracks, t));
    }
    m.opening = c.crack_opening;
    if (options.remove_compressive_opening) m.compressive = remove_compressive_opening(c.cracks, m.opening);
}

FragmentDeformation::~FragmentDeformation() = default;
FragmentDeformation::FragmentDeformation(FragmentDeformation&&) noexcept = default;
FragmentDeformation& FragmentDeformation::operator=(FragmentDeformation&&) noexcept = default;

const DeformationOptions& FragmentDeformation::options() const { return impl_->opt; }
double FragmentDeformation::cell_size() const { return impl_->r_c; }
const std::vector<Vec3>& FragmentDeformation::opening() const { return impl_->opening; }
std::size_t FragmentDeformation::compressive_vertices() const { return impl_->compressive; }

// Crack-opening displacement at x (ch. 6.4 "Crack opening displacements", listing 2 lines 21-33),
// summed over every crack with a triangle within opening_band r_f of x.
//  - Face: the sign is that of grad Phi_f(x) . n_tri. Phi_f is the crack's recorded fine distance,
//    so its gradient points from the fine crack surface towards x; n_tri points from - to +.
//    Without a usable fine gradient (x outside the crack grid's band) the coarse side
//    (x - y_f) . n_tri decides.
//  - Weight w_Delta, offset +-w_Delta [u](y_f): when the closest coarse point y is on this crack
//    (y = y_f) the face moves by the full +-[u]/2 (w = 1/2). Otherwise (y on the ordinary surface
//    or another crack) the thesis blends with w = 1/2 at the fracture surface, 0 outside the crack
//    grid's narrow band and linear between. The fracture faces of the output mesh sit at the
//    thickening distance h = sqrt(3) r_f / 2 from the crack, so we implement
//        w = 1/2 clamp((B r_f - |x - y_f|) / (B r_f - h), 0, 1),   B = opening_band (3),
//    which makes both cases give 1/2 where a cut face meets the ordinary surface.
Vec3 FragmentDeformation::Impl::opening_offset(const Vec3& x, const TriangleGrid::Hit& closest_crack, bool closest_is_crack,
                                               DeformationStats& s) const {
    const CoarseDisplacement& c = *coarse;
    const double band = opt.opening_band * r_f;
    const std::vector<TriangleGrid::Hit> hits = crack_grid->within(x, band);
    if (hits.empty()) return Vec3::Zero();
    // The closest triangle of each crack (hits are sorted by index: ties go to the lower index).
    std::vector<TriangleGrid::Hit> best(cracks->cracks.size());
    for (const TriangleGrid::Hit& hit : hits) {
        TriangleGrid::Hit& b = best[std::size_t(c.cracks.region_of(std::size_t(hit.triangle)))];
        if (hit.distance < b.distance) b = hit;
    }
    Vec3 cod = Vec3::Zero();
    bool any = false;
    for (std::size_t r = 0; r < best.size(); ++r) {
        const TriangleGrid::Hit& b = best[r];
        if (b.triangle < 0) continue;
        const Vec3& n = crack_normal[std::size_t(b.triangle)];
        const Vec3 g = sample_gradient(cracks->cracks[r], x);
        double side = 0;
        if (g.norm() >= kMinGradient && std::abs(g.dot(n)) > 1e-3 * g.norm()) {
            side = g.dot(n);
        } else {
            side = (x - b.point).dot(n);
            if (std::abs(side) <= 1e-9 * r_f) continue;  // x on the sheet's plane beyond it: no face
            ++s.sign_from_coarse;
        }
        const bool same = closest_is_crack && c.cracks.region_of(std::size_t(closest_crack.triangle)) == int(r);
        const double w = same ? 0.5 : 0.5 * std::clamp((band - b.distance) / (band - h), 0.0, 1.0);
        if (w <= 0) continue;
        cod += (side > 0 ? w : -w) * interpolate(c.cracks, opening, b.triangle, b.bary);
        any = true;
    }
    if (any) ++s.opened;
    return cod;
}

// Gap closing (ch. 6.4 "Closing gaps", listing 2 lines 10-14): a vertex on a cut face lies on
// Phi_f = Phi_u - h = 0 of some crack; it moves along the unit gradient by -Phi_u(x) onto the
// recorded surface Phi_u = 0: x_c = x - (Phi_f(x) + h) grad Phi_f / |grad Phi_f|. The crack with the
// smallest |Phi_f(x)| within gap_tolerance r_f is used.
Vec3 FragmentDeformation::Impl::closing_offset(const Vec3& x, DeformationStats& s) const {
    const double tol = opt.gap_tolerance * r_f;
    int which = -1;
    double phi_best = 0;
    for (std::size_t r = 0; r < cracks->cracks.size(); ++r) {
        if (!inside(crack_boxes[r], x, r_f)) continue;
        const double phi = sample(cracks->cracks[r], x);
        if (std::abs(phi) <= tol && (which < 0 || std::abs(phi) < std::abs(phi_best))) {
            which = int(r);
            phi_best = phi;
        }
    }
    if (which < 0) return Vec3::Zero();
    const Vec3 g = sample_gradient(cracks->cracks[std::size_t(which)], x);
    const double len = g.norm();
    if (len < kMinGradient) return Vec3::Zero();
    ++s.closed;
    return -(phi_best + h) * g / len;
}

// Listing 2: u_c / u from the closest coarse triangle (lines 17-20), the opening (21-33), both
// scaled, then the gap closing (36-37), all evaluated at the undeformed x.
Vec3 FragmentDeformation::Impl::deform(const Vec3& x, DeformationStats& s) const {
    ++s.vertices;
    Vec3 u = Vec3::Zero();
    if (opt.mode != DisplacementMode::none) {
        const CoarseDisplacement& c = *coarse;
        const TriangleGrid::Hit hs = surface_grid->closest(x);
        const TriangleGrid::Hit hc = crack_grid->closest(x);
        const bool on_crack = hc.triangle >= 0 && (hs.triangle < 0 || hc.distance < hs.distance);
        if (on_crack) {
            ++s.on_crack;
            u = interpolate(c.cracks, c.crack_average, hc.triangle, hc.bary);  // u_c(y)
        } else {
            u = interpolate(c.surface, c.surface_displacement, hs.triangle, hs.bary);  // u(y)
        }
        if (opt.mode == DisplacementMode::continuous_and_opening) u += opening_offset(x, hc, on_crack, s);
        u *= opt.scale;
    }
    if (opt.close_gaps) u += closing_offset(x, s);
    s.max_displacement = std::max(s.max_displacement, u.norm());
    return x + u;
}

std::vector<Vec3> FragmentDeformation::deformed(const std::vector<Vec3>& x, DeformationStats* stats) const {
    std::vector<Vec3> out(x.size());
    // Fixed chunks, each with its own statistics, combined in chunk order.
    constexpr std::size_t kChunk = 1024;
    std::vector<DeformationStats> per((x.size() + kChunk - 1) / kChunk);
    tbb::parallel_for(std::size_t(0), per.size(), [&](std::size_t k) {
        const std::size_t end = std::min(x.size(), (k + 1) * kChunk);
        for (std::size_t i = k * kChunk; i < end; ++i) out[i] = impl_->deform(x[i], per[k]);
    });
    if (stats)
        for (const DeformationStats& p : per) stats->add(p);
    return out;
}

void FragmentDeformation::apply(SurfaceMesh& mesh, DeformationStats* stats) const {
    mesh.vertices = deformed(mesh.vertices, stats);
}

}  // namespace cf
