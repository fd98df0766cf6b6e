// Software z-buffer rasteriser for scene previews (scene_preview.hpp). Three stages, each
// deterministic whatever the thread count:
//  1. per piece (parallel, one output per piece): vertices to camera space and pixels, triangles
//     culled (back faces), shaded (flat) and clipped at the near plane; triangles that cover no
//     pixel centre are dropped, which removes much of a fine fragment mesh at preview resolution.
//  2. per band of kBandRows rows (parallel): every piece overlapping the band, in pose order, its
//     triangles in mesh order, into the band's own z-buffer rows (nearest wins, the first on
//     ties), so each pixel has one writer and one fixed order of candidates.
//  3. per row (parallel): ground plane or sky where no piece is nearer; then the outline, which
//     reads the finished map of which piece is seen where.
#include "nodes/rigid/scene_preview.hpp"

#include "nodes/domain/fragment_palette.hpp"

#include "nodes/segment/preview_render.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace cf::rigid {
namespace {

constexpr int kMinSize = 16, kMaxSize = 8192;  // [pixels], as the fragment preview
constexpr int kBandRows = 8;                    // rows per rasterisation task (60 tasks for 480 rows)
constexpr double kPi = 3.14159265358979323846;

// Sky and ground colours (RGB in [0, 1]).
const Vec3 kHorizon(0.86, 0.90, 0.95), kZenith(0.42, 0.60, 0.86), kNadir(0.60, 0.62, 0.66);
const Vec3 kCheckLight(0.91, 0.90, 0.87), kCheckDark(0.78, 0.77, 0.74);

std::string str(double v) {
    std::ostringstream out;
    out << v;  // 40, 0.5, 1e-300, nan
    return out.str();
}

// Camera axes: right, up and forward are unit and orthogonal; (right, up, -forward) is
// right-handed. Camera space is (x right, y up, z = depth along forward).
struct CameraFrame {
    Vec3 eye, right, up, forward;
    double focal = 0;   // [pixels]
    double cx = 0, cy = 0;  // image centre [pixels]
    double near = 0;    // [m] geometry nearer than this (along forward) is clipped
    int width = 0, height = 0;
};

CameraFrame camera_frame(const SceneCamera& c) {
    CameraFrame f;
    f.eye = c.position;
    f.forward = (c.target - c.position).normalized();
    f.right = f.forward.cross(c.up.normalized()).normalized();
    f.up = f.right.cross(f.forward);
    f.focal = 0.5 * c.height / std::tan(0.5 * c.fov_degrees * kPi / 180);
    f.cx = 0.5 * c.width;
    f.cy = 0.5 * c.height;
    // Relative to the viewing distance: depth resolution is no concern in double precision, but
    // a vertex at depth ~0 would project to infinity.
    f.near = 1e-3 * (c.target - c.position).norm();
    f.width = c.width;
    f.height = c.height;
    return f;
}

struct ScreenPoint {
    double x, y, inv_z;  // [pixels] (x right, y down), 1 / depth [1/m]
};

// A camera-space point at depth >= cam.near in pixel coordinates.
inline ScreenPoint project(const Vec3& v, const CameraFrame& cam) {
    const double inv_z = 1 / v.z();
    return {cam.cx + cam.focal * v.x() * inv_z, cam.cy - cam.focal * v.y() * inv_z, inv_z};
}

// A projected triangle ready to rasterise, its corners ordered so that area2 and the three edge
// functions are positive inside.
struct ScreenTriangle {
    ScreenPoint v[3];
    double area2 = 0;          // twice the pixel area (> 0)
    int x0, x1, y0, y1;        // inclusive pixel range whose centres may be inside
    float shade = 0;           // colour factor (ambient + diffuse)
    bool inside = false;       // a fracture face (region "inside"): drawn in the piece's inside shade
};

// Orders the corners, finds the pixel range; false if the triangle covers no pixel centre (common
// for a fine fragment mesh at preview resolution) or is degenerate / edge-on.
bool set_up(const ScreenPoint& a, const ScreenPoint& b, const ScreenPoint& c, const CameraFrame& cam,
            ScreenTriangle& t) {
    t.area2 = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
    if (!(std::abs(t.area2) > 0) || !std::isfinite(t.area2)) return false;
    t.v[0] = a;
    t.v[1] = t.area2 > 0 ? b : c;
    t.v[2] = t.area2 > 0 ? c : b;
    t.area2 = std::abs(t.area2);
    // Pixel i is covered if its centre i + 0.5 is inside; clamp in double before converting (a
    // vertex just beyond the near plane projects far outside the image).
    auto range = [](double lo, double hi, int n, int& i0, int& i1) {
        i0 = std::max(0, int(std::ceil(std::clamp(lo - 0.5, -1.0, double(n)))));
        i1 = std::min(n - 1, int(std::floor(std::clamp(hi - 0.5, -1.0, double(n)))));
    };
    range(std::min({a.x, b.x, c.x}), std::max({a.x, b.x, c.x}), cam.width, t.x0, t.x1);
    range(std::min({a.y, b.y, c.y}), std::max({a.y, b.y, c.y}), cam.height, t.y0, t.y1);
    return t.x0 <= t.x1 && t.y0 <= t.y1;
}

// Edge function of the edge a -> b at pixel centre (px, py), evaluated on the endpoints in a
// canonical order so that the two triangles sharing the edge get exactly opposite values: no
// pixel centre on a shared edge is then missed or covered twice (with the tie rule below).
inline double edge_function(const ScreenPoint& a, const ScreenPoint& b, double px, double py) {
    if (a.x < b.x || (a.x == b.x && a.y < b.y)) return (b.x - a.x) * (py - a.y) - (b.y - a.y) * (px - a.x);
    return -((a.x - b.x) * (py - b.y) - (a.y - b.y) * (px - b.x));
}

// Whether a pixel centre exactly on the edge a -> b belongs to this triangle: the two triangles
// sharing an edge traverse it in opposite directions, so exactly one of them owns it.
inline bool owns_ties(const ScreenPoint& a, const ScreenPoint& b) { return b.y > a.y || (b.y == a.y && b.x > a.x); }

// Which triangle is drawn at a pixel: the pose slot in the frame and the piece's drawable
// (>= 0) or clipped triangle (-1 - k); slot -1 for none.
struct PixelOwner {
    std::int32_t slot = -1, item = 0;
};

// The z-buffer (1 / depth, 0 = nothing) and owners of the image, written band by band.
struct DepthImage {
    int width = 0;
    std::vector<double> inv_depth;
    std::vector<PixelOwner> owner;
};

// Rasterises t into rows [row0, row1): nearest wins, the earlier triangle on ties.
void rasterise(const ScreenTriangle& t, int row0, int row1, PixelOwner who, DepthImage& image) {
    const bool tie0 = owns_ties(t.v[1], t.v[2]), tie1 = owns_ties(t.v[2], t.v[0]), tie2 = owns_ties(t.v[0], t.v[1]);
    const double inv_area = 1 / t.area2;
    const int y0 = std::max(t.y0, row0), y1 = std::min(t.y1, row1 - 1);
    for (int y = y0; y <= y1; ++y) {
        const double py = y + 0.5;
        for (int x = t.x0; x <= t.x1; ++x) {
            const double px = x + 0.5;
            const double e0 = edge_function(t.v[1], t.v[2], px, py);  // opposite corner 0
            if (e0 < 0 || (e0 == 0 && !tie0)) continue;
            const double e1 = edge_function(t.v[2], t.v[0], px, py);
            if (e1 < 0 || (e1 == 0 && !tie1)) continue;
            const double e2 = edge_function(t.v[0], t.v[1], px, py);
            if (e2 < 0 || (e2 == 0 && !tie2)) continue;
            // 1 / depth is affine in screen space, so barycentric interpolation is exact.
            const double iz = (e0 * t.v[0].inv_z + e1 * t.v[1].inv_z + e2 * t.v[2].inv_z) * inv_area;
            const std::size_t p = std::size_t(y) * std::size_t(image.width) + std::size_t(x);
            if (iz > image.inv_depth[p]) {
                image.inv_depth[p] = iz;
                image.owner[p] = who;
            }
        }
    }
}

// One piece of the frame after stage 1. Drawable triangles are kept as (mesh triangle, shade,
// rows), not as ScreenTriangles: set_up is repeated in stage 2, which is cheaper than writing
// (and page-faulting) ~100 bytes per triangle for a few hundred thousand triangles.
struct Drawable {
    std::uint32_t triangle;  // index into the rest mesh
    float shade;
    std::int32_t y0, y1;     // pixel rows
    bool inside;             // a fracture face
};
struct ProjectedPiece {
    const SurfaceMesh* mesh = nullptr;
    std::vector<ScreenPoint> screen;        // per vertex (meaningful where a drawable uses it)
    std::vector<Drawable> drawables;        // entirely in front of the near plane
    std::vector<ScreenTriangle> clipped;    // the rare triangles cut by the near plane
    int y0 = std::numeric_limits<int>::max(), y1 = -1;  // rows of all the above
    Vec3 colour = Vec3::Zero();
    Vec3 inside_colour = Vec3::Zero();  // of its fracture faces (fragment_palette.hpp's inside shade)
    std::string error;  // reported after the parallel loop, the first in pose order
};

// Clips the camera-space triangle, which crosses depth cam.near, there (Sutherland-Hodgman
// against one plane: it becomes one or two triangles) and keeps what covers pixel centres.
void clip(const Vec3 (&v)[3], float shade, bool inside, const CameraFrame& cam, ProjectedPiece& out) {
    Vec3 poly[4];
    int n = 0;
    for (int k = 0; k < 3; ++k) {
        const Vec3& a = v[k];
        const Vec3& b = v[(k + 1) % 3];
        const bool ina = a.z() >= cam.near, inb = b.z() >= cam.near;
        if (ina) poly[n++] = a;
        if (ina != inb) poly[n++] = a + (cam.near - a.z()) / (b.z() - a.z()) * (b - a);
    }
    for (int k = 1; k + 1 < n; ++k) {
        ScreenTriangle t;
        if (!set_up(project(poly[0], cam), project(poly[k], cam), project(poly[k + 1], cam), cam, t)) continue;
        t.shade = shade;
        t.inside = inside;
        out.clipped.push_back(t);
        out.y0 = std::min(out.y0, t.y0);
        out.y1 = std::max(out.y1, t.y1);
    }
}

// Per-task scratch space, reused from piece to piece (fresh allocations page-fault).
struct Scratch {
    std::vector<Vec3> world, camera;
};

void project_piece(const Animation& a, int index, const PiecePose& pose, const Vec3& colour, const CameraFrame& cam,
                   const Vec3& light, Scratch& scratch, ProjectedPiece& result) {
    result.colour = colour;
    result.inside_colour = inside_shade(colour);
    const AnimationPiece& piece = a.pieces[std::size_t(index)];
    const std::string who = "piece " + std::to_string(index) + " ('" + piece.name + "')";
    if (!piece.rest_mesh) {
        result.error = who + ": no rest mesh";
        return;
    }
    if (!pose.position.allFinite() || !pose.rotation.coeffs().allFinite() ||
        std::abs(pose.rotation.norm() - 1) > 1e-6) {
        result.error = who + ": pose is not finite or its rotation is not a unit quaternion";
        return;
    }
    const SurfaceMesh& mesh = *piece.rest_mesh;
    result.mesh = &mesh;
    const int inside_region = region_id(mesh, "inside");
    const Eigen::Matrix3d rotation = pose.rotation.toRotationMatrix();
    std::vector<Vec3>& world = scratch.world;
    std::vector<Vec3>& camera = scratch.camera;
    world.resize(mesh.num_vertices());
    camera.resize(mesh.num_vertices());
    result.screen.resize(mesh.num_vertices());  // once per vertex: ~6 triangles share each
    result.drawables.reserve(mesh.num_triangles() / 2);  // about the front-facing half
    for (std::size_t i = 0; i < mesh.num_vertices(); ++i) {
        world[i] = pose.position + rotation * mesh.vertices[i];
        if (!world[i].allFinite()) {
            result.error = who + ": vertex " + std::to_string(i) + " is not finite";
            return;
        }
        const Vec3 d = world[i] - cam.eye;
        camera[i] = Vec3(d.dot(cam.right), d.dot(cam.up), d.dot(cam.forward));
        if (camera[i].z() >= cam.near) result.screen[i] = project(camera[i], cam);
    }
    const int nv = int(mesh.num_vertices());
    for (std::size_t t = 0; t < mesh.num_triangles(); ++t) {
        const Tri& tri = mesh.triangles[t];
        if (tri[0] < 0 || tri[0] >= nv || tri[1] < 0 || tri[1] >= nv || tri[2] < 0 || tri[2] >= nv) {
            result.error = who + ": triangle " + std::to_string(t) + " has a vertex index out of range [0, " +
                           std::to_string(nv) + ")";
            return;
        }
        const std::size_t i0 = std::size_t(tri[0]), i1 = std::size_t(tri[1]), i2 = std::size_t(tri[2]);
        const int in_front = (camera[i0].z() >= cam.near) + (camera[i1].z() >= cam.near) + (camera[i2].z() >= cam.near);
        if (in_front == 0) continue;  // behind the near plane
        const Vec3& w0 = world[i0];
        Vec3 n = (world[i1] - w0).cross(world[i2] - w0);
        // Back faces (and edge-on ones) are culled: rest meshes are closed and outward (SurfaceMesh's
        // counter-clockwise convention), so a front face always hides them; this halves the work.
        if (!(n.dot(cam.eye - w0) > 0)) continue;
        n.normalize();
        const float shade = float(kSceneAmbient + kSceneDiffuse * std::max(0.0, n.dot(light)));
        const bool inside = inside_region >= 0 && mesh.region_of(t) == inside_region;
        if (in_front < 3) {
            const Vec3 v[3] = {camera[i0], camera[i1], camera[i2]};
            clip(v, shade, inside, cam, result);
            continue;
        }
        ScreenTriangle st;
        if (!set_up(result.screen[i0], result.screen[i1], result.screen[i2], cam, st)) continue;
        result.drawables.push_back({std::uint32_t(t), shade, st.y0, st.y1, inside});
        result.y0 = std::min(result.y0, st.y0);
        result.y1 = std::max(result.y1, st.y1);
    }
}

// Stage 2 for rows [row0, row1): the pieces in pose order, each piece's triangles in mesh order.
void rasterise_band(const std::vector<ProjectedPiece>& pieces, const CameraFrame& cam, int row0, int row1,
                    DepthImage& image) {
    for (std::size_t slot = 0; slot < pieces.size(); ++slot) {
        const ProjectedPiece& p = pieces[slot];
        if (p.y1 < row0 || p.y0 >= row1) continue;
        for (std::size_t k = 0; k < p.drawables.size(); ++k) {
            const Drawable& d = p.drawables[k];
            if (d.y1 < row0 || d.y0 >= row1) continue;
            const Tri& tri = p.mesh->triangles[d.triangle];
            ScreenTriangle t;
            set_up(p.screen[std::size_t(tri[0])], p.screen[std::size_t(tri[1])], p.screen[std::size_t(tri[2])], cam, t);
            rasterise(t, row0, row1, {std::int32_t(slot), std::int32_t(k)}, image);
        }
        for (std::size_t k = 0; k < p.clipped.size(); ++k)
            rasterise(p.clipped[k], row0, row1, {std::int32_t(slot), -1 - std::int32_t(k)}, image);
    }
}


}  // namespace

