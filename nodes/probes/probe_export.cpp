#include "nodes/probes/probe_export.hpp"

#include "graph/atomic_write.hpp"
#include "nodes/export/number_text.hpp"
#include "nodes/export/vtp_writer.hpp"

#include <map>

namespace cf::probes {

void write_probe_csv(const std::filesystem::path& path, const std::vector<ProbeSample>& samples, const GridSlice* slice) {
    graph::write_atomically(path, [&](std::ostream& os) {
        os << (slice ? "i,j" : "point") << ",x,y,z,ux,uy,uz,sxx,syy,szz,syz,sxz,sxy,s1,s2,s3\n";
        for (const ProbeSample& s : samples) {
            if (slice) os << s.index % slice->nu << ',' << s.index / slice->nu;
            else os << s.index;
            const Eigen::Matrix3d& t = s.stress;
            for (double x : {s.x.x(), s.x.y(), s.x.z(), s.u.x(), s.u.y(), s.u.z(), t(0, 0), t(1, 1), t(2, 2), t(1, 2), t(0, 2),
                             t(0, 1), s.principal[0], s.principal[1], s.principal[2]}) {
                os << ',';
                write_real(os, x);
            }
            os << '\n';
        }
    });
}

void write_probe_slice_vtp(const std::filesystem::path& path, const std::vector<ProbeSample>& samples, const GridSlice& slice) {
    SurfaceMesh m;
    std::map<int, int> vertex_of;  // grid index -> vertex
    VtpArray u{"u", 3, {}}, diag{"stress_diagonal", 3, {}}, shear{"stress_shear", 3, {}}, s1{"sigma_1", 1, {}},
        s2{"sigma_2", 1, {}}, s3{"sigma_3", 1, {}};
    for (const ProbeSample& s : samples) {
        vertex_of[s.index] = static_cast<int>(m.vertices.size());
        m.vertices.push_back(s.x);
        const Eigen::Matrix3d& t = s.stress;
        for (int k = 0; k < 3; ++k) u.values.push_back(s.u[k]);
        for (double x : {t(0, 0), t(1, 1), t(2, 2)}) diag.values.push_back(x);
        for (double x : {t(1, 2), t(0, 2), t(0, 1)}) shear.values.push_back(x);
        s1.values.push_back(s.principal[0]);
        s2.values.push_back(s.principal[1]);
        s3.values.push_back(s.principal[2]);
    }
    for (int j = 0; j + 1 < slice.nv; ++j)
        for (int i = 0; i + 1 < slice.nu; ++i) {
            const int g[4] = {i + slice.nu * j, i + 1 + slice.nu * j, i + 1 + slice.nu * (j + 1), i + slice.nu * (j + 1)};
            int v[4];
            bool all = true;
            for (int k = 0; k < 4; ++k) {
                const auto it = vertex_of.find(g[k]);
                all = all && it != vertex_of.end();
                if (all) v[k] = it->second;
            }
            if (!all) continue;
            m.triangles.push_back({v[0], v[1], v[2]});
            m.triangles.push_back({v[0], v[2], v[3]});
        }
    VtpFields f;
    f.point_data = {u, diag, shear, s1, s2, s3};
    graph::write_atomically(path, [&](std::ostream& os) { write_vtp(os, m, f); });
}

}  // namespace cf::probes
