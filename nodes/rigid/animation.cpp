#include "nodes/rigid/animation.hpp"
#include "nodes/rigid/animation_checks.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>
#include <stdexcept>

namespace cf::rigid {

const char* piece_class_name(PieceClass c) {
    switch (c) {
        case PieceClass::original: return "original";
        case PieceClass::hull: return "hull";
        case PieceClass::mesh: return "mesh";
        case PieceClass::breakable: return "breakable";
        case PieceClass::large: return "large";
    }
    return "unknown";  // a value cast from an out-of-range integer
}

int last_visible_frame(const Animation& a, const AnimationPiece& p) {
    return p.last_frame == -1 ? static_cast<int>(a.frames.size()) - 1 : p.last_frame;
}

const PiecePose* find_pose(const AnimationFrame& frame, int piece) {
    auto it = std::lower_bound(frame.poses.begin(), frame.poses.end(), piece,
                               [](const std::pair<int, PiecePose>& e, int p) { return e.first < p; });
    return it != frame.poses.end() && it->first == piece ? &it->second : nullptr;
}

namespace {

[[noreturn]] void fail(const std::string& what) { throw std::invalid_argument("invalid animation: " + what); }

std::string piece_label(const Animation& a, int i) {
    return "piece " + std::to_string(i) + " \"" + a.pieces[static_cast<std::size_t>(i)].name + "\"";
}

std::string frame_label(const Animation& a, std::size_t f) {
    std::ostringstream s;
    s << "frame " << f << " (t = " << a.frames[f].time << " s)";
    return s.str();
}

void check_timing(const Animation& a) {
    if (!std::isfinite(a.frame_rate) || a.frame_rate <= 0) {
        std::ostringstream s;
        s << "frame_rate is " << a.frame_rate << " 1/s; it must be a finite number > 0";
        fail(s.str());
    }
    if (a.frames.empty()) fail("it has no frames (frame 0, the initial state, is required)");
    for (std::size_t f = 0; f < a.frames.size(); ++f) {
        if (!std::isfinite(a.frames[f].time)) fail(frame_label(a, f) + ": the time is not finite");
        if (f > 0 && !(a.frames[f].time > a.frames[f - 1].time))
            fail(frame_label(a, f) + ": its time is not after frame " + std::to_string(f - 1) +
                 "'s; frame times must increase strictly");
    }
}

void check_rest_mesh(const Animation& a, int i) {
    const SurfaceMesh* m = a.pieces[static_cast<std::size_t>(i)].rest_mesh.get();
    if (!m) fail(piece_label(a, i) + " has no rest mesh");
    if (m->vertices.empty() || m->triangles.empty()) fail(piece_label(a, i) + " has an empty rest mesh");
    for (std::size_t v = 0; v < m->vertices.size(); ++v)
        if (!m->vertices[v].allFinite())
            fail(piece_label(a, i) + ": rest mesh vertex " + std::to_string(v) + " is not finite");
    const int n = static_cast<int>(m->vertices.size());
    for (std::size_t t = 0; t < m->triangles.size(); ++t)
        for (int v : m->triangles[t])
            if (v < 0 || v >= n)
                fail(piece_label(a, i) + ": rest mesh triangle " + std::to_string(t) + " uses vertex " +
                     std::to_string(v) + " of " + std::to_string(n));
}

void check_pieces(const Animation& a) {
    const int n = static_cast<int>(a.pieces.size());
    const int frames = static_cast<int>(a.frames.size());
    std::map<std::string, int> by_name;
    for (int i = 0; i < n; ++i) {
        const AnimationPiece& p = a.pieces[static_cast<std::size_t>(i)];
        if (p.name.empty()) fail("piece " + std::to_string(i) + " has an empty name");
        auto [it, fresh] = by_name.emplace(p.name, i);
        if (!fresh) fail("pieces " + std::to_string(it->second) + " and " + std::to_string(i) + " are both named \"" + p.name + "\"");
        if (p.parent < -1 || p.parent >= n || p.parent == i)
            fail(piece_label(a, i) + " has parent " + std::to_string(p.parent) + "; it must be -1 or another piece's index in [0, " +
                 std::to_string(n) + ")");
        check_rest_mesh(a, i);
        if (!std::isfinite(p.volume) || p.volume < 0 || !std::isfinite(p.mass) || p.mass < 0)
            fail(piece_label(a, i) + ": volume and mass must be finite and >= 0");
        if (p.first_frame < 0 || p.first_frame >= frames)
            fail(piece_label(a, i) + " has first_frame " + std::to_string(p.first_frame) + " but there are frames 0.." +
                 std::to_string(frames - 1));
        if (p.last_frame != -1 && (p.last_frame < p.first_frame || p.last_frame >= frames))
            fail(piece_label(a, i) + " has last_frame " + std::to_string(p.last_frame) + "; it must be -1 or in [first_frame = " +
                 std::to_string(p.first_frame) + ", " + std::to_string(frames - 1) + "]");
    }
}

void check_pose(const Animation& a, std::size_t f, int i, const PiecePose& q) {
    const std::string where = frame_label(a, f) + ", " + piece_label(a, i);
    if (!q.position.allFinite() || !q.rotation.coeffs().allFinite() || !q.velocity.allFinite() ||
        !q.angular_velocity.allFinite())
        fail(where + ": the pose is not finite");
    const double norm = q.rotation.norm();
    if (std::abs(norm - 1) > 1e-9) {
        std::ostringstream s;
        s << where << ": the rotation quaternion has norm " << norm << "; it must be a unit quaternion (|q| - 1 <= 1e-9)";
        fail(s.str());
    }
}

bool alive_at(const Animation& a, const AnimationPiece& p, int f) {
    return f >= p.first_frame && f <= last_visible_frame(a, p);
}

void check_frame(const Animation& a, std::size_t f) {
    const int n = static_cast<int>(a.pieces.size());
    int previous = -1;
    for (const auto& [i, pose] : a.frames[f].poses) {
        if (i < 0 || i >= n) fail(frame_label(a, f) + " has a pose for piece " + std::to_string(i) + ", which does not exist");
        if (i <= previous)
            fail(frame_label(a, f) + ": the pose of " + piece_label(a, i) + " comes after piece " + std::to_string(previous) +
                 "'s; poses must be in strictly increasing piece index");
        previous = i;
        const AnimationPiece& p = a.pieces[static_cast<std::size_t>(i)];
        if (!alive_at(a, p, static_cast<int>(f)))
            fail(frame_label(a, f) + " has a pose for " + piece_label(a, i) + ", which is visible only in frames " +
                 std::to_string(p.first_frame) + ".." + std::to_string(last_visible_frame(a, p)));
        check_pose(a, f, i, pose);
    }
    for (int i = 0; i < n; ++i)
        if (alive_at(a, a.pieces[static_cast<std::size_t>(i)], static_cast<int>(f)) && !find_pose(a.frames[f], i))
            fail(frame_label(a, f) + " has no pose for " + piece_label(a, i) + ", which is visible from frame " +
                 std::to_string(a.pieces[static_cast<std::size_t>(i)].first_frame) + " to " +
                 std::to_string(last_visible_frame(a, a.pieces[static_cast<std::size_t>(i)])));
}

}  // namespace

void check_animation(const Animation& a) {
    check_timing(a);
    check_pieces(a);
    for (std::size_t f = 0; f < a.frames.size(); ++f) check_frame(a, f);
}

}  // namespace cf::rigid
