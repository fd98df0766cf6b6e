#include "nodes/bem/operators.hpp"

#include "nodes/bem/surface_intersection.hpp"
#include "nodes/domain/mesh_topology.hpp"

#include "graph/cancel_token.hpp"

#include <tbb/parallel_for.h>
#include <tbb/parallel_for_each.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <sstream>
#include <stdexcept>

namespace cf::bem {

double surface_operator_bytes(std::size_t M, std::size_t N, bool single_layer) {
    const double m = 3.0 * M, n = 3.0 * N;
    return 8.0 * ((single_layer ? m * m : 0.0) + 2 * m * n + n * n);
}

double crack_operator_bytes(std::size_t Ms, std::size_t Ns, std::size_t Nc) {
    const double c = 3.0 * Nc;
    // W, X, HY twice (copy-on-write keeps the previous step), then the solver's Y, Schur factor and
    // A^-1 B (about 3 (Ms + Ns) x c).
    return 8.0 * ((3.0 * Ms * c + 3.0 * Ns * c + c * c) * 2 + 2 * c * c + 3.0 * (Ms + Ns) * c);
}

void check_memory_budget(double bytes, double budget, const std::string& what) {
    if (bytes > budget) {
        std::ostringstream os;
        os.precision(3);
        os << what << " needs " << bytes / 1e9 << " GB of dense matrices, above the memory budget of " << budget / 1e9
           << " GB; use a coarser BEM mesh (fewer triangles) or raise the memory budget parameter";
        throw MemoryBudgetExceeded(os.str());
    }
}

std::vector<std::vector<int>> colour_elements(const std::vector<ElementGeometry>& g, std::size_t first, std::size_t last) {
    int max_node = -1;
    for (std::size_t e = first; e < last; ++e)
        for (int v : g[e].nodes) max_node = std::max(max_node, v);
    std::vector<std::vector<int>> node_elems(max_node + 1);
    std::vector<int> colour(last - first, -1);
    std::vector<std::vector<int>> groups;
    std::vector<char> used;
    for (std::size_t e = first; e < last; ++e) {
        used.assign(groups.size() + 1, 0);
        for (int v : g[e].nodes)
            for (int o : node_elems[v]) used[colour[o - first]] = 1;
        int c = 0;
        while (used[c]) ++c;
        colour[e - first] = c;
        if (c == static_cast<int>(groups.size())) groups.emplace_back();
        groups[c].push_back(static_cast<int>(e));
        for (int v : g[e].nodes) node_elems[v].push_back(static_cast<int>(e));
    }
    return groups;
}

namespace {

// Runs fn(e) for every element of `groups` (colour_elements' colours) with the additions into each
// node's columns in colour order, as one parallel loop per colour would, but without a barrier
// between colours: an element waits only for the element of the next lower colour on each of its
// nodes (at most three), so a heavy element (a sheet corner's square-root pairs) holds up its
// neighbours, not the whole next colour. Every column still gets its contributions in the same order,
// so the result is bit for bit that of the colour-by-colour loop, whatever the thread count.
// Polls the running node's cancel token per element (an element's pairs take well under 0.1 s).
template <class Fn>
void for_each_colour(const std::vector<ElementGeometry>& g, const std::vector<std::vector<int>>& groups, Fn fn) {
    const CancelToken cancel = CancelToken::current();
    std::size_t lo = g.size(), hi = 0;
    for (const auto& grp : groups)
        for (int e : grp) {
            lo = std::min(lo, std::size_t(e));
            hi = std::max(hi, std::size_t(e) + 1);
        }
    if (lo >= hi) return;
    // Per node, the last element seen in colour order; each element's successors on its nodes.
    int max_node = -1;
    for (std::size_t e = lo; e < hi; ++e)
        for (int v : g[e].nodes) max_node = std::max(max_node, v);
    std::vector<int> last_on_node(std::size_t(max_node + 1), -1);
    std::vector<std::array<int, 3>> successors(hi - lo, {-1, -1, -1});
    std::vector<std::atomic<int>> waiting(hi - lo);
    std::vector<int> ready;
    for (const auto& grp : groups)
        for (int e : grp) {
            int preds = 0;
            for (int v : g[e].nodes) {
                const int p = last_on_node[std::size_t(v)];
                last_on_node[std::size_t(v)] = e;
                if (p < 0) continue;
                // A predecessor twice (two shared nodes) is counted once, so its one release frees e.
                auto& succ = successors[std::size_t(p) - lo];
                if (std::find(succ.begin(), succ.end(), e) != succ.end()) continue;
                *std::find(succ.begin(), succ.end(), -1) = e;
                ++preds;
            }
            waiting[std::size_t(e) - lo].store(preds, std::memory_order_relaxed);
            if (preds == 0) ready.push_back(e);
        }
    tbb::parallel_for_each(ready.begin(), ready.end(), [&](int e, tbb::feeder<int>& feeder) {
        cancel.poll();
        fn(e);
        for (int s : successors[std::size_t(e) - lo])
            if (s >= 0 && waiting[std::size_t(s) - lo].fetch_sub(1, std::memory_order_acq_rel) == 1) feeder.add(s);
    });
}

template <class Mat>
void add_block(Mat& m, Eigen::Index r, Eigen::Index c, const Mat3& b) {
    m.template block<3, 3>(r, c) += b;
}

// Square tiles for the transposing passes below: 48 rows (16 elements or nodes) keep a source and a
// destination tile in L1. Tiles are fixed by the matrix size, not the thread count, and each
// destination entry is written by one task, so the result is deterministic.
constexpr Eigen::Index tile = 48;

// dst += src^T (dst rows x cols, src cols x rows), tiled and in parallel over column tiles.
void add_transpose(Matrix& dst, const Matrix& src) {
    const Eigen::Index rows = dst.rows(), cols = dst.cols();
    const Eigen::Index nct = (cols + tile - 1) / tile;
    tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, nct, 1), [&](const tbb::blocked_range<Eigen::Index>& r) {
        for (Eigen::Index jt = r.begin(); jt != r.end(); ++jt) {
            const Eigen::Index j0 = jt * tile, nj = std::min(tile, cols - j0);
            for (Eigen::Index i0 = 0; i0 < rows; i0 += tile) {
                const Eigen::Index ni = std::min(tile, rows - i0);
                dst.block(i0, j0, ni, nj) += src.block(j0, i0, nj, ni).transpose();
            }
        }
    });
}

