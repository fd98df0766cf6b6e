#include "nodes/simplify/remesh.hpp"

#include "graph/diagnostics.hpp"
#include "graph/machine_memory.hpp"
#include "nodes/domain/mesh_topology.hpp"
#include "nodes/simplify/degenerate_cleanup.hpp"
#include "nodes/simplify/mesh_repair.hpp"
#include "nodes/simplify/quality_repair.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <limits>
#include <cmath>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

namespace cf {

SurfaceMesh without_unused_vertices(const SurfaceMesh& m) {
    std::vector<int> map(m.vertices.size(), -1);
    SurfaceMesh out;
    out.region = m.region;
    out.region_names = m.region_names;
    for (const Tri& t : m.triangles) {
        Tri n{};
        for (int k = 0; k < 3; ++k) {
            int& id = map[t[k]];
            if (id < 0) {
                id = int(out.vertices.size());
                out.vertices.push_back(m.vertices[t[k]]);
            }
            n[k] = id;
        }
        out.triangles.push_back(n);
    }
    return out;
}

namespace {
// Angle-weighted (pseudo-)normals, unit (zero where every incident triangle is degenerate).
std::vector<Vec3> vertex_normals(const SurfaceMesh& mesh) {
    std::vector<Vec3> normal(mesh.vertices.size(), Vec3::Zero());
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        const Vec3 n = triangle_normal(mesh, t);  // unit; zero for a sliver
        const Tri& f = mesh.triangles[t];
        for (int k = 0; k < 3; ++k) {
            const Vec3 e1 = mesh.vertices[f[(k + 1) % 3]] - mesh.vertices[f[k]];
            const Vec3 e2 = mesh.vertices[f[(k + 2) % 3]] - mesh.vertices[f[k]];
            normal[f[k]] += std::atan2(e1.cross(e2).norm(), e1.dot(e2)) * n;
        }
    }
    for (Vec3& n : normal)
        if (n.norm() > 0) n.normalize();
    return normal;
}
}  // namespace

void offset_along_normals(SurfaceMesh& mesh, double distance) {
    // Angle-weighted (pseudo-)normals: they do not depend on how a flat face or a crease is
    // triangulated, so the collinear vertices QEM leaves along a box edge all move alike and
    // stay collinear. Area weighting moved them by different amounts and folded the thin
    // triangles there into slivers and self-intersections.
    const std::vector<Vec3> normal = vertex_normals(mesh);
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v) mesh.vertices[v] += distance * normal[v];
}

namespace {

// Vertices whose remaining incident triangles form more than one fan (a pinch after deletion).
std::vector<int> pinched_vertices(const SurfaceMesh& m, const std::vector<char>& keep) {
    std::vector<std::vector<std::pair<int, int>>> link(m.vertices.size());
    for (std::size_t t = 0; t < m.triangles.size(); ++t) {
        if (!keep[t]) continue;
        const Tri& tri = m.triangles[t];
        for (int k = 0; k < 3; ++k) link[tri[k]].push_back({tri[(k + 1) % 3], tri[(k + 2) % 3]});
    }
    std::vector<int> out;
    for (std::size_t v = 0; v < link.size(); ++v) {
        if (link[v].size() < 2) continue;
        std::unordered_map<int, int> parent;
        auto root = [&](int x) {
            while (parent[x] != x) x = parent[x] = parent[parent[x]];
            return x;
        };
        for (auto [a, b] : link[v]) {
            if (!parent.count(a)) parent[a] = a;
            if (!parent.count(b)) parent[b] = b;
            parent[root(a)] = root(b);
        }
        int comps = 0;
        for (auto& [x, p] : parent)
            if (root(x) == x) ++comps;
        if (comps > 1) out.push_back(int(v));
    }
    return out;
}

}  // namespace

