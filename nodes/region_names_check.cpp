// A pipeline check run by the loader (`crackflow validate`, and `run` before anything runs): the
// boundary conditions of solve.sgbem name regions of the mesh its operators were assembled on;
// where that mesh's region names follow from the pipeline alone (procedural shapes, half-space
// regions, simplify.remesh with or without regions carried from another known mesh), a name the
// mesh will not have is reported at the parameter's FILE:LINE (issue 13); so is one a mesh file
// read by import.mesh does not have (its face groups, read by the parser alone). Every name is also
// handed to the assemble.sgbem node (its 'boundary_regions'), which checks it against the mesh
// before assembling: meshes whose regions only running tells are known only then.
#include "graph/pipeline.hpp"
#include "graph/run_node.hpp"
#include "nodes/bem/boundary_conditions.hpp"
#include "nodes/import/read_mesh.hpp"
#include "nodes/regions/region_spec.hpp"
#include "nodes/registration.hpp"

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <mutex>
#include <optional>
#include <set>

namespace cf {

namespace {

using graph::Plan;
using graph::PlanInput;
using graph::PlanNode;
using Names = std::optional<std::set<std::string>>;  // nullopt: not known without running

const PlanInput* find_input(const PlanNode& n, const std::string& port) {
    for (const PlanInput& in : n.inputs)
        if (in.port == port) return &in;
    return nullptr;
}

// The node an input comes from, through a loop variable to the node giving its initial value
// (the loop's later values come from the body, which assembles on the same mesh in every
// shipped fracture loop; a body that changes meshes is checked at run time). -1: not followed.
int source_node(const Plan& plan, const PlanInput& in, int depth = 0) {
    if (depth > 8) return -1;
    if (in.kind == graph::SourceKind::NodeOutput) return in.source;
    if (in.kind == graph::SourceKind::LoopVariable || in.kind == graph::SourceKind::LoopEach ||
        in.kind == graph::SourceKind::LoopFinal)
        for (const PlanInput& init : plan.nodes[std::size_t(in.source)].loop_init)
            if (init.port == in.source_port) return source_node(plan, init, depth + 1);
    return -1;
}

std::string param_text(const PlanNode& n, const std::string& name) {
    const auto it = n.params.find(name);
    return it != n.params.end() && std::holds_alternative<std::string>(it->second) ? std::get<std::string>(it->second) : "";
}
bool param_bool(const PlanNode& n, const std::string& name) {
    const auto it = n.params.find(name);
    return it != n.params.end() && std::holds_alternative<bool>(it->second) && std::get<bool>(it->second);
}

// Region names of a mesh file (the loader resolved the path): its parser alone, no checks, so a
// misspelt boundary-condition region is reported by validate, before any level set is computed.
// Files over 64 MB (seconds to parse) and files that do not parse are left to the assembly's check.
Names file_regions(const std::string& path) {
    namespace fs = std::filesystem;
    std::error_code ec;
    if (path.empty() || !fs::is_regular_file(path, ec) || fs::file_size(path, ec) > (std::uintmax_t(64) << 20) || ec)
        return std::nullopt;
    try {
        std::ifstream in(path, std::ios::binary);
        const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        if (!in && !in.eof()) return std::nullopt;
        const MeshSoup soup = read_mesh_soup(path, fs::path(path).extension().string(), bytes);
        std::set<std::string> names;
        for (const SoupFace& f : soup.faces)
            names.insert(f.region < 0 ? std::string("default") : soup.region_names.at(std::size_t(f.region)));
        if (names.empty()) return std::nullopt;
        return names;
    } catch (const std::exception&) {
        return std::nullopt;  // import.mesh reports the file's own errors when it runs
    }
}

// Region names of the mesh node `i` outputs, where the pipeline alone decides them.
Names mesh_regions(const Plan& plan, int i, int depth = 0) {
    if (i < 0 || depth > 16) return std::nullopt;
    const PlanNode& n = plan.nodes[std::size_t(i)];
    if (n.is_loop()) return std::nullopt;
    const std::string& type = n.type->name();
    auto upstream = [&](const std::string& port) -> Names {
        const PlanInput* in = find_input(n, port);
        return in ? mesh_regions(plan, source_node(plan, *in), depth + 1) : Names{};
    };
    auto spec_names = [&]() -> Names {
        try {
            std::set<std::string> names;
            for (const auto& d : parse_region_spec(param_text(n, "regions"))) names.insert(d.name);
            return names;
        } catch (const std::exception&) {
            return std::nullopt;  // the node reports its own spec error
        }
    };
    if (type.rfind("shape.", 0) == 0 && n.type->inputs().empty()) {
        // A procedural shape's region names do not depend on its parameters: build its default
        // (small) mesh once to read them, so they are never written down twice.
        static std::map<std::string, std::set<std::string>> cache;
        static std::mutex m;
        std::lock_guard<std::mutex> lock(m);
        auto it = cache.find(type);
        if (it == cache.end()) {
            try {
                const graph::NodeResult r = graph::run_node(*n.type, {}, {});
                const auto o = r.outputs.find("mesh");
                if (o == r.outputs.end()) return std::nullopt;
                const SurfaceMesh& mesh = o->second.get<SurfaceMesh>();
                std::set<std::string> names;
                for (int k = 0; k < mesh.num_regions(); ++k) names.insert(mesh.region_name(k));
                it = cache.emplace(type, std::move(names)).first;
            } catch (const std::exception&) {
                return std::nullopt;
            }
        }
        return it->second;
    }
    if (type == "import.mesh") return file_regions(param_text(n, "path"));
    if (type == "regions.halfspace") {
        Names names = spec_names();
        if (!names) return names;
        const Names rest = param_bool(n, "keep_unmatched") ? upstream("mesh") : Names{std::set<std::string>{"default"}};
        if (!rest) return std::nullopt;
        names->insert(rest->begin(), rest->end());
        return names;
    }
    if (type == "simplify.remesh") {
        const bool carried = find_input(n, "regions_from") != nullptr;
        const Names base = carried ? upstream("regions_from") : Names{std::set<std::string>{"surface"}};
        if (param_text(n, "regions").empty()) return base;
        Names names = spec_names();
        const Names rest = carried ? base : Names{std::set<std::string>{"default"}};
        if (!names || !rest) return std::nullopt;
        names->insert(rest->begin(), rest->end());
        return names;
    }
    return std::nullopt;
}

void check_boundary_condition_regions(Plan& plan, std::vector<graph::Diagnostic>& diags) {
    for (const PlanNode& n : plan.nodes) {
        if (n.is_loop() || n.type->name() != "solve.sgbem" || find_input(n, "conditions")) continue;
        const PlanInput* ops = find_input(n, "operators");
        const int assemble = ops ? source_node(plan, *ops) : -1;
        if (assemble < 0 || plan.nodes[std::size_t(assemble)].is_loop() ||
            plan.nodes[std::size_t(assemble)].type->name() != "assemble.sgbem")
            continue;
        bem::BoundaryConditions bc;
        try {
            bc = bem::parse_boundary_conditions(param_text(n, "boundary_conditions"));
        } catch (const std::exception&) {
            continue;  // reported by the parameter's own check
        }
        // For the run: the assembly checks these names before its expensive part.
        std::string& handed = std::get<std::string>(plan.nodes[std::size_t(assemble)].params["boundary_regions"] =
                                                        param_text(plan.nodes[std::size_t(assemble)], "boundary_regions"));
        for (const auto& kv : bc.regions) handed += (handed.empty() ? "" : ";") + n.name + ":" + kv.first;
        const PlanInput* mesh_in = find_input(plan.nodes[std::size_t(assemble)], "mesh");
        const int mesh = mesh_in ? source_node(plan, *mesh_in) : -1;
        const Names names = mesh_regions(plan, mesh);
        if (!names) continue;
        const auto loc = n.param_locs.count("boundary_conditions") ? n.param_locs.at("boundary_conditions") : n.loc;
        const std::vector<std::string> known(names->begin(), names->end());
        std::string list;
        for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
        const PlanNode& source = plan.nodes[std::size_t(mesh)];
        for (const auto& [region, condition] : bc.regions)
            if (!names->count(region))
                diags.push_back({loc,
                                 "parameter 'boundary_conditions' of node '" + n.name + "' names region '" + region +
                                     "', which the mesh from node '" + source.name + "' (" + source.type->name() +
                                     ") will not have (its regions: " + list + ")",
                                 graph::did_you_mean(region, known)});
    }
}

}  // namespace

void add_plan_checks(graph::NodeRegistry& r) { r.add_plan_check(check_boundary_condition_regions); }

}  // namespace cf
