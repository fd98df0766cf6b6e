// Node adapters for nodes/fields: fields.homogeneous, fields.layered, fields.granular, fields.vdb.
// Each outputs a ScalarField (toughness [Pa*sqrt(m)] or strength [Pa]) with its compressive factor.
#include "graph/node_context.hpp"
#include "graph/registry.hpp"
#include "nodes/domain/material.hpp"
#include "nodes/fields/closed_form_fields.hpp"
#include "nodes/fields/grid_fields.hpp"
#include "nodes/registration.hpp"
#include "nodes/vec3_param.hpp"

#include <stdexcept>

namespace cf {
namespace {

void common_params(graph::NodeType& t) {
    t.param_choice("quantity", "toughness", {"toughness", "strength"},
                   "what the field describes: toughness K_c [Pa*sqrt(m)] (propagation) or tensile strength [Pa] (initiation)");
    t.param_real("compressive_factor", 2, "", "f_c: compressive toughness/strength = f_c * tensile (thesis ch. 4.4, 4.5.1)")
        .above(0);
    t.output<ScalarField>("field", "value and gradient at any point");
}

// Runs `make` and wraps the source; bad settings become node errors naming the parameter.
template <class MakeSource>
void emit(graph::NodeContext& c, MakeSource make) {
    try {
        const FieldQuantity q = parse_quantity(c.string("quantity"));
        ScalarField f = make_field(make(), q, c.real("compressive_factor"));
        c.count("lower_bound", f.source->lower_bound());
        c.out("field", std::move(f));
    } catch (const std::invalid_argument& e) {
        c.fail(e.what());
    }
}

graph::NodeType homogeneous_node() {
    graph::NodeType t("fields.homogeneous", "A constant toughness or strength field (thesis ch. 4.5).");
    t.param_real("value", 1e6, "Pa*sqrt(m) or Pa", "the constant value (unit by quantity)").at_least(0);
    common_params(t);
    t.run([](graph::NodeContext& c) { emit(c, [&] { return std::make_shared<HomogeneousField>(c.real("value")); }); });
    return t;
}

graph::NodeType layered_node() {
    graph::NodeType t("fields.layered",
                      "Layered material K(p) = a - b cos(f p.l) with analytic gradient (thesis ch. 4.5.3, fig. 19). "
                      "Also a strength varying with height (fig. 18): l = e_z, minimum a - b where f p.l = 0.");
    t.param_real("a", 1e6, "Pa*sqrt(m) or Pa", "mean value");
    t.param_real("b", 1e5, "Pa*sqrt(m) or Pa", "amplitude; the field spans [a - |b|, a + |b|]");
    t.param_real("frequency", 100, "rad/m", "spatial frequency f; layers repeat every 2 pi / f").at_least(0);
    t.param_reals("direction", {0, 0, 1}, "", "layer normal l (normalised)").size(3);
    common_params(t);
    t.run([](graph::NodeContext& c) {
        const Vec3 l = vec3_param(c, "direction");
        emit(c, [&] {
            return std::make_shared<LayeredField>(c.real("a"), c.real("b"), c.real("frequency"), l);
        });
    });
    return t;
}

graph::NodeType granular_node() {
    graph::NodeType t("fields.granular",
                      "Granular material (thesis ch. 4.5.3): a seeded periodic Voronoi grain structure; the value rises from "
                      "'value' on grain boundaries to (1 + rise) * value inside grains. The distance to the nearest grain "
                      "boundary is stored on an OpenVDB grid covering one tile, repeated seamlessly.");
    t.param_real("value", 1e6, "Pa*sqrt(m) or Pa", "value on grain boundaries (the minimum)").at_least(0);
    t.param_real("rise", 0.1, "", "fractional rise from boundary to grain interior").above(-1);
    t.param_real("grain_size", 1e-2, "m", "mean grain spacing").above(0);
    t.param_int("grains_per_tile", 64, "grains in one periodic tile (tile edge = grain_size * cbrt(grains))").range(8, 4096);
    t.param_int("seed", 1, "random seed of the grain placement").at_least(0);
    t.param_int("voxels_per_grain", 8, "distance-grid voxels per grain_size").range(2, 64);
    t.param_real("interior_depth", 0.25, "", "depth below a boundary, in grain sizes, where the rise is complete").above(0);
    common_params(t);
    t.run([](graph::NodeContext& c) {
        GranularSettings s;
        s.boundary_value = c.real("value");
        s.rise = c.real("rise");
        s.grain_size = c.real("grain_size");
        s.grains_per_tile = static_cast<int>(c.integer("grains_per_tile"));
        s.seed = static_cast<std::uint64_t>(c.integer("seed"));
        s.voxels_per_grain = static_cast<int>(c.integer("voxels_per_grain"));
        s.interior_depth = c.real("interior_depth");
        emit(c, [&] { return std::make_shared<GranularField>(s); });
    });
    return t;
}

graph::NodeType vdb_node() {
    graph::NodeType t("fields.vdb", "A field read from a float grid of a .vdb file, trilinearly interpolated, times 'scale'.");
    t.param_string("file", "", "path of the .vdb file; a relative path is looked up beside the pipeline file, then on CRACKFLOW_DATA_PATH").required().reads_file();
    t.param_string("grid", "toughness", "name of the float grid in the file");
    t.param_real("scale", 1, "", "factor applied to the grid values (e.g. to convert units)");
    common_params(t);
    t.run([](graph::NodeContext& c) {
        emit(c, [&] { return std::make_shared<VdbFileField>(c.string("file"), c.string("grid"), c.real("scale")); });
    });
    return t;
}

graph::NodeType material_node() {
    graph::NodeType t("material.brittle",
                      "An isotropic linear-elastic brittle material (App. A items 3-8). Every parameter is required, so a "
                      "pipeline states its material in one place; assemble.sgbem, initiate.* and propagate.fronts read it.");
    // Physical ranges (a value inside the range must give a meaningful run: E = 1e300 overflowed the
    // BEM quadrature into K = 1e297): soft gels about 1e3 Pa to diamond 1.2e12 Pa; aerogels about
    // 1 kg/m^3 to osmium 2.3e4 kg/m^3; strengths up to 1e11 Pa; toughness up to 1e9 Pa sqrt(m).
    t.param_real("E", 0, "Pa", "Young's modulus, between 1e3 (soft gel) and 1e13 (beyond diamond)").required().range(1e3, 1e13);
    t.param_real("nu", 0, "", "Poisson's ratio, in (0, 0.5)").required().above(0).below(0.5);
    t.param_real("rho", 0, "kg/m^3", "density (sets the Rayleigh speed, hence simulated time), between 1 and 1e5")
        .required()
        .range(1, 1e5);
    t.param_real("tensile_strength", 0, "Pa", "tensile strength (crack initiation, ch. 4.4), up to 1e11").required().above(0).below(1e11);
    t.param_real("toughness", 0, "Pa*sqrt(m)", "fracture toughness K_c (ch. 4.5), up to 1e9").required().above(0).below(1e9);
    t.param_real("compressive_factor", 0, "", "f_c: compressive strength and toughness = f_c * tensile").required().at_least(1);
    t.output<Material>("material", "the material");
    t.run([](graph::NodeContext& c) {
        Material m;
        m.E = c.real("E");
        m.nu = c.real("nu");
        m.rho = c.real("rho");
        m.tensile_strength = c.real("tensile_strength");
        m.toughness = c.real("toughness");
        m.compressive_factor = c.real("compressive_factor");
        try {
            validate(m);
        } catch (const std::invalid_argument& e) {
            c.fail(e.what());
        }
        c.out("material", m);
    });
    return t;
}

}  // namespace

void register_fields_nodes(graph::NodeRegistry& r) {
    r.add(material_node());
    r.add(homogeneous_node());
    r.add(layered_node());
    r.add(granular_node());
    r.add(vdb_node());
}

}  // namespace cf