std::string scene_camera_problem(const SceneCamera& c) {
    if (!c.position.allFinite()) return "position: not finite";
    if (!c.target.allFinite()) return "target: not finite";
    const double distance = (c.target - c.position).norm();
    if (!(distance > 0) || !std::isfinite(distance)) return "target: equals position (no view direction)";
    if (!c.up.allFinite() || !(c.up.norm() > 0) || !std::isfinite(c.up.norm())) return "up: zero or not finite";
    const Vec3 view = (c.target - c.position) / distance;
    if (view.cross(c.up.normalized()).norm() < 1e-6) return "up: parallel to the view direction";
    if (!(c.fov_degrees > 0 && c.fov_degrees < 180))
        return "fov_degrees: " + str(c.fov_degrees) + " is not in (0, 180) degrees";
    if (c.width < kMinSize || c.width > kMaxSize)
        return "width: " + std::to_string(c.width) + " pixels is not in [16, 8192]";
    if (c.height < kMinSize || c.height > kMaxSize)
        return "height: " + std::to_string(c.height) + " pixels is not in [16, 8192]";
    return "";
}

Vec3 scene_light_direction(const SceneCamera& c) {
    const CameraFrame f = camera_frame(c);
    return (-1.0 * f.right + 1.0 * f.up - 1.5 * f.forward).normalized();
}