int repair_self_intersections(SurfaceMesh& mesh, int max_rounds) {
    const CancelToken cancel = CancelToken::current();
    for (int round = 0; round < max_rounds; ++round) {
        const auto pairs = self_intersecting_pairs(mesh, cancel);
        if (pairs.empty()) return round;
        // Vertices of the intersecting triangles, widened by `round` vertex rings.
        std::vector<char> marked(mesh.vertices.size(), 0);
        for (auto [a, b] : pairs)
            for (int t : {a, b})
                for (int v : mesh.triangles[t]) marked[v] = 1;
        for (int r = 0; r < round; ++r) {
            std::vector<char> next = marked;
            for (const Tri& t : mesh.triangles)
                if (marked[t[0]] || marked[t[1]] || marked[t[2]])
                    for (int v : t) next[v] = 1;
            marked.swap(next);
        }
        // Delete the one-ring (every triangle touching a marked vertex), then any pinches.
        std::vector<char> keep(mesh.triangles.size(), 1);
        for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
            for (int v : mesh.triangles[t])
                if (marked[v]) keep[t] = 0;
        for (int guard = 0; guard < 100; ++guard) {
            cancel.poll();
            const auto pinched = pinched_vertices(mesh, keep);
            if (pinched.empty()) break;
            for (int v : pinched) {
                cancel.poll();  // one pass over the triangles per pinched vertex
                for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
                    if (keep[t] && std::find(mesh.triangles[t].begin(), mesh.triangles[t].end(), v) != mesh.triangles[t].end())
                        keep[t] = 0;
            }
        }
        SurfaceMesh kept;
        kept.vertices = mesh.vertices;
        for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
            if (keep[t]) kept.triangles.push_back(mesh.triangles[t]);
        if (kept.triangles.size() < mesh.triangles.size() / 2)
            throw std::runtime_error("self-intersection repair would delete more than half of the mesh (" +
                                     std::to_string(pairs.size()) + " intersecting pairs)");
        kept = without_unused_vertices(kept);
        fill_holes(kept, cancel);
        mesh = std::move(kept);
    }
    return max_rounds;
}

double remesh_bytes_estimate(const LevelSet& object) {
    // The dual-contoured mesh has about two triangles per surface voxel, and the narrow band is
    // 2 half_width voxels thick around the surface. Each dense triangle costs its share of the
    // dual contouring, our mesh, CGAL's halfedge copy and the QEM queue (measured, see remesh.hpp).
    const double surface_voxels = double(active_voxel_count(object)) / (2 * object.half_width);
    return 2 * surface_voxels * kRemeshBytesPerDenseTriangle;
}

void check_remesh_memory(const LevelSet& object) {
    const double need = remesh_bytes_estimate(object), have = available_memory_bytes();
    if (have > 0 && need > 0.8 * have) {
        std::ostringstream m;
        m.precision(3);
        m << "remeshing this level set (" << active_voxel_count(object) << " active voxels of " << object.voxel_size
          << " m) needs about " << need / 1e9 << " GB, more than the " << have / 1e9
          << " GB this process may use; use a larger voxel_size for the level set (memory falls with its square)";
        throw std::invalid_argument(m.str());
    }
}

