// glTF 2.0 binary of one surface mesh (mesh_writers.hpp), through tinygltf (Debian's compiled
// library: no implementation macro here). Per-vertex attributes come from the corners
// (corner_vertices.hpp); one primitive per region so each region gets its own material.
#include "nodes/export/corner_vertices.hpp"
#include "nodes/export/glb_builder.hpp"
#include "nodes/export/mesh_checks.hpp"
#include "nodes/export/mesh_writers.hpp"

#include <sstream>
#include <stdexcept>

namespace cf {

namespace {

Vec3 colour_of(const std::string& name, const std::vector<std::pair<std::string, Vec3>>& colours) {
    for (const auto& [n, c] : colours)
        if (n == name) return c;
    return Vec3(0.7, 0.7, 0.7);
}

}  // namespace

void write_glb(std::ostream& os, const SurfaceMesh& m, const std::string& name,
               const std::vector<std::pair<std::string, Vec3>>& colours) {
    check_writable(m);
    SurfaceMesh flat;  // without normals the faces get their own (flat) normals
    const SurfaceMesh* src = &m;
    if (!m.has_normals()) {
        flat = m;
        flat.corner_normal.resize(m.triangles.size());
        for (std::size_t t = 0; t < m.triangles.size(); ++t) flat.corner_normal[t].fill(triangle_normal(m, t));
        src = &flat;
    }
    const CornerVertices cv = split_corner_vertices(*src);
    GlbBuilder g;
    std::vector<float> pos, nrm, uv;
    for (std::size_t i = 0; i < cv.vertex.size(); ++i) {
        for (int k = 0; k < 3; ++k) pos.push_back(float(m.vertices[std::size_t(cv.vertex[i])][k]));
        for (int k = 0; k < 3; ++k) nrm.push_back(float(cv.normal[i][k]));
        if (!cv.uv.empty()) {
            uv.push_back(float(cv.uv[i].x()));
            uv.push_back(float(1.0 - cv.uv[i].y()));
        }
    }
    const int a_pos = g.add_floats(pos, 3, TINYGLTF_TYPE_VEC3, TINYGLTF_TARGET_ARRAY_BUFFER, true);
    const int a_nrm = g.add_floats(nrm, 3, TINYGLTF_TYPE_VEC3, TINYGLTF_TARGET_ARRAY_BUFFER, false);
    const int a_uv = uv.empty() ? -1 : g.add_floats(uv, 2, TINYGLTF_TYPE_VEC2, TINYGLTF_TARGET_ARRAY_BUFFER, false);
    tinygltf::Mesh mesh;
    mesh.name = name;
    for (int r = 0; r < m.num_regions(); ++r) {
        std::vector<std::uint32_t> idx;
        for (std::size_t t = 0; t < m.triangles.size(); ++t)
            if (m.region_of(t) == r)
                for (int v : cv.triangles[t]) idx.push_back(std::uint32_t(v));
        if (idx.empty()) continue;  // an unused material would draw a validator note
        const int material = g.add_material(m.region_name(r), colour_of(m.region_name(r), colours));
        tinygltf::Primitive prim;
        prim.attributes["POSITION"] = a_pos;
        prim.attributes["NORMAL"] = a_nrm;
        if (a_uv >= 0) prim.attributes["TEXCOORD_0"] = a_uv;
        prim.indices = g.add_indices(idx);
        prim.material = material;
        prim.mode = TINYGLTF_MODE_TRIANGLES;
        mesh.primitives.push_back(prim);
    }
    g.model.meshes.push_back(mesh);
    tinygltf::Node node;
    node.name = name;
    node.mesh = 0;
    g.model.nodes.push_back(node);
    tinygltf::Scene scene;
    scene.nodes.push_back(0);
    g.model.scenes.push_back(scene);
    g.model.defaultScene = 0;
    tinygltf::TinyGLTF writer;
    std::ostringstream bytes;
    if (!writer.WriteGltfSceneToStream(&g.model, bytes, false, true))
        throw std::runtime_error("cannot encode the glTF binary of '" + name + "'");
    os << bytes.str();
}

}  // namespace cf
