// OpenVDB translation unit: crack grids, strip recording and the marker tests of fig. 27.
#include "nodes/levelset/crack_grids.hpp"

#include "nodes/levelset/level_set_grid.hpp"

#include <openvdb/tools/Interpolation.h>
#include <openvdb/tools/MeshToVolume.h>

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace cf {

const char* to_string(MarkerHit h) {
    switch (h) {
        case MarkerHit::none: return "none";
        case MarkerHit::left_object: return "left_object";
        case MarkerHit::crossed_crack: return "crossed_crack";
        case MarkerHit::self_intersection: return "self_intersection";
    }
    return "?";
}

namespace {

// Squared distance from p to triangle abc (closest-point regions, Ericson, RTCD 5.1.5).
double distance2_point_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 ab = b - a, ac = c - a, ap = p - a;
    const double d1 = ab.dot(ap), d2 = ac.dot(ap);
    if (d1 <= 0 && d2 <= 0) return ap.squaredNorm();
    const Vec3 bp = p - b;
    const double d3 = ab.dot(bp), d4 = ac.dot(bp);
    if (d3 >= 0 && d4 <= d3) return bp.squaredNorm();
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) {
        const double v = d1 / (d1 - d3);
        return (ap - v * ab).squaredNorm();
    }
    const Vec3 cp = p - c;
    const double d5 = ab.dot(cp), d6 = ac.dot(cp);
    if (d6 >= 0 && d5 <= d6) return cp.squaredNorm();
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) {
        const double w = d2 / (d2 - d6);
        return (ap - w * ac).squaredNorm();
    }
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
        const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return (bp - w * (c - b)).squaredNorm();
    }
    const double denom = 1 / (va + vb + vc);
    const double v = vb * denom, w = vc * denom;
    return (ap - ab * v - ac * w).squaredNorm();
}

// Degenerate triangles (a deactivated marker next to another: p0 == p1) still contribute
// their edges, which distance2_point_triangle handles only if the area is not exactly zero.
double distance2_point_segment(const Vec3& p, const Vec3& a, const Vec3& b) {
    const Vec3 ab = b - a;
    const double l2 = ab.squaredNorm();
    double t = l2 > 0 ? std::clamp((p - a).dot(ab) / l2, 0.0, 1.0) : 0.0;
    return (p - a - t * ab).squaredNorm();
}

double distance2_robust(const Vec3& p, const Triangle3& t) {
    const Vec3 n = (t[1] - t[0]).cross(t[2] - t[0]);
    const double scale = std::max({(t[1] - t[0]).squaredNorm(), (t[2] - t[0]).squaredNorm(), (t[2] - t[1]).squaredNorm()});
    if (n.squaredNorm() <= 1e-24 * scale * scale || scale == 0)
        return std::min({distance2_point_segment(p, t[0], t[1]), distance2_point_segment(p, t[1], t[2]),
                         distance2_point_segment(p, t[2], t[0])});
    return distance2_point_triangle(p, t[0], t[1], t[2]);
}

using Accessor = openvdb::FloatGrid::Accessor;