// Completes a matrix of which only the 3x3 blocks (a, b) with a <= b were written: block (b, a) =
// block (a, b)^T. Only whole 3x3 blocks are mirrored, so tiles are multiples of 3.
void mirror_upper_blocks(Matrix& m) {
    const Eigen::Index n = m.rows(), nt = (n + tile - 1) / tile;
    static_assert(tile % 3 == 0, "tiles must hold whole 3x3 blocks");
    tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, nt, 1), [&](const tbb::blocked_range<Eigen::Index>& r) {
        for (Eigen::Index jt = r.begin(); jt != r.end(); ++jt) {
            const Eigen::Index j0 = jt * tile, nj = std::min(tile, n - j0);
            for (Eigen::Index i0 = j0 + tile; i0 < n; i0 += tile) {
                const Eigen::Index ni = std::min(tile, n - i0);
                m.block(i0, j0, ni, nj) = m.block(j0, i0, nj, ni).transpose();
            }
            for (Eigen::Index b = j0; b < j0 + nj; b += 3)
                for (Eigen::Index a = b + 3; a < j0 + nj; a += 3) m.block<3, 3>(a, b) = m.block<3, 3>(b, a).transpose();
        }
    });
}

}  // namespace

std::shared_ptr<const SurfaceOperators> assemble_surface_operators(const SurfaceMesh& mesh, const Material& material,
                                                                   const AssemblyOptions& options) {
    validate(material);
    if (mesh.triangles.empty()) throw std::invalid_argument("BEM surface mesh has no triangles");
    check_memory_budget(surface_operator_bytes(mesh.num_triangles(), mesh.num_vertices(), options.single_layer),
                        options.memory_budget_bytes,
                        "BEM assembly of " + std::to_string(mesh.num_triangles()) + " triangles");
    auto out = std::make_shared<SurfaceOperators>();
    out->mesh = mesh;
    out->elastic = ElasticConstants(material.E, material.nu);
    out->options = options;
    out->geometry = element_geometries(mesh, "BEM surface mesh");
    const auto& g = out->geometry;
    const Eigen::Index M = static_cast<Eigen::Index>(g.size()), N = static_cast<Eigen::Index>(mesh.num_vertices());
    const PairQuadrature& quad = shared_pair_quadrature(options.quadrature);
    const ElasticConstants ec = out->elastic;
    // Every 3x3 block (a, b), a <= b, of V is assigned once and the rest mirrored: no zeroing needed.
    if (options.single_layer) out->V.resize(3 * M, 3 * M);
    // K = KU + KLT^T and D = H + H^T. Each element task b writes only columns it owns, which keeps its
    // writes in a few columns (cache friendly): columns nodes(b) of KU and H, columns 3b..3b+2 of KLT.
    Matrix& KU = out->K;
    KU.setZero(3 * M, 3 * N);
    Matrix KLT = Matrix::Zero(3 * N, 3 * M), H = Matrix::Zero(3 * N, 3 * N);
    Matrix& V = out->V;
    for_each_colour(g, colour_elements(g, 0, g.size()), [&](int b) {
        const ElementGeometry& gb = g[b];
        PairBlocks blk;
        for (int a = 0; a <= b; ++a) {
            const ElementGeometry& ga = g[a];
            const PairIntegrals p = pair_integrals(ga, gb, true, quad);
            pair_blocks(ga, gb, p, ec, options.single_layer, blk);
            if (options.single_layer) V.block<3, 3>(3 * a, 3 * b) = blk.U;
            for (int be = 0; be < 3; ++be) add_block(KU, 3 * a, 3 * gb.nodes[be], blk.Kb[be]);
            if (a != b)
                for (int al = 0; al < 3; ++al) add_block(KLT, 3 * ga.nodes[al], 3 * b, blk.Ka[al].transpose());
            const double half = (a == b) ? 0.5 : 1.0;
            for (int al = 0; al < 3; ++al)
                for (int be = 0; be < 3; ++be) add_block(H, 3 * ga.nodes[al], 3 * gb.nodes[be], half * blk.H[al][be]);
        }
    });
    if (options.single_layer) mirror_upper_blocks(V);
    add_transpose(KU, KLT);
    KLT.resize(0, 0);
    if (options.rigid_motion_rows) out->rigid_motion = impose_rigid_motion_rows(KU, g, check_topology(mesh).is_closed_manifold());
    out->D = H;
    add_transpose(out->D, H);
    out->pairs_computed = static_cast<std::int64_t>(M) * (M + 1) / 2;
    return out;
}