namespace {

// render_scene_image's steps, in the order it calls them.

void check_preview_inputs(const Animation& a, std::size_t f, const SceneCamera& c, const Vec3& ground_point,
                          const Vec3& ground_normal, bool ground) {
    if (const std::string problem = scene_camera_problem(c); !problem.empty())
        throw std::invalid_argument("scene preview camera: " + problem);
    if (f >= a.frames.size())
        throw std::invalid_argument("frame " + std::to_string(f) + ": out of range, the animation has " +
                                    std::to_string(a.frames.size()) + " frames");
    if (ground) {
        if (!ground_point.allFinite()) throw std::invalid_argument("ground_point: not finite");
        if (!ground_normal.allFinite() || !(ground_normal.norm() > 0) || !std::isfinite(ground_normal.norm()))
            throw std::invalid_argument("ground_normal: zero or not finite");
    }
    for (const auto& [index, pose] : a.frames[f].poses)
        if (index < 0 || std::size_t(index) >= a.pieces.size())
            throw std::invalid_argument("frame " + std::to_string(f) + ": pose of piece " + std::to_string(index) +
                                        ", out of range (the animation has " + std::to_string(a.pieces.size()) +
                                        " pieces)");
}

// 1. Every posed piece projected (in parallel, one output per piece).
std::vector<ProjectedPiece> project_pieces(const Animation& a, std::size_t f, const CameraFrame& cam, const Vec3& light) {
    const AnimationFrame& frame = a.frames[f];
    const std::vector<Vec3> colours = scene_piece_colours(a);
    std::vector<ProjectedPiece> per_piece(frame.poses.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, frame.poses.size()), [&](const auto& r) {
        Scratch scratch;
        for (std::size_t i = r.begin(); i != r.end(); ++i) {
            const auto& [index, pose] = frame.poses[i];
            project_piece(a, index, pose, colours[std::size_t(index)], cam, light, scratch, per_piece[i]);
        }
    });
    for (const ProjectedPiece& p : per_piece)
        if (!p.error.empty()) throw std::invalid_argument("frame " + std::to_string(f) + ": " + p.error);
    return per_piece;
}

