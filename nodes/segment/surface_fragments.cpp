// CGAL translation unit: the input surface intersected with a fragment's cell
// (surface_fragments.hpp). Corefinement (CGAL::Polygon_mesh_processing) splits the faces of both
// meshes along their intersection and keeps the parts of each inside the other; a visitor records
// for every face which input triangle it came from (-1: a cell face), so attributes can be copied.
#include "nodes/segment/surface_fragments.hpp"

#include "nodes/domain/mesh_topology.hpp"
#include "nodes/simplify/cgal_surface_mesh.hpp"

#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Polygon_mesh_processing/repair_degeneracies.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>
#include <CGAL/boost/graph/Euler_operations.h>
#include <CGAL/boost/graph/helpers.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <tuple>

namespace cf {

namespace PMP = CGAL::Polygon_mesh_processing;
using cgal_mesh::Mesh;
using Face = Mesh::Face_index;
using OriginMap = Mesh::Property_map<Face, int>;

Vec2 InsideUvProjection::operator()(const Vec3& p, const Vec3& n) const {
    const Vec3 q = (p - origin) / scale;
    const Vec3 a = n.cwiseAbs();
    if (a.x() >= a.y() && a.x() >= a.z()) return Vec2(q.y(), q.z());
    if (a.y() >= a.z()) return Vec2(q.x(), q.z());
    return Vec2(q.x(), q.y());
}

namespace {

constexpr const char* kOrigin = "f:cf_origin";
constexpr int kMendRounds = 3;  // rounds of mending folded fracture faces, as the cell repair's

// Carries the origin of every face through the corefinement: a split face's pieces keep its
// origin, a face copied into the output brings it along. Copies share the maps and the current value.
struct OriginVisitor : PMP::Corefinement::Default_visitor<Mesh> {
    const Mesh* input = nullptr;
    const Mesh* cell = nullptr;
    OriginMap in_map, cell_map, out_map;
    std::shared_ptr<int> current = std::make_shared<int>(-1);

