#include "nodes/export/corner_vertices.hpp"

#include <cstring>
#include <map>
#include <tuple>

namespace cf {

CornerVertices split_corner_vertices(const SurfaceMesh& m) {
    CornerVertices out;
    const bool uv = m.has_uv(), normal = m.has_normals();
    // Exact-value keys: corners written from the same numbers weld, anything else stays apart.
    using Key = std::tuple<int, double, double, double, double, double>;
    std::map<Key, int> index;
    out.triangles.resize(m.triangles.size());
    for (std::size_t t = 0; t < m.triangles.size(); ++t)
        for (int k = 0; k < 3; ++k) {
            const Vec2 u = uv ? m.corner_uv[t][k] : Vec2::Zero();
            const Vec3 n = normal ? m.corner_normal[t][k] : Vec3::Zero();
            const Key key{m.triangles[t][k], u.x(), u.y(), n.x(), n.y(), n.z()};
            auto [it, added] = index.try_emplace(key, int(out.vertex.size()));
            if (added) {
                out.vertex.push_back(m.triangles[t][k]);
                if (uv) out.uv.push_back(u);
                if (normal) out.normal.push_back(n);
            }
            out.triangles[t][k] = it->second;
        }
    return out;
}

}  // namespace cf
