// Node adapters for nodes/initiate: initiate.cracks (stress-based initiation, thesis ch. 4.4) and
// initiate.user_crack (a user-given initial crack, App. A item 12).
#include "graph/node_context.hpp"
#include "graph/registry.hpp"
#include "nodes/initiate/stress_initiation.hpp"
#include "nodes/initiate/surface_queries.hpp"
#include "nodes/initiate/user_crack.hpp"
#include "nodes/registration.hpp"
#include "nodes/vec3_param.hpp"

#include <stdexcept>

namespace cf {
namespace {

graph::NodeType cracks_node() {
    graph::NodeType t("initiate.cracks",
                      "Starts new cracks where the surface stress of the BEM solution (eq. 4.6) exceeds the strength (thesis "
                      "ch. 4.4, rules (a)-(d)): a hexagon of radius 0.2 r_c in the principal plane, offset into the body from "
                      "the element with the largest excess first; never within r_c of a crack front, never twice from one "
                      "element, never touching the surface or another crack sheet. E and nu are the BEM's.");
    t.input<bem::BemSolution>("solution", "from solve.sgbem for the state's crack sheets");
    t.input<propagate::FractureState>("state", "fracture state of the step");
    t.input<ScalarField>("strength", "tensile strength field [Pa] (quantity strength); its f_c scales compression");
    t.optional_input<LevelSet>("object",
                               "level set of the object; when connected, a hexagon whose centre lies outside it is skipped "
                               "(needed where the BEM surface is larger than the object: a scene's class (d) fragment)");
    t.output<propagate::FractureState>("state", "the state with the new cracks (fresh fronts, recorded hexagons)");
    t.param_int("max_cracks", 10, "largest number of stress-initiated cracks in the whole simulation (App. A item 21)")
        .at_least(0);
    t.param_real("snap_distance", 0, "m",
                 "with 'object': elements of the BEM surface up to this far outside the object have their hexagons "
                 "placed below the object's surface instead (farther ones are skipped); 0: r_c / 4. A scene sets it "
                 "from the body's BEM standoff")
        .at_least(0);
    t.param_bool("branching", false,
                 "crack faces initiate too (branching; their stress from u_c +- [u]/2 costs one surface integral per "
                 "crack vertex)");
    t.run([](graph::NodeContext& c) {
        const ScalarField& strength = c.in<ScalarField>("strength");
        if (strength.quantity != FieldQuantity::strength)
            c.fail(std::string("input 'strength' is a ") + quantity_name(strength.quantity) +
                   " field; connect a field with quantity 'strength' [Pa]");
        propagate::FractureState state = c.in<propagate::FractureState>("state");
        initiate::CrackInitiationSettings s;
        s.max_cracks = static_cast<int>(c.integer("max_cracks"));
        s.branching = c.boolean("branching");
        if (c.has("object")) s.object = &c.in<LevelSet>("object");
        s.snap_distance = c.real("snap_distance");
        initiate::CrackInitiationReport r;
        try {
            r = initiate::initiate_cracks(state, c.in<bem::BemSolution>("solution"), strength, s);
        } catch (const std::invalid_argument& e) {
            c.fail(std::string("inputs 'solution' / 'state': ") + e.what());
        }
        c.count("cracks_added", r.cracks_added);
        c.count("cracks_initiated", state.cracks_initiated);
        c.count("from_surface", r.from_surface);
        c.count("from_crack_faces", r.from_crack_faces);
        c.count("crack_face_candidates", r.crack_face_candidates);
        c.count("candidates_over_strength", r.selection.over_strength);
        c.count("skipped_near_front", r.selection.skipped_near_front);
        c.count("over_budget", r.selection.over_budget);
        c.count("skipped_outside", r.skipped_outside);
        c.count("skipped_surface", r.skipped_surface);
        c.count("skipped_crack", r.skipped_crack);
        c.count("triangles_added", static_cast<double>(r.triangles_added));
        c.count("cracks", state.num_cracks());
        c.out("state", std::move(state));
    });
    return t;
}

graph::NodeType user_crack_node() {
    graph::NodeType t("initiate.user_crack",
                      "Adds an initial crack given by the user (thesis App. A item 12): the disk of 'radius' around 'centre' "
                      "in the plane with 'normal', or with a 'front_direction' d the half-disk on the +d side (an edge crack: "
                      "centre on a face, d into the body). The BEM sheet is that region kept max(r_f, 0.05 r_c) inside the "
                      "surface, meshed with edges ~r_c; the recorded fine crack is the whole (half-)disk.");
    t.input<propagate::FractureState>("state", "fracture state to add the crack to");
    t.input<SurfaceMesh>("mesh", "the ordinary BEM surface (closed, outward oriented)");
    t.input<LevelSet>("object", "level set of the object (to check that the crack is inside)");
    t.output<propagate::FractureState>("state", "the state with the crack (a fresh front)");
    t.param_reals("centre", {}, "m", "centre of the crack disk (on a face for an edge crack)").size(3).required();
    t.param_reals("normal", {}, "", "normal of the crack plane (any length)").size(3).required();
    t.param_reals("front_direction", {0, 0, 0}, "",
                  "0 0 0: full disk; else the half-disk on this side of the centre (projected into the plane)")
        .size(3);
    t.param_real("radius", 0, "m", "radius of the crack disk").above(0).required();
    t.run([](graph::NodeContext& c) {
        propagate::FractureState state = c.in<propagate::FractureState>("state");
        const SurfaceMesh& mesh = c.in<SurfaceMesh>("mesh");
        const LevelSet& object = c.in<LevelSet>("object");
        if (object.empty()) c.fail("input 'object' is an empty level set; connect the object's level set");
        if (state.initiated.size() != mesh.num_triangles())
            c.fail("input 'mesh' has " + std::to_string(mesh.num_triangles()) + " triangles but input 'state' was started for " +
                   std::to_string(state.initiated.size()) + " surface elements; connect the BEM surface the state belongs to");
        initiate::UserCrackSpec spec;
        spec.centre = vec3_param(c, "centre");
        spec.normal = vec3_param(c, "normal");
        spec.front_direction = vec3_param(c, "front_direction");
        spec.radius = c.real("radius");
        const std::string name = "user_crack" + std::to_string(state.num_cracks());
        initiate::UserCrack crack;
        try {
            crack = initiate::build_user_crack(spec, mesh, [&](const Vec3& p) { return sample(object, p); }, state.r_c,
                                               state.r_f, name);
            initiate::TriangleObstacles existing;
            existing.add(state.cracks, "crack sheets of the state");
            if (existing.intersects(crack.sheet))
                c.fail("the crack (parameter 'centre', 'radius') touches or crosses a crack already in the state; move or "
                       "shrink it");
            propagate::add_crack(state, crack.sheet, crack.recorded);
        } catch (const std::invalid_argument& e) {
            c.fail(e.what());
        }
        c.count("sheet_triangles", static_cast<double>(crack.sheet.num_triangles()));
        c.count("sheet_vertices", static_cast<double>(crack.sheet.num_vertices()));
        c.count("recorded_triangles", static_cast<double>(crack.recorded.size()));
        c.count("margin", crack.margin);
        c.count("cracks", state.num_cracks());
        c.out("state", std::move(state));
    });
    return t;
}

}  // namespace

void register_initiate_nodes(graph::NodeRegistry& r) {
    r.add(cracks_node());
    r.add(user_crack_node());
}

}  // namespace cf
