#include "nodes/export/mesh_checks.hpp"

#include <stdexcept>
#include <string>

namespace cf {

void check_writable(const SurfaceMesh& m) {
    const long long nv = static_cast<long long>(m.vertices.size());
    for (std::size_t t = 0; t < m.triangles.size(); ++t)
        for (int v : m.triangles[t])
            if (v < 0 || v >= nv)
                throw std::invalid_argument("cannot write mesh: triangle " + std::to_string(t) + " refers to vertex " +
                                            std::to_string(v) + " but the mesh has " + std::to_string(nv) +
                                            " vertices (the stage that made this mesh has a bug)");
    if (!m.region.empty() && m.region.size() != m.triangles.size())
        throw std::invalid_argument("cannot write mesh: it has " + std::to_string(m.region.size()) +
                                    " region ids for " + std::to_string(m.triangles.size()) + " triangles");
}

}  // namespace cf
