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
           s.options.quadrature.farfield_boost == opt.quadrature.farfield_boost &&
           s.options.quadrature.fold_angle == opt.quadrature.fold_angle && s.options.quadrature.fold_order == opt.quadrature.fold_order;
}

// assemble_step's steps, in the order it calls them.

// The method, hybrid threshold and front elements: chosen on the first assembly, inherited after.
void settle_method(const AssemblyRequest& rq, BemOperators& out) {
    const BemOperators* prev = rq.previous;
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
        out.tip_elements = rq.tip_elements.value_or(true);  // square-root front elements (issue 13)
    }
    if (out.switch_elements < 0)
        throw std::invalid_argument("parameter 'switch_elements' is " + std::to_string(out.switch_elements) +
                                    "; give the number of BEM elements (>= 0) above which growth is estimated");
}

// Surface blocks: the previous operators' or the given ones when nothing they depend on changed,
// else assembled. Returns the previous operators when they are reused (null otherwise).
const BemOperators* surface_blocks(const AssemblyRequest& rq, BemOperators& out, AssemblyReport& rep) {
    const SurfaceMesh& mesh = *rq.mesh;
    const BemOperators* prev = rq.previous;
    const ElasticConstants ec(rq.material.E, rq.material.nu);
    const BemOperators* reuse = (prev && prev->surface && surface_reusable(*prev->surface, mesh, ec, rq.options)) ? prev : nullptr;
    if (prev && !reuse && prev->estimated)
        throw std::invalid_argument("the surface mesh, material or quadrature changed after crack growth became estimated; the "
                                    "estimated openings belong to the old surface (keep the same mesh and material in the loop)");
    const bool given = !reuse && rq.surface_blocks && surface_reusable(*rq.surface_blocks, mesh, ec, rq.options);
    out.surface = reuse ? reuse->surface : given ? rq.surface_blocks : assemble_surface_operators(mesh, rq.material, rq.options);
    rep.surface_reused = reuse != nullptr || given;
    return reuse;
}

// Estimated growth past the frozen vertices needs the 'openings' input (unless the update is off).
void need_openings(const AssemblyRequest& rq, CrackMethod method, const SurfaceMesh& cracks, std::size_t frozen_vertices) {
    if (rq.openings || !rq.opening_update) return;
    if (cracks.num_vertices() > frozen_vertices)
        throw std::invalid_argument("crack growth is estimated (method " + std::string(method_name(method)) +
                                    ") but input 'openings' is not connected; connect fracture.geometry's 'openings' "
                                    "of the same state as 'cracks'");
}

const CrackOpeningEstimate& no_openings() {
    static const CrackOpeningEstimate none;
    return none;
}

// The openings to integrate: none when the update is off.
const CrackOpeningEstimate& openings_to_integrate(const AssemblyRequest& rq) {
    return (rq.openings && rq.opening_update) ? *rq.openings : no_openings();
}

// Already estimating: integrate the openings that joined. A step that initiated nothing in a
// body without cracks (a rigid-body collision whose stresses stay below the strength everywhere,
// method estimator) keeps the empty crack set; crack sheets that vanish are an error.
void continue_estimating(const AssemblyRequest& rq, const BemOperators& reuse, BemOperators& out, AssemblyReport& rep) {
    static const SurfaceMesh no_cracks;
    out.cracks = reuse.cracks;
    const bool given = rq.cracks && rq.cracks->num_triangles() > 0;
    if (!given && reuse.estimated->cracks.num_triangles() > 0)
        throw std::invalid_argument("input 'cracks' is empty but the previous step had " +
                                    std::to_string(reuse.estimated->cracks.num_triangles()) +
                                    " crack triangles; connect the 'cracks' of the same fracture state as 'previous'");
    const SurfaceMesh& cracks = given ? *rq.cracks : no_cracks;
    need_openings(rq, out.method, cracks, reuse.estimated->frozen_vertices);
    out.estimated = update_estimated_growth(*out.surface, reuse.estimated, cracks, 0, 0, openings_to_integrate(rq), rq.step);
    rep.estimated = true;
    rep.crack_pairs = out.estimated->pairs_last;
}