namespace {

// append_crack_elements' steps, in the order it calls them.

// The crack mesh must extend the previously assembled one: old triangles and vertices unchanged.
void check_appended(const CrackOperators* previous, const SurfaceMesh& cracks) {
    if (!previous) return;
    const SurfaceMesh& pc = previous->cracks;
    const std::size_t old_tris = pc.num_triangles(), old_verts = pc.num_vertices();
    bool prefix = cracks.num_triangles() >= old_tris && cracks.num_vertices() >= old_verts;
    for (std::size_t t = 0; prefix && t < old_tris; ++t) prefix = cracks.triangles[t] == pc.triangles[t];
    for (std::size_t v = 0; prefix && v < old_verts; ++v) prefix = cracks.vertices[v] == pc.vertices[v];
    if (!prefix)
        throw std::invalid_argument("crack mesh does not extend the previously assembled one (" + std::to_string(old_tris) +
                                    " triangles, " + std::to_string(old_verts) +
                                    " vertices must stay unchanged at the front); crack elements can only be appended");
}

void check_crack_budget(const SurfaceOperators& surface, const SurfaceMesh& cracks, double memory_budget_bytes) {
    try {
        check_memory_budget(crack_operator_bytes(surface.mesh.num_triangles(), surface.mesh.num_vertices(), cracks.num_vertices()),
                            memory_budget_bytes >= 0 ? memory_budget_bytes : surface.options.memory_budget_bytes,
                            "crack blocks for " + std::to_string(cracks.num_vertices()) + " crack nodes");
    } catch (const std::invalid_argument& e) {
        throw std::invalid_argument(std::string(e.what()) +
                                    "; or keep the crack blocks from growing: assemble.sgbem method: hybrid (with switch_elements "
                                    "below this size) or method: estimator (thesis ch. 5)");
    }
}

// The geometry of the crack elements from old_tris on, appended to `geometry`.
void append_crack_geometry(const SurfaceMesh& cracks, std::size_t old_tris, std::vector<ElementGeometry>& geometry) {
    for (std::size_t t = old_tris; t < cracks.num_triangles(); ++t) {
        try {
            geometry.push_back(element_geometry(cracks, t));
        } catch (const std::invalid_argument& e) {
            throw std::invalid_argument(std::string("crack mesh (crack '") + cracks.region_name(cracks.region_of(t)) +
                                        "'): " + e.what());
        }
    }
}

// m at its new size (rows x cols) with the old block in its top-left corner and zeros elsewhere.
void grow_block(Matrix& m, const Matrix* old, Eigen::Index rows, Eigen::Index cols, Eigen::Index old_rows,
                Eigen::Index old_cols) {
    m.resize(rows, cols);
    if (old && old_rows > 0 && old_cols > 0) m.topLeftCorner(old_rows, old_cols) = *old;
    m.rightCols(cols - old_cols).setZero();
    m.bottomRows(rows - old_rows).setZero();
}

// The integrals of one new crack element b against every surface element (W, X) and against
// the crack elements up to b (HY's upper part). Task b owns the columns nodes(b) of W, X and HY,
// so tasks of one colour run in parallel.
class CrackElementColumns {
public:
    // `observer`: sees every pair's P1 blocks (AppendedPairs), or null.
    CrackElementColumns(const SurfaceOperators& surface, CrackOperators& out, AppendedPairs* observer)
        : gs_(surface.geometry), gc_(out.geometry), quad_(shared_pair_quadrature(surface.options.quadrature)),
          ec_(surface.elastic), W_(out.W), X_(out.X), HY_(out.HY), observer_(observer) {}