// 2. The pieces rasterised in bands of rows.
DepthImage rasterise_pieces(const std::vector<ProjectedPiece>& per_piece, const CameraFrame& cam, int width, int height) {
    const int bands = (height + kBandRows - 1) / kBandRows;
    const std::size_t pixels = std::size_t(width) * std::size_t(height);
    DepthImage depth;
    depth.width = width;
    depth.inv_depth.assign(pixels, 0.0);
    depth.owner.assign(pixels, PixelOwner{});
    tbb::parallel_for(tbb::blocked_range<int>(0, bands), [&](const tbb::blocked_range<int>& r) {
        for (int b = r.begin(); b != r.end(); ++b)
            rasterise_band(per_piece, cam, b * kBandRows, std::min(height, (b + 1) * kBandRows), depth);
    });
    return depth;
}

// What a pixel's ray meets when no piece is nearer: the ground plane (a fading checkerboard of
// 1 m squares) or the sky (a gradient by elevation).
class Backdrop {
public:
    Backdrop(const SceneCamera& c, const CameraFrame& cam, const Vec3& ground_point, const Vec3& ground_normal, bool ground)
        : cam_(cam), ground_(ground), ground_point_(ground_point),
          n_(ground ? Vec3(ground_normal.normalized()) : Vec3::UnitZ()) {
        // In-plane axes of the checkerboard: the world x axis projected on the plane (y if the
        // plane is nearly perpendicular to x), so a z-up ground has squares along x and y.
        const Vec3 axis = std::abs(n_.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
        e1_ = (axis - axis.dot(n_) * n_).normalized();
        e2_ = n_.cross(e1_);
        plane_offset_ = (ground_point - cam.eye).dot(n_);
        // Haze length: the checkerboard fades into the horizon over ~15 viewing distances.
        haze_ = 15 * std::max(1.0, (c.target - c.position).norm());
        vertical_ = c.up.normalized();
    }

    Vec3 ray(int x, int y) const {
        return Vec3((cam_.focal * cam_.forward + (x + 0.5 - cam_.cx) * cam_.right - (y + 0.5 - cam_.cy) * cam_.up)
                        .normalized());
    }
    // Ray parameter [m] of the ground, -1: none.
    double ground_hit(const Vec3& dir) const {
        if (!ground_) return -1.0;
        const double t = plane_offset_ / dir.dot(n_);
        return t > 0 && std::isfinite(t) ? t : -1.0;
    }

    Vec3 colour(const Vec3& dir) const {
        if (const double t = ground_hit(dir); t > 0) {
            const Vec3 mean_check = 0.5 * (kCheckLight + kCheckDark);
            const Vec3 d = cam_.eye + t * dir - ground_point_;
            // 1 m squares; parity in double (fmod is exact; no overflow far away).
            const bool light_square = std::fmod(std::floor(d.dot(e1_)) + std::floor(d.dot(e2_)), 2.0) == 0;
            // Contrast fades with distance and where squares shrink below ~4 pixels
            // (gone at 2), which would alias into noise.
            const double footprint = t / (cam_.focal * std::abs(dir.dot(n_)));  // [m/pixel]
            const double fade = std::exp(-t / haze_);
            const double contrast = fade * std::clamp((0.5 - footprint) / 0.25, 0.0, 1.0);
            const Vec3 square = light_square ? kCheckLight : kCheckDark;
            const Vec3 check = mean_check + contrast * (square - mean_check);
            return fade * check + (1 - fade) * kHorizon;
        }
        const double s = dir.dot(vertical_);  // sky gradient by elevation
        return s >= 0 ? Vec3(kHorizon + s * (kZenith - kHorizon)) : Vec3(kHorizon - s * (kNadir - kHorizon));
    }

private:
    const CameraFrame& cam_;
    bool ground_;
    Vec3 ground_point_, n_, e1_, e2_, vertical_;
    double plane_offset_ = 0, haze_ = 0;
};

// 3a. Where the ground is nearer than the piece found there, the pixel shows the ground.
void reveal_ground(const Backdrop& backdrop, const CameraFrame& cam, int height, DepthImage& depth) {
    const int width = depth.width;
    tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const tbb::blocked_range<int>& r) {
        for (int y = r.begin(); y != r.end(); ++y)
            for (int x = 0; x < width; ++x) {
                const std::size_t p = std::size_t(y) * std::size_t(width) + std::size_t(x);
                if (depth.owner[p].slot < 0) continue;
                const Vec3 dir = backdrop.ray(x, y);
                const double t = backdrop.ground_hit(dir);
                if (t > 0 && 1 / (t * dir.dot(cam.forward)) > depth.inv_depth[p]) depth.owner[p].slot = -1;
            }
    });
}