namespace {

// The offset surface {phi = offset} of `object` as a level set and iso-value within its band. The
// offset is taken on the signed distance field, not by moving mesh vertices: an exact distance
// offset cannot fold, while moving the vertices of QEM's needles along their normals folded them
// onto their neighbours (issue 13). Offsets reaching beyond the band are taken in steps, each
// re-distanced from the contour of the previous one.
struct OffsetSurface {
    LevelSet rebuilt;  // used when the offset exceeds the band
    const LevelSet* grid = nullptr;
    double iso = 0;  // [m]
};

OffsetSurface offset_surface(const LevelSet& object, double offset) {
    OffsetSurface s;
    s.grid = &object;
    s.iso = offset;
    const double reach = (object.half_width - 1.5) * object.voxel_size;
    while (s.iso > reach) {
        const SurfaceMesh shell = without_unused_vertices(level_set_to_mesh(*s.grid, 0, reach));
        LevelSet next = level_set_from_mesh(shell, object.voxel_size, object.half_width);
        s.rebuilt = std::move(next);
        s.grid = &s.rebuilt;
        s.iso -= reach;
    }
    return s;
}

// Closest point of the iso-surface by Newton steps along the gradient (a signed distance field has
// |grad| = 1 near the surface, so two or three steps reach it to a small fraction of a voxel).
Vec3 project_to(const LevelSet& grid, double iso, Vec3 p) {
    for (int i = 0; i < 4; ++i) {
        const double f = sample(grid, p) - iso;
        const Vec3 g = sample_gradient(grid, p);
        const double gg = g.squaredNorm();
        if (!(gg > 0.25)) break;  // outside the band or at a medial point: keep the point
        p -= f / gg * g;
        if (std::abs(f) < 1e-3 * grid.voxel_size) break;
    }
    return p;
}

// `m` without its edge-connected shells whose bounding-box diagonal is below `size` [m]; `dropped`
// counts them.
SurfaceMesh without_small_shells(const SurfaceMesh& m, double size, std::size_t& dropped) {
    const std::vector<int> comp = triangle_components(m);
    const int n = comp.empty() ? 0 : *std::max_element(comp.begin(), comp.end()) + 1;
    std::vector<Box3> box(std::size_t(n), Box3{Vec3::Constant(std::numeric_limits<double>::infinity()),
                                               Vec3::Constant(-std::numeric_limits<double>::infinity())});
    for (std::size_t t = 0; t < m.triangles.size(); ++t)
        for (int v : m.triangles[t]) {
            box[comp[t]].min = box[comp[t]].min.cwiseMin(m.vertices[v]);
            box[comp[t]].max = box[comp[t]].max.cwiseMax(m.vertices[v]);
        }
    std::vector<char> keep(static_cast<std::size_t>(n), 0);
    dropped = 0;
    for (int c = 0; c < n; ++c) {
        keep[c] = box[c].extent().norm() >= size;
        dropped += keep[c] ? 0 : 1;
    }
    if (dropped == 0) return m;
    SurfaceMesh out;
    out.vertices = m.vertices;
    for (std::size_t t = 0; t < m.triangles.size(); ++t)
        if (keep[comp[t]]) out.triangles.push_back(m.triangles[t]);
    return without_unused_vertices(out);
}

// Moves every vertex of a mesh whose vertices lie on the iso-surface {phi = iso} outward so that
// its triangles straddle the surface instead of cutting inside it: with the corners on a surface of
// curvature kappa, a triangle's depth below it at barycentric b is kappa/2 sum b_i b_j |e_ij|^2,
// whose mean over the triangle is 3/4 of its value at the centroid; each vertex moves by 3/4 of the
// mean centroid depth of its triangles (0 on flat faces). Returns the mean shift [m].
double straddle_surface(SurfaceMesh& m, const LevelSet& grid, double iso) {
    const double cap = (grid.half_width - 1) * grid.voxel_size;  // beyond the band phi is clamped
    std::vector<double> sum(m.vertices.size(), 0.0);
    std::vector<int> count(m.vertices.size(), 0);
    for (std::size_t t = 0; t < m.triangles.size(); ++t) {
        const double depth = std::clamp(iso - sample(grid, triangle_centroid(m, t)), -cap, cap);
        for (int v : m.triangles[t]) {
            sum[v] += depth;
            ++count[v];
        }
    }
    const std::vector<Vec3> normal = vertex_normals(m);
    double total = 0;
    for (std::size_t v = 0; v < m.vertices.size(); ++v) {
        if (count[v] == 0) continue;
        const double shift = 0.75 * sum[v] / count[v];
        m.vertices[v] += shift * normal[v];
        total += shift;
    }
    return m.vertices.empty() ? 0 : total / double(m.vertices.size());
}

std::string fmt3(double x) {
    std::ostringstream os;
    os.precision(3);
    os << x;
    return os.str();
}

}  // namespace

