// OpenVDB translation unit: object level set from a mesh, measures, sampling, meshing, VDB I/O.
#include "nodes/levelset/level_set_grid.hpp"
#include "nodes/domain/mesh_topology.hpp"
#include "nodes/domain/triangle_closest_point.hpp"

#include "graph/atomic_write.hpp"
#include "graph/diagnostics.hpp"
#include "nodes/levelset/vdb_write.hpp"

#include <openvdb/io/File.h>
#include <openvdb/tools/Interpolation.h>
#include <openvdb/tools/LevelSetMeasure.h>
#include <openvdb/tools/MeshToVolume.h>
#include <openvdb/tools/VolumeToMesh.h>
#include <openvdb/thread/Threading.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <atomic>
#include <array>
#include <cmath>
#include <map>
#include <memory>
#include <numeric>
#include <mutex>
#include <sstream>
#include <stdexcept>

namespace cf {

void ensure_openvdb_initialized() {
    static std::once_flag once;
    std::call_once(once, [] { openvdb::initialize(); });
}

namespace {

// One closed shell of a (possibly multi-shell) surface: its triangles, signed volume and how many
// other shells enclose it.
struct Shell {
    std::vector<Tri> triangles;
    double volume = 0;
    Vec3 lo = Vec3::Constant(INFINITY), hi = Vec3::Constant(-INFINITY);
    int depth = 0;
};

// Solid angle of triangle (a, b, c) seen from the origin (Van Oosterom and Strackee).
double solid_angle(const Vec3& a, const Vec3& b, const Vec3& c) {
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    return 2 * std::atan2(a.dot(b.cross(c)), la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la);
}

// Shells (connected by shared vertices) with their nesting depth by the generalised winding number.
std::vector<Shell> shells_of(const SurfaceMesh& mesh) {
    std::vector<int> parent(mesh.vertices.size());
    std::iota(parent.begin(), parent.end(), 0);
    auto find = [&](int v) {
        while (parent[v] != v) v = parent[v] = parent[parent[v]];
        return v;
    };
    for (const Tri& t : mesh.triangles) {
        const int a = find(t[0]);
        parent[find(t[1])] = a;
        parent[find(t[2])] = a;
    }
    std::map<int, int> index;
    std::vector<Shell> shells;
    for (const Tri& t : mesh.triangles) {
        const auto [it, fresh] = index.emplace(find(t[0]), int(shells.size()));
        if (fresh) shells.emplace_back();
        Shell& s = shells[it->second];
        s.triangles.push_back(t);
        const Vec3 &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]], &c = mesh.vertices[t[2]];
        s.volume += a.dot(b.cross(c)) / 6;
        s.lo = s.lo.cwiseMin(a).cwiseMin(b).cwiseMin(c);
        s.hi = s.hi.cwiseMax(a).cwiseMax(b).cwiseMax(c);
    }
    for (std::size_t i = 0; shells.size() > 1 && i < shells.size(); ++i) {
        const Vec3& p = mesh.vertices[shells[i].triangles[0][0]];
        for (std::size_t j = 0; j < shells.size(); ++j) {
            if (j == i || (p.array() < shells[j].lo.array()).any() || (p.array() > shells[j].hi.array()).any()) continue;
            double w = 0;
            for (const Tri& t : shells[j].triangles)
                w += solid_angle(mesh.vertices[t[0]] - p, mesh.vertices[t[1]] - p, mesh.vertices[t[2]] - p);
            if (std::abs(w) > 2 * M_PI) ++shells[i].depth;  // |winding number| > 1/2
        }
    }
    return shells;
}

// meshToVolume's interrupter, which also remembers the last progress figure it was asked with:
// the band expansion starts at 54 % (OpenVDB 10's MeshToVolume.h).
struct PhaseInterrupter : CancelInterrupter {
    using CancelInterrupter::CancelInterrupter;
    bool wasInterrupted(int percent = -1) override {
        if (percent >= 0) last_percent.store(percent, std::memory_order_relaxed);
        return CancelInterrupter::wasInterrupted(percent);
    }
    std::atomic<int> last_percent{0};
};

