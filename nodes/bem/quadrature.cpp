#include "nodes/bem/quadrature.hpp"

#include <Eigen/Eigenvalues>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

namespace cf::bem {

void gauss_legendre_01(int n, std::vector<double>& points, std::vector<double>& weights) {
    if (n < 1 || n > 64) throw std::invalid_argument("gauss_legendre_01: n = " + std::to_string(n) + " outside [1, 64]");
    // Golub-Welsch: eigenvalues of the Jacobi matrix of the Legendre recurrence.
    Eigen::MatrixXd J = Eigen::MatrixXd::Zero(n, n);
    for (int k = 1; k < n; ++k) {
        const double b = k / std::sqrt(4.0 * k * k - 1.0);
        J(k, k - 1) = J(k - 1, k) = b;
    }
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(J);
    points.resize(n);
    weights.resize(n);
    for (int k = 0; k < n; ++k) {
        const double v0 = es.eigenvectors()(0, k);
        points[k] = 0.5 * (es.eigenvalues()(k) + 1.0);
        weights[k] = v0 * v0;  // 2 v0^2 on [-1,1], halved on [0,1]
    }
}

void graded_gauss_01(int n, std::vector<double>& points, std::vector<double>& weights) {
    gauss_legendre_01(n, points, weights);
    for (int k = 0; k < n; ++k) {
        const double w = points[k];
        points[k] = w * w * (3 - 2 * w);
        weights[k] *= 6 * w * (1 - w);
    }
}

TriangleRule collapsed_gauss_triangle_rule(int n, bool graded) {
    std::vector<double> g, w;
    if (graded) graded_gauss_01(n, g, w);
    else gauss_legendre_01(n, g, w);
    TriangleRule r;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            r.s.push_back(g[i]);
            r.t.push_back(g[j] * (1 - g[i]));
            r.w.push_back(w[i] * w[j] * (1 - g[i]));
        }
    return r;
}

TriangleRule symmetric_triangle_rule_3() {
    TriangleRule r;
    r.s = {1.0 / 6, 2.0 / 3, 1.0 / 6};
    r.t = {1.0 / 6, 1.0 / 6, 2.0 / 3};
    r.w = {1.0 / 6, 1.0 / 6, 1.0 / 6};
    return r;
}

TriangleRule symmetric_triangle_rule_6() {
    const double a = 0.445948490915965, wa = 0.223381589678011 / 2;
    const double b = 0.091576213509771, wb = 0.109951743655322 / 2;
    TriangleRule r;
    r.s = {a, 1 - 2 * a, a, b, 1 - 2 * b, b};
    r.t = {a, a, 1 - 2 * a, b, b, 1 - 2 * b};
    r.w = {wa, wa, wa, wb, wb, wb};
    return r;
}

PairRule sauter_schwab_rule(PairKind kind, int n, bool graded) {
    if (kind == PairKind::separated) throw std::invalid_argument("sauter_schwab_rule: separated pairs use regular rules");
    std::vector<double> g, gw;
    if (graded) graded_gauss_01(n, g, gw);
    else gauss_legendre_01(n, g, gw);
    PairRule r;
    // Points on S = {0 <= x2 <= x1 <= 1} mapped to (s,t) = (x1 - x2, x2) (unit Jacobian).
    auto add = [&](double x1, double x2, double y1, double y2, double w) {
        r.sx.push_back(x1 - x2);
        r.tx.push_back(x2);
        r.sy.push_back(y1 - y2);
        r.ty.push_back(y2);
        r.w.push_back(w);
    };
    for (int a = 0; a < n; ++a)
        for (int b = 0; b < n; ++b)
            for (int c = 0; c < n; ++c)
                for (int d = 0; d < n; ++d) {
                    const double X = g[a], E1 = g[b], E2 = g[c], E3 = g[d];
                    const double W = gw[a] * gw[b] * gw[c] * gw[d];
                    switch (kind) {
                    case PairKind::identical: {
                        const double j = W * X * X * X * E1 * E1 * E2;
                        add(X, X * (1 - E1 + E1 * E2), X * (1 - E1 * E2 * E3), X * (1 - E1), j);
                        add(X * (1 - E1 * E2 * E3), X * (1 - E1), X, X * (1 - E1 + E1 * E2), j);
                        add(X, X * (E1 - E1 * E2 + E1 * E2 * E3), X * (1 - E1 * E2), X * (E1 - E1 * E2), j);
                        add(X * (1 - E1 * E2), X * (E1 - E1 * E2), X, X * (E1 - E1 * E2 + E1 * E2 * E3), j);
                        add(X * (1 - E1 * E2 * E3), X * (E1 - E1 * E2 * E3), X, X * (E1 - E1 * E2), j);
                        add(X, X * (E1 - E1 * E2), X * (1 - E1 * E2 * E3), X * (E1 - E1 * E2 * E3), j);
                        break;
                    }
                    case PairKind::common_edge: {
                        const double j0 = W * X * X * X * E1 * E1, j = j0 * E2;
                        add(X, X * E1 * E3, X * (1 - E1 * E2), X * E1 * (1 - E2), j0);
                        add(X, X * E1, X * (1 - E1 * E2 * E3), X * E1 * E2 * (1 - E3), j);
                        add(X * (1 - E1 * E2), X * E1 * (1 - E2), X, X * E1 * E2 * E3, j);
                        add(X * (1 - E1 * E2 * E3), X * E1 * E2 * (1 - E3), X, X * E1, j);
                        add(X * (1 - E1 * E2 * E3), X * E1 * (1 - E2 * E3), X, X * E1 * E2, j);
                        break;
                    }
                    case PairKind::common_vertex: {
                        const double j = W * X * X * X * E2;
                        add(X, X * E1, X * E2, X * E2 * E3, j);
                        add(X * E2, X * E2 * E3, X, X * E1, j);
                        break;
                    }
                    case PairKind::separated: break;
                    }
                }
    return r;
}

int regular_zone(double rho, int boost) {
    int z;
    if (rho >= 16) z = 0;
    else if (rho >= 3) z = 1;
    else if (rho >= 2) z = 2;
    else if (rho >= 1.5) z = 3;
    else z = 4;
    z += boost;
    return z < num_regular_zones ? z : num_regular_zones - 1;
}

const TriangleRule& regular_zone_rule(int zone) {
    static const std::array<TriangleRule, num_regular_zones> rules = [] {
        std::array<TriangleRule, num_regular_zones> r;
        r[0] = symmetric_triangle_rule_3();
        r[1] = symmetric_triangle_rule_6();
        const int n[num_regular_zones] = {0, 0, 4, 5, 6, 7, 8, 10};
        for (int k = 2; k < num_regular_zones; ++k) r[k] = collapsed_gauss_triangle_rule(n[k]);
        return r;
    }();
    if (zone < 0 || zone >= num_regular_zones) throw std::out_of_range("regular_zone_rule: zone " + std::to_string(zone));
    return rules[zone];
}

}  // namespace cf::bem
