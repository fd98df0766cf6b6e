// Verification of the remeshed BEM surface (issue 13; docs/verification.md, rigid_translation_remeshed):
// a real scanned object (the bunny and the armadillo of CGAL's demo data), remeshed by
// simplify.remesh to about 1000 triangles, one Dirichlet patch (a half-space cap) translated
// rigidly by d and everything else traction-free. The exact solution is the rigid translation:
// u = d everywhere, zero traction everywhere, so every computed traction is error, and a folded
// or needle triangle shows as a traction spike (1e8-1e10 Pa on a PMMA object before the remesher
// guaranteed element shape). The bar is 1e-6 E |d| / L, L the object's longest side.
#include "nodes/bem/boundary_conditions.hpp"
#include "nodes/bem/operators.hpp"
#include "nodes/bem/solver.hpp"
#include "nodes/domain/verification_case.hpp"
#include "nodes/import/read_mesh.hpp"
#include "nodes/levelset/level_set.hpp"
#include "nodes/regions/assign_regions.hpp"
#include "nodes/regions/region_spec.hpp"
#include "nodes/registration.hpp"
#include "nodes/simplify/mesh_quality.hpp"
#include "nodes/simplify/remesh.hpp"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <stdexcept>

namespace cf {
namespace {

std::string fmt(double x) {
    std::ostringstream os;
    os.precision(3);
    os << x;
    return os.str();
}

// data/meshes/<name>.off from $CRACKFLOW_MESH_DATA, ./data/meshes (as the shipped pipelines read
// it), or extracted from the Debian package libcgal-demo's data.tar.gz into a temporary folder.
std::filesystem::path demo_mesh(const std::string& name) {
    const std::string file = name + ".off";
    if (const char* dir = std::getenv("CRACKFLOW_MESH_DATA"))
        if (std::filesystem::exists(std::filesystem::path(dir) / file)) return std::filesystem::path(dir) / file;
    if (std::filesystem::exists(std::filesystem::path("data/meshes") / file)) return std::filesystem::path("data/meshes") / file;
    const std::filesystem::path tarball = "/usr/share/doc/libcgal-demo/data.tar.gz";
    const std::filesystem::path dir = std::filesystem::temp_directory_path() / "crackflow-verify-meshes";
    const std::filesystem::path out = dir / "data" / "meshes" / file;
    if (!std::filesystem::exists(out) && std::filesystem::exists(tarball)) {
        std::filesystem::create_directories(dir);
        const std::string cmd = "tar -xzf " + tarball.string() + " -C " + dir.string() + " data/meshes/" + file + " 2>/dev/null";
        if (std::system(cmd.c_str()) != 0) std::filesystem::remove(out);
    }
    if (!std::filesystem::exists(out))
        throw std::runtime_error(file + " not found in $CRACKFLOW_MESH_DATA, ./data/meshes or " + tarball.string() +
                                 ": install the Debian package libcgal-demo or point CRACKFLOW_MESH_DATA at its data/meshes");
    return out;
}

struct RigidTranslation {
    std::size_t triangles = 0, cap_triangles = 0;
    double min_angle = 0, min_dihedral = 0;
    double max_traction = 0;  // [Pa]
    double bar = 0;           // 1e-6 E |d| / L [Pa]
    double displacement_error = 0;  // max |u - d| / |d| over the free nodes
    double identity_residual = 0;   // max over cap elements of |((1/2 M01 + K) d)_a| / (|a| |d|)
};

RigidTranslation rigid_translation(const std::string& name) {
    const SurfaceMesh input = read_mesh(demo_mesh(name));
    const Box3 box = bounding_box(input);
    int axis = 0;
    box.extent().maxCoeff(&axis);
    const double L = box.extent()[axis];
    const LevelSet ls = level_set_from_mesh(input, L / 160);  // as the remesh tests and pipelines
    RemeshOptions opt;
    opt.target_triangles = 1000;
    opt.offset_voxels = 1;
    SurfaceMesh mesh = remesh(ls, opt).mesh;
    // The cap: the last 15 % of the object along its longest side (the bunny's back, the
    // armadillo's ears and hands).
    const char axis_name = "xyz"[axis];
    const double cut = box.max[axis] - 0.15 * L;
    mesh = assign_regions(mesh, parse_region_spec(std::string("cap: ") + axis_name + " >= " + fmt(cut)), false).mesh;
    Material mat;  // PMMA, SI units
    mat.E = 3.1e9;
    mat.nu = 0.327;
    const Vec3 d = 1e-3 * L * Vec3(1, -2, 3).normalized();
    std::ostringstream bc;
    bc.precision(17);
    bc << "cap: displacement " << d.x() << " " << d.y() << " " << d.z() << "; *: traction 0 0 0";
    const bem::ResolvedConditions rc = bem::resolve(bem::parse_boundary_conditions(bc.str()), mesh);
    const auto ops = bem::assemble_surface_operators(mesh, mat, bem::AssemblyOptions{});
    // The discrete solution is exactly u = d, t = 0 as far as (1/2 M01 + K) d = 0 holds row by row
    // (D d = 0 holds algebraically: the surface curls and Guenter matrices of the hats sum to zero
    // per element). That identity is Gauss's solid-angle integral, exact on any closed polyhedron,
    // so its residual per element, relative to |a| |d|, is the quadrature error driving the traction.
    double identity_residual = 0;
    {
        bem::Vector dn(3 * mesh.num_vertices());
        for (std::size_t v = 0; v < mesh.num_vertices(); ++v) dn.segment<3>(3 * v) = d;
        const bem::Vector res = 0.5 * bem::mass_times_nodal(*ops, dn) + ops->K * dn;
        for (std::size_t a = 0; a < mesh.num_triangles(); ++a)
            if (rc.dirichlet[a])
                identity_residual = std::max(identity_residual, res.segment<3>(3 * a).norm() / (ops->geometry[a].area * d.norm()));
    }
    const auto sol = bem::solve_sgbem(ops, nullptr, rc, {}, nullptr);
    RigidTranslation r;
    r.triangles = mesh.num_triangles();
    const MeshQuality q = measure_quality(mesh);
    r.min_angle = q.min_angle_deg;
    r.min_dihedral = q.min_dihedral_deg;
    for (std::size_t a = 0; a < mesh.num_triangles(); ++a) {
        r.cap_triangles += rc.dirichlet[a] ? 1 : 0;
        r.max_traction = std::max(r.max_traction, sol->traction[a].norm());
    }
    for (std::size_t v = 0; v < mesh.num_vertices(); ++v)
        if (!rc.node_fixed[v]) r.displacement_error = std::max(r.displacement_error, (sol->displacement[v] - d).norm() / d.norm());
    r.bar = 1e-6 * mat.E * d.norm() / L;
    r.identity_residual = identity_residual;
    return r;
}

VerificationResult rigid_translation_remeshed() {
    VerificationResult out;
    out.tolerance = 1e-6;
    out.passed = true;
    for (const char* name : {"bunny00", "armadillo"}) {
        const RigidTranslation r = rigid_translation(name);
        // error: the largest traction in units of E |d| / L
        const double e = r.max_traction / r.bar * 1e-6;
        out.error = std::max(out.error, e);
        out.passed = out.passed && e <= out.tolerance;
        out.details += std::string(out.details.empty() ? "" : "; ") + name + ": " + std::to_string(r.triangles) +
                       " triangles (" + std::to_string(r.cap_triangles) + " in the cap), min angle " + fmt(r.min_angle) +
                       " deg, min dihedral " + fmt(r.min_dihedral) + " deg, max traction " + fmt(r.max_traction) +
                       " Pa = " + fmt(e) + " E|d|/L, free-node |u - d|/|d| " + fmt(r.displacement_error) +
                       ", cap identity residual " + fmt(r.identity_residual);
    }
    return out;
}

}  // namespace

void add_remesh_verification_cases(std::vector<VerificationCase>& cases) {
    cases.push_back({"rigid_translation_remeshed",
                     "issue 13: bunny and armadillo remeshed to 1000 triangles, a cap translated rigidly, the rest free: "
                     "max traction below 1e-6 E |d| / L (exact: 0)",
                     rigid_translation_remeshed});
}

}  // namespace cf