    void operator()(int b) const {
        const ElementGeometry& gb = gc_[b];
        PairBlocks blk;
        for (std::size_t a = 0; a < gs_.size(); ++a) {
            const ElementGeometry& ga = gs_[a];
            const PairIntegrals p = pair_integrals(ga, gb, false, quad_);
            pair_blocks(ga, gb, p, ec_, false, blk);
            if (observer_) observer_->surface_pair(b, static_cast<int>(a), blk);
            for (int be = 0; be < 3; ++be) {
                add_block(W_, 3 * static_cast<Eigen::Index>(a), 3 * gb.nodes[be], blk.Kb[be]);
                for (int al = 0; al < 3; ++al) add_block(X_, 3 * ga.nodes[al], 3 * gb.nodes[be], blk.H[al][be]);
            }
        }
        for (int a = 0; a <= b; ++a) {
            const ElementGeometry& ga = gc_[a];
            const PairIntegrals p = pair_integrals(ga, gb, true, quad_);
            pair_blocks(ga, gb, p, ec_, false, blk);
            if (observer_) observer_->crack_pair(a, b, blk);
            const double half = (a == b) ? 0.5 : 1.0;
            for (int al = 0; al < 3; ++al)
                for (int be = 0; be < 3; ++be) add_block(HY_, 3 * ga.nodes[al], 3 * gb.nodes[be], half * blk.H[al][be]);
        }
    }

private:
    const std::vector<ElementGeometry>& gs_;
    const std::vector<ElementGeometry>& gc_;
    const PairQuadrature& quad_;
    const ElasticConstants ec_;
    Matrix& W_;
    Matrix& X_;
    Matrix& HY_;
    AppendedPairs* observer_;
};

}  // namespace