// Rasterise one triangle into a crack grid: every voxel whose thickened distance
// d - sqrt(3) r_f/2 lies below the band limit gets min(old, new). Columns run along the axis
// closest to the triangle normal, limited to the slab |n.(x - a)| <= reach around the plane.
std::size_t rasterise_triangle(Accessor& acc, const Triangle3& t, double r_f, double half_width) {
    const double thick = crack_half_thickness(r_f);
    const double band = half_width * r_f;
    const double reach = band + thick;  // d < reach <=> value inside the band
    Vec3 lo = t[0].cwiseMin(t[1]).cwiseMin(t[2]).array() - reach;
    Vec3 hi = t[0].cwiseMax(t[1]).cwiseMax(t[2]).array() + reach;
    Vec3 n = (t[1] - t[0]).cross(t[2] - t[0]);
    const double nn = n.norm();
    int axis = 2;
    bool planar = nn > 1e-12 * (hi - lo).squaredNorm();
    if (planar) {
        n /= nn;
        n.cwiseAbs().maxCoeff(&axis);
    }
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    openvdb::Coord lo_i, hi_i;
    for (int a = 0; a < 3; ++a) {
        lo_i[a] = int(std::floor(lo[a] / r_f));
        hi_i[a] = int(std::ceil(hi[a] / r_f));
    }
    std::size_t written = 0;
    openvdb::Coord ijk;
    for (int i = lo_i[u]; i <= hi_i[u]; ++i) {
        for (int j = lo_i[v]; j <= hi_i[v]; ++j) {
            int k0 = lo_i[axis], k1 = hi_i[axis];
            if (planar && std::abs(n[axis]) > 1e-3) {
                // Points with |n.(x - a)| <= reach: an interval along `axis` in this column.
                Vec3 x;
                x[u] = i * r_f;
                x[v] = j * r_f;
                x[axis] = 0;
                const double c = n.dot(t[0] - x) / n[axis];  // axis coordinate on the plane
                const double half = reach / std::abs(n[axis]);
                k0 = std::max(k0, int(std::floor((c - half) / r_f)));
                k1 = std::min(k1, int(std::ceil((c + half) / r_f)));
            }
            for (int k = k0; k <= k1; ++k) {
                ijk[u] = i;
                ijk[v] = j;
                ijk[axis] = k;
                const Vec3 p(ijk[0] * r_f, ijk[1] * r_f, ijk[2] * r_f);
                const double d2 = distance2_robust(p, t);
                if (d2 >= reach * reach) continue;
                const float value = float(std::sqrt(d2) - thick);
                const float old = acc.getValue(ijk);
                if (value < old || !acc.isValueOn(ijk)) acc.setValue(ijk, std::min(value, old));
                ++written;
            }
        }
    }
    return written;
}

openvdb::FloatGrid::Ptr new_crack_grid(double r_f, double half_width) {
    ensure_openvdb_initialized();
    auto g = openvdb::FloatGrid::create(float(half_width * r_f));
    g->setTransform(openvdb::math::Transform::createLinearTransform(r_f));
    g->setGridClass(openvdb::GRID_LEVEL_SET);
    return g;
}

// Trilinear sampling with a private accessor (one per thread).
struct FieldSampler {
    explicit FieldSampler(const LevelSet& ls)
        : acc(grid_of(ls).getConstAccessor()), inv(1.0 / ls.voxel_size), h(ls.voxel_size) {}
    double value(const Vec3& p) const {
        return openvdb::tools::BoxSampler::sample(acc, openvdb::Vec3R(p.x() * inv, p.y() * inv, p.z() * inv));
    }
    Vec3 gradient(const Vec3& p) const {
        Vec3 g;
        for (int a = 0; a < 3; ++a) {
            Vec3 e = Vec3::Zero();
            e[a] = 0.5 * h;
            g[a] = (value(p + e) - value(p - e)) / h;
        }
        return g;
    }
    openvdb::FloatGrid::ConstAccessor acc;
    double inv, h;
};

}  // namespace

std::vector<Triangle3> strip_triangles(const FrontMotion& m) {
    if (m.p0.size() != m.p1.size())
        throw std::invalid_argument("front motion has " + std::to_string(m.p0.size()) + " start and " +
                                    std::to_string(m.p1.size()) + " end positions; they must match");
    std::vector<Triangle3> tris;
    const std::size_t n = m.p0.size();
    if (n == 1) {
        tris.push_back({m.p0[0], m.p1[0], m.p1[0]});  // a lone marker sweeps a segment
        return tris;
    }
    const std::size_t pairs = m.closed ? n : (n == 0 ? 0 : n - 1);
    for (std::size_t i = 0; i < pairs; ++i) {
        const std::size_t j = (i + 1) % n;
        tris.push_back({m.p0[i], m.p0[j], m.p1[j]});
        tris.push_back({m.p0[i], m.p1[j], m.p1[i]});
    }
    return tris;
}