// The triangles as meshToLevelSet hands them to meshToVolume (corners rounded to float, then to float
// index-space points), with one addition: every corner read polls the cancel token. OpenVDB asks its
// interrupter only per polygon while voxelising and then between phases, and the sign classification,
// band expansion and renormalisation in between take up to a second on a fine grid of an imported mesh
// (issue 16: Ctrl-C within 0.5 s). Those phases read triangle corners throughout, so a read on a
// cancelled run cancels the parallel loop it runs in, as OpenVDB's own voxeliser does when interrupted
// (thread::cancelGroupExecution: no new chunks start; running ones finish, so the trees stay
// consistent), and the interrupter ends the conversion at its next check. The grid is then incomplete,
// and the caller's poll() throws. On a run that is not cancelled the values are meshToLevelSet's, bit
// for bit (test LevelSet.CancellableConversionEqualsMeshToLevelSet).
struct CancellableTriangles {
    std::vector<openvdb::Vec3s> points;  // index space
    std::vector<openvdb::Vec3I> triangles;
    const PhaseInterrupter* interrupter = nullptr;  // its token, and the stage meshToVolume is in

    std::size_t polygonCount() const { return triangles.size(); }
    std::size_t pointCount() const { return points.size(); }
    std::size_t vertexCount(std::size_t) const { return 3; }
    void getIndexSpacePoint(std::size_t n, std::size_t v, openvdb::Vec3d& pos) const {
        // Voxelisation and sign classification stop at once. The band expansion is left to finish
        // its pass (the interrupter is asked between passes): its parallel_reduce bodies own the
        // leaves they create through raw pointers, and a cancelled reduce destroys its split bodies
        // without joining them, which leaked those leaves (LeakSanitizer, 2026-12-03). crackflow run
        // still exits within 0.3 s of Ctrl-C (runtime/cancel_deadline.hpp).
        if (interrupter->token.requested() && interrupter->last_percent.load(std::memory_order_relaxed) < 54)
            openvdb::thread::cancelGroupExecution();
        pos = points[triangles[n][int(v)]];
    }
};

// A parallel loop over `n` leaves that stops starting chunks once the run is cancelled (the
// chunks running finish, so the tree stays consistent; the caller polls afterwards).
template <class Body>
void polled_for(std::size_t n, const Body& body, const CancelToken& cancel) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n), [&](const tbb::blocked_range<std::size_t>& r) {
        if (cancel.requested()) {
            openvdb::thread::cancelGroupExecution();
            return;
        }
        body(r);
    });
}

// meshToVolume's last steps on the band shell_grid gets with them disabled: one renormalisation
// step (on exact distances it moves values inward where upwind differences see a kink:
// object_band.cpp's band_value), then, when `trim` (meshToVolume trims bands under 4 voxels), the
// band trimmed to +-half_width voxels and pruned. Its own functors in the same order, but polled per
// chunk of leaves (in meshToVolume they run between two checks of its interrupter: 4 s on the
// armadillo at r_f = 0.2 mm on a loaded machine).
void renormalise_and_trim_like_mesh_to_volume(openvdb::FloatGrid& grid, float voxel_size, float half_width, bool trim,
                                             const CancelToken& cancel) {
    namespace m2v = openvdb::tools::mesh_to_volume_internal;
    openvdb::FloatTree& tree = grid.tree();
    const float width = half_width * voxel_size;
    std::vector<openvdb::FloatTree::LeafNodeType*> nodes;
    nodes.reserve(tree.leafCount());
    tree.getNodes(nodes);
    const std::size_t n = nodes.size();
    std::unique_ptr<float[]> buffer{new float[openvdb::FloatTree::LeafNodeType::SIZE * n]};
    const float offset = float(0.8 * voxel_size);
    polled_for(n, m2v::OffsetValues<openvdb::FloatTree>(nodes, -offset), cancel);
    polled_for(n, m2v::Renormalize<openvdb::FloatTree>(tree, nodes, buffer.get(), voxel_size), cancel);
    polled_for(n, m2v::MinCombine<openvdb::FloatTree>(nodes, buffer.get()), cancel);
    polled_for(n, m2v::OffsetValues<openvdb::FloatTree>(nodes, offset - m2v::Tolerance<float>::epsilon()), cancel);
    if (!trim || cancel.requested()) return;
    polled_for(n, m2v::InactivateValues<openvdb::FloatTree>(nodes, width, width), cancel);
    if (cancel.requested()) return;
    prune_level_set_polled(tree, width, -width, cancel);
}