    OriginMap& map_of(const Mesh& m) { return &m == input ? in_map : &m == cell ? cell_map : out_map; }
    void before_subface_creations(Face f, Mesh& m) { *current = map_of(m)[f]; }
    void after_subface_created(Face f, Mesh& m) { map_of(m)[f] = *current; }
    void after_face_copy(Face src, const Mesh& ms, Face dst, Mesh& md) { map_of(md)[dst] = map_of(ms)[src]; }
};

// Barycentric weights of p on triangle (a, b, c) (p projected onto its plane).
Vec3 barycentric(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 e0 = b - a, e1 = c - a, d = p - a;
    const double d00 = e0.dot(e0), d01 = e0.dot(e1), d11 = e1.dot(e1), d20 = d.dot(e0), d21 = d.dot(e1);
    const double den = d00 * d11 - d01 * d01;
    if (!(std::abs(den) > 0)) return Vec3(1.0 / 3, 1.0 / 3, 1.0 / 3);
    const double v = (d11 * d20 - d01 * d21) / den, w = (d00 * d21 - d01 * d20) / den;
    return Vec3(1 - v - w, v, w);
}

// Why `m` cannot enter the corefinement, or "".
std::string corefinement_problem(const Mesh& m) {
    if (!CGAL::is_closed(m)) return "is not closed";
    if (!CGAL::is_triangle_mesh(m)) return "is not a triangle mesh";
    if (PMP::does_self_intersect(m)) return "intersects itself";
    return "";
}

// CGAL's corefinement lists its output in an order that changes from run to run (ties between the
// two meshes' boxes are broken by heap addresses), although the mesh is the same. Rebuilt with its
// vertices sorted by position and its faces by their vertices (each face from its smallest vertex,
// orientation kept), the result, its mending and the files written are the same in every run.
// Returns false when a face cannot be added (the result was not a manifold triangle mesh).
bool canonical_order(const Mesh& m, const OriginMap& origin, Mesh& out) {
    using Vertex = Mesh::Vertex_index;
    std::vector<Vertex> vs(m.vertices().begin(), m.vertices().end());
    std::stable_sort(vs.begin(), vs.end(), [&](Vertex a, Vertex b) {
        const auto &p = m.point(a), &q = m.point(b);
        return std::make_tuple(p.x(), p.y(), p.z()) < std::make_tuple(q.x(), q.y(), q.z());
    });
    std::vector<int> rank(m.number_of_vertices() + m.number_of_removed_vertices(), -1);
    for (std::size_t k = 0; k < vs.size(); ++k) rank[vs[k].idx()] = int(k);
    struct Entry {
        std::array<int, 3> v;
        int origin;
    };
    std::vector<Entry> faces;
    faces.reserve(m.number_of_faces());
    for (Face f : m.faces()) {
        Entry e{{-1, -1, -1}, origin[f]};
        int k = 0;
        for (Vertex v : CGAL::vertices_around_face(m.halfedge(f), m))
            if (k < 3) e.v[std::size_t(k++)] = rank[v.idx()];
        std::rotate(e.v.begin(), std::min_element(e.v.begin(), e.v.end()), e.v.end());
        faces.push_back(e);
    }
    std::stable_sort(faces.begin(), faces.end(), [](const Entry& a, const Entry& b) { return a.v < b.v; });
    out.clear();
    out.reserve(Mesh::size_type(vs.size()), Mesh::size_type(3 * faces.size() / 2), Mesh::size_type(faces.size()));
    std::vector<Vertex> added;
    added.reserve(vs.size());
    for (Vertex v : vs) added.push_back(out.add_vertex(m.point(v)));
    OriginMap out_origin = out.add_property_map<Face, int>(kOrigin, -1).first;
    for (const Entry& e : faces) {
        const Face f = out.add_face(added[std::size_t(e.v[0])], added[std::size_t(e.v[1])], added[std::size_t(e.v[2])]);
        if (f == Mesh::null_face()) return false;
        out_origin[f] = e.origin;
    }
    return true;
}

// Dual contouring at an adaptivity > 0 occasionally folds a few triangles of a cell where cells of
// different sizes are merged on the bisector of a crack gap, deep inside the object: a few
// fracture faces of the result then cross each other. They are cut out with every fracture face
// around their vertices and each hole is triangulated (new fracture faces; a hole may end on the
// input's faces, which stay); what still crosses, and any hole that could not be filled, is cut out
// again with one more vertex ring, at most `rounds` times. Returns false, leaving `out` half
// mended, when the rounds run out or only an input face could unpinch a hole: the caller then
// repairs the cell and clips again. Linear in the result's size per round; no search of the
// whole cell. `crossing`: the fracture faces' crossing pairs as they are (the caller's test found
// them; round 0 does not search again).
bool mend_folded_fracture_faces(Mesh& out, OriginMap origin, int rounds, std::vector<std::pair<Face, Face>> crossing) {
    using Vertex = Mesh::Vertex_index;
    using Halfedge = Mesh::Halfedge_index;
    for (int round = 0; round <= rounds; ++round) {
        std::vector<std::pair<Face, Face>> pairs;
        if (round == 0) {
            pairs = std::move(crossing);
        } else {
            std::vector<Face> fracture;
            for (Face f : out.faces())
                if (origin[f] < 0) fracture.push_back(f);
            PMP::self_intersections(fracture, out, std::back_inserter(pairs));
        }
        std::vector<char> marked(out.number_of_vertices() + out.number_of_removed_vertices(), 0);
        bool any = !pairs.empty();
        for (const auto& [a, b] : pairs)
            for (Face f : {a, b})
                for (Vertex v : CGAL::vertices_around_face(out.halfedge(f), out)) marked[v.idx()] = 1;
        for (Halfedge h : out.halfedges())
            if (out.is_border(h)) {  // a hole left open
                marked[out.target(h).idx()] = 1;
                any = true;
            }
        if (!any) return true;
        if (round == rounds) return false;
        for (int r = 0; r < round; ++r) {
            std::vector<char> next = marked;
            for (Vertex v : out.vertices())
                if (marked[v.idx()])
                    for (Vertex w : CGAL::vertices_around_target(out.halfedge(v), out)) next[w.idx()] = 1;
            marked.swap(next);
        }
        std::vector<char> cut(out.number_of_faces() + out.number_of_removed_faces(), 0);
        std::vector<Vertex> rim;  // vertices of cut faces
        auto cut_face = [&](Face f) {
            if (cut[f.idx()]) return true;
            if (origin[f] >= 0) return false;  // the fold reaches the input's faces
            cut[f.idx()] = 1;
            for (Vertex v : CGAL::vertices_around_face(out.halfedge(f), out)) rim.push_back(v);
            return true;
        };
        for (Face f : out.faces()) {
            if (origin[f] >= 0) continue;  // the input's faces stay: a hole may end on them
            for (Vertex v : CGAL::vertices_around_face(out.halfedge(f), out))
                if (marked[v.idx()]) {
                    cut_face(f);
                    break;
                }
        }
        // A vertex whose remaining faces would form two fans or more pinches the hole into loops
        // that share it, which cannot be triangulated: its faces go too.
        for (std::size_t k = 0; k < rim.size(); ++k) {
            const Vertex v = rim[k];
            int runs = 0;
            bool previous = false, first = false, begun = false;
            for (Halfedge h : CGAL::halfedges_around_target(out.halfedge(v), out)) {
                const Face f = out.face(h);
                const bool kept = f != Mesh::null_face() && !cut[f.idx()];
                if (!begun) first = kept, begun = true;
                else if (kept && !previous) ++runs;
                previous = kept;
            }
            if (first && !previous) ++runs;  // the cyclic sequence's wrap-around
            if (runs < 2) continue;
            for (Halfedge h : CGAL::halfedges_around_target(out.halfedge(v), out))
                if (out.face(h) != Mesh::null_face() && !cut_face(out.face(h))) return false;
        }
        for (Face f : out.faces())
            if (cut[f.idx()]) CGAL::Euler::remove_face(out.halfedge(f), out);
        std::vector<char> done(out.number_of_halfedges() + out.number_of_removed_halfedges(), 0);
        for (Halfedge h : out.halfedges()) {
            if (!out.is_border(h) || done[h.idx()]) continue;
            for (Halfedge g : CGAL::halfedges_around_face(h, out)) done[g.idx()] = 1;
            std::vector<Face> patch;
            PMP::triangulate_hole(out, h, std::back_inserter(patch));
            for (Face f : patch) origin[f] = -1;  // a recycled face slot keeps its old value
        }
    }
    return false;
}

}  // namespace

struct SurfaceClipper::Impl {
    SurfaceMesh input;
    Mesh mesh;  // with the origin map: input triangle index per face
    InsideUvProjection projection;
    int inside = 0;

