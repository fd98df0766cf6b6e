#include "nodes/segment/fragment_sheet.hpp"

#include "graph/cancel_token.hpp"
#include "nodes/domain/fragment_palette.hpp"
#include "nodes/segment/preview_render.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace cf {

namespace {

// An orthographic view: camera direction d (scene -> camera), image up u, right r = u x d.
struct View {
    Vec3 d, u, r;
};

View make_view(const Vec3& d, const Vec3& up) {
    View v;
    v.d = d.normalized();
    v.u = (up - up.dot(v.d) * v.d).normalized();
    v.r = v.u.cross(v.d);
    return v;
}

// The four views of the sheet: oblique, front, side, top (oblique only without a sheet).
std::vector<View> sheet_views(const SheetOptions& o) {
    const Vec3 up = o.up.normalized();
    std::vector<View> views{make_view(o.view, up)};
    if (!o.contact_sheet) return views;
    const Vec3 front = (o.view - o.view.dot(up) * up).normalized();
    views.push_back(make_view(front, up));
    views.push_back(make_view(up.cross(front), up));
    views.push_back(make_view(up, -front));
    return views;
}

constexpr double kAmbient = 0.3, kDiffuse = 0.7, kOutline = 0.7;
const Vec3 kBackground(0.93, 0.94, 0.96);
const Vec3 kCutAwayGrey(0.78, 0.78, 0.8);  // the object's far walls behind the cracks

// One view drawn into its own buffers (z-buffer, piece id, colour), then outlined.
struct ViewImage {
    int w, h;
    std::vector<double> depth;
    std::vector<long long> key;  // fragment index << 32 | triangle: the tie-break and the outline
    std::vector<Vec3> colour;
    ViewImage(int w_, int h_)
        : w(w_), h(h_), depth(std::size_t(w_) * std::size_t(h_), -std::numeric_limits<double>::infinity()),
          key(depth.size(), -1), colour(depth.size(), kBackground) {}
};

// `cancel` is polled per pixel row: one triangle may cover most of a large view.
void draw_triangle(ViewImage& img, const std::array<Vec3, 3>& s, long long key, const Vec3& rgb, const CancelToken& cancel) {
    const double x0 = std::min({s[0].x(), s[1].x(), s[2].x()}), x1 = std::max({s[0].x(), s[1].x(), s[2].x()});
    const double y0 = std::min({s[0].y(), s[1].y(), s[2].y()}), y1 = std::max({s[0].y(), s[1].y(), s[2].y()});
    const int px0 = std::max(0, int(std::ceil(x0 - 0.5))), px1 = std::min(img.w - 1, int(std::floor(x1 - 0.5)));
    const int py0 = std::max(0, int(std::ceil(y0 - 0.5))), py1 = std::min(img.h - 1, int(std::floor(y1 - 0.5)));
    const double area = (s[1].x() - s[0].x()) * (s[2].y() - s[0].y()) - (s[2].x() - s[0].x()) * (s[1].y() - s[0].y());
    if (!(std::abs(area) > 0)) return;
    for (int py = py0; py <= py1; ++py) {
        if (py1 > py0 + 16) cancel.poll();
        for (int px = px0; px <= px1; ++px) {
            const double x = px + 0.5, y = py + 0.5;
            double w[3];
            for (int k = 0; k < 3; ++k) {
                const Vec3 &a = s[(k + 1) % 3], &b = s[(k + 2) % 3];
                w[k] = ((b.x() - a.x()) * (y - a.y()) - (x - a.x()) * (b.y() - a.y())) / area;
            }
            if (w[0] < 0 || w[1] < 0 || w[2] < 0) continue;
            const double z = w[0] * s[0].z() + w[1] * s[1].z() + w[2] * s[2].z();
            const std::size_t p = std::size_t(py) * std::size_t(img.w) + std::size_t(px);
            if (z > img.depth[p] || (z == img.depth[p] && key < img.key[p])) {
                img.depth[p] = z;
                img.key[p] = key;
                img.colour[p] = rgb;
            }
        }
    }
}

// Darkens a piece's pixels next to another piece or the background (4-neighbourhood).
void outline(ViewImage& img, const CancelToken& cancel) {
    std::vector<Vec3> out = img.colour;
    auto piece = [&](int x, int y) { return img.key[std::size_t(y) * std::size_t(img.w) + std::size_t(x)] >> 32; };
    for (int y = 0; y < img.h; ++y) {
        cancel.poll();
        for (int x = 0; x < img.w; ++x) {
            const std::size_t p = std::size_t(y) * std::size_t(img.w) + std::size_t(x);
            if (img.key[p] < 0) continue;
            const long long me = piece(x, y);
            const bool edge = (x > 0 && piece(x - 1, y) != me) || (x + 1 < img.w && piece(x + 1, y) != me) ||
                              (y > 0 && piece(x, y - 1) != me) || (y + 1 < img.h && piece(x, y + 1) != me);
            if (edge) out[p] = kOutline * img.colour[p];
        }
    }
    img.colour = std::move(out);
}

// One mesh of a sheet: where it is drawn, in which colours, which of its faces.
struct SheetItem {
    const SurfaceMesh* mesh = nullptr;
    Vec3 shift = Vec3::Zero();   // [m] added to its vertices (the explode)
    Vec3 colour, inside_colour;  // of its faces, and of those in the region "inside"
    bool back_faces = false;     // draw the faces turned away from the camera (lit from behind) instead of the front ones
    bool framed = true;          // the views are framed on the items that have this set
};

ViewImage render_view(const std::vector<SheetItem>& items, const Vec3& centre, double pixels_per_metre, const View& v,
                      int w, int h, const CancelToken& cancel) {
    ViewImage img(w, h);
    const Vec3 light = (-1.0 * v.r + 1.0 * v.u + 1.5 * v.d).normalized();
    for (std::size_t i = 0; i < items.size(); ++i) {
        cancel.poll();
        const SheetItem& item = items[i];
        const SurfaceMesh& m = *item.mesh;
        const int inside = region_id(m, "inside");
        const double facing = item.back_faces ? -1 : 1;
        for (std::size_t t = 0; t < m.triangles.size(); ++t) {
            const Vec3 n = facing * triangle_normal(m, t);
            if (!(n.dot(v.d) > 0)) continue;  // closed meshes: back faces are hidden (or, cut away, the front ones)
            std::array<Vec3, 3> s;
            for (int k = 0; k < 3; ++k) {
                const Vec3 q = m.vertices[std::size_t(m.triangles[t][k])] + item.shift - centre;
                s[k] = Vec3(0.5 * w + q.dot(v.r) * pixels_per_metre, 0.5 * h - q.dot(v.u) * pixels_per_metre, q.dot(v.d));
            }
            const Vec3 base = inside >= 0 && m.region_of(t) == inside ? item.inside_colour : item.colour;
            const Vec3 rgb = (base * (kAmbient + kDiffuse * std::max(0.0, n.dot(light)))).cwiseMin(1.0);
            draw_triangle(img, s, (static_cast<long long>(i) << 32) | static_cast<long long>(t), rgb, cancel);
        }
    }
    outline(img, cancel);
    return img;
}

void check_sheet_options(const SheetOptions& o) {
    if (o.width < 16 || o.height < 16 || o.width > 8192 || o.height > 8192)
        throw std::invalid_argument("preview size must be between 16 and 8192 pixels per side");
    PreviewOptions camera;
    camera.up = o.up;
    camera.view = o.view;
    if (const std::string problem = preview_camera_problem(camera); !problem.empty())
        throw std::invalid_argument("preview camera: " + problem);
}

// The sheet of `items`, framed on the items marked `framed`.
std::vector<unsigned char> render_sheet(const std::vector<SheetItem>& items, const SheetOptions& o, int* sheet_width,
                                        int* sheet_height) {
    const CancelToken cancel = CancelToken::current();
    // The scene's centre and radius after the explode: one scale for every view.
    Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    for (std::size_t i = 0; i < items.size(); ++i)
        if (items[i].framed)
            for (const Vec3& p : items[i].mesh->vertices) {
                lo = lo.cwiseMin(p + items[i].shift);
                hi = hi.cwiseMax(p + items[i].shift);
            }
    if (!(lo.allFinite() && hi.allFinite())) throw std::invalid_argument("the meshes to preview have no vertices");
    const Vec3 centre = 0.5 * (lo + hi);
    const double radius = std::max(0.5 * (hi - lo).norm(), 1e-300);
    const int cols = o.contact_sheet ? 2 : 1, W = o.width, H = o.height, vw = W / cols, vh = H / cols;
    const double scale = 0.48 * std::min(vw, vh) / radius;
    const std::vector<View> views = sheet_views(o);
    std::vector<ViewImage> images(views.size(), ViewImage(1, 1));
    tbb::parallel_for(std::size_t(0), views.size(), [&](std::size_t k) {
        images[k] = render_view(items, centre, scale, views[k], vw, vh, cancel);
    });
    // An odd width or height leaves a last column or row of background.
    std::vector<unsigned char> rgb(std::size_t(W) * std::size_t(H) * 3);
    for (std::size_t p = 0; p < std::size_t(W) * std::size_t(H); ++p)
        for (int ch = 0; ch < 3; ++ch) rgb[3 * p + std::size_t(ch)] = (unsigned char)std::lround(255.0 * kBackground[ch]);
    for (std::size_t k = 0; k < images.size(); ++k) {
        const int ox = int(k % 2) * vw, oy = int(k / 2) * vh;
        for (int y = 0; y < vh; ++y) {
            cancel.poll();
            for (int x = 0; x < vw; ++x) {
                Vec3 col = images[k].colour[std::size_t(y) * std::size_t(vw) + std::size_t(x)];
                // A 1-pixel grey rule between the views of the sheet.
                if (o.contact_sheet && ((x == 0 && ox > 0) || (y == 0 && oy > 0))) col = Vec3(0.6, 0.6, 0.62);
                unsigned char* px = &rgb[(std::size_t(oy + y) * std::size_t(W) + std::size_t(ox + x)) * 3];
                for (int ch = 0; ch < 3; ++ch) px[ch] = (unsigned char)std::lround(255.0 * std::clamp(col[ch], 0.0, 1.0));
            }
        }
    }
    if (sheet_width) *sheet_width = W;
    if (sheet_height) *sheet_height = H;
    return rgb;
}

}  // namespace