openvdb::FloatGrid::Ptr shell_grid(const SurfaceMesh& mesh, const std::vector<Tri>& triangles, double r_f,
                                   double half_width, const CancelToken& cancel) {
    auto xform = openvdb::math::Transform::createLinearTransform(r_f);
    std::vector<openvdb::Vec3s> world;
    world.reserve(mesh.vertices.size());
    for (const Vec3& v : mesh.vertices) world.emplace_back(float(v.x()), float(v.y()), float(v.z()));
    PhaseInterrupter interrupter(cancel);
    CancellableTriangles adapter{std::vector<openvdb::Vec3s>(world.size()), {}, &interrupter};
    // meshToLevelSet's own point transform: the same loop written here rounds some index-space
    // corners differently by one float ulp (measured on a torus: 74 of 288 points), which moves
    // band values by a few ulps.
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, world.size()),
                      openvdb::tools::mesh_to_volume_internal::TransformPoints<openvdb::Vec3s>(
                          world.data(), adapter.points.data(), *xform));
    adapter.triangles.reserve(triangles.size());
    for (const Tri& t : triangles) adapter.triangles.emplace_back(t[0], t[1], t[2]);
    // Sign by scan conversion, then flood fill of the interior tiles (ch. 6.1, [52]); the band of
    // half_width voxels on both sides, as meshToLevelSet asks for it.
    // The renormalisation and trimming run here instead, polled (they are meshToVolume's last steps
    // and its longest stretch without an interrupter check).
    const int flags = openvdb::tools::DISABLE_RENORMALIZATION | openvdb::tools::DISABLE_NARROW_BAND_TRIMMING;
    openvdb::FloatGrid::Ptr g = openvdb::tools::meshToVolume<openvdb::FloatGrid>(
        interrupter, adapter, *xform, float(half_width), float(half_width), flags);
    cancel.poll();
    const float voxel = float(xform->voxelSize()[0]);
    const float width = float(half_width) * voxel;
    if (g->tree().activeVoxelCount() > 0)  // meshToVolume returns an empty band untouched
        renormalise_and_trim_like_mesh_to_volume(*g, voxel, float(half_width), width < voxel * 4.0f, cancel);
    cancel.poll();
    return g;
}

bool has_degenerate_triangle(const SurfaceMesh& mesh) {
    for (const Tri& t : mesh.triangles)
        if (is_degenerate_triangle(mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]])) return true;
    return false;
}

}  // namespace