MarkerTest test_marker(const LevelSet* object, const std::vector<LevelSet>& cracks, int own, const Vec3& p0,
                       const Vec3& p1) {
    MarkerTest r;
    const Vec3 d = p1 - p0;
    const double len = d.norm();
    // (a) left the object.
    if (object && sample(*object, p1) > 0) {
        r.hit = MarkerHit::left_object;
        return r;
    }
    if (cracks.empty()) return r;
    const double r_f = cracks.front().voxel_size;
    const int steps = std::max(1, int(std::ceil(len / (0.25 * r_f))));
    // (b) crossed another crack anywhere on (0, 1].
    for (std::size_t c = 0; c < cracks.size(); ++c) {
        if (int(c) == own || cracks[c].empty()) continue;
        FieldSampler f(cracks[c]);
        for (int s = 1; s <= steps; ++s) {
            const double alpha = double(s) / steps;
            if (f.value(p0 + alpha * d) < 0) {
                r.hit = MarkerHit::crossed_crack;
                r.other_crack = int(c);
                r.alpha = alpha;
                return r;
            }
        }
    }
    // (c) self-intersection, eq. (6.2): far enough from p0 along a 45-degree cone, close to the
    // crack, and moving towards it.
    if (own >= 0 && std::size_t(own) < cracks.size() && !cracks[own].empty() && len > 0) {
        FieldSampler f(cracks[own]);
        const double phi0 = f.value(p0);
        const double sin45 = std::sqrt(0.5);
        for (int s = 1; s <= steps; ++s) {
            const double alpha = double(s) / steps;
            const Vec3 x = p0 + alpha * d;
            const double cone = phi0 + alpha * len * sin45;
            if (cone <= 0) continue;
            if (f.value(x) >= crack_half_thickness(r_f)) continue;  // Phi_f(x) < sqrt(3) r_f / 2
            if (f.gradient(x).dot(d) < 0) {
                r.hit = MarkerHit::self_intersection;
                r.alpha = alpha;
                return r;
            }
        }
    }
    return r;
}

struct CrackRecorder::Impl {
    double r_f = 0, half_width = 3;
    std::vector<openvdb::FloatGrid::Ptr> grids;
};

CrackRecorder::CrackRecorder(double r_f, double half_width) : impl_(std::make_unique<Impl>()) {
    if (!(r_f > 0)) throw std::invalid_argument("crack voxel size r_f must be positive");
    impl_->r_f = r_f;
    impl_->half_width = half_width;
}
CrackRecorder::CrackRecorder(const CrackLevelSets& start) : CrackRecorder(start.voxel_size, start.half_width) {
    for (const LevelSet& ls : start.cracks) {
        if (std::abs(ls.voxel_size - start.voxel_size) > 1e-12 * start.voxel_size)
            throw std::invalid_argument("crack grids have different voxel sizes");
        impl_->grids.push_back(grid_of(ls).deepCopy());
    }
}
CrackRecorder::~CrackRecorder() = default;
CrackRecorder::CrackRecorder(CrackRecorder&&) noexcept = default;
CrackRecorder& CrackRecorder::operator=(CrackRecorder&&) noexcept = default;

int CrackRecorder::add_crack() {
    impl_->grids.push_back(new_crack_grid(impl_->r_f, impl_->half_width));
    impl_->grids.back()->setName("crack" + std::to_string(impl_->grids.size() - 1));
    return int(impl_->grids.size()) - 1;
}
std::size_t CrackRecorder::num_cracks() const { return impl_->grids.size(); }
double CrackRecorder::voxel_size() const { return impl_->r_f; }

std::size_t CrackRecorder::add_triangles(int crack, const std::vector<Triangle3>& tris) {
    if (crack < 0 || std::size_t(crack) >= impl_->grids.size())
        throw std::out_of_range("crack index " + std::to_string(crack) + " out of range");
    for (const Triangle3& t : tris)
        for (const Vec3& p : t)
            if (!p.allFinite()) throw std::invalid_argument("crack triangle with a non-finite coordinate");
    auto acc = impl_->grids[crack]->getAccessor();
    std::size_t n = 0;
    for (const Triangle3& t : tris) n += rasterise_triangle(acc, t, impl_->r_f, impl_->half_width);
    return n;
}

std::vector<std::vector<MarkerTest>> CrackRecorder::record_substep(const std::vector<FrontMotion>& motions,
                                                                   const LevelSet* object,
                                                                   std::size_t* voxels_written) {
    if (motions.size() != impl_->grids.size())
        throw std::invalid_argument("record_substep got " + std::to_string(motions.size()) + " front motions for " +
                                    std::to_string(impl_->grids.size()) + " cracks");
    for (const FrontMotion& m : motions)
        if (m.p0.size() != m.p1.size()) throw std::invalid_argument("front motion with mismatched p0/p1 sizes");
    // Phase 1 (read-only): test against the grids up to the previous sub-step.
    std::vector<LevelSet> views;
    for (auto& g : impl_->grids) views.push_back(wrap_grid(g, impl_->r_f, impl_->half_width));
    std::vector<std::vector<MarkerTest>> tests(motions.size());
    tbb::parallel_for(std::size_t(0), motions.size(), [&](std::size_t c) {
        const FrontMotion& m = motions[c];
        tests[c].resize(m.p0.size());
        for (std::size_t i = 0; i < m.p0.size(); ++i)
            if (m.p0[i] != m.p1[i]) tests[c][i] = test_marker(object, views, int(c), m.p0[i], m.p1[i]);
    });
    views.clear();
    // Phase 2: each crack writes only its own grid, so cracks run in parallel.
    std::vector<std::size_t> written(motions.size(), 0);
    tbb::parallel_for(std::size_t(0), motions.size(), [&](std::size_t c) {
        written[c] = add_triangles(int(c), strip_triangles(motions[c]));
    });
    if (voxels_written) {
        *voxels_written = 0;
        for (std::size_t w : written) *voxels_written += w;
    }
    return tests;
}