RemeshResult remesh(const LevelSet& object, const RemeshOptions& opt, const CancelToken& cancel) {
    if (opt.target_triangles < 4)
        throw std::invalid_argument("target triangle count must be at least 4, got " + std::to_string(opt.target_triangles));
    if (!(opt.offset_voxels >= 0))
        throw std::invalid_argument("offset must be a non-negative number of voxels, got " + graph::format_number(opt.offset_voxels));
    check_remesh_memory(object);
    RemeshResult res;
    const OffsetSurface surface = offset_surface(object, opt.offset_voxels * object.voxel_size);
    SurfaceMesh dense = without_unused_vertices(level_set_to_mesh(*surface.grid, opt.adaptivity, surface.iso));
    cancel.poll();  // between the stages; the simplification polls on its own
    res.dense_triangles = dense.num_triangles();
    if (dense.triangles.empty()) throw std::runtime_error("the level set has no surface to mesh");
    const MeshTopologyReport dense_topo = check_topology(dense);
    if (!dense_topo.is_closed_manifold())
        throw std::runtime_error("the dual-contoured mesh is not a closed manifold (" + dense_topo.describe() +
                                 "); try a smaller voxel size");
    // A shell smaller than one element (a voxel-sized bubble where the offset surfaces of two close
    // parts of the object meet, or a speck) cannot be meshed at the target size without folds.
    const double element_edge = std::sqrt(4 * surface_area(dense) / (std::sqrt(3.0) * double(opt.target_triangles)));
    dense = without_small_shells(dense, element_edge, res.dropped_shells);
    if (dense.triangles.empty())
        throw std::runtime_error("every shell of the surface is smaller than one element of the target size (" + fmt3(element_edge) +
                                 " m); raise target_triangles");
    if (dense.num_triangles() < opt.target_triangles)
        throw std::invalid_argument("target of " + std::to_string(opt.target_triangles) +
                                    " triangles exceeds the dual-contoured mesh (" + std::to_string(dense.num_triangles()) +
                                    " triangles); lower the target or the voxel size");
    // QEM keeps the shape (sharp edges, thin parts) but not the element shape: on flat faces and
    // rounded edges the plane quadrics vanish or coincide and it leaves needles and caps (down to
    // 0.04 degrees, folded onto their neighbours). So it stops at a few times the target, and
    // isotropic remeshing makes the elements, projecting every vertex onto the offset surface of
    // the distance field (QEM's own folds are not followed), its edge length set from the area and
    // corrected until the count fits.
    const std::size_t mid_count = std::min(dense.num_triangles(), kRemeshQemOversampling * opt.target_triangles);
    const SurfaceMesh mid = without_unused_vertices(simplify_to_count(dense, mid_count, cancel));
    const double dense_volume = signed_volume(dense);
    dense = SurfaceMesh{};
    cancel.poll();
    // The element-shape repair runs on each candidate (it may collapse or split a few edges), then
    // exact self-intersection repair (which fills holes with new triangles) and the repair again:
    // all keep the mesh closed, manifold and oriented.
    const QualityBounds bounds{opt.min_angle_deg, opt.min_dihedral_deg};
    double projection_iso = surface.iso;  // moved out with the volume correction below
    const SurfaceProjection project = [&](const Vec3& p) { return project_to(*surface.grid, projection_iso, p); };
    struct Counters {
        std::size_t sliver_flips = 0, sliver_collapses = 0, flips = 0, collapses = 0, moves = 0, splits = 0;
    };
    auto clean = [&](SurfaceMesh& m, Counters& n) {
        const DegenerateCleanup c = remove_degenerate_triangles(m);
        n.sliver_flips += c.flips;
        n.sliver_collapses += c.collapses;
        const QualityRepair q = improve_quality(m, bounds, project);
        n.flips += q.flips;
        n.collapses += q.collapses;
        n.moves += q.moves;
        n.splits += q.splits;
    };
    const double area = surface_area(mid);
    double edge = std::sqrt(4 * area / (std::sqrt(3.0) * double(opt.target_triangles)));
    SurfaceMesh mesh;
    Counters counters;
    double best_error = std::numeric_limits<double>::infinity(), best_iso = surface.iso;
    for (int attempt = 0; attempt < 6; ++attempt) {
        // Two candidates: feature lines at sharp edges only, and also at narrow bevels (box edges
        // rounded to a voxel, which the first rounds off by an element); the one meeting the
        // bounds whose volume is closest to the dense contour's is taken.
        SurfaceMesh candidate;
        Counters n;
        double candidate_iso = surface.iso, candidate_score = std::numeric_limits<double>::infinity();
        for (const bool bevels : {false, true}) {
            projection_iso = surface.iso;
            SurfaceMesh m = isotropic_remesh(mid, edge, kRemeshIsotropicIterations, kRemeshFeatureDihedralDeg, opt.min_dihedral_deg,
                                             bevels, project, cancel);
            // With every vertex on the surface, the chords of curved parts cut inside it (by h^2 / 8R:
            // 10 % of the chain link's volume at 288 triangles), and the BEM surface would lie inside
            // the object the offset is meant to enclose. Moving the vertices out so the triangles
            // straddle the surface restores the enclosed volume, shell by shell, as QEM's placement
            // did; the repair then projects onto the iso-surface shifted by the mean of that move.
            // Where the shifted mesh cannot meet the bounds (the armadillo's claws, thinner than an
            // element), the mesh on the surface is taken.
            for (const bool straddle : {true, false}) {
                SurfaceMesh c = m;
                projection_iso = surface.iso;
                if (straddle) {
                    // The local move, then what the enclosed volume still lacks, uniformly.
                    projection_iso += straddle_surface(c, *surface.grid, surface.iso);
                    const double gap = (dense_volume - signed_volume(c)) / surface_area(c);
                    offset_along_normals(c, gap);
                    projection_iso += gap;
                }
                Counters cn;
                clean(c, cn);
                const MeshQuality q = measure_quality(c, opt.min_angle_deg, opt.min_dihedral_deg);
                const bool ok = q.angles_below + q.dihedrals_below == 0;
                const double score = (ok ? 0.0 : 1e6) + std::abs(signed_volume(c) - dense_volume) / std::abs(dense_volume);
                if (score < candidate_score) {
                    candidate_score = score;
                    candidate = std::move(c);
                    n = cn;
                    candidate_iso = projection_iso;
                }
                if (ok) break;  // the straddling mesh met the bounds: no need for the other
            }
        }
        projection_iso = candidate_iso;
        const double ratio = double(candidate.num_triangles()) / double(opt.target_triangles);
        if (std::abs(ratio - 1) < best_error) {
            best_error = std::abs(ratio - 1);
            mesh = std::move(candidate);
            counters = n;
            best_iso = projection_iso;
        }
        if (best_error <= 0.02) break;
        edge *= std::sqrt(ratio);  // the count goes with 1 / edge^2
    }
    projection_iso = best_iso;
    res.self_intersections_before = self_intersecting_pairs(mesh, cancel).size();
    cancel.poll();
    if (res.self_intersections_before > 0) {
        res.repair_rounds = repair_self_intersections(mesh, opt.max_repair_rounds);
        clean(mesh, counters);
    }
    res.sliver_flips = counters.sliver_flips;
    res.sliver_collapses = counters.sliver_collapses;
    res.quality_flips = counters.flips;
    res.quality_collapses = counters.collapses;
    res.quality_moves = counters.moves;
    res.quality_splits = counters.splits;
    res.self_intersections_after = self_intersecting_pairs(mesh, cancel).size();
    const MeshTopologyReport topo = check_topology(mesh);
    if (!topo.is_closed_manifold() || res.self_intersections_after > 0)
        throw std::runtime_error("remeshing could not meet its guarantees: " + topo.describe() + ", " +
                                 std::to_string(res.self_intersections_after) + " self-intersecting pairs left");
    if (!(signed_volume(mesh) > 0)) throw std::runtime_error("remeshed surface is inward oriented");
    res.quality = measure_quality(mesh, opt.min_angle_deg, opt.min_dihedral_deg);
    if (res.quality.angles_below > 0 || res.quality.dihedrals_below > 0)
        throw std::runtime_error(
            "remeshing could not meet its element-shape bounds (min_angle " + fmt3(opt.min_angle_deg) + " deg, min_dihedral " +
            fmt3(opt.min_dihedral_deg) + " deg): " + std::to_string(res.quality.angles_below) + " triangles and " +
            std::to_string(res.quality.dihedrals_below) + " edges below them, " + describe(res.quality) +
            "; raise target_triangles (smaller elements follow thin parts), lower the voxel size of the level set, or "
            "lower min_angle / min_dihedral");
    res.mesh = std::move(mesh);
    return res;
}

}  // namespace cf
