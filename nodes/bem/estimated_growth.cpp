#include "nodes/bem/estimated_growth.hpp"

#include "graph/cancel_token.hpp"
#include "nodes/bem/solver.hpp"
#include "nodes/bem/surface_intersection.hpp"

#include <tbb/parallel_for.h>

#include <stdexcept>
#include <string>

namespace cf::bem {

const char* method_name(CrackMethod m) {
    switch (m) {
        case CrackMethod::full: return "full";
        case CrackMethod::estimator: return "estimator";
        case CrackMethod::hybrid: return "hybrid";
    }
    return "?";
}

namespace {

void check_extends(const EstimatedGrowth& prev, const SurfaceMesh& cracks) {
    bool prefix = cracks.num_triangles() >= prev.cracks.num_triangles() && cracks.num_vertices() >= prev.cracks.num_vertices();
    for (std::size_t t = 0; prefix && t < prev.cracks.num_triangles(); ++t) prefix = cracks.triangles[t] == prev.cracks.triangles[t];
    for (std::size_t v = 0; prefix && v < prev.cracks.num_vertices(); ++v) prefix = cracks.vertices[v] == prev.cracks.vertices[v];
    if (!prefix)
        throw std::invalid_argument("crack mesh does not extend the one of the previous estimated step (" +
                                    std::to_string(prev.cracks.num_triangles()) + " triangles, " +
                                    std::to_string(prev.cracks.num_vertices()) +
                                    " vertices must stay unchanged); crack elements can only be appended");
}

// One crack element whose nodes in `mask` have openings to integrate.
struct PendingElement {
    ElementGeometry g;
    unsigned char mask = 0;
    std::array<Vec3, 3> du;  // per local node; zero where not in mask
};

// update_estimated_growth's steps, in the order it calls them.

// The first estimated step: the frozen part of the crack mesh (already in the BEM system) and
// zero right-hand-side updates.
void start_growth(const SurfaceOperators& surface, const SurfaceMesh& cracks, std::size_t frozen_triangles,
                  std::size_t frozen_vertices, int step, EstimatedGrowth& out) {
    if (frozen_triangles > cracks.num_triangles() || frozen_vertices > cracks.num_vertices())
        throw std::invalid_argument("the crack mesh has fewer elements than the ones already in the BEM system");
    out.frozen_triangles = frozen_triangles;
    out.frozen_vertices = frozen_vertices;
    SurfaceMesh frozen;
    frozen.vertices.assign(cracks.vertices.begin(), cracks.vertices.begin() + static_cast<std::ptrdiff_t>(frozen_vertices));
    frozen.triangles.assign(cracks.triangles.begin(), cracks.triangles.begin() + static_cast<std::ptrdiff_t>(frozen_triangles));
    out.frozen_unknown = frozen_triangles ? crack_interior_nodes(frozen) : std::vector<char>(frozen_vertices, 0);
    out.k_opening = Vector::Zero(3 * static_cast<Eigen::Index>(surface.geometry.size()));
    out.d_opening = Vector::Zero(3 * static_cast<Eigen::Index>(surface.mesh.num_vertices()));
    out.switch_step = step;
}

// Geometry of the elements from first_new on (default-constructed before): new elements must
// be as regular and as clear of the surface as assembled ones.
std::vector<ElementGeometry> new_element_geometry(const SurfaceOperators& surface, const SurfaceMesh& cracks,
                                                  std::size_t first_new) {
    std::vector<ElementGeometry> geometry;
    geometry.reserve(cracks.num_triangles());
    for (std::size_t t = 0; t < cracks.num_triangles(); ++t) {
        if (t < first_new) {
            geometry.emplace_back();  // not needed unless pending (filled below)
            continue;
        }
        try {
            geometry.push_back(element_geometry(cracks, t));
        } catch (const std::invalid_argument& e) {
            throw std::invalid_argument(std::string("crack mesh (crack '") + cracks.region_name(cracks.region_of(t)) + "'): " + e.what());
        }
    }
    if (first_new < cracks.num_triangles()) check_crack_clear_of_surface(surface.geometry, geometry, first_new, cracks);
    return geometry;
}

// Nodes whose opening joins now: known, not an unknown of the frozen system, not yet taken.
void join_openings(const CrackOpeningEstimate& openings, EstimatedGrowth& out) {
    const std::size_t Nc = out.cracks.num_vertices();
    std::size_t joined = 0;
    for (std::size_t v = 0; v < Nc && !openings.known.empty(); ++v) {
        if (!openings.known[v] || out.estimated[v]) continue;
        if (v < out.frozen_unknown.size() && out.frozen_unknown[v]) continue;
        if (!openings.opening[v].allFinite())
            throw std::invalid_argument("estimated crack opening at crack vertex " + std::to_string(v) + " is not finite");
        out.estimated[v] = 1;
        out.opening[v] = openings.opening[v];
        ++joined;
    }
    out.nodes_last = joined;
    out.front_active = openings.front_active;
}

// (element, node) pairs not integrated yet, in element order; marked integrated in `out`.
std::vector<PendingElement> pending_elements(const SurfaceMesh& cracks, const std::vector<ElementGeometry>& geometry,
                                             std::size_t first_new, EstimatedGrowth& out) {
    std::vector<PendingElement> pending;
    for (std::size_t t = 0; t < cracks.num_triangles(); ++t) {
        unsigned char mask = 0;
        for (int k = 0; k < 3; ++k)
            if (out.estimated[cracks.triangles[t][k]] && !(out.integrated[t] & (1u << k))) mask |= static_cast<unsigned char>(1u << k);
        if (!mask) continue;
        PendingElement p;
        p.g = (t >= first_new) ? geometry[t] : element_geometry(cracks, t);
        p.mask = mask;
        for (int k = 0; k < 3; ++k) p.du[k] = (mask & (1u << k)) ? out.opening[cracks.triangles[t][k]] : Vec3::Zero();
        pending.push_back(p);
        out.integrated[t] |= mask;
    }
    return pending;
}

// k_opening += W du and d_opening += X du over the pending pairs. Surface element a owns rows
// 3a.. of k_opening; its three nodes' D-type contributions are kept per element and summed in
// element order afterwards, so the result does not depend on threads.
void integrate_pending(const SurfaceOperators& surface, const std::vector<PendingElement>& pending, EstimatedGrowth& out) {
    const std::size_t Ms = surface.geometry.size();
    const PairQuadrature& quad = shared_pair_quadrature(surface.options.quadrature);
    const ElasticConstants ec = surface.elastic;
    std::vector<std::array<Vec3, 3>> node_part(Ms);
    const CancelToken cancel = CancelToken::current();  // every 256 pairs (a few milliseconds)
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, Ms, 4), [&](const tbb::blocked_range<std::size_t>& r) {
        PairBlocks blk;
        for (std::size_t a = r.begin(); a != r.end(); ++a) {
            const ElementGeometry& ga = surface.geometry[a];
            Vec3 k_part = Vec3::Zero();
            std::array<Vec3, 3> d_part = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
            std::size_t pairs = 0;
            for (const PendingElement& p : pending) {
                if ((pairs++ & 255u) == 0) cancel.poll();
                const PairIntegrals pi = pair_integrals(ga, p.g, false, quad);
                pair_blocks(ga, p.g, pi, ec, false, blk);
                for (int be = 0; be < 3; ++be) {
                    if (!(p.mask & (1u << be))) continue;
                    k_part += blk.Kb[be] * p.du[be];
                    for (int al = 0; al < 3; ++al) d_part[al] += blk.H[al][be] * p.du[be];
                }
            }
            out.k_opening.segment<3>(3 * static_cast<Eigen::Index>(a)) += k_part;
            node_part[a] = d_part;
        }
    });
    for (std::size_t a = 0; a < Ms; ++a)
        for (int al = 0; al < 3; ++al) out.d_opening.segment<3>(3 * static_cast<Eigen::Index>(surface.geometry[a].nodes[al])) += node_part[a][al];
}

}  // namespace