    // The clipped CGAL mesh as a SurfaceMesh with regions and corner attributes.
    SurfaceMesh convert(const Mesh& out, const OriginMap& origin) const {
        SurfaceMesh m = cgal_mesh::from_cgal(out);
        m.region_names.resize(std::size_t(inside));
        for (int r = 0; r < inside; ++r) m.region_names[std::size_t(r)] = input.region_name(r);
        m.region_names.push_back(kInsideRegion);
        m.region.resize(m.triangles.size());
        m.corner_uv.resize(m.triangles.size());
        m.corner_normal.resize(m.triangles.size());
        std::size_t t = 0;
        for (Face f : out.faces()) {
            const int o = origin[f];
            const Tri& tri = m.triangles[t];
            if (o < 0) {
                const Vec3 n = triangle_normal(m, t);
                m.region[t] = inside;
                for (int k = 0; k < 3; ++k) {
                    m.corner_uv[t][k] = projection(m.vertices[std::size_t(tri[k])], n);
                    m.corner_normal[t][k] = n;
                }
            } else {
                const Tri& src = input.triangles[std::size_t(o)];
                const Vec3 &a = input.vertices[std::size_t(src[0])], &b = input.vertices[std::size_t(src[1])],
                           &c = input.vertices[std::size_t(src[2])];
                const Vec3 n = triangle_normal(input, std::size_t(o));
                m.region[t] = input.region_of(std::size_t(o));
                for (int k = 0; k < 3; ++k) {
                    const Vec3& p = m.vertices[std::size_t(tri[k])];
                    const Vec3 w = barycentric(p, a, b, c);
                    if (input.has_uv()) {
                        const auto& uv = input.corner_uv[std::size_t(o)];
                        m.corner_uv[t][k] = w[0] * uv[0] + w[1] * uv[1] + w[2] * uv[2];
                    } else {
                        m.corner_uv[t][k] = projection(p, n);
                    }
                    if (input.has_normals()) {
                        const auto& nn = input.corner_normal[std::size_t(o)];
                        const Vec3 s = w[0] * nn[0] + w[1] * nn[1] + w[2] * nn[2];
                        m.corner_normal[t][k] = s.norm() > 0 ? Vec3(s.normalized()) : n;
                    } else {
                        m.corner_normal[t][k] = n;
                    }
                }
            }
            ++t;
        }
        return grouped_by_region(std::move(m));
    }