CrackLevelSets CrackRecorder::snapshot() const {
    CrackLevelSets s;
    s.voxel_size = impl_->r_f;
    s.half_width = impl_->half_width;
    for (const auto& g : impl_->grids) s.cracks.push_back(wrap_grid(g->deepCopy(), impl_->r_f, impl_->half_width));
    return s;
}

CrackLevelSets CrackRecorder::release() {
    CrackLevelSets s;
    s.voxel_size = impl_->r_f;
    s.half_width = impl_->half_width;
    for (auto& g : impl_->grids) s.cracks.push_back(wrap_grid(std::move(g), impl_->r_f, impl_->half_width));
    impl_->grids.clear();
    return s;
}

LevelSet planar_disk_crack(const Vec3& center, const Vec3& normal, double radius, double r_f, double half_width) {
    if (!(radius > 0) || !std::isfinite(radius))
        throw std::invalid_argument("planar crack radius must be positive, got " + std::to_string(radius));
    if (!(normal.norm() > 0) || !normal.allFinite())
        throw std::invalid_argument("planar crack normal must be a non-zero vector");
    if (!center.allFinite()) throw std::invalid_argument("planar crack centre must be finite");
    const Vec3 n = normal.normalized();
    Vec3 e1 = (std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY()).cross(n).normalized();
    const Vec3 e2 = n.cross(e1);
    // Chord sag R (1 - cos(pi/N)) <= r_f/10; rings about 16 voxels apart keep triangles compact.
    const double sag = std::min(0.1 * r_f / radius, 1.0);
    const int sectors = std::clamp(int(std::ceil(M_PI / std::acos(1 - sag))), 8, 4096);
    const int rings = std::clamp(int(std::ceil(radius / (16 * r_f))), 1, 4096);
    std::vector<Triangle3> tris;
    auto point = [&](int ring, int sector) {
        const double r = radius * ring / rings, a = 2 * M_PI * sector / sectors;
        return Vec3(center + r * (std::cos(a) * e1 + std::sin(a) * e2));
    };
    for (int ring = 0; ring < rings; ++ring)
        for (int s = 0; s < sectors; ++s) {
            const int s1 = (s + 1) % sectors;
            if (ring == 0) {
                tris.push_back({center, point(1, s), point(1, s1)});
            } else {
                tris.push_back({point(ring, s), point(ring + 1, s), point(ring + 1, s1)});
                tris.push_back({point(ring, s), point(ring + 1, s1), point(ring, s1)});
            }
        }
    CrackRecorder rec(r_f, half_width);
    rec.add_crack();
    rec.add_triangles(0, tris);
    return rec.release().cracks.front();
}

LevelSet reference_strip_level_set(const std::vector<Triangle3>& tris, double r_f, double half_width) {
    ensure_openvdb_initialized();
    std::vector<openvdb::Vec3s> points;
    std::vector<openvdb::Vec3I> faces;
    for (const Triangle3& t : tris) {
        const unsigned base = unsigned(points.size());
        for (const Vec3& p : t) points.emplace_back(float(p.x()), float(p.y()), float(p.z()));
        faces.emplace_back(base, base + 1, base + 2);
    }
    const double thick = crack_half_thickness(r_f);
    auto xform = openvdb::math::Transform::createLinearTransform(r_f);
    // Band: distances up to half_width r_f + thickness, so d - thick covers the same band.
    auto g = openvdb::tools::meshToUnsignedDistanceField<openvdb::FloatGrid>(*xform, points, faces, {},
                                                                              float(half_width + thick / r_f));
    const float t = float(thick);
    for (auto it = g->beginValueOn(); it; ++it) it.setValue(*it - t);
    return wrap_grid(g, r_f, half_width);
}

}  // namespace cf
