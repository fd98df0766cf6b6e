// OpenVDB translation unit: object level set from a mesh, measures, sampling, meshing, VDB I/O.
#include "nodes/levelset/level_set_grid.hpp"
#include "nodes/domain/mesh_topology.hpp"

#include "graph/atomic_write.hpp"
#include "graph/diagnostics.hpp"

#include <openvdb/io/File.h>
#include <openvdb/tools/Interpolation.h>
#include <openvdb/tools/LevelSetMeasure.h>
#include <openvdb/tools/MeshToVolume.h>
#include <openvdb/tools/VolumeToMesh.h>

#include <cmath>
#include <mutex>
#include <sstream>
#include <stdexcept>

namespace cf {

void ensure_openvdb_initialized() {
    static std::once_flag once;
    std::call_once(once, [] { openvdb::initialize(); });
}

LevelSet level_set_from_mesh(const SurfaceMesh& mesh, double r_f, double half_width, double max_voxels) {
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
    std::vector<openvdb::Vec3s> points;
    points.reserve(mesh.vertices.size());
    for (const Vec3& v : mesh.vertices) points.emplace_back(float(v.x()), float(v.y()), float(v.z()));
    std::vector<openvdb::Vec3I> tris;
    tris.reserve(mesh.triangles.size());
    for (const Tri& t : mesh.triangles) tris.emplace_back(t[0], t[1], t[2]);
    auto xform = openvdb::math::Transform::createLinearTransform(r_f);
    // Sign by scan conversion, then flood fill of the interior tiles (ch. 6.1, [52]).
    openvdb::FloatGrid::Ptr g = openvdb::tools::meshToLevelSet<openvdb::FloatGrid>(*xform, points, tris, float(half_width));
    g->setName("object");
    bool any_inside = false;
    for (auto it = g->cbeginValueOn(); it; ++it)
        if (*it < 0) { any_inside = true; break; }
    if (!any_inside)
        throw std::invalid_argument("voxel size r_f = " + graph::format_number(r_f) +
                                    " m is too large for the object: no voxel lies inside it");
    return wrap_grid(g, r_f, half_width);
}

double level_set_volume(const LevelSet& ls) {
    return openvdb::tools::levelSetVolume(grid_of(ls), true);
}

double sample(const LevelSet& ls, const Vec3& p) {
    const auto& g = grid_of(ls);
    openvdb::tools::GridSampler<openvdb::FloatGrid, openvdb::tools::BoxSampler> s(g);
    return s.wsSample(openvdb::Vec3d(p.x(), p.y(), p.z()));
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

SurfaceMesh level_set_to_mesh(const LevelSet& ls, double adaptivity) {
    if (!(adaptivity >= 0 && adaptivity <= 1))
        throw std::invalid_argument("mesh adaptivity must lie in [0, 1], got " + graph::format_number(adaptivity));
    std::vector<openvdb::Vec3s> points;
    std::vector<openvdb::Vec3I> tris;
    std::vector<openvdb::Vec4I> quads;
    openvdb::tools::volumeToMesh(grid_of(ls), points, tris, quads, 0.0, adaptivity);
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
    graph::write_atomically_via_path(path, [&](const std::filesystem::path& tmp) {
        openvdb::io::File f(tmp.string());
        f.write(out);
        f.close();
    });
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
