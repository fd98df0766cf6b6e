#include "nodes/bem/boundary_conditions.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace cf::bem {

namespace {
std::string trim(const std::string& s) {
    const auto b = s.find_first_not_of(" \t\r\n");
    if (b == std::string::npos) return "";
    const auto e = s.find_last_not_of(" \t\r\n");
    return s.substr(b, e - b + 1);
}
}  // namespace

BoundaryConditions parse_boundary_conditions(const std::string& text) {
    BoundaryConditions bc;
    std::stringstream all(text);
    std::string clause;
    const std::string form = "expected '<region>: displacement|traction x y z' or '<region>: pressure p' (or '*: ...' for "
                             "all other regions)";
    // Which clauses a region had: a traction/displacement and a pressure may share a region.
    std::map<std::string, std::pair<bool, bool>> seen;  // name -> (vector clause, pressure clause)
    while (std::getline(all, clause, ';')) {
        clause = trim(clause);
        if (clause.empty()) continue;
        const auto colon = clause.find(':');
        if (colon == std::string::npos) throw std::invalid_argument("boundary condition '" + clause + "': missing ':'; " + form);
        const std::string name = trim(clause.substr(0, colon));
        if (name.empty()) throw std::invalid_argument("boundary condition '" + clause + "': empty region name; " + form);
        std::istringstream rest(clause.substr(colon + 1));
        std::string kind;
        rest >> kind;
        const bool is_pressure = kind == "pressure";
        RegionCondition::Kind k = RegionCondition::Kind::traction;
        if (kind == "displacement") k = RegionCondition::Kind::displacement;
        else if (kind != "traction" && !is_pressure)
            throw std::invalid_argument("boundary condition '" + clause + "': unknown kind '" + kind + "'; " + form);
        double v[3] = {0, 0, 0};
        for (int i = 0; i < (is_pressure ? 1 : 3); ++i)
            if (!(rest >> v[i]) || !std::isfinite(v[i]))
                throw std::invalid_argument("boundary condition '" + clause + "': needs " +
                                            (is_pressure ? "one finite number (the pressure in Pa)" : "three finite numbers") +
                                            "; " + form);
        std::string extra;
        if (rest >> extra) throw std::invalid_argument("boundary condition '" + clause + "': unexpected '" + extra + "'; " + form);
        const std::string who = name == "*" ? "'*' (all other regions)" : "region '" + name + "'";
        auto& [had_vector, had_pressure] = seen[name];
        if ((is_pressure && had_pressure) || (!is_pressure && had_vector))
            throw std::invalid_argument("boundary condition for " + who + " given twice");
        RegionCondition* rc = nullptr;
        if (name == "*") {
            if (!bc.others) bc.others = RegionCondition{};
            rc = &*bc.others;
        } else {
            rc = &bc.regions[name];
        }
        if (is_pressure) {
            had_pressure = true;
            rc->pressure = v[0];
        } else {
            had_vector = true;
            rc->kind = k;
            rc->value = Vec3(v[0], v[1], v[2]);
        }
        if (had_pressure && rc->kind == RegionCondition::Kind::displacement)
            throw std::invalid_argument("boundary condition: pressure on " + who +
                                        ", which has a displacement (Dirichlet) condition; a pressure acts on traction "
                                        "(Neumann) regions only: remove the pressure or make the region a traction");
    }
    return bc;
}

std::string check_named_regions(const std::string& named, const SurfaceMesh& mesh) {
    std::map<std::string, std::size_t> triangles;  // region name -> triangles
    for (int r = 0; r < mesh.num_regions(); ++r) triangles[mesh.region_name(r)] = 0;
    for (std::size_t t = 0; t < mesh.num_triangles(); ++t) ++triangles[mesh.region_name(mesh.region_of(t))];
    std::string known;
    for (const auto& kv : triangles)
        if (kv.second > 0) known += (known.empty() ? "" : ", ") + kv.first;
    std::stringstream all(named);
    std::string entry;
    while (std::getline(all, entry, ';')) {
        const auto colon = entry.find(':');
        if (colon == std::string::npos) continue;
        const std::string node = entry.substr(0, colon), region = entry.substr(colon + 1);
        const auto it = triangles.find(region);
        if (it == triangles.end() || it->second == 0)
            return "node '" + node + "' names region '" + region + "' in its boundary_conditions, which this mesh " +
                   (it == triangles.end() ? "does not have" : "has no triangles of") + " (its regions: " + known +
                   "); checked before assembling. Fix the name, or the regions of the mesh (the groups or materials "
                   "of its file, regions.halfspace, simplify.remesh)";
    }
    return "";
}

