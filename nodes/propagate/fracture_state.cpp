#include "nodes/propagate/fracture_state.hpp"

#include "graph/diagnostics.hpp"

#include <algorithm>
#include <map>
#include <stdexcept>

namespace cf::propagate {

bool FractureState::has_active_markers() const {
    for (const FrontState& f : fronts) {
        if (f.fresh) return true;
        for (const MarkerState& m : f.markers.markers)
            if (m.active) return true;
    }
    return false;
}

FractureState start_fracture_state(double r_c, double r_f, double half_width, std::size_t surface_elements) {
    if (!(r_f > 0)) throw std::invalid_argument("r_f (level-set voxel size) must be > 0 m, got " + graph::format_number(r_f));
    if (!(r_c > r_f))
        throw std::invalid_argument("r_c (" + graph::format_number(r_c) + " m) must be larger than r_f (" + graph::format_number(r_f) +
                                    " m): the crack front is resolved finer than the BEM mesh (ratio 20-50 in the thesis)");
    FractureState s;
    s.r_c = r_c;
    s.r_f = r_f;
    s.grids.voxel_size = r_f;
    s.grids.half_width = half_width;
    s.initiated.assign(surface_elements, 0);
    return s;
}

std::vector<Triangle3> mesh_triangles(const SurfaceMesh& m) {
    std::vector<Triangle3> out;
    out.reserve(m.num_triangles());
    for (const Tri& t : m.triangles) out.push_back({m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]]});
    return out;
}

namespace {

bool has_interior_node(const SurfaceMesh& sheet) {
    std::map<std::pair<int, int>, int> edges;
    for (const Tri& t : sheet.triangles)
        for (int k = 0; k < 3; ++k) ++edges[{std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3])}];
    std::vector<char> boundary(sheet.num_vertices(), 0), used(sheet.num_vertices(), 0);
    for (const Tri& t : sheet.triangles)
        for (int v : t) used[v] = 1;
    for (const auto& [e, n] : edges)
        if (n == 1) boundary[e.first] = boundary[e.second] = 1;
    for (std::size_t v = 0; v < sheet.num_vertices(); ++v)
        if (used[v] && !boundary[v]) return true;
    return false;
}

}  // namespace

int add_crack(FractureState& state, const SurfaceMesh& sheet, const std::vector<Triangle3>& recorded) {
    if (sheet.num_triangles() == 0) throw std::invalid_argument("a new crack sheet has no triangles");
    if (!has_interior_node(sheet))
        throw std::invalid_argument("a new crack sheet has no interior node: its opening would have no unknown "
                                    "(thesis ch. 4.4); make it larger than one BEM edge r_c");
    if (recorded.empty()) throw std::invalid_argument("a new crack has no recorded surface (empty crack)");
    SurfaceMesh& cracks = state.cracks;
    const int region = state.num_cracks();
    const int offset = static_cast<int>(cracks.vertices.size());
    cracks.region.resize(cracks.triangles.size(), 0);
    cracks.region_names.resize(region);
    for (int r = 0; r < region; ++r)
        if (cracks.region_names[r].empty()) cracks.region_names[r] = "crack" + std::to_string(r);
    cracks.region_names.push_back(sheet.region_names.empty() || sheet.region_names[0].empty()
                                      ? "crack" + std::to_string(region)
                                      : sheet.region_names[0]);
    cracks.vertices.insert(cracks.vertices.end(), sheet.vertices.begin(), sheet.vertices.end());
    SurfaceMesh own;  // the sheet alone with crack-mesh vertex ids, to find its fronts
    own.vertices = cracks.vertices;
    for (const Tri& t : sheet.triangles) {
        const Tri g{t[0] + offset, t[1] + offset, t[2] + offset};
        cracks.triangles.push_back(g);
        cracks.region.push_back(region);
        own.triangles.push_back(g);
        own.region.push_back(region);
    }
    for (CrackFront& f : extract_fronts(own)) {
        FrontState fs;
        fs.front = std::move(f);
        fs.front.region = region;
        state.fronts.push_back(std::move(fs));
    }
    CrackRecorder rec(state.r_f, state.grids.half_width);
    rec.add_crack();
    rec.add_triangles(0, recorded);
    state.grids.cracks.push_back(rec.release().cracks.at(0));
    return region;
}

std::vector<char> moving_front_nodes(const FractureState& state) {
    std::vector<char> out(state.cracks.num_vertices(), 0);
    for (const FrontState& fs : state.fronts) {
        const auto& nodes = fs.front.nodes;
        const std::size_t n = nodes.size(), edges = fs.front.num_edges();
        const int per = std::max(fs.markers.per_edge, 1);
        const bool placed = !fs.fresh && fs.markers.markers.size() >= edges * static_cast<std::size_t>(per);
        for (std::size_t i = 0; i < edges; ++i) {
            bool active = !placed;
            for (int k = 0; placed && !active && k < per; ++k) active = fs.markers.markers[i * per + k].active;
            if (!active) continue;
            if (nodes[i] < static_cast<int>(out.size())) out[nodes[i]] = 1;
            if (nodes[(i + 1) % n] < static_cast<int>(out.size())) out[nodes[(i + 1) % n]] = 1;
        }
    }
    return out;
}

}  // namespace cf::propagate
