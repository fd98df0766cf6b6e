#include "nodes/bem/assembly_step.hpp"

#include "nodes/bem/tip_elements.hpp"

#include <stdexcept>
#include <string>

namespace cf::bem {

namespace {

bool same_mesh(const SurfaceMesh& a, const SurfaceMesh& b) { return a.vertices == b.vertices && a.triangles == b.triangles; }

bool surface_reusable(const SurfaceOperators& s, const SurfaceMesh& mesh, const ElasticConstants& ec, const AssemblyOptions& opt) {
    return same_mesh(s.mesh, mesh) && s.elastic.mu == ec.mu && s.elastic.nu == ec.nu && s.options.single_layer == opt.single_layer &&
           s.options.quadrature.singular_order == opt.quadrature.singular_order &&
           s.options.quadrature.farfield_boost == opt.quadrature.farfield_boost;
}

}  // namespace

CrackMethod parse_crack_method(const std::string& name) {
    if (name == "full") return CrackMethod::full;
    if (name == "estimator") return CrackMethod::estimator;
    if (name == "hybrid") return CrackMethod::hybrid;
    throw std::invalid_argument("unknown crack method '" + name + "'; use full, estimator or hybrid");
}

BemOperators assemble_step(const AssemblyRequest& rq, AssemblyReport& rep) {
    const SurfaceMesh& mesh = *rq.mesh;
    const BemOperators* prev = rq.previous;
    BemOperators out;
    // The method is chosen once, on the first assembly.
    if (prev) {
        if (rq.method && *rq.method != prev->method)
            throw std::invalid_argument(std::string("parameter 'method' is ") + method_name(*rq.method) +
                                        " but the previous operators were assembled with " + method_name(prev->method) +
                                        "; set the method on the first assembly only (the loop's assemble inherits it)");
        if (rq.method && *rq.method == CrackMethod::hybrid && rq.switch_elements != prev->switch_elements)
            throw std::invalid_argument("parameter 'switch_elements' is " + std::to_string(rq.switch_elements) +
                                        " but the previous operators switch at " + std::to_string(prev->switch_elements) +
                                        "; set it on the first assembly only");
        out.method = prev->method;
        out.switch_elements = prev->switch_elements;
        if (rq.tip_elements && *rq.tip_elements != prev->tip_elements)
            throw std::invalid_argument(std::string("parameter 'front_elements' is ") + (*rq.tip_elements ? "square_root" : "linear") +
                                        " but the previous operators were assembled with " +
                                        (prev->tip_elements ? "square_root" : "linear") +
                                        "; set it on the first assembly only (the loop's assemble inherits it)");
        out.tip_elements = prev->tip_elements;
    } else {
        out.method = rq.method.value_or(CrackMethod::full);
        out.switch_elements = rq.switch_elements;
        out.tip_elements = rq.tip_elements.value_or(false);
    }
    if (out.switch_elements < 0)
        throw std::invalid_argument("parameter 'switch_elements' is " + std::to_string(out.switch_elements) +
                                    "; give the number of BEM elements (>= 0) above which growth is estimated");
    // Surface blocks: reused when nothing they depend on changed.
    const ElasticConstants ec(rq.material.E, rq.material.nu);
    const BemOperators* reuse = (prev && prev->surface && surface_reusable(*prev->surface, mesh, ec, rq.options)) ? prev : nullptr;
    if (prev && !reuse && prev->estimated)
        throw std::invalid_argument("the surface mesh, material or quadrature changed after crack growth became estimated; the "
                                    "estimated openings belong to the old surface (keep the same mesh and material in the loop)");
    const bool given = !reuse && rq.surface_blocks && surface_reusable(*rq.surface_blocks, mesh, ec, rq.options);
    out.surface = reuse ? reuse->surface : given ? rq.surface_blocks : assemble_surface_operators(mesh, rq.material, rq.options);
    rep.surface_reused = reuse != nullptr || given;
    const bool has_cracks = rq.cracks && rq.cracks->num_triangles() > 0;
    rep.elements = mesh.num_triangles() + (has_cracks ? rq.cracks->num_triangles() : 0);
    const std::shared_ptr<const CrackOperators> prev_cracks = reuse ? reuse->cracks : nullptr;
    static const CrackOpeningEstimate no_openings;
    const CrackOpeningEstimate& openings = (rq.openings && rq.opening_update) ? *rq.openings : no_openings;
    auto need_openings = [&](const SurfaceMesh& cracks, std::size_t frozen_vertices) {
        if (rq.openings || !rq.opening_update) return;
        if (cracks.num_vertices() > frozen_vertices)
            throw std::invalid_argument("crack growth is estimated (method " + std::string(method_name(out.method)) +
                                        ") but input 'openings' is not connected; connect fracture.geometry's 'openings' "
                                        "of the same state as 'cracks'");
    };
    // Already estimating: integrate the openings that joined.
    if (reuse && reuse->estimated) {
        out.cracks = reuse->cracks;
        if (!has_cracks) throw std::invalid_argument("input 'cracks' is empty but the previous step had crack sheets");
        need_openings(*rq.cracks, reuse->estimated->frozen_vertices);
        out.estimated = update_estimated_growth(*out.surface, reuse->estimated, *rq.cracks, 0, 0, openings, rq.step);
        rep.estimated = true;
        rep.crack_pairs = out.estimated->pairs_last;
        return out;
    }
    const bool switch_now = out.method == CrackMethod::estimator ||
                            (out.method == CrackMethod::hybrid && static_cast<long long>(rep.elements) > out.switch_elements);
    if (switch_now) {
        // With previous operators, the cracks of the last full solve stay in the system as they are
        // and the growth since is estimated. On the first assembly (method estimator, or a hybrid
        // threshold below the starting count, as the thesis' method E) the surface is solved without
        // crack unknowns and every crack, the given ones included, enters through the estimators only.
        static const SurfaceMesh no_cracks;
        const SurfaceMesh& cracks = has_cracks ? *rq.cracks : no_cracks;
        if (reuse) out.cracks = reuse->cracks;
        const std::size_t ft = out.cracks ? out.cracks->cracks.num_triangles() : 0;
        const std::size_t fv = out.cracks ? out.cracks->cracks.num_vertices() : 0;
        if (reuse) need_openings(cracks, fv);
        out.estimated = update_estimated_growth(*out.surface, nullptr, cracks, ft, fv, reuse ? openings : no_openings, rq.step);
        rep.switched = rep.estimated = true;
        rep.crack_pairs = out.estimated->pairs_last;
        return out;
    }
    // Full BEM: crack elements appended to the system.
    if (has_cracks) {
        // This node's budget, not that of the assembly whose surface blocks are reused.
        out.cracks = append_crack_elements(*out.surface, prev_cracks, *rq.cracks, rq.options.memory_budget_bytes);
        rep.crack_pairs = static_cast<std::size_t>(out.cracks->pairs_computed_last);
        if (out.tip_elements) {
            // The front moves every step: the square-root blocks are re-integrated from the P1 base.
            out.tip = tip_crack_operators(*out.surface, *out.cracks);
            rep.tip_pairs = static_cast<std::size_t>(out.tip->tip_pairs_computed);
        }
    }
    return out;
}

}  // namespace cf::bem