bool ResolvedConditions::pure_neumann() const {
    for (char d : dirichlet)
        if (d) return false;
    return true;
}

ResolvedConditions resolve(const BoundaryConditions& bc, const SurfaceMesh& mesh) {
    const int nreg = mesh.num_regions();
    std::map<std::string, int> ids;
    for (int r = 0; r < nreg; ++r) ids[mesh.region_name(r)] = r;
    for (const auto& kv : bc.regions)
        if (!ids.count(kv.first)) {
            std::string known;
            for (const auto& i : ids) known += (known.empty() ? "" : ", ") + i.first;
            throw std::invalid_argument("boundary condition names region '" + kv.first +
                                        "', which the mesh does not have (regions: " + known + ")");
        }
    std::vector<const RegionCondition*> per_region(nreg, nullptr);
    std::vector<char> used(nreg, 0);
    for (std::size_t t = 0; t < mesh.num_triangles(); ++t) used[mesh.region_of(t)] = 1;
    for (const auto& kv : bc.regions)
        if (!used[ids.at(kv.first)])
            throw std::invalid_argument("boundary condition names region '" + kv.first +
                                        "', which has no triangles on this mesh (a region that lost its triangles to "
                                        "an earlier region, or to remeshing); fix the regions or drop the condition");
    std::string uncovered;
    for (int r = 0; r < nreg; ++r) {
        auto it = bc.regions.find(mesh.region_name(r));
        per_region[r] = it != bc.regions.end() ? &it->second : bc.others ? &*bc.others : nullptr;
        if (!per_region[r] && used[r])
            uncovered += (uncovered.empty() ? "" : ", ") + std::to_string(r) + " ('" + mesh.region_name(r) + "')";
    }
    if (!uncovered.empty())
        throw std::invalid_argument("regions without a boundary condition: " + uncovered +
                                    "; give each a 'name: traction x y z', 'name: pressure p' or 'name: displacement x y z', or add '*: ...'");
    if (!bc.element_tractions.empty() && bc.element_tractions.size() != mesh.num_triangles())
        throw std::invalid_argument("per-element tractions: " + std::to_string(bc.element_tractions.size()) +
                                    " values for " + std::to_string(mesh.num_triangles()) + " triangles");
    ResolvedConditions out;
    const std::size_t M = mesh.num_triangles(), N = mesh.num_vertices();
    out.dirichlet.assign(M, 0);
    out.traction.assign(M, Vec3::Zero());
    out.node_fixed.assign(N, 0);
    out.displacement.assign(N, Vec3::Zero());
    std::vector<int> node_region(N, -1);
    for (std::size_t t = 0; t < M; ++t) {
        const int r = mesh.region_of(t);
        const RegionCondition& rc = *per_region[r];
        if (rc.kind == RegionCondition::Kind::displacement) {
            out.dirichlet[t] = 1;
            for (int v : mesh.triangles[t]) {
                if (out.node_fixed[v] && (out.displacement[v] - rc.value).norm() > 1e-12 * (1 + rc.value.norm()))
                    throw std::invalid_argument("node " + std::to_string(v) + " is shared by Dirichlet regions '" +
                                                mesh.region_name(node_region[v]) + "' and '" + mesh.region_name(r) +
                                                "' with different displacements; make them equal or make one a traction");
                out.node_fixed[v] = 1;
                out.displacement[v] = rc.value;
                node_region[v] = r;
            }
        } else {
            // Pressure: -p n with the element's own outward normal (thesis ch. 2.2 Neumann data).
            out.traction[t] = rc.value - rc.pressure * triangle_normal(mesh, t) +
                              (bc.element_tractions.empty() ? Vec3::Zero() : bc.element_tractions[t]);
        }
    }
    return out;
}

}  // namespace cf::bem
