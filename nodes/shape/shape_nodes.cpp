// Node adapters for nodes/shape: shape.box, shape.sphere, shape.cylinder, shape.notched_bar,
// shape.torus. Each reads its parameters into the shape's spec, calls the plain function and
// reports the mesh size and its regions.
#include "graph/node_context.hpp"
#include "graph/registry.hpp"
#include "nodes/registration.hpp"
#include "nodes/vec3_param.hpp"
#include "nodes/regions/region_stats.hpp"
#include "nodes/shape/box.hpp"
#include "nodes/shape/cylinder.hpp"
#include "nodes/shape/icosphere.hpp"
#include "nodes/shape/notched_bar.hpp"
#include "nodes/shape/torus.hpp"

#include <cmath>
#include <functional>
#include <stdexcept>

namespace cf {
namespace {


// Runs a shape function, turning its spec errors into node errors, and reports the result.
void emit(graph::NodeContext& c, const std::function<SurfaceMesh()>& make) {
    SurfaceMesh m;
    try {
        m = make();
    } catch (const std::invalid_argument& e) {
        c.fail(e.what());
    }
    c.count("triangles", static_cast<double>(m.num_triangles()));
    c.count("vertices", static_cast<double>(m.num_vertices()));
    count_region_stats(c, m);
    c.out("mesh", std::move(m));
}

void centre_param(graph::NodeType& t) { t.param_reals("centre", {0, 0, 0}, "m", "centre of the shape (x, y, z)").size(3); }

graph::NodeType box_node() {
    graph::NodeType t("shape.box", "Axis-aligned box; each face a uniform grid of triangles, n cells along every edge "
                                   "(2*n*n triangles a face) or cells of about 'cell_size' along each axis (for slender "
                                   "boxes, e.g. a BEM mesh of a bar). Regions: x_min, x_max, y_min, y_max, z_min, z_max.");
    t.output<SurfaceMesh>("mesh", "closed, outward-oriented box surface");
    t.param_reals("size", {1, 1, 1}, "m", "edge lengths along x, y, z").size(3).above(0);
    centre_param(t);
    t.param_int("subdivisions", 4, "grid cells per edge (n), when 'cell_size' is 0").range(1, 512);
    t.param_real("cell_size", 0, "m", "> 0: round(size / cell_size) cells along each axis instead of 'subdivisions'")
        .at_least(0);
    t.run([](graph::NodeContext& c) {
        BoxSpec s;
        s.size = vec3_param(c, "size");
        s.centre = vec3_param(c, "centre");
        s.subdivisions = static_cast<int>(c.integer("subdivisions"));
        s.cell_size = c.real("cell_size");
        emit(c, [s] { return make_box(s); });
    });
    return t;
}

graph::NodeType sphere_node() {
    graph::NodeType t("shape.sphere",
                      "Icosphere: the icosahedron split k times, 20*4^k triangles, k chosen so the count is nearest "
                      "the target (reported as 'triangles' and 'level'). Every vertex lies on the sphere. Region: "
                      "surface.");
    t.output<SurfaceMesh>("mesh", "closed, outward-oriented sphere surface");
    t.param_real("radius", 0.5, "m", "sphere radius").above(0);
    centre_param(t);
    t.param_int("triangles", 320, "target triangle count (achievable: 20, 80, 320, 1280, ... 1310720)").range(1, 2000000);
    t.param_choice("projection", "per_level", {"per_level", "once"},
                   "per_level: each level's new vertices go onto the sphere along its true normal before the next "
                   "split (near-equilateral triangles); once: split the flat icosahedron, then project every "
                   "vertex along the true normal (geodesic sphere)");
    t.run([](graph::NodeContext& c) {
        SphereSpec s;
        s.radius = c.real("radius");
        s.centre = vec3_param(c, "centre");
        s.level = icosphere_level_for(static_cast<double>(c.integer("triangles")));
        s.projection = c.string("projection") == "once" ? SphereProjection::Once : SphereProjection::PerLevel;
        c.count("level", s.level);
        emit(c, [s] { return make_icosphere(s); });
    });
    return t;
}

graph::NodeType cylinder_node() {
    graph::NodeType t("shape.cylinder",
                      "Closed circular cylinder along z (the inscribed regular prism), centred at 'centre'. "
                      "Regions: side, top, bottom.");
    t.output<SurfaceMesh>("mesh", "closed, outward-oriented cylinder surface");
    t.param_real("radius", 0.5, "m", "radius (rim vertices lie on it)").above(0);
    t.param_real("height", 1, "m", "length along z").above(0);
    centre_param(t);
    t.param_int("segments", 32, "vertices around the rim").range(3, 20000);
    t.param_int("rings", 8, "bands along the height").range(1, 20000);
    t.param_choice("caps", "fan", {"fan", "rings"},
                   "fan: one centre vertex per cap; rings: concentric bands of quads, a fan only innermost");
    t.param_int("cap_rings", 3, "concentric bands per cap when caps: rings").range(1, 20000);
    t.run([](graph::NodeContext& c) {
        CylinderSpec s;
        s.radius = c.real("radius");
        s.height = c.real("height");
        s.centre = vec3_param(c, "centre");
        s.segments = static_cast<int>(c.integer("segments"));
        s.rings = static_cast<int>(c.integer("rings"));
        s.caps = c.string("caps") == "rings" ? CapStyle::Rings : CapStyle::Fan;
        s.cap_rings = static_cast<int>(c.integer("cap_rings"));
        emit(c, [s] { return make_cylinder(s); });
    });
    return t;
}

graph::NodeType notched_bar_node() {
    graph::NodeType t("shape.notched_bar",
                      "Notched bar of the 3-point-bending test (thesis fig. 19, 35): a box along x with a notch "
                      "across the middle of its bottom face (-z). Regions: rest, support_left, support_right "
                      "(bottom strips), load (top centre strip), notch.");
    t.output<SurfaceMesh>("mesh", "closed, outward-oriented bar surface");
    NotchedBarSpec d;
    t.param_real("length", d.length, "m", "extent along x").above(0);
    t.param_real("height", d.height, "m", "extent along z").above(0);
    t.param_real("depth", d.depth, "m", "extent along y").above(0);
    centre_param(t);
    t.param_choice("notch", "v", {"v", "rectangular"}, "notch cross-section: v groove or rectangular slot");
    t.param_real("notch_width", d.notch_width, "m", "x extent of the notch opening (< length)").above(0);
    t.param_real("notch_depth", d.notch_depth, "m", "z extent of the notch (< height)").above(0);
    t.param_real("support_span", d.support_span, "m", "distance between the support strip centres").above(0);
    t.param_real("strip_width", d.strip_width, "m", "x width of each support strip and of the load strip").above(0);
    t.param_real("resolution", d.resolution, "m", "target edge length").above(0);
    t.run([](graph::NodeContext& c) {
        NotchedBarSpec s;
        s.length = c.real("length");
        s.height = c.real("height");
        s.depth = c.real("depth");
        s.centre = vec3_param(c, "centre");
        s.notch = c.string("notch") == "rectangular" ? NotchShape::Rectangular : NotchShape::V;
        s.notch_width = c.real("notch_width");
        s.notch_depth = c.real("notch_depth");
        s.support_span = c.real("support_span");
        s.strip_width = c.real("strip_width");
        s.resolution = c.real("resolution");
        emit(c, [s] { return make_notched_bar(s); });
    });
    return t;
}

graph::NodeType torus_node() {
    graph::NodeType t("shape.torus",
                      "Torus around z, the chain link of thesis fig. 36, pulled along x: regions pull_left and "
                      "pull_right are the outer faces around -x and +x (for Dirichlet displacement along their "
                      "normals), rest is the remainder.");
    t.output<SurfaceMesh>("mesh", "closed, outward-oriented torus surface");
    TorusSpec d;
    t.param_real("major_radius", d.major_radius, "m", "axis-to-tube-centre distance (> minor_radius)").above(0);
    t.param_real("minor_radius", d.minor_radius, "m", "tube radius").above(0);
    centre_param(t);
    t.param_int("major_segments", d.major_segments, "segments around z (even)").range(4, 20000);
    t.param_int("minor_segments", d.minor_segments, "segments around the tube").range(3, 20000);
    t.param_real("pull_angle", d.pull_angle, "rad", "half-angle of each pulled patch in both tube angles")
        .above(0)
        .below(std::acos(-1.0) / 2);
    t.run([](graph::NodeContext& c) {
        TorusSpec s;
        s.major_radius = c.real("major_radius");
        s.minor_radius = c.real("minor_radius");
        s.centre = vec3_param(c, "centre");
        s.major_segments = static_cast<int>(c.integer("major_segments"));
        s.minor_segments = static_cast<int>(c.integer("minor_segments"));
        s.pull_angle = c.real("pull_angle");
        emit(c, [s] { return make_torus(s); });
    });
    return t;
}

}  // namespace

void register_shape_nodes(graph::NodeRegistry& r) {
    r.add(box_node());
    r.add(sphere_node());
    r.add(cylinder_node());
    r.add(notched_bar_node());
    r.add(torus_node());
}

}  // namespace cf