namespace {

LevelSet object_level_set(const SurfaceMesh& mesh, double r_f, double half_width, double max_voxels, bool exact,
                          const CancelToken& cancel) {
    ensure_openvdb_initialized();
    if (!(r_f > 0) || !std::isfinite(r_f))
        throw std::invalid_argument("voxel size r_f must be a positive number of metres, got " + graph::format_number(r_f));
    if (!(half_width >= 1))
        throw std::invalid_argument("narrow-band half-width must be at least 1 voxel, got " + graph::format_number(half_width));
    if (mesh.triangles.empty()) throw std::invalid_argument("the surface mesh has no triangles");
    for (const Vec3& v : mesh.vertices)
        if (!v.allFinite()) throw std::invalid_argument("the surface mesh has a vertex with a non-finite coordinate");
    const MeshTopologyReport topo = check_topology(mesh);
    if (!topo.is_closed_manifold())
        throw std::invalid_argument("the object level set needs a closed, manifold, consistently oriented surface "
                                    "mesh, but this one has " + topo.describe() +
                                    "; close the holes or remesh the input first");
    const double vol = signed_volume(mesh);
    if (!(vol > 0))
        throw std::invalid_argument("the surface mesh encloses a non-positive signed volume (" + graph::format_number(vol) +
                                    " m^3): its triangles face inward; flip their orientation");
    // Several shells: a shell inside an odd number of others bounds a cavity and must face into it
    // (negative signed volume); inside an even number it is solid (positive). The flood fill of
    // mesh-to-volume cannot tell a cavity from the inside, so each shell gets its own grid and the
    // grids are combined outermost first: solids united, cavities subtracted.
    std::vector<Shell> shells = shells_of(mesh);
    for (std::size_t i = 0; i < shells.size(); ++i) {
        const Shell& sh = shells[i];
        const bool cavity = sh.depth % 2 == 1;
        if ((sh.volume > 0) != cavity) continue;
        std::ostringstream m;
        m << "shell " << i << " of the surface mesh (" << sh.triangles.size() << " triangles, signed volume " << sh.volume
          << " m^3) ";
        if (cavity)
            m << "lies inside " << sh.depth << " other shell(s), so it bounds a cavity and its normals should point into "
              << "the cavity, but they point outwards";
        else
            m << "is inside-out: its normals point inwards";
        m << "; flip its orientation (import.mesh: reorient: true does it)";
        throw std::invalid_argument(m.str());
    }
    const Box3 box = bounding_box(mesh);
    const double thinnest = box.extent().minCoeff();
    if (thinnest < 4 * r_f) {
        std::ostringstream s;
        s << "voxel size r_f = " << r_f << " m is too large for the object: its thinnest bounding-box side is "
          << thinnest << " m, less than 4 voxels; use r_f <= " << thinnest / 4 << " m";
        throw std::invalid_argument(s.str());
    }
    const double band_voxels = surface_area(mesh) / (r_f * r_f) * 2 * half_width;
    if (band_voxels > max_voxels) {
        std::ostringstream s;
        s << "voxel size r_f = " << r_f << " m is too small for this object: the narrow band would hold about "
          << band_voxels << " voxels (limit " << max_voxels << "); use r_f >= "
          << r_f * std::sqrt(band_voxels / max_voxels) << " m";
        throw std::invalid_argument(s.str());
    }
    openvdb::FloatGrid::Ptr g;
    if (exact && shells.size() == 1 && !has_degenerate_triangle(mesh)) {
        g = exact_band_grid(mesh, r_f, half_width, cancel);
        cancel.poll();
    } else if (shells.size() == 1) {
        g = shell_grid(mesh, mesh.triangles, r_f, half_width, cancel);
    } else {
        std::stable_sort(shells.begin(), shells.end(), [](const Shell& a, const Shell& b) { return a.depth < b.depth; });
        for (const Shell& sh : shells) {
            openvdb::FloatGrid::Ptr part = shell_grid(mesh, sh.triangles, r_f, half_width, cancel);
            if (!g) g = part;
            else if (sh.depth % 2 == 1) csg_difference_polled(*g, *part, cancel);
            else csg_union_polled(*g, *part, cancel);
        }
    }
    g->setName("object");
    bool any_inside = false;
    for (auto it = g->cbeginValueOn(); it; ++it)
        if (*it < 0) { any_inside = true; break; }
    if (!any_inside)
        throw std::invalid_argument("voxel size r_f = " + graph::format_number(r_f) +
                                    " m is too large for the object: no voxel lies inside it");
    return wrap_grid(g, r_f, half_width);
}

}  // namespace

LevelSet level_set_from_mesh(const SurfaceMesh& mesh, double r_f, double half_width, double max_voxels,
                             const CancelToken& cancel) {
    return object_level_set(mesh, r_f, half_width, max_voxels, false, cancel);
}

LevelSet exact_level_set_from_mesh(const SurfaceMesh& mesh, double r_f, double half_width, double max_voxels,
                                   const CancelToken& cancel) {
    return object_level_set(mesh, r_f, half_width, max_voxels, true, cancel);
}

GridDifference compare_grids(const LevelSet& a, const LevelSet& b, double tolerance, std::size_t max_listed) {
    const auto &ga = grid_of(a), &gb = grid_of(b);
    auto acc_a = ga.getConstAccessor();
    auto acc_b = gb.getConstAccessor();
    GridDifference d;
    auto list = [&](const openvdb::Coord& c) {
        if (d.differing.size() < max_listed) d.differing.push_back({c[0], c[1], c[2]});
    };
    for (auto it = ga.cbeginValueOn(); it; ++it) {
        const float vb = acc_b.getValue(it.getCoord());
        const bool sign = (*it < 0) != (vb < 0);
        d.sign_differs += sign;
        const double diff = std::abs(double(*it) - double(vb));
        if (acc_b.isValueOn(it.getCoord())) {
            ++d.active_in_both;
            d.max_abs_difference = std::max(d.max_abs_difference, diff);
            if (sign || diff > tolerance) list(it.getCoord());
        } else {
            ++d.active_only_in_a;
            list(it.getCoord());
        }
    }
    for (auto it = gb.cbeginValueOn(); it; ++it)
        if (!acc_a.isValueOn(it.getCoord())) {
            ++d.active_only_in_b;
            d.sign_differs += (*it < 0) != (acc_a.getValue(it.getCoord()) < 0);
            list(it.getCoord());
        }
    return d;
}

double level_set_volume_openvdb(const LevelSet& ls) { return openvdb::tools::levelSetVolume(grid_of(ls), true); }