// 3b. Colours: a piece's shade, darkened on its outline (the neighbours' owners, final after
// 3a), else the backdrop.
std::vector<unsigned char> shade_pixels(const std::vector<ProjectedPiece>& per_piece, const DepthImage& depth,
                                        const Backdrop& backdrop, int height) {
    const int width = depth.width;
    std::vector<unsigned char> image(3 * std::size_t(width) * std::size_t(height));
    tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const tbb::blocked_range<int>& r) {
        for (int y = r.begin(); y != r.end(); ++y)
            for (int x = 0; x < width; ++x) {
                const std::size_t p = std::size_t(y) * std::size_t(width) + std::size_t(x);
                const PixelOwner o = depth.owner[p];
                Vec3 rgb;
                if (o.slot >= 0) {
                    const ProjectedPiece& piece = per_piece[std::size_t(o.slot)];
                    const double shade = o.item >= 0 ? piece.drawables[std::size_t(o.item)].shade
                                                     : piece.clipped[std::size_t(-1 - o.item)].shade;
                    const bool inside = o.item >= 0 ? piece.drawables[std::size_t(o.item)].inside
                                                    : piece.clipped[std::size_t(-1 - o.item)].inside;
                    auto other = [&](std::size_t q) { return depth.owner[q].slot != o.slot; };
                    const bool edge = (x > 0 && other(p - 1)) || (x + 1 < width && other(p + 1)) ||
                                      (y > 0 && other(p - std::size_t(width))) ||
                                      (y + 1 < height && other(p + std::size_t(width)));
                    rgb = (shade * (inside ? piece.inside_colour : piece.colour)).cwiseMin(1.0).cwiseMax(0.0) * (edge ? kSceneOutline : 1.0);
                } else {
                    rgb = backdrop.colour(backdrop.ray(x, y));
                }
                for (int k = 0; k < 3; ++k)
                    image[3 * p + std::size_t(k)] =
                        static_cast<unsigned char>(std::lround(255 * std::clamp(rgb[k], 0.0, 1.0)));
            }
    });
    return image;
}

}  // namespace