    // Faces ordered by region (stable), so each material is one block in an OBJ and a glTF
    // primitive reads contiguous faces.
    static SurfaceMesh grouped_by_region(SurfaceMesh m) {
        std::vector<std::size_t> order(m.triangles.size());
        for (std::size_t t = 0; t < order.size(); ++t) order[t] = t;
        std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return m.region[a] < m.region[b]; });
        SurfaceMesh out = m;
        for (std::size_t k = 0; k < order.size(); ++k) {
            out.triangles[k] = m.triangles[order[k]];
            out.region[k] = m.region[order[k]];
            out.corner_uv[k] = m.corner_uv[order[k]];
            out.corner_normal[k] = m.corner_normal[order[k]];
        }
        return out;
    }
};

SurfaceClipper::SurfaceClipper(const SurfaceMesh& input) : impl_(std::make_unique<Impl>()) {
    const std::string fix = "; repair the input mesh (simplify.remesh, or a modelling tool) or set mesher: levelset";
    if (input.triangles.empty()) throw std::invalid_argument("the input surface has no triangles" + fix);
    impl_->input = input;
    impl_->mesh = cgal_mesh::to_cgal(input, "the surface mesher");
    if (const std::string p = corefinement_problem(impl_->mesh); !p.empty())
        throw std::invalid_argument("the input surface " + p + fix);
    OriginMap origin = impl_->mesh.add_property_map<Face, int>(kOrigin, -1).first;
    int t = 0;
    for (Face f : impl_->mesh.faces()) origin[f] = t++;  // faces in triangle order (to_cgal adds them so)
    const Box3 box = bounding_box(input);
    impl_->projection.origin = box.min;
    impl_->projection.scale = std::max(box.extent().maxCoeff(), 1e-300);
    impl_->inside = input.num_regions();
}

SurfaceClipper::~SurfaceClipper() = default;

const SurfaceMesh& SurfaceClipper::input() const { return impl_->input; }
const InsideUvProjection& SurfaceClipper::projection() const { return impl_->projection; }
int SurfaceClipper::inside_region() const { return impl_->inside; }