double level_set_volume(const LevelSet& ls) {
    const openvdb::FloatGrid& g = grid_of(ls);
    // OpenVDB's levelSetVolume (LevelSetMeasure) in the same arithmetic, step for step, without the
    // area it computes alongside and with the six neighbours of a voxel read from its leaf's buffer
    // instead of through a stencil's accessor (the volume was 55 of the notched bar's 145 ms in
    // levelset.from_mesh, most of it in those lookups; now about 25):
    // per leaf, sum over the active voxels within 1.5 voxels of the surface of
    // delta(phi) (x . grad phi), the leaf sums sorted and added, / 3 (the divergence theorem).
    // Grids it would refuse go to it for its error.
    if (!g.hasUniformVoxels() || g.getGridClass() != openvdb::GRID_LEVEL_SET || g.empty())
        return openvdb::tools::levelSetVolume(g, true);
    using LeafT = openvdb::FloatTree::LeafNodeType;
    std::vector<const LeafT*> leaves;
    leaves.reserve(g.tree().leafCount());
    for (auto it = g.tree().cbeginLeaf(); it; ++it) leaves.push_back(it.getLeaf());
    const double dx = g.voxelSize()[0], inv_dx = 1.0 / dx;
    const float inv_2dx = float(0.5 / dx);                    // GradStencil's mInv2Dx
    const double eps = 1.5, c = 0.5 / eps, d = 2 * openvdb::math::pi<double>() * c;  // DiracDelta(1.5)
    std::vector<double> sums(leaves.size(), 0.0);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, leaves.size()), [&](const tbb::blocked_range<std::size_t>& r) {
        openvdb::tree::ValueAccessor<const openvdb::FloatTree, false> acc(g.tree());
        for (std::size_t l = r.begin(); l != r.end(); ++l) {
            const LeafT& leaf = *leaves[l];
            const float* v = leaf.buffer().data();
            const openvdb::Coord o = leaf.origin();
            double sum = 0;
            for (auto it = leaf.cbeginValueOn(); it; ++it) {
                const openvdb::Index off = it.pos();
                const double phi = inv_dx * v[off];
                const double dd = std::abs(phi) > eps ? 0 : c * (1 + std::cos(d * phi));
                if (!(dd > 0.0)) continue;
                const int x = int(off >> 6), y = int((off >> 3) & 7), z = int(off & 7);
                const openvdb::Coord p(o[0] + x, o[1] + y, o[2] + z);
                // GradStencil's central differences: the neighbour from this leaf where it lies in it.
                auto neighbour = [&](int axis, int q, int step) -> float {
                    static constexpr int kStride[3] = {64, 8, 1};
                    if (q + step >= 0 && q + step < 8) return v[int(off) + step * kStride[axis]];
                    openvdb::Coord n = p;
                    n[axis] += step;
                    return acc.getValue(n);
                };
                const float gx = (neighbour(0, x, 1) - neighbour(0, x, -1)) * inv_2dx;
                const float gy = (neighbour(1, y, 1) - neighbour(1, y, -1)) * inv_2dx;
                const float gz = (neighbour(2, z, 1) - neighbour(2, z, -1)) * inv_2dx;
                sum += dd * (gx * double(p[0]) + gy * double(p[1]) + gz * double(p[2]));
            }
            sums[l] = sum;
        }
    });
    std::sort(sums.begin(), sums.end());  // as LevelSetMeasure: sorted, then added in order
    double total = 0.0;
    for (const double x : sums) total += x;
    return total / 3.0 * openvdb::math::Pow3(dx);
}

double sample(const LevelSet& ls, const Vec3& p) {
    const auto& g = grid_of(ls);
    openvdb::tools::GridSampler<openvdb::FloatGrid, openvdb::tools::BoxSampler> s(g);
    return s.wsSample(openvdb::Vec3d(p.x(), p.y(), p.z()));
}

std::vector<double> sample_points(const LevelSet& ls, const std::vector<Vec3>& points) {
    const auto& g = grid_of(ls);
    std::vector<double> values(points.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), 1024), [&](const tbb::blocked_range<std::size_t>& r) {
        const openvdb::FloatGrid::ConstAccessor acc = g.getConstAccessor();
        openvdb::tools::GridSampler<openvdb::FloatGrid::ConstAccessor, openvdb::tools::BoxSampler> s(acc, g.transform());
        for (std::size_t i = r.begin(); i < r.end(); ++i)
            values[i] = s.wsSample(openvdb::Vec3d(points[i].x(), points[i].y(), points[i].z()));
    });
    return values;
}