std::shared_ptr<const EstimatedGrowth> update_estimated_growth(const SurfaceOperators& surface,
                                                               const std::shared_ptr<const EstimatedGrowth>& previous,
                                                               const SurfaceMesh& cracks, std::size_t frozen_triangles,
                                                               std::size_t frozen_vertices, const CrackOpeningEstimate& openings,
                                                               int step) {
    auto out = previous ? std::make_shared<EstimatedGrowth>(*previous) : std::make_shared<EstimatedGrowth>();
    if (previous) check_extends(*previous, cracks);
    else start_growth(surface, cracks, frozen_triangles, frozen_vertices, step, *out);
    const std::size_t old_tris = out->cracks.num_triangles();
    out->cracks = cracks;
    const std::size_t Nc = cracks.num_vertices();
    if (!openings.known.empty() && (openings.known.size() != Nc || openings.opening.size() != Nc))
        throw std::invalid_argument("the crack opening estimate has " + std::to_string(openings.known.size()) +
                                    " vertices but the crack mesh has " + std::to_string(Nc) +
                                    "; connect the openings of the same fracture state as the cracks");
    out->opening.resize(Nc, Vec3::Zero());
    out->estimated.resize(Nc, 0);
    out->integrated.resize(cracks.num_triangles(), 0);
    const std::size_t first_new = std::max(old_tris, out->frozen_triangles);
    const std::vector<ElementGeometry> geometry = new_element_geometry(surface, cracks, first_new);
    join_openings(openings, *out);
    const std::vector<PendingElement> pending = pending_elements(cracks, geometry, first_new, *out);
    out->pairs_last = pending.size() * surface.geometry.size();
    if (!pending.empty()) integrate_pending(surface, pending, *out);
    return out;
}

}  // namespace cf::bem
