#include "nodes/propagate/sif_export.hpp"

#include "graph/atomic_write.hpp"
#include "nodes/export/number_text.hpp"
#include "nodes/export/vtp_writer.hpp"
#include "nodes/propagate/crack_front.hpp"

#include <map>
#include <stdexcept>

namespace cf::propagate {

std::vector<FrontSifRow> front_sif_rows(const SurfaceMesh& cracks, const std::vector<bem::FrontEdgeSif>& sifs, double nu,
                                        const ScalarField* toughness) {
    std::map<std::pair<int, int>, const bem::FrontEdgeSif*> by_edge;
    for (const auto& s : sifs) {
        if (s.v0 < 0 || s.v1 < 0 || std::size_t(std::max(s.v0, s.v1)) >= cracks.num_vertices())
            throw std::invalid_argument("SIF record for edge " + std::to_string(s.v0) + " -> " + std::to_string(s.v1) +
                                        " names a vertex the crack mesh does not have (SIFs and cracks from different steps)");
        by_edge[{std::min(s.v0, s.v1), std::max(s.v0, s.v1)}] = &s;
    }
    std::vector<FrontSifRow> rows;
    if (cracks.num_triangles() == 0) return rows;
    const auto fronts = extract_fronts(cracks);
    for (std::size_t f = 0; f < fronts.size(); ++f) {
        const auto& nodes = fronts[f].nodes;
        for (std::size_t i = 0; i < fronts[f].num_edges(); ++i) {
            const int a = nodes[i], b = nodes[(i + 1) % nodes.size()];
            const auto it = by_edge.find({std::min(a, b), std::max(a, b)});
            if (it == by_edge.end()) continue;
            const bem::FrontEdgeSif& s = *it->second;
            FrontSifRow r;
            r.front = static_cast<int>(f);
            r.edge = static_cast<int>(i);
            r.front_edges = static_cast<int>(fronts[f].num_edges());
            r.region = fronts[f].region;
            r.v0 = s.v0;
            r.v1 = s.v1;
            r.midpoint = 0.5 * (cracks.vertices[s.v0] + cracks.vertices[s.v1]);
            r.e1 = s.e1;
            r.e2 = s.e2;
            r.e3 = s.e3;
            r.KI = s.KI;
            r.KII = s.KII;
            r.KIII = s.KIII;
            r.K_eff = effective_sif({s.KI, s.KII, s.KIII}, nu);  // eq. (4.7)
            if (toughness && toughness->source) r.K_c = toughness->value(r.midpoint);
            rows.push_back(r);
        }
    }
    return rows;
}

std::vector<FrontSifRow> front_node_sif_rows(const SurfaceMesh& cracks, const std::vector<bem::FrontEdgeSif>& sifs, double nu,
                                             const ScalarField* toughness) {
    const std::vector<FrontSifRow> edges = front_sif_rows(cracks, sifs, nu, toughness);
    std::map<std::pair<int, int>, const FrontSifRow*> by_index;  // (front, edge) -> row
    for (const FrontSifRow& r : edges) by_index[{r.front, r.edge}] = &r;
    std::vector<FrontSifRow> rows;
    if (cracks.num_triangles() == 0) return rows;
    const auto fronts = extract_fronts(cracks);
    for (std::size_t f = 0; f < fronts.size(); ++f) {
        const CrackFront& front = fronts[f];
        const int n = static_cast<int>(front.nodes.size()), ne = static_cast<int>(front.num_edges());
        for (int i = 0; i < n; ++i) {
            std::vector<const FrontSifRow*> adj;  // the edges ending and starting at node i
            for (int e : {i - 1, i}) {
                if (!front.closed && (e < 0 || e >= ne)) continue;
                const auto it = by_index.find({static_cast<int>(f), (e + ne) % ne});
                if (it != by_index.end()) adj.push_back(it->second);
            }
            if (adj.empty()) continue;
            FrontSifRow r;
            r.front = static_cast<int>(f);
            r.edge = i;
            r.front_edges = n;
            r.region = front.region;
            r.v0 = front.nodes[i];
            r.midpoint = cracks.vertices[r.v0];
            Vec3 e1 = Vec3::Zero(), e2 = Vec3::Zero();
            for (const FrontSifRow* a : adj) {
                const double w = 1.0 / adj.size();
                r.KI += w * a->KI;
                r.KII += w * a->KII;
                r.KIII += w * a->KIII;
                e1 += w * a->e1;
                e2 += w * a->e2;
            }
            // Orthonormalise as ch. 4.5.2 does: keep the normal, make the forward direction orthogonal to it.
            r.e2 = e2.normalized();
            r.e1 = (e1 - e1.dot(r.e2) * r.e2).normalized();
            r.e3 = r.e1.cross(r.e2);
            r.K_eff = effective_sif({r.KI, r.KII, r.KIII}, nu);  // eq. (4.7)
            if (toughness && toughness->source) r.K_c = toughness->value(r.midpoint);
            rows.push_back(r);
        }
    }
    return rows;
}

void write_front_sifs_csv(const std::filesystem::path& path, const std::vector<FrontSifRow>& rows, bool nodes) {
    graph::write_atomically(path, [&](std::ostream& os) {
        os << (nodes ? "front,node,crack,vertex" : "front,edge,crack,v0,v1")
           << ",x,y,z,e1x,e1y,e1z,e2x,e2y,e2z,e3x,e3y,e3z,KI,KII,KIII,K_eff,K_c\n";
        for (const FrontSifRow& r : rows) {
            os << r.front << ',' << r.edge << ',' << r.region << ',' << r.v0;
            if (!nodes) os << ',' << r.v1;
            for (const Vec3* v : {&r.midpoint, &r.e1, &r.e2, &r.e3})
                for (int k = 0; k < 3; ++k) {
                    os << ',';
                    write_real(os, (*v)[k]);
                }
            for (double x : {r.KI, r.KII, r.KIII, r.K_eff, r.K_c}) {
                os << ',';
                write_real(os, x);
            }
            os << '\n';
        }
    });
}

void write_front_sifs_vtp(const std::filesystem::path& path, const std::vector<FrontSifRow>& rows) {
    std::vector<Vec3> points;
    std::vector<std::vector<int>> lines;
    std::vector<std::size_t> line_start;  // first row of each line
    VtpArray KI{"K_I", 1, {}}, KII{"K_II", 1, {}}, KIII{"K_III", 1, {}}, Keff{"K_eff", 1, {}}, Kc{"K_c", 1, {}},
        normal{"normal", 3, {}}, forward{"forward", 3, {}}, crack{"crack", 1, {}};
    for (std::size_t k = 0; k < rows.size(); ++k) {
        const FrontSifRow& r = rows[k];
        const bool continues = k > 0 && rows[k - 1].front == r.front && rows[k - 1].edge + 1 == r.edge;
        if (!continues) {
            lines.emplace_back();
            line_start.push_back(k);
        }
        lines.back().push_back(static_cast<int>(points.size()));
        points.push_back(r.midpoint);
        KI.values.push_back(r.KI);
        KII.values.push_back(r.KII);
        KIII.values.push_back(r.KIII);
        Keff.values.push_back(r.K_eff);
        Kc.values.push_back(r.K_c);
        crack.values.push_back(r.region);
        for (int c = 0; c < 3; ++c) {
            normal.values.push_back(r.e2[c]);
            forward.values.push_back(r.e1[c]);
        }
    }
    // A whole front closes its loop; a single-point run cannot be a polyline: repeat its point.
    for (std::size_t l = 0; l < lines.size(); ++l) {
        const FrontSifRow& first = rows[line_start[l]];
        if (static_cast<int>(lines[l].size()) == first.front_edges && first.edge == 0 && lines[l].size() > 2)
            lines[l].push_back(lines[l].front());
        if (lines[l].size() == 1) lines[l].push_back(lines[l].front());
    }
    graph::write_atomically(path, [&](std::ostream& os) {
        write_vtp_lines(os, points, lines, {KI, KII, KIII, Keff, Kc, normal, forward, crack});
    });
}

}  // namespace cf::propagate