bool SurfaceClipper::clip(const SurfaceMesh& cell_in, SurfaceMesh& result, std::string* problem, bool* folded) const {
    if (folded) *folded = false;
    auto fail = [&](const std::string& why) {
        if (problem) *problem = why;
        return false;
    };
    // Built face by face (Surface_mesh refuses a face that would make it non-manifold): the
    // polygon-soup route of cgal_mesh::to_cgal checks the soup first and cost as much as the
    // corefinement.
    Mesh cell;
    cell.reserve(Mesh::size_type(cell_in.vertices.size()), Mesh::size_type(3 * cell_in.triangles.size() / 2),
                 Mesh::size_type(cell_in.triangles.size()));
    std::vector<Mesh::Vertex_index> vertex;
    vertex.reserve(cell_in.vertices.size());
    for (const Vec3& p : cell_in.vertices) vertex.push_back(cell.add_vertex(cgal_mesh::Kernel::Point_3(p.x(), p.y(), p.z())));
    for (const Tri& t : cell_in.triangles)
        if (cell.add_face(vertex[std::size_t(t[0])], vertex[std::size_t(t[1])], vertex[std::size_t(t[2])]) == Mesh::null_face())
            return fail("its cell mesh is not manifold");
    for (Mesh::Vertex_index v : vertex)
        if (cell.is_isolated(v)) cell.remove_vertex(v);
    // Dual contouring leaves an occasional zero-area triangle where the cell's two terms meet in a
    // crease (outside the object); CGAL counts it as a self-intersection. Collapsing it keeps the
    // mesh closed and manifold (linear time).
    PMP::remove_degenerate_faces(cell);
    if (cell.has_garbage()) cell.collect_garbage();
    if (!CGAL::is_closed(cell)) return fail("its cell mesh is not closed");
    if (!CGAL::is_triangle_mesh(cell)) return fail("its cell mesh is not a triangle mesh");
    // Self-intersections of the cell matter only where they end up in the fragment: dual contouring
    // may fold a few triangles where the fracture faces meet the offset surface, outside the input,
    // which the intersection drops. So only the fracture faces of the result are tested (below),
    // not the whole cell, a test that cost more than the corefinement itself.
    Mesh input = impl_->mesh;  // corefinement splits the faces of both operands
    Mesh out;
    OriginVisitor v;
    v.input = &input;
    v.cell = &cell;
    v.in_map = input.property_map<Face, int>(kOrigin).first;
    v.cell_map = cell.add_property_map<Face, int>(kOrigin, -1).first;
    v.out_map = out.add_property_map<Face, int>(kOrigin, -1).first;
    bool ok = false;
    try {
        ok = PMP::corefine_and_compute_intersection(input, cell, out, CGAL::parameters::visitor(v));
    } catch (const std::exception& e) {
        return fail(std::string("the corefinement failed: ") + e.what());
    }
    if (!ok) return fail("the intersection with its cell is not manifold");
    if (out.has_garbage()) out.collect_garbage();
    if (out.number_of_faces() == 0) return fail("its cell does not meet the input surface");
    {
        Mesh ordered;
        if (!CGAL::is_triangle_mesh(out) || !canonical_order(out, out.property_map<Face, int>(kOrigin).first, ordered))
            return fail("the intersection with its cell is not a manifold triangle mesh");
        out = std::move(ordered);
    }
    {
        const OriginMap origin = out.property_map<Face, int>(kOrigin).first;
        std::vector<Face> fracture;
        for (Face f : out.faces())
            if (origin[f] < 0) fracture.push_back(f);
        // All crossing pairs at once (no early exit as in does_self_intersect): a fold is mended
        // from them, and without a fold the search visits every box either way.
        std::vector<std::pair<Face, Face>> crossing;
        PMP::self_intersections(fracture, out, std::back_inserter(crossing));
        if (!crossing.empty()) {
            Mesh unmended;
            if (folded) unmended = out;
            if (!mend_folded_fracture_faces(out, origin, kMendRounds, std::move(crossing))) {
                if (!folded) return fail("its fracture faces intersect each other");
                out = std::move(unmended);
                *folded = true;
            }
        }
        if (out.has_garbage()) out.collect_garbage();
    }
    SurfaceMesh m = impl_->convert(out, out.property_map<Face, int>(kOrigin).first);
    const MeshTopologyReport topo = check_topology(m, 0.0);
    if (!(topo.closed() && topo.manifold() && topo.consistently_oriented()))
        return fail("the clipped mesh is not a closed manifold (" + topo.describe() + ")");
    result = std::move(m);
    return true;
}

}  // namespace cf
