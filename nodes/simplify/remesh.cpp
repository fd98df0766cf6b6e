#include "nodes/simplify/remesh.hpp"

#include "graph/diagnostics.hpp"
#include "graph/machine_memory.hpp"
#include "nodes/domain/mesh_topology.hpp"
#include "nodes/simplify/degenerate_cleanup.hpp"
#include "nodes/simplify/mesh_repair.hpp"

#include <Eigen/Geometry>

#include <algorithm>
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

void offset_along_normals(SurfaceMesh& mesh, double distance) {
    // Angle-weighted (pseudo-)normals: they do not depend on how a flat face or a crease is
    // triangulated, so the collinear vertices QEM leaves along a box edge all move alike and
    // stay collinear. Area weighting moved them by different amounts and folded the thin
    // triangles there into slivers and self-intersections.
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
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
        const double len = normal[v].norm();
        if (len > 0) mesh.vertices[v] += distance / len * normal[v];
    }
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

RemeshResult remesh(const LevelSet& object, const RemeshOptions& opt, const CancelToken& cancel) {
    if (opt.target_triangles < 4)
        throw std::invalid_argument("target triangle count must be at least 4, got " + std::to_string(opt.target_triangles));
    if (!(opt.offset_voxels >= 0))
        throw std::invalid_argument("offset must be a non-negative number of voxels, got " + graph::format_number(opt.offset_voxels));
    check_remesh_memory(object);
    RemeshResult res;
    SurfaceMesh dense = without_unused_vertices(level_set_to_mesh(object, opt.adaptivity));
    cancel.poll();  // between the stages; the simplification polls on its own
    res.dense_triangles = dense.num_triangles();
    if (dense.triangles.empty()) throw std::runtime_error("the level set has no surface to mesh");
    const MeshTopologyReport dense_topo = check_topology(dense);
    if (!dense_topo.is_closed_manifold())
        throw std::runtime_error("the dual-contoured mesh is not a closed manifold (" + dense_topo.describe() +
                                 "); try a smaller voxel size");
    if (dense.num_triangles() < opt.target_triangles)
        throw std::invalid_argument("target of " + std::to_string(opt.target_triangles) +
                                    " triangles exceeds the dual-contoured mesh (" + std::to_string(dense.num_triangles()) +
                                    " triangles); lower the target or the voxel size");
    SurfaceMesh mesh = without_unused_vertices(simplify_to_count(dense, opt.target_triangles, cancel));
    cancel.poll();
    offset_along_normals(mesh, opt.offset_voxels * object.voxel_size);
    // QEM on flat faces leaves zero-area caps and needles (all plane quadrics vanish there);
    // hole filling in the repair can leave more: both are removed before the final check.
    auto clean = [&] {
        const DegenerateCleanup c = remove_degenerate_triangles(mesh);
        res.sliver_flips += c.flips;
        res.sliver_collapses += c.collapses;
    };
    clean();
    res.self_intersections_before = self_intersecting_pairs(mesh, cancel).size();
    cancel.poll();
    if (res.self_intersections_before > 0) {
        res.repair_rounds = repair_self_intersections(mesh, opt.max_repair_rounds);
        clean();
    }
    res.self_intersections_after = self_intersecting_pairs(mesh, cancel).size();
    const MeshTopologyReport topo = check_topology(mesh);
    if (!topo.is_closed_manifold() || res.self_intersections_after > 0)
        throw std::runtime_error("remeshing could not meet its guarantees: " + topo.describe() + ", " +
                                 std::to_string(res.self_intersections_after) + " self-intersecting pairs left");
    if (!(signed_volume(mesh) > 0)) throw std::runtime_error("remeshed surface is inward oriented");
    res.mesh = std::move(mesh);
    return res;
}

}  // namespace cf