std::vector<unsigned char> render_fragment_sheet(const std::vector<SurfaceMesh>& meshes,
                                                 const std::vector<Vec3>& centroids, const SheetOptions& o,
                                                 int* sheet_width, int* sheet_height) {
    if (meshes.empty()) throw std::invalid_argument("no fragments to render");
    if (centroids.size() != meshes.size()) throw std::invalid_argument("one centroid per fragment mesh is needed");
    check_sheet_options(o);
    Vec3 c = Vec3::Zero();
    for (const Vec3& p : centroids) c += p;
    c /= double(centroids.size());
    std::vector<SheetItem> items(meshes.size());
    for (std::size_t i = 0; i < meshes.size(); ++i) {
        items[i].mesh = &meshes[i];
        items[i].shift = o.explode * (centroids[i] - c);
        items[i].colour = fragment_colour(i);
        items[i].inside_colour = fragment_inside_colour(i);
    }
    return render_sheet(items, o, sheet_width, sheet_height);
}

std::vector<unsigned char> render_crack_sheet(const SurfaceMesh& object, const std::vector<SurfaceMesh>& cracks,
                                              const SheetOptions& o, int* sheet_width, int* sheet_height) {
    check_sheet_options(o);
    std::vector<SheetItem> items;
    SheetItem far_walls;
    far_walls.mesh = &object;
    far_walls.colour = far_walls.inside_colour = kCutAwayGrey;
    far_walls.back_faces = true;
    items.push_back(far_walls);
    for (std::size_t i = 0; i < cracks.size(); ++i) {
        SheetItem crack;
        crack.mesh = &cracks[i];
        crack.colour = crack.inside_colour = fragment_colour(i);
        crack.framed = false;  // the same framing at every step: the object's
        items.push_back(crack);
    }
    return render_sheet(items, o, sheet_width, sheet_height);
}

void write_crack_sheet(const std::filesystem::path& png, const SurfaceMesh& object, const std::vector<SurfaceMesh>& cracks,
                       const SheetOptions& o) {
    int w = 0, h = 0;
    const std::vector<unsigned char> rgb = render_crack_sheet(object, cracks, o, &w, &h);
    write_png_rgb(png, w, h, rgb.data());
}

void write_fragment_sheet(const std::filesystem::path& png, const std::vector<SurfaceMesh>& meshes,
                          const std::vector<Vec3>& centroids, const SheetOptions& o) {
    int w = 0, h = 0;
    const std::vector<unsigned char> rgb = render_fragment_sheet(meshes, centroids, o, &w, &h);
    write_png_rgb(png, w, h, rgb.data());
}

}  // namespace cf
