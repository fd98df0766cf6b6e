#include "nodes/initiate/stress_initiation.hpp"

#include "nodes/bem/interior_evaluation.hpp"
#include "nodes/initiate/element_stresses.hpp"
#include "nodes/initiate/surface_queries.hpp"

#include <stdexcept>
#include <string>

namespace cf::initiate {

std::vector<Segment> front_segments(const propagate::FractureState& state) {
    std::vector<Segment> out;
    const std::vector<Vec3>& x = state.cracks.vertices;
    for (const propagate::FrontState& f : state.fronts) {
        const std::vector<int>& n = f.front.nodes;
        for (std::size_t i = 0; i < f.front.num_edges(); ++i) out.push_back({x.at(n[i]), x.at(n[(i + 1) % n.size()])});
    }
    return out;
}

namespace {

// A BEM surface stands off the object's surface: outward by the remesh offset, and by its chords
// across curved parts and rounded edges. Where it does, a hexagon placed at its usual depth below the
// element (eq. of ch. 4.4) would start too close to the object's surface or outside it. With the
// object's level set, each element's reference point moves along its normal onto the object's
// surface, so hexagons start at the same depth below the material as on an exact surface. Elements
// farther than `snap` outside the object (a class (d) fragment's BEM mesh where a chip broke off)
// stay where they are, and the inside test then skips their hexagons.
void place_on_object_surface(std::vector<ElementStress>& elements, const LevelSet& object, double snap) {
    for (ElementStress& e : elements) {
        const double d = distance_along(object, e.centroid, -e.normal);  // beyond the narrow band too
        if (d < snap) e.centroid -= d * e.normal;
    }
}

}  // namespace

CrackInitiationReport initiate_cracks(propagate::FractureState& state, const bem::BemSolution& sol,
                                      const ScalarField& strength, const CrackInitiationSettings& settings) {
    if (!sol.surface) throw std::invalid_argument("crack initiation: the BEM solution has no surface");
    const SurfaceMesh& surface = sol.surface->mesh;
    if (state.initiated.size() != surface.num_triangles())
        throw std::invalid_argument("crack initiation: the fracture state tracks " + std::to_string(state.initiated.size()) +
                                    " surface elements but the BEM solution's surface has " +
                                    std::to_string(surface.num_triangles()) +
                                    " triangles; start the state for the mesh the BEM solves on");
    CrackInitiationReport rep;
    std::vector<ElementStress> elements = surface_element_stresses(sol);
    std::vector<char> initiated = state.initiated;
    const std::size_t n_surface = elements.size();
    if (settings.object)
        place_on_object_surface(elements, *settings.object,
                                settings.snap_distance > 0 ? settings.snap_distance : 0.25 * state.r_c);

    if (settings.branching && sol.cracks && sol.cracks->cracks.num_triangles() > 0) {
        const std::vector<Vec3> uc = bem::crack_average_displacement(sol);  // ch. 6.4
        for (const CrackFaceStress& f : crack_face_stresses(sol, uc)) {
            // The side of the larger excess competes (one crack per element at most).
            elements.push_back(strength_excess(f.plus, strength) >= strength_excess(f.minus, strength) ? f.plus : f.minus);
            initiated.push_back(0);
            ++rep.crack_face_candidates;
        }
    }

    TriangleObstacles surface_triangles, crack_triangles;
    surface_triangles.add(surface, "ordinary BEM surface");
    crack_triangles.add(state.cracks, "crack sheets of the fracture state");

    InitiationSettings s;
    s.r_c = state.r_c;
    s.max_cracks = settings.max_cracks;
    s.existing_cracks = state.cracks_initiated;
    const CandidateCheck admissible = [&](const Initiation& c) {
        if (!inside_closed_mesh(surface, c.centre) || (settings.object && !(sample(*settings.object, c.centre) < 0))) {
            ++rep.skipped_outside;
            return false;
        }
        SurfaceMesh hex = hexagon_crack(c.centre, c.plane_normal, state.r_c, "new");
        if (surface_triangles.intersects(hex)) {
            ++rep.skipped_surface;
            return false;
        }
        if (crack_triangles.intersects(hex)) {
            ++rep.skipped_crack;
            return false;
        }
        crack_triangles.add(hex, "new hexagon");
        return true;
    };
    const std::vector<Initiation> chosen =
        select_initiations(elements, strength, initiated, front_segments(state), s, admissible, &rep.selection);

    for (std::size_t k = 0; k < chosen.size(); ++k) {
        const Initiation& c = chosen[k];
        const bool on_surface = static_cast<std::size_t>(c.element) < n_surface;
        const std::string name = "crack" + std::to_string(state.num_cracks()) +
                                 (on_surface ? "_surface" + std::to_string(c.element)
                                             : "_branch" + std::to_string(c.element - n_surface));
        SurfaceMesh hex = hexagon_crack(c.centre, c.plane_normal, state.r_c, name);
        propagate::add_crack(state, hex, propagate::mesh_triangles(hex));
        if (on_surface) {
            state.initiated[c.element] = 1;
            ++rep.from_surface;
        } else {
            ++rep.from_crack_faces;
        }
        ++state.cracks_initiated;
        ++rep.cracks_added;
        rep.triangles_added += hex.num_triangles();
    }
    state.elements_added += rep.triangles_added;
    return rep;
}

}  // namespace cf::initiate
