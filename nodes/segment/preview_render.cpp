// OpenVDB translation unit: exploded-fragment preview via LevelSetRayTracer.
#include "nodes/segment/preview_render.hpp"

#include "graph/atomic_write.hpp"
#include "graph/cancel_token.hpp"
#include "nodes/levelset/level_set_grid.hpp"

#include <openvdb/tools/RayTracer.h>
#include <openvdb/tools/SignedFloodFill.h>

#include <png.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace cf {

void write_png_rgb(const std::filesystem::path& path, int width, int height, const unsigned char* rgb) {
    graph::write_atomically_via_path(path, [&](const std::filesystem::path& tmp) {
        png_image img{};
        img.version = PNG_IMAGE_VERSION;
        img.width = png_uint_32(width);
        img.height = png_uint_32(height);
        img.format = PNG_FORMAT_RGB;
        if (!png_image_write_to_file(&img, tmp.c_str(), 0, rgb, 0, nullptr))
            throw std::runtime_error("cannot write PNG " + path.string() + ": " + img.message);
    });
}

namespace {

// Lambert shading with a key light from the camera's upper left and a weaker fill light from its
// lower right, clamped to [0, 1] (Film::convertToBitBuffer does not clamp), warm base colour.
class LambertShader : public openvdb::tools::BaseShader {
public:
    // `back` points from the scene to the camera, `up` is the image's vertical (unit, orthogonal).
    LambertShader(const openvdb::Vec3R& back, const openvdb::Vec3R& up) {
        const openvdb::Vec3R right = up.cross(back);
        key_ = (-0.4 * right + 0.6 * up + 0.8 * back).unit();
        fill_ = (0.7 * right + 0.2 * up + 0.4 * back).unit();
    }
    openvdb::tools::Film::RGBA operator()(const openvdb::Vec3R&, const openvdb::Vec3R& normal,
                                          const openvdb::Vec3R& dir) const override {
        openvdb::Vec3R n = normal;
        if (n.dot(dir) > 0) n = -n;  // face the camera
        const double light = 0.15 + 0.75 * std::max(0.0, n.dot(key_)) + 0.25 * std::max(0.0, n.dot(fill_));
        auto c = [&](double base) { return float(std::clamp(base * light, 0.0, 1.0)); };
        return openvdb::tools::Film::RGBA(c(0.95), c(0.62), c(0.35), 1.0f);
    }
    BaseShader* copy() const override { return new LambertShader(*this); }

private:
    openvdb::Vec3R key_, fill_;
};

}  // namespace

std::string preview_camera_problem(const PreviewOptions& opt) {
    if (!opt.up.allFinite() || !(opt.up.norm() > 0)) return "'up' must be a finite non-zero vector, e.g. [0, 0, 1]";
    if (!opt.view.allFinite() || !(opt.view.norm() > 0)) return "'view' must be a finite non-zero vector";
    if (opt.up.cross(opt.view).norm() < 1e-3 * opt.up.norm() * opt.view.norm())
        return "'view' is parallel to 'up'; tilt it, e.g. [0.5, -1.2, 0.7] for z up";
    return "";
}

void render_fragments_preview(const std::filesystem::path& png, const Fragments& fr, const PreviewOptions& opt) {
    if (fr.fragments.empty()) throw std::invalid_argument("no fragments to render");
    if (opt.width < 16 || opt.height < 16 || opt.width > 8192 || opt.height > 8192)
        throw std::invalid_argument("preview size must be between 16 and 8192 pixels per side");
    if (const std::string problem = preview_camera_problem(opt); !problem.empty())
        throw std::invalid_argument("preview camera: " + problem);
    const double up_norm = opt.up.norm(), view_norm = opt.view.norm();
    ensure_openvdb_initialized();
    const CancelToken cancel = CancelToken::current();  // polled per fragment copied and per image row
    const double r_f = fr.voxel_size;
    // Common centroid (volume weighted), then each fragment shifted by a whole number of voxels.
    Vec3 c = Vec3::Zero();
    double v = 0;
    for (const Fragment& f : fr.fragments) {
        c += f.volume * f.centroid;
        v += f.volume;
    }
    c /= v > 0 ? v : 1;
    const float bg = float(fr.fragments[0].grid.background());
    auto scene = openvdb::FloatGrid::create(bg);
    scene->setTransform(openvdb::math::Transform::createLinearTransform(r_f));
    scene->setGridClass(openvdb::GRID_LEVEL_SET);
    auto acc = scene->getAccessor();
    for (const Fragment& f : fr.fragments) {
        cancel.poll();
        const Vec3 shift = opt.explode * (f.centroid - c) / r_f;
        const openvdb::Coord off(int(std::lround(shift.x())), int(std::lround(shift.y())), int(std::lround(shift.z())));
        for (auto it = grid_of(f.grid).cbeginValueOn(); it; ++it) {
            const openvdb::Coord ijk = it.getCoord() + off;
            const float value = *it;
            if (!acc.isValueOn(ijk) || value < acc.getValue(ijk)) acc.setValue(ijk, value);
        }
    }
    openvdb::tools::signedFloodFill(scene->tree());
    const openvdb::CoordBBox bb = scene->evalActiveVoxelBoundingBox();
    const openvdb::Vec3d lo = scene->indexToWorld(bb.min()), hi = scene->indexToWorld(bb.max());
    const openvdb::Vec3d centre = 0.5 * (lo + hi);
    const double radius = 0.5 * (hi - lo).length();
    openvdb::tools::Film film(size_t(opt.width), size_t(opt.height), openvdb::tools::Film::RGBA(0.93f, 0.94f, 0.96f, 1.0f));
    const double fov_focal = 50.0;  // 50 mm lens on the default 41.2 mm aperture: ~45 degrees
    const double distance = radius / std::tan(0.5 * 0.69) * 1.1;
    const Vec3 view = opt.view / view_norm, up = opt.up / up_norm;
    const openvdb::Vec3d eye = centre + distance * openvdb::Vec3d(view.x(), view.y(), view.z());
    openvdb::tools::PerspectiveCamera cam(film, openvdb::Vec3R(0.0), eye, fov_focal);
    cam.lookAt(centre, openvdb::Vec3R(up.x(), up.y(), up.z()));
    const Vec3 image_up = (up - up.dot(view) * view).normalized();
    LambertShader shader(openvdb::Vec3R(view.x(), view.y(), view.z()),
                         openvdb::Vec3R(image_up.x(), image_up.y(), image_up.z()));
    // rayTrace() renders all rows in one call; the same tracer driven row by row can stop between
    // rows (a row of 8192 pixels at 16 samples is well under 0.1 s). Each task gets its own copy,
    // as LevelSetRayTracer::render gives each of its tasks.
    const openvdb::tools::LevelSetRayTracer<openvdb::FloatGrid> tracer(*scene, shader, cam,
                                                                        size_t(std::max(1, opt.samples_per_pixel)), 0);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, size_t(opt.height)), [&](const tbb::blocked_range<size_t>& rows) {
        const openvdb::tools::LevelSetRayTracer<openvdb::FloatGrid> local(tracer);
        for (size_t j = rows.begin(); j != rows.end(); ++j) {
            cancel.poll();
            local(tbb::blocked_range<size_t>(j, j + 1));
        }
    });
    auto buffer = film.convertToBitBuffer<unsigned char>(false);
    write_png_rgb(png, opt.width, opt.height, buffer.get());
}

}  // namespace cf