std::shared_ptr<const CrackOperators> append_crack_elements(const SurfaceOperators& surface,
                                                            const std::shared_ptr<const CrackOperators>& previous,
                                                            const SurfaceMesh& cracks, double memory_budget_bytes,
                                                            AppendedPairs* observer) {
    const std::size_t old_tris = previous ? previous->cracks.num_triangles() : 0;
    const std::size_t old_verts = previous ? previous->cracks.num_vertices() : 0;
    check_appended(previous.get(), cracks);
    check_crack_budget(surface, cracks, memory_budget_bytes);
    // Copy-on-write without copying twice: the small members are copied, the dense blocks are
    // allocated at their new size and the previous blocks copied into them (peak: old + new).
    auto out = std::make_shared<CrackOperators>();
    if (previous) {
        out->geometry = previous->geometry;
        out->pairs_computed = previous->pairs_computed;
    }
    out->cracks = cracks;
    append_crack_geometry(cracks, old_tris, out->geometry);
    check_crack_clear_of_surface(surface.geometry, out->geometry, old_tris, cracks);
    const Eigen::Index Ms = static_cast<Eigen::Index>(surface.geometry.size());
    const Eigen::Index Ns = static_cast<Eigen::Index>(surface.mesh.num_vertices());
    const Eigen::Index Nc = static_cast<Eigen::Index>(cracks.num_vertices()), Nc0 = static_cast<Eigen::Index>(old_verts);
    grow_block(out->W, previous ? &previous->W : nullptr, 3 * Ms, 3 * Nc, 3 * Ms, 3 * Nc0);
    grow_block(out->X, previous ? &previous->X : nullptr, 3 * Ns, 3 * Nc, 3 * Ns, 3 * Nc0);
    grow_block(out->HY, previous ? &previous->HY : nullptr, 3 * Nc, 3 * Nc, 3 * Nc0, 3 * Nc0);
    if (observer) observer->begin(out->geometry, old_tris);
    for_each_colour(out->geometry, colour_elements(out->geometry, old_tris, out->geometry.size()),
                    CrackElementColumns(surface, *out, observer));
    std::int64_t added = 0;
    for (std::size_t b = old_tris; b < out->geometry.size(); ++b)
        added += static_cast<std::int64_t>(Ms) + static_cast<std::int64_t>(b) + 1;
    out->pairs_computed_last = added;
    out->pairs_computed += added;
    return out;
}

Vector mass_times_nodal(const SurfaceOperators& s, const Vector& u) {
    Vector out = Vector::Zero(3 * s.geometry.size());
    for (std::size_t a = 0; a < s.geometry.size(); ++a)
        for (int v : s.geometry[a].nodes) out.segment<3>(3 * a) += s.geometry[a].area / 3 * u.segment<3>(3 * v);
    return out;
}

Vector mass_transpose_times_elemental(const SurfaceOperators& s, const Vector& t) {
    Vector out = Vector::Zero(3 * s.mesh.num_vertices());
    for (std::size_t a = 0; a < s.geometry.size(); ++a)
        for (int v : s.geometry[a].nodes) out.segment<3>(3 * v) += s.geometry[a].area / 3 * t.segment<3>(3 * a);
    return out;
}

}  // namespace cf::bem