std::vector<unsigned char> render_scene_image(const Animation& a, std::size_t f, const SceneCamera& c,
                                              const Vec3& ground_point, const Vec3& ground_normal, bool ground) {
    check_preview_inputs(a, f, c, ground_point, ground_normal, ground);
    const CameraFrame cam = camera_frame(c);
    const Vec3 light = scene_light_direction(c);
    // 1. Project every piece. 2. Rasterise bands of rows. 3. Ground or sky where no piece is
    // nearer, then the outline.
    const std::vector<ProjectedPiece> per_piece = project_pieces(a, f, cam, light);
    DepthImage depth = rasterise_pieces(per_piece, cam, c.width, c.height);
    const Backdrop backdrop(c, cam, ground_point, ground_normal, ground);
    reveal_ground(backdrop, cam, c.height, depth);
    return shade_pixels(per_piece, depth, backdrop, c.height);
}

void render_scene_preview(const Animation& a, std::size_t f, const SceneCamera& c, const std::filesystem::path& png,
                          const Vec3& ground_point, const Vec3& ground_normal, bool ground) {
    const std::vector<unsigned char> image = render_scene_image(a, f, c, ground_point, ground_normal, ground);
    write_png_rgb(png, c.width, c.height, image.data());  // atomic (graph::write_atomically_via_path)
}

}  // namespace cf::rigid