Vec3 sample_gradient(const LevelSet& ls, const Vec3& p) {
    const double h = ls.voxel_size * 0.5;
    Vec3 grad;
    for (int a = 0; a < 3; ++a) {
        Vec3 e = Vec3::Zero();
        e[a] = h;
        grad[a] = (sample(ls, p + e) - sample(ls, p - e)) / (2 * h);
    }
    return grad;
}

std::size_t active_voxel_count(const LevelSet& ls) { return grid_of(ls).activeVoxelCount(); }

Box3 active_bounding_box(const LevelSet& ls) {
    const auto& g = grid_of(ls);
    Box3 b{Vec3::Constant(1), Vec3::Constant(-1)};
    if (g.activeVoxelCount() == 0) return b;
    const openvdb::CoordBBox bb = g.evalActiveVoxelBoundingBox();
    for (int a = 0; a < 3; ++a) {
        b.min[a] = bb.min()[a] * ls.voxel_size;
        b.max[a] = bb.max()[a] * ls.voxel_size;
    }
    return b;
}

SurfaceMesh level_set_to_mesh(const LevelSet& ls, double adaptivity, double isovalue) {
    if (!(adaptivity >= 0 && adaptivity <= 1))
        throw std::invalid_argument("mesh adaptivity must lie in [0, 1], got " + graph::format_number(adaptivity));
    // The cells around the iso-surface need defined values on both sides: one voxel of band.
    if (!(std::abs(isovalue) <= (ls.half_width - 1) * ls.voxel_size))
        throw std::invalid_argument("iso-value " + graph::format_number(isovalue) + " m lies outside the narrow band less a voxel (" +
                                    graph::format_number((ls.half_width - 1) * ls.voxel_size) + " m)");
    std::vector<openvdb::Vec3s> points;
    std::vector<openvdb::Vec3I> tris;
    std::vector<openvdb::Vec4I> quads;
    openvdb::tools::volumeToMesh(grid_of(ls), points, tris, quads, isovalue, adaptivity);
    SurfaceMesh m;
    m.vertices.reserve(points.size());
    for (const auto& p : points) m.vertices.emplace_back(p.x(), p.y(), p.z());
    m.triangles.reserve(tris.size() + 2 * quads.size());
    // OpenVDB emits polygons clockwise seen from outside; reverse to our counter-clockwise.
    for (const auto& t : tris) m.triangles.push_back({int(t[2]), int(t[1]), int(t[0])});
    for (const auto& q : quads) {
        m.triangles.push_back({int(q[2]), int(q[1]), int(q[0])});
        m.triangles.push_back({int(q[3]), int(q[2]), int(q[0])});
    }
    return m;
}

void write_vdb(const std::filesystem::path& path, const std::vector<std::pair<std::string, LevelSet>>& grids) {
    ensure_openvdb_initialized();
    openvdb::GridPtrVec out;
    for (const auto& [name, ls] : grids) {
        // Share the tree (no deep copy); only the name and class are set on the new grid.
        openvdb::FloatGrid::Ptr g =
            openvdb::FloatGrid::create(std::const_pointer_cast<openvdb::FloatTree>(grid_of(ls).constTreePtr()));
        g->setTransform(grid_of(ls).transform().copy());
        g->setName(name);
        g->setGridClass(openvdb::GRID_LEVEL_SET);
        out.push_back(g);
    }
    write_vdb_file_checked(path, out);
}

std::vector<std::pair<std::string, LevelSet>> read_vdb(const std::filesystem::path& path) {
    ensure_openvdb_initialized();
    openvdb::io::File f(path.string());
    try {
        f.open();
    } catch (const std::exception& e) {
        throw std::runtime_error("cannot read VDB file " + path.string() + ": " + e.what());
    }
    std::vector<std::pair<std::string, LevelSet>> out;
    openvdb::GridPtrVecPtr grids = f.getGrids();
    for (auto& base : *grids) {
        auto g = openvdb::gridPtrCast<openvdb::FloatGrid>(base);
        if (!g) continue;
        const double vs = g->voxelSize()[0];
        const double hw = std::abs(double(g->background())) / vs;
        out.emplace_back(g->getName(), wrap_grid(g, vs, hw));
    }
    f.close();
    return out;
}

}  // namespace cf