// The switch to estimated growth. With previous operators, the cracks of the last full solve
// stay in the system as they are and the growth since is estimated. On the first assembly
// (method estimator, or a hybrid threshold below the starting count, as the thesis' method E)
// the surface is solved without crack unknowns and every crack, the given ones included, enters
// through the estimators only.
void start_estimating(const AssemblyRequest& rq, const BemOperators* reuse, BemOperators& out, AssemblyReport& rep) {
    static const SurfaceMesh no_cracks;
    const SurfaceMesh& cracks = rq.cracks && rq.cracks->num_triangles() > 0 ? *rq.cracks : no_cracks;
    if (reuse) out.cracks = reuse->cracks;
    const std::size_t ft = out.cracks ? out.cracks->cracks.num_triangles() : 0;
    const std::size_t fv = out.cracks ? out.cracks->cracks.num_vertices() : 0;
    if (reuse) need_openings(rq, out.method, cracks, fv);
    out.estimated = update_estimated_growth(*out.surface, nullptr, cracks, ft, fv,
                                            reuse ? openings_to_integrate(rq) : no_openings(), rq.step);
    rep.switched = rep.estimated = true;
    rep.crack_pairs = out.estimated->pairs_last;
}

// Full BEM: crack elements appended to the system.
void append_cracks(const AssemblyRequest& rq, const BemOperators* reuse, BemOperators& out, AssemblyReport& rep) {
    const std::shared_ptr<const CrackOperators> prev_cracks = reuse ? reuse->cracks : nullptr;
    // This node's budget, not that of the assembly whose surface blocks are reused.
    // With square-root elements the corrections of the new elements' pairs are made inside the append,
    // from the P1 blocks it has at hand (TipCorrectionsOfAppend).
    std::unique_ptr<TipCorrectionsOfAppend> corrections;
    if (out.tip_elements) corrections = std::make_unique<TipCorrectionsOfAppend>(*out.surface, *rq.cracks);
    out.cracks = append_crack_elements(*out.surface, prev_cracks, *rq.cracks, rq.options.memory_budget_bytes, corrections.get());
    rep.crack_pairs = static_cast<std::size_t>(out.cracks->pairs_computed_last);
    if (out.tip_elements) {
        // The front moves every step: the square-root blocks are re-integrated from the P1 base.
        out.tip = tip_crack_operators(*out.surface, *out.cracks, reuse && reuse->tip ? reuse->tip.get() : nullptr, corrections.get());
        rep.tip_pairs = static_cast<std::size_t>(out.tip->tip_pairs_computed);
        rep.tip_pairs_reused = static_cast<std::size_t>(out.tip->tip_pairs_reused);
        rep.tip_pairs_in_append = static_cast<std::size_t>(out.tip->tip_pairs_in_append);
    }
}

}  // namespace

CrackMethod parse_crack_method(const std::string& name) {
    if (name == "full") return CrackMethod::full;
    if (name == "estimator") return CrackMethod::estimator;
    if (name == "hybrid") return CrackMethod::hybrid;
    throw std::invalid_argument("unknown crack method '" + name + "'; use full, estimator or hybrid");
}

BemOperators assemble_step(const AssemblyRequest& rq, AssemblyReport& rep) {
    BemOperators out;
    settle_method(rq, out);
    const BemOperators* reuse = surface_blocks(rq, out, rep);
    const bool has_cracks = rq.cracks && rq.cracks->num_triangles() > 0;
    rep.elements = rq.mesh->num_triangles() + (has_cracks ? rq.cracks->num_triangles() : 0);
    if (reuse && reuse->estimated) {
        continue_estimating(rq, *reuse, out, rep);
        return out;
    }
    const bool switch_now = out.method == CrackMethod::estimator ||
                            (out.method == CrackMethod::hybrid && static_cast<long long>(rep.elements) > out.switch_elements);
    if (switch_now) start_estimating(rq, reuse, out, rep);
    else if (has_cracks) append_cracks(rq, reuse, out, rep);
    return out;
}

}  // namespace cf::bem
