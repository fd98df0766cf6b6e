#include "nodes/bem/solver.hpp"

#include "nodes/bem/column_chunks.hpp"

#include "nodes/bem/nearly_touching.hpp"
#include "nodes/bem/tip_elements.hpp"

#include <algorithm>
#include <map>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>
#include <stdexcept>

#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

namespace cf::bem {

namespace {

std::vector<Eigen::Index> dofs3(const std::vector<int>& ids) {
    std::vector<Eigen::Index> out;
    out.reserve(3 * ids.size());
    for (int i : ids)
        for (int j = 0; j < 3; ++j) out.push_back(3 * static_cast<Eigen::Index>(i) + j);
    return out;
}

Matrix solve_matrix(const SurfaceSystem& s, const Matrix& f) {
    if (s.pure_neumann) return s.r_factor.solve(f);
    const Eigen::Index nd = 3 * static_cast<Eigen::Index>(s.d_elements.size());
    const Eigen::Index nn = 3 * static_cast<Eigen::Index>(s.n_nodes.size());
    if (nd == 0) return s.s_factor.solve(f);
    if (nn == 0) return s.v_factor.solve(f);
    // With V_DD = L L^T and W = L^-1 K_DN: z = L^-1 f_D, u = S^-1 (f_N - W^T z), s_D = L^-T (z + W u).
    Matrix z = f.topRows(nd);
    s.v_factor.solve_lower_in_place(z);
    Matrix out(nd + nn, f.cols());
    out.bottomRows(nn) = s.s_factor.solve(f.bottomRows(nn) - s.l_inv_k.transpose() * z);
    z.noalias() += s.l_inv_k * out.bottomRows(nn);
    s.v_factor.solve_upper_in_place(z);
    out.topRows(nd) = z;
    return out;
}

void require(bool ok, const std::string& what) {
    if (!ok) throw std::runtime_error(what);
}

// A surface block that is not positive definite: where the integrals are worst (the double layer's
// rigid-motion residual, rigid_motion_rows.hpp) and where the mesh is too tight for its integrals
// (nearly_touching.hpp), if somewhere, else the mesh properties the method needs.
void require_surface(bool ok, const SurfaceOperators& o, const std::string& what) {
    if (ok) return;
    const std::string row = describe_worst_row(o.geometry, o.rigid_motion.worst_element, o.rigid_motion.max_residual);
    const std::string where = describe_nearly_touching(o.geometry);
    const std::string check = "check that the surface is closed, consistently oriented and free of self-intersections";
    const std::string folds =
        "with blunter folds (simplify.remesh min_dihedral, 30 degrees by default; lib/surface.yaml 'min_dihedral')";
    std::string text = what + "; ";
    if (!row.empty())
        text += "the integrals are worst at " + row + "; " +
                (where.empty() ? "remesh with more, smaller triangles (simplify.remesh target_triangles; lib/surface.yaml "
                                 "'triangles') or " + folds
                               : "also " + where + "; or remesh " + folds) +
                "; else ";
    else if (!where.empty())
        text += "the likeliest cause: " + where + "; else ";
    text += check;
    throw std::runtime_error(text);
}

std::shared_ptr<const SurfaceSystem> factor_surface(const std::shared_ptr<const SurfaceOperators>& ops,
                                                    const ResolvedConditions& bc) {
    auto sys = std::make_shared<SurfaceSystem>();
    sys->ops = ops;
    sys->dirichlet = bc.dirichlet;
    sys->pure_neumann = bc.pure_neumann();
    const SurfaceOperators& o = *ops;
    const std::size_t N = o.mesh.num_vertices();
    if (sys->pure_neumann) {
        // Regulariser rows (eq. 7.2, 7.3), positions relative to the area centroid.
        double A = 0;
        Vec3 c = Vec3::Zero();
        for (const auto& g : o.geometry) {
            A += g.area;
            c += g.area * g.centroid;
        }
        c /= A;
        sys->T = Matrix::Zero(6, 3 * N);
        for (const auto& g : o.geometry) {
            const Vec3 sum = g.p[0] + g.p[1] + g.p[2] - 3 * c;
            for (int i = 0; i < 3; ++i) {
                const int v = g.nodes[i];
                const double w = g.area / (3 * A);
                const Vec3 xb = 0.25 * (g.p[i] - c + sum);
                for (int j = 0; j < 3; ++j) sys->T(j, 3 * v + j) += w;
                // u x xb = -[xb]_x u
                Mat3 cx;
                cx << 0, -xb.z(), xb.y(), xb.z(), 0, -xb.x(), -xb.y(), xb.x(), 0;
                sys->T.block<3, 3>(3, 3 * v) -= w * cx;
            }
        }
        const double g = o.D.trace() / (3.0 * N);
        sys->gamma = g * g;
        Matrix DR = sys->gamma * sys->T.transpose() * sys->T;
        add_lower_gram(DR, o.D);  // lower triangle of D^T D + gamma T^T T
        sys->r_factor.compute(std::move(DR));
        require_surface(sys->r_factor.ok(), o, "regularised Neumann matrix D_R (eq. 7.4) is not positive definite");
        return sys;
    }
    if (o.V.size() == 0)
        throw std::invalid_argument("the operators were assembled without the single layer V, but the boundary conditions have "
                                    "displacement regions; assemble with single_layer = true");
    for (std::size_t a = 0; a < bc.dirichlet.size(); ++a)
        if (bc.dirichlet[a]) sys->d_elements.push_back(static_cast<int>(a));
    for (std::size_t v = 0; v < N; ++v)
        if (!bc.node_fixed[v]) sys->n_nodes.push_back(static_cast<int>(v));
    const auto idxD = dofs3(sys->d_elements);
    const auto idxN = dofs3(sys->n_nodes);
    if (!idxD.empty()) {
        sys->v_factor.compute(o.V(idxD, idxD));
        require_surface(sys->v_factor.ok(), o, "single-layer block V_DD is not positive definite");
    }
    if (!idxN.empty()) {
        Matrix S = o.D(idxN, idxN);
        if (!idxD.empty()) {
            sys->l_inv_k = o.K(idxD, idxN);
            sys->v_factor.solve_lower_in_place(sys->l_inv_k);
            add_lower_gram(S, sys->l_inv_k);  // lower triangle of D_NN + W^T W
        }
        sys->s_factor.compute(std::move(S));
        require_surface(sys->s_factor.ok(), o, "SGBEM complement D_NN + K^T V^-1 K is not positive definite");
    }
    return sys;
}

struct CrackCoupling {
    Matrix B, C;  // size(s) x k and k x size(s)
};

CrackCoupling coupling(const SurfaceSystem& sys, const CrackOperators& cr, const std::vector<int>& nodes) {
    const auto idxC = dofs3(nodes);
    CrackCoupling out;
    if (sys.pure_neumann) {
        const Matrix Xc = cr.X(Eigen::all, idxC);
        out.B = sys.ops->D.transpose() * Xc;
        out.C = Xc.transpose();
        return out;
    }
    const auto idxD = dofs3(sys.d_elements);
    const auto idxN = dofs3(sys.n_nodes);
    const Eigen::Index nd = idxD.size(), nn = idxN.size(), k = idxC.size();
    out.B.resize(nd + nn, k);
    out.B.topRows(nd) = -cr.W(idxD, idxC);
    out.B.bottomRows(nn) = cr.X(idxN, idxC);
    out.C = out.B.transpose();
    out.C.leftCols(nd) *= -1;
    return out;
}

// Y(ia, ib) from its upper part (Y = HY + HY^T) without forming Y (c^2 doubles for a large crack).
Matrix y_block(const CrackOperators& cr, const std::vector<Eigen::Index>& ia, const std::vector<Eigen::Index>& ib) {
    return cr.HY(ia, ib) + cr.HY(ib, ia).transpose();
}

// Y(ia, ib) - C Z, in column chunks on parallel tasks (column_chunks.hpp: bit for bit the single
// Eigen product; chunks of other widths changed the last bits, and with them armadillo_splitting's
// fragments). Z has a column per entry of ib.
Matrix y_minus_product(const CrackOperators& cr, const std::vector<Eigen::Index>& ia, const std::vector<Eigen::Index>& ib,
                       const Matrix& C, const Matrix& Z) {
    Matrix out(static_cast<Eigen::Index>(ia.size()), static_cast<Eigen::Index>(ib.size()));
    for_column_chunks(out.cols(), [&](Eigen::Index c0, Eigen::Index w) {
        const std::vector<Eigen::Index> cols(ib.begin() + c0, ib.begin() + c0 + w);
        out.middleCols(c0, w) = y_block(cr, ia, cols) - C * Z.middleCols(c0, w);
    });
    return out;
}

// C M for the coupling of `nodes` (see coupling()), from the blocks W and X in column chunks, so
// that neither B nor C (size(s) x 3 nodes each) is formed: mixed C = [W_D,C^T, X_N,C^T], pure
// Neumann C = X_C^T.
Matrix coupling_c_times(const SurfaceSystem& sys, const CrackOperators& cr, const std::vector<int>& nodes, const Matrix& M) {
    const auto idxC = dofs3(nodes);
    const Eigen::Index k = static_cast<Eigen::Index>(idxC.size());
    Matrix out(k, M.cols());
    constexpr Eigen::Index chunk = 192;
    const auto idxD = dofs3(sys.d_elements);
    const auto idxN = dofs3(sys.n_nodes);
    const Eigen::Index nd = static_cast<Eigen::Index>(idxD.size());
    // Chunks of rows of the result, each on one task (the same products as one after the other).
    tbb::parallel_for(Eigen::Index(0), (k + chunk - 1) / chunk, [&](Eigen::Index ci) {
        const Eigen::Index c0 = ci * chunk;
        const Eigen::Index n = std::min(chunk, k - c0);
        const std::vector<Eigen::Index> cols(idxC.begin() + c0, idxC.begin() + c0 + n);
        if (sys.pure_neumann) {
            const Matrix Xc = cr.X(Eigen::all, cols);
            out.middleRows(c0, n).noalias() = Xc.transpose() * M;
        } else {
            Matrix part = Matrix::Zero(n, M.cols());
            if (nd) {
                const Matrix Wc = cr.W(idxD, cols);
                part.noalias() += Wc.transpose() * M.topRows(nd);
            }
            if (!idxN.empty()) {
                const Matrix Xc = cr.X(idxN, cols);
                part.noalias() += Xc.transpose() * M.bottomRows(M.rows() - nd);
            }
            out.middleRows(c0, n) = part;
        }
    });
    return out;
}

// solve_sgbem's steps, in the order it calls them.

// The boundary conditions must have been resolved on the operators' mesh.
void check_conditions_mesh(const ResolvedConditions& bc, std::size_t M, std::size_t N) {
    if (bc.dirichlet.size() != M || bc.node_fixed.size() != N)
        throw std::invalid_argument("boundary conditions were resolved on a different mesh (" +
                                    std::to_string(bc.dirichlet.size()) + " triangles, operators have " +
                                    std::to_string(M) + ")");
}

// Pure Neumann: eq. (7.4) has a solution only for balanced loads; the resultants go into `sol`.
void check_balance(const SurfaceOperators& o, const ResolvedConditions& bc, const SolveOptions& options, BemSolution& sol) {
    load_resultants(o, bc.traction, sol.residual_force, sol.residual_torque);
    const std::size_t M = o.geometry.size();
    double fref = 0, L = (bounding_box(o.mesh).extent()).norm();
    for (std::size_t a = 0; a < M; ++a) fref += o.geometry[a].area * bc.traction[a].norm();
    if (fref > 0 && (sol.residual_force.norm() > options.balance_tolerance * fref ||
                     sol.residual_torque.norm() > options.balance_tolerance * fref * L)) {
        std::ostringstream os;
        os.precision(4);
        os << "pure Neumann loads are not balanced: net force " << sol.residual_force.transpose() << " N and torque "
           << sol.residual_torque.transpose() << " N m (relative " << sol.residual_force.norm() / fref << " and "
           << sol.residual_torque.norm() / (fref * L) << ", tolerance " << options.balance_tolerance
           << "); fix the tractions so they sum to zero, or hold a region with a displacement condition";
        throw std::invalid_argument(os.str());
    }
}

// The solve's memory budget [bytes]: its own, or the one the surface operators were assembled with.
double solve_budget(const SurfaceOperators& o, const SolveOptions& options) {
    return options.memory_budget_bytes >= 0 ? options.memory_budget_bytes : o.options.memory_budget_bytes;
}

// Dense bytes of a Schur complement on k crack unknowns over a surface system of n unknowns: the
// coupling B and C (n x k each), Z = A^-1 B, and S, its Cholesky factor and the Y block (k x k).
double schur_bytes(double n, double k) { return 8.0 * (3 * n * k + 3 * k * k); }
// Its extension from ko to ko + kn unknowns: the new columns' B, C and Z, the new Z and L (the old
// ones are kept by the previous solution), and the blocks Son, Sno, LnoT, Snn.
double schur_extension_bytes(double n, double ko, double kn) {
    return 8.0 * (3 * n * kn + n * (ko + kn) + (ko + kn) * (ko + kn) + 3 * ko * kn + 2 * kn * kn);
}

// Surface factorisation: reuse when operators and partition are the same; a new one is checked
// against the budget first.
void choose_surface_system(const std::shared_ptr<const SurfaceOperators>& surface, const ResolvedConditions& bc,
                           const BemSolution* previous, const std::shared_ptr<const SurfaceSystem>& surface_factor,
                           double budget, BemSolution& sol) {
    if (previous && previous->system && previous->system->ops == surface && previous->system->dirichlet == bc.dirichlet) {
        sol.system = previous->system;
        sol.reused_surface_factor = true;
    } else if (surface_factor && surface_factor->ops == surface && surface_factor->dirichlet == bc.dirichlet) {
        sol.system = surface_factor;
        sol.reused_surface_factor = true;
    } else {
        // The factor's dense blocks: V_DD, the complement S and V^-1 K_DN (or D_R of eq. 7.4 and
        // the Gram product it is formed from), before any is allocated.
        double nd = 0, nn = 0;
        for (char d : bc.dirichlet) nd += d ? 3 : 0;
        for (char fixed : bc.node_fixed) nn += fixed ? 0 : 3;
        const double n3 = 3.0 * double(bc.node_fixed.size());
        const double bytes = bc.pure_neumann() ? 8.0 * 2 * n3 * n3 : 8.0 * (nd * nd + nn * nn + nd * nn);
        check_memory_budget(bytes, budget, "factorising the surface system (" + std::to_string(std::size_t(nd + nn)) + " unknowns)");
        sol.system = factor_surface(surface, bc);
    }
}

// Known data: g~ (P1, on closure of Gamma_D) and f~ (P0, on Gamma_N).
struct KnownData {
    Vector g, f;
};

KnownData known_data(const ResolvedConditions& bc, std::size_t M, std::size_t N) {
    KnownData k{Vector::Zero(3 * N), Vector::Zero(3 * M)};
    for (std::size_t v = 0; v < N; ++v) k.g.segment<3>(3 * v) = bc.displacement[v];
    for (std::size_t a = 0; a < M; ++a) k.f.segment<3>(3 * a) = bc.traction[a];
    return k;
}

// Right-hand sides of eq. (2.27) / (7.4).
Vector surface_rhs(const SurfaceOperators& o, const SurfaceSystem& sys, const KnownData& known) {
    const Vector& g = known.g;
    const Vector& f = known.f;
    Vector rhs;
    if (sys.pure_neumann) {
        const Vector fN = 0.5 * mass_transpose_times_elemental(o, f) - o.K.transpose() * f;
        rhs = o.D.transpose() * fN;
    } else {
        Vector r1 = 0.5 * mass_times_nodal(o, g) + o.K * g;
        if (o.V.size()) r1 -= o.V * f;
        const Vector r2 = 0.5 * mass_transpose_times_elemental(o, f) - o.K.transpose() * f - o.D * g;
        rhs.resize(sys.size());
        const auto idxD = dofs3(sys.d_elements);
        const auto idxN = dofs3(sys.n_nodes);
        // Plain copies (not r1(idxD)): GCC 12 warns about Eigen's indexed view here (-Wfree-nonheap-object).
        for (std::size_t i = 0; i < idxD.size(); ++i) rhs[static_cast<Eigen::Index>(i)] = r1[idxD[i]];
        const Eigen::Index nd = static_cast<Eigen::Index>(idxD.size());
        for (std::size_t i = 0; i < idxN.size(); ++i) rhs[nd + static_cast<Eigen::Index>(i)] = r2[idxN[i]];
    }
    return rhs;
}

// Estimated openings du on the right-hand side (eq. 4.2, first row): A s = f - B w with w = -du.
void add_estimated_growth(const SurfaceOperators& o, const SurfaceSystem& sys, const EstimatedGrowth& eg, Vector& rhs) {
    const std::size_t M = o.geometry.size(), N = o.mesh.num_vertices();
    if (eg.k_opening.size() != 3 * static_cast<Eigen::Index>(M) || eg.d_opening.size() != 3 * static_cast<Eigen::Index>(N))
        throw std::invalid_argument("estimated crack growth was integrated against a different surface mesh");
    if (sys.pure_neumann) {
        rhs += o.D.transpose() * eg.d_opening;  // through the normal equations of eq. (7.4)
    } else {
        const auto idxD = dofs3(sys.d_elements);
        const auto idxN = dofs3(sys.n_nodes);
        rhs.head(idxD.size()) -= eg.k_opening(idxD);
        rhs.tail(idxN.size()) += eg.d_opening(idxN);
    }
}

// Whether the previous step's Schur factor can be extended by rows for the new crack nodes: same
// surface factor, no square-root front elements (they change the basis of every node near the
// front each step), and no old unknown whose node left the interior or whose support changed.
bool can_extend_schur(const CrackOperators& cr, const BemSolution* previous, const BemSolution& sol,
                      const std::vector<char>& interior, const SolveOptions& options) {
    const CrackSchur* old = previous ? previous->schur.get() : nullptr;
    bool extend = options.extend_schur && !cr.tip_elements && old && previous->system == sol.system && previous->cracks &&
                  !previous->cracks->tip_elements && old->crack_triangles <= cr.cracks.num_triangles();
    if (extend) {
        std::vector<char> was_dof(cr.cracks.num_vertices(), 0);
        for (int v : old->dof_nodes) {
            if (v >= static_cast<int>(interior.size()) || !interior[v]) extend = false;
            else was_dof[v] = 1;
        }
        for (std::size_t t = old->crack_triangles; extend && t < cr.cracks.num_triangles(); ++t)
            for (int v : cr.cracks.triangles[t])
                if (was_dof[v]) extend = false;  // the support of an old unknown changed
    }
    return extend;
}

// The old Schur factor (eq. 4.3) extended by the rows of the interior nodes that were no unknown
// before: a block Cholesky update, the old rows untouched.
void extend_schur_by(const SurfaceSystem& sys, const CrackOperators& cr, const CrackSchur& old, const std::vector<int>& fresh,
                     double budget, CrackSchur& schur, BemSolution& sol) {
    schur.dof_nodes = old.dof_nodes;
    schur.dof_nodes.insert(schur.dof_nodes.end(), fresh.begin(), fresh.end());
    if (fresh.empty()) {
        // No new unknown (the new triangles only touch front nodes): the old factor stands
        // (and Eigen's triangular solve must not see zero columns).
        schur.Z = old.Z;
        schur.L = old.L;
        sol.extended_schur = true;
        sol.schur_rows_added = 0;
        return;
    }
    const Eigen::Index ko = 3 * static_cast<Eigen::Index>(old.dof_nodes.size());
    const Eigen::Index kn = 3 * static_cast<Eigen::Index>(fresh.size());
    check_memory_budget(schur_extension_bytes(double(sys.size()), double(ko), double(kn)), budget,
                        "extending the crack Schur complement (eq. 4.3) to " + std::to_string(ko + kn) + " crack unknowns");
    const CrackCoupling cn = coupling(sys, cr, fresh);
    const Matrix Zn = solve_matrix(sys, cn.B);
    const auto io = dofs3(old.dof_nodes), in = dofs3(fresh);
    // C_n Z_o and the coupling of the old unknowns with Z_n are independent: one task each, and the
    // products and solves below in column chunks (column_chunks.hpp).
    Matrix Son, Sno;
    tbb::parallel_invoke([&] { Son = y_block(cr, io, in) - coupling_c_times(sys, cr, old.dof_nodes, Zn); },
                         [&] { Sno = y_minus_product(cr, in, io, cn.C, old.Z); });
    Son = 0.5 * (Son + Sno.transpose());
    Matrix Snn = y_minus_product(cr, in, in, cn.C, Zn);
    Snn = 0.5 * (Snn + Snn.transpose()).eval();
    Matrix LnoT(ko, kn);
    for_column_chunks(kn, [&](Eigen::Index c0, Eigen::Index w) {
        LnoT.middleCols(c0, w) = old.L.triangularView<Eigen::Lower>().solve(Son.middleCols(c0, w));
    });
    for_column_chunks(kn, [&](Eigen::Index c0, Eigen::Index w) {
        Snn.middleCols(c0, w).noalias() -= LnoT.transpose() * LnoT.middleCols(c0, w);
    });
    Eigen::LLT<Matrix> lnn(Snn);
    require(lnn.info() == Eigen::Success, "crack Schur complement (eq. 4.3) lost positive definiteness on extension");
    schur.Z.resize(sys.size(), ko + kn);
    schur.Z << old.Z, Zn;
    // [old L, 0; LnoT^T, L_nn], column by column on parallel tasks (plain copies).
    const Matrix Lnn = lnn.matrixL();  // the upper triangle zero
    schur.L.resize(ko + kn, ko + kn);
    for_column_chunks(ko + kn, [&](Eigen::Index c0, Eigen::Index w) {
        for (Eigen::Index j = c0; j < c0 + w; ++j) {
            if (j < ko) {
                schur.L.col(j).head(ko) = old.L.col(j);
                schur.L.col(j).tail(kn) = LnoT.row(j).transpose();
            } else {
                schur.L.col(j).head(ko).setZero();
                schur.L.col(j).tail(kn) = Lnn.col(j - ko);
            }
        }
    });
    sol.extended_schur = true;
    sol.schur_rows_added = static_cast<std::size_t>(kn);
}

void extend_schur(const SurfaceSystem& sys, const CrackOperators& cr, const CrackSchur& old,
                  const std::vector<char>& interior, double budget, CrackSchur& schur, BemSolution& sol) {
    std::vector<char> was_dof(cr.cracks.num_vertices(), 0);
    for (int v : old.dof_nodes) was_dof[v] = 1;
    std::vector<int> fresh;
    for (std::size_t v = 0; v < interior.size(); ++v)
        if (interior[v] && !was_dof[v]) fresh.push_back(static_cast<int>(v));
    extend_schur_by(sys, cr, old, fresh, budget, schur, sol);
}

// Square-root front elements: which crack nodes' basis functions are those of the previous solve's
// operators (every element at the node existed then, with the same nodes, place and kind, and none
// joined it). The blocks between two such nodes are bit for bit those of the step before (tip_elements:
// the same corrections added in the same order; the P1 blocks are append-only), so the part of the
// previous Schur factor on a leading run of them stands.
std::vector<char> unchanged_basis(const CrackOperators& cr, const TipBasis& basis, const CrackOperators& prev) {
    const std::size_t old_elements = prev.cracks.num_triangles();
    std::vector<char> same(cr.cracks.num_vertices(), 1);
    const TipBasis before = tip_basis(prev.cracks);
    for (std::size_t e = 0; e < cr.cracks.num_triangles(); ++e) {
        const bool kept = e < old_elements && prev.geometry[e].nodes == cr.geometry[e].nodes && prev.geometry[e].p == cr.geometry[e].p &&
                          same_tip_kind(before.kind[e], basis.kind[e]);
        if (!kept)
            for (int v : cr.cracks.triangles[e]) same[v] = 0;
    }
    for (std::size_t v = prev.cracks.num_vertices(); v < same.size(); ++v) same[v] = 0;
    return same;
}

// The unknowns' order for a new factor: the kept prefix of the old order, then the rest, the nodes
// least likely to change next first: settled nodes (every element at them plain; their basis never
// changes again), then by how many solves their basis has stood (a crack whose front stopped keeps its
// nodes), then by index (deterministic). Returns the length of the kept prefix.
std::size_t order_tip_unknowns(const CrackOperators& cr, const TipBasis& basis, const std::vector<int>& dof_nodes,
                               const CrackSchur* old, const std::vector<char>* same, CrackSchur& schur) {
    std::vector<char> settled(cr.cracks.num_vertices(), 1);
    for (std::size_t e = 0; e < cr.cracks.num_triangles(); ++e)
        if (basis.kind[e].type != TipElementKind::plain)
            for (int v : cr.cracks.triangles[e]) settled[v] = 0;
    for (std::size_t v = 0; v < cr.cracks.num_vertices(); ++v)
        if (basis.front[v]) settled[v] = 0;
    std::vector<int> stood(cr.cracks.num_vertices(), 1);  // solves the node's basis has stood, counting this one
    std::size_t kept = 0;
    if (old && same) {
        for (std::size_t k = 0; k < old->dof_nodes.size(); ++k) {
            const int v = old->dof_nodes[k];
            if (v < static_cast<int>(same->size()) && (*same)[v]) stood[v] = old->stood[k] + 1;
        }
        while (kept < old->dof_nodes.size() && stood[old->dof_nodes[kept]] > 1) ++kept;
    }
    std::vector<char> in_prefix(cr.cracks.num_vertices(), 0);
    schur.dof_nodes.assign(old ? old->dof_nodes.begin() : dof_nodes.begin(),
                           old ? old->dof_nodes.begin() + static_cast<std::ptrdiff_t>(kept) : dof_nodes.begin());
    for (int v : schur.dof_nodes) in_prefix[v] = 1;
    std::vector<int> rest;
    for (int v : dof_nodes)
        if (!in_prefix[v]) rest.push_back(v);
    const int forever = std::numeric_limits<int>::max();
    auto key = [&](int v) { return settled[v] ? forever : stood[v]; };
    std::sort(rest.begin(), rest.end(), [&](int a, int b) { return key(a) != key(b) ? key(a) > key(b) : a < b; });
    schur.dof_nodes.insert(schur.dof_nodes.end(), rest.begin(), rest.end());
    schur.stood.resize(schur.dof_nodes.size());
    for (std::size_t k = 0; k < schur.dof_nodes.size(); ++k) schur.stood[k] = stood[schur.dof_nodes[k]];
    return kept;
}

// Square-root front elements: the previous factor kept on its leading run of nodes whose basis did not
// change, the other unknowns appended in the same block Cholesky update as extend_schur. Returns false
// (nothing done) when nothing of the previous factor can be kept: another surface system, or its first
// node changed.
bool extend_tip_schur(const SurfaceSystem& sys, const CrackOperators& cr, const TipBasis& basis, const BemSolution* previous,
                      const std::vector<int>& dof_nodes, const SolveOptions& options, double budget, CrackSchur& schur,
                      BemSolution& sol) {
    const CrackSchur* old = previous ? previous->schur.get() : nullptr;
    if (!(options.extend_schur && cr.tip_elements && old && previous->system == sol.system && previous->cracks &&
          previous->cracks->tip_elements && old->crack_triangles <= cr.cracks.num_triangles()))
        return false;
    if (cr.tip_pairs_computed == 0 && old->crack_triangles == cr.cracks.num_triangles() && old->dof_nodes.size() == dof_nodes.size()) {
        // Nothing new was integrated and no element joined: the blocks are those of the step before
        // (the same corrections added in the same order), so is the factor.
        schur = *old;
        for (int& n : schur.stood) ++n;
        sol.extended_schur = true;
        sol.schur_rows_added = 0;
        return true;
    }
    const std::vector<char> same = unchanged_basis(cr, basis, *previous->cracks);
    CrackSchur ordered;
    const std::size_t kept = order_tip_unknowns(cr, basis, dof_nodes, old, &same, ordered);
    if (kept == 0) return false;  // nothing to keep: factor anew
    CrackSchur prefix;
    prefix.dof_nodes.assign(ordered.dof_nodes.begin(), ordered.dof_nodes.begin() + static_cast<std::ptrdiff_t>(kept));
    const Eigen::Index ks = 3 * static_cast<Eigen::Index>(kept);
    prefix.Z = old->Z.leftCols(ks);
    prefix.L = old->L.topLeftCorner(ks, ks);
    const std::vector<int> fresh(ordered.dof_nodes.begin() + static_cast<std::ptrdiff_t>(kept), ordered.dof_nodes.end());
    extend_schur_by(sys, cr, prefix, fresh, budget, schur, sol);
    schur.stood = ordered.stood;
    return true;
}

// The crack nodes that carry unknowns: the interior nodes, or with square-root front elements (`basis`
// given) every node of an element where rho is not identically 0.
std::vector<int> crack_dof_nodes(const CrackOperators& cr, const std::vector<char>& interior, const TipBasis* basis) {
    std::vector<int> dof_nodes;
    if (basis) {
        // Every node of an element where rho is not identically 0 (tip_basis: only a triangle whose three
        // edges are all front edges has rho = 0; corner triangles with a chord keep their basis).
        std::vector<char> carries(interior.size(), 0);
        for (std::size_t e = 0; e < cr.cracks.num_triangles(); ++e)
            if (basis->kind[e].type != TipElementKind::zero)
                for (int v : cr.cracks.triangles[e]) carries[v] = 1;
        for (std::size_t v = 0; v < interior.size(); ++v)
            if (carries[v]) dof_nodes.push_back(static_cast<int>(v));
    } else {
        for (std::size_t v = 0; v < interior.size(); ++v)
            if (interior[v]) dof_nodes.push_back(static_cast<int>(v));
    }
    if (dof_nodes.empty())
        throw std::invalid_argument("the crack mesh has no interior node, so it carries no opening unknown; every crack "
                                    "needs at least one node off its front");
    return dof_nodes;
}

// The Schur complement S = Y - C A^-1 B on the crack unknowns (eq. 4.3), factorised anew.
void factor_schur(const SurfaceSystem& sys, const CrackOperators& cr, const TipBasis* basis, const std::vector<int>& dof_nodes,
                  double budget, CrackSchur& schur, BemSolution& sol) {
    // Square-root front elements: the nodes least likely to change first, so that the next step can keep
    // the factor on them (order_tip_unknowns).
    if (basis) order_tip_unknowns(cr, *basis, dof_nodes, nullptr, nullptr, schur);
    else schur.dof_nodes = dof_nodes;
    check_memory_budget(schur_bytes(double(sys.size()), 3.0 * double(schur.dof_nodes.size())), budget,
                        "the crack Schur complement (eq. 4.3) on " + std::to_string(3 * schur.dof_nodes.size()) +
                            " crack unknowns");
    const CrackCoupling c = coupling(sys, cr, schur.dof_nodes);
    schur.Z = solve_matrix(sys, c.B);
    const auto ic = dofs3(schur.dof_nodes);
    Matrix S = y_minus_product(cr, ic, ic, c.C, schur.Z);
    S = 0.5 * (S + S.transpose()).eval();
    Eigen::LLT<Matrix> llt(S);
    require(llt.info() == Eigen::Success, "crack Schur complement (eq. 4.3) is not positive definite; check crack orientation");
    schur.L = llt.matrixL();
    sol.schur_rows_added = ic.size();
}

// Pressure on the crack faces as nodal loads, -p int psi_k n per node.
Vector crack_face_loads(const CrackOperators& cr, const CrackLoads& loads) {
    Vector load = Vector::Zero(3 * cr.cracks.num_vertices());
    for (std::size_t e = 0; e < cr.geometry.size(); ++e) {
        const int r = cr.cracks.region_of(e);
        const double p = r < static_cast<int>(loads.pressure.size()) ? loads.pressure[r] : 0.0;
        for (int k = 0; k < 3; ++k) {
            const double area = cr.tip_elements ? cr.basis_integral[e][k] : cr.geometry[e].area / 3;  // int psi_k
            load.segment<3>(3 * cr.geometry[e].nodes[k]) -= p * area * cr.geometry[e].normal;
        }
    }
    return load;
}

// Cracks: Schur complement on the crack unknowns (eq. 4.3), built or extended, then solved for the
// openings; `s` (the surface solution) is corrected by -Z w. Returns the opening per crack node.
std::vector<Vec3> solve_cracks(const SurfaceSystem& sys, const CrackOperators& cr, const CrackLoads& loads,
                               const KnownData& known, const BemSolution* previous, const SolveOptions& options,
                               Vector& s, BemSolution& sol) {
    const std::vector<char> interior = crack_interior_nodes(cr.cracks);
    auto schur = std::make_shared<CrackSchur>();
    schur->crack_triangles = cr.cracks.num_triangles();
    const double budget = solve_budget(*sys.ops, options);
    if (can_extend_schur(cr, previous, sol, interior, options)) {
        extend_schur(sys, cr, *previous->schur, interior, budget, *schur, sol);
    } else {
        // Square-root front elements: their basis once per solve, for the unknowns and their order.
        const std::optional<TipBasis> basis = cr.tip_elements ? std::optional<TipBasis>(tip_basis(cr.cracks)) : std::nullopt;
        const TipBasis* tb = basis ? &*basis : nullptr;
        const std::vector<int> dof_nodes = crack_dof_nodes(cr, interior, tb);
        if (!(tb && extend_tip_schur(sys, cr, *tb, previous, dof_nodes, options, budget, *schur, sol)))
            factor_schur(sys, cr, tb, dof_nodes, budget, *schur, sol);
    }
    // Right-hand side of the crack rows: face loads minus known surface data.
    const auto ic = dofs3(schur->dof_nodes);
    const Vector load = crack_face_loads(cr, loads);
    Vector gc = load(ic) - cr.W(Eigen::all, ic).transpose() * known.f - cr.X(Eigen::all, ic).transpose() * known.g;
    gc -= coupling_c_times(sys, cr, schur->dof_nodes, s);
    Vector w = schur->L.triangularView<Eigen::Lower>().solve(gc);
    schur->L.triangularView<Eigen::Lower>().transpose().solveInPlace(w);
    s -= schur->Z * w;
    std::vector<Vec3> cod(cr.cracks.num_vertices(), Vec3::Zero());
    for (std::size_t k = 0; k < schur->dof_nodes.size(); ++k) cod[schur->dof_nodes[k]] = -w.segment<3>(3 * k);
    if (cr.tip_elements) {
        // Front nodes carry square-root coefficients, not openings: the opening there is 0.
        sol.front_coefficient.assign(cod.size(), Vec3::Zero());
        for (std::size_t v = 0; v < cod.size(); ++v)
            if (!interior[v]) {
                sol.front_coefficient[v] = cod[v];
                cod[v] = Vec3::Zero();
            }
    }
    sol.schur = schur;
    return cod;
}

// Surface displacement and traction from the unknowns s: the given data where it was given.
void write_surface_solution(const SurfaceSystem& sys, const ResolvedConditions& bc, const Vector& s, std::size_t N,
                            BemSolution& sol) {
    sol.displacement.assign(N, Vec3::Zero());
    sol.traction = bc.traction;
    if (sys.pure_neumann) {
        for (std::size_t v = 0; v < N; ++v) sol.displacement[v] = s.segment<3>(3 * v);
    } else {
        for (std::size_t v = 0; v < N; ++v) sol.displacement[v] = bc.displacement[v];
        for (std::size_t k = 0; k < sys.d_elements.size(); ++k) sol.traction[sys.d_elements[k]] = s.segment<3>(3 * k);
        const std::size_t off = 3 * sys.d_elements.size();
        for (std::size_t k = 0; k < sys.n_nodes.size(); ++k) sol.displacement[sys.n_nodes[k]] = s.segment<3>(off + 3 * k);
    }
}

}  // namespace

Eigen::Index SurfaceSystem::size() const {
    return pure_neumann ? 3 * static_cast<Eigen::Index>(ops->mesh.num_vertices())
                        : 3 * static_cast<Eigen::Index>(d_elements.size() + n_nodes.size());
}

Vector SurfaceSystem::solve(const Vector& f) const { return solve_matrix(*this, f); }

std::vector<char> crack_interior_nodes(const SurfaceMesh& cracks) {
    std::vector<char> interior(cracks.num_vertices(), 0);
    std::map<std::pair<int, int>, int> edges;
    for (const Tri& t : cracks.triangles)
        for (int k = 0; k < 3; ++k) {
            const int a = t[k], b = t[(k + 1) % 3];
            ++edges[{std::min(a, b), std::max(a, b)}];
        }
    for (const Tri& t : cracks.triangles)
        for (int v : t) interior[v] = 1;
    for (const auto& e : edges) {
        if (e.second > 2)
            throw std::invalid_argument("crack mesh edge (" + std::to_string(e.first.first) + ", " +
                                        std::to_string(e.first.second) + ") has " + std::to_string(e.second) +
                                        " triangles; crack sheets must be manifold");
        if (e.second == 1) interior[e.first.first] = interior[e.first.second] = 0;
    }
    return interior;
}

void load_resultants(const SurfaceOperators& s, const std::vector<Vec3>& traction, Vec3& force, Vec3& torque) {
    double A = 0;
    Vec3 c = Vec3::Zero();
    for (const auto& g : s.geometry) {
        A += g.area;
        c += g.area * g.centroid;
    }
    c /= A;
    force.setZero();
    torque.setZero();
    for (std::size_t a = 0; a < s.geometry.size(); ++a) {
        force += s.geometry[a].area * traction[a];
        torque += s.geometry[a].area * (s.geometry[a].centroid - c).cross(traction[a]);
    }
}

std::shared_ptr<const BemSolution> solve_sgbem(const std::shared_ptr<const SurfaceOperators>& surface,
                                               const std::shared_ptr<const CrackOperators>& cracks,
                                               const ResolvedConditions& bc, const CrackLoads& loads,
                                               const BemSolution* previous, const SolveOptions& options,
                                               const std::shared_ptr<const EstimatedGrowth>& estimated,
                                               const std::shared_ptr<const SurfaceSystem>& surface_factor) {
    const SurfaceOperators& o = *surface;
    const std::size_t M = o.geometry.size(), N = o.mesh.num_vertices();
    check_conditions_mesh(bc, M, N);
    auto sol = std::make_shared<BemSolution>();
    sol->surface = surface;
    sol->cracks = cracks;
    // 1. Pure Neumann: balanced loads. 2. The surface factorisation, reused where possible.
    if (bc.pure_neumann()) check_balance(o, bc, options, *sol);
    choose_surface_system(surface, bc, previous, surface_factor, solve_budget(o, options), *sol);
    const SurfaceSystem& sys = *sol->system;
    // 3. Right-hand side, with estimated growth (ch. 5.2) if any, and the surface solve.
    const KnownData known = known_data(bc, M, N);
    Vector rhs = surface_rhs(o, sys, known);
    if (estimated) {
        add_estimated_growth(o, sys, *estimated, rhs);
        sol->estimated = estimated;
    }
    Vector s = sys.solve(rhs);
    // 4. Crack openings by the Schur complement (eq. 4.3), correcting s. 5. Surface fields.
    std::vector<Vec3> cod;
    if (cracks && cracks->cracks.num_triangles() > 0) cod = solve_cracks(sys, *cracks, loads, known, previous, options, s, *sol);
    sol->crack_opening = std::move(cod);
    write_surface_solution(sys, bc, s, N, *sol);
    return sol;
}

const SurfaceMesh* current_crack_mesh(const BemSolution& sol) {
    if (sol.estimated) return &sol.estimated->cracks;
    return sol.cracks ? &sol.cracks->cracks : nullptr;
}

std::vector<Vec3> current_crack_opening(const BemSolution& sol) {
    if (!sol.estimated) return sol.crack_opening;
    std::vector<Vec3> out = sol.estimated->opening;
    for (std::size_t v = 0; v < sol.crack_opening.size() && v < out.size(); ++v)
        if (v < sol.estimated->frozen_unknown.size() && sol.estimated->frozen_unknown[v]) out[v] = sol.crack_opening[v];
    return out;
}

}  // namespace cf::bem
