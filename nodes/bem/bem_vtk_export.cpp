#include "nodes/bem/bem_vtk_export.hpp"

#include "graph/atomic_write.hpp"

namespace cf::bem {

namespace {

VtpArray vectors(const std::string& name, const std::vector<Vec3>& v) {
    VtpArray a;
    a.name = name;
    a.components = 3;
    a.values.reserve(3 * v.size());
    for (const Vec3& x : v)
        for (int k = 0; k < 3; ++k) a.values.push_back(x[k]);
    return a;
}

}  // namespace

VtpFields surface_fields(const BemSolution& sol) {
    VtpFields f;
    f.point_data.push_back(vectors("u", sol.displacement));
    f.cell_data.push_back(vectors("traction", sol.traction));
    VtpArray d;
    d.name = "dirichlet";
    for (std::size_t e = 0; e < sol.traction.size(); ++e)
        d.values.push_back(sol.system && e < sol.system->dirichlet.size() && sol.system->dirichlet[e] ? 1.0 : 0.0);
    f.cell_data.push_back(std::move(d));
    return f;
}

VtpFields crack_fields(const BemSolution& sol, const std::vector<Vec3>& average) {
    VtpFields f;
    f.point_data.push_back(vectors("du", sol.crack_opening));
    if (!average.empty()) f.point_data.push_back(vectors("u_average", average));
    return f;
}

void write_bem_vtk(const BemSolution& sol, const std::filesystem::path& surface_path,
                   const std::filesystem::path& crack_path, bool crack_average) {
    const VtpFields sf = surface_fields(sol);
    graph::write_atomically(surface_path, [&](std::ostream& os) { write_vtp(os, sol.surface->mesh, sf); });
    if (!sol.cracks || sol.cracks->cracks.num_triangles() == 0) return;
    const VtpFields cf = crack_fields(sol, crack_average ? crack_average_displacement(sol) : std::vector<Vec3>{});
    graph::write_atomically(crack_path, [&](std::ostream& os) { write_vtp(os, sol.cracks->cracks, cf); });
}

}  // namespace cf::bem
