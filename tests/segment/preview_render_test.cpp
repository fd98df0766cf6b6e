// The exploded preview (ch. 6.4): the camera's `up` decides which scene axis is drawn upwards,
// so a column standing along z looks tall with up = z and wide with up = x; bad cameras throw.
#include "nodes/levelset/level_set.hpp"
#include "nodes/segment/fragments.hpp"
#include "nodes/segment/preview_render.hpp"
#include "nodes/domain/fragment_palette.hpp"
#include "nodes/segment/fragment_sheet.hpp"
#include "tests/levelset/test_meshes.hpp"

#include <gtest/gtest.h>
#include <png.h>

#include <filesystem>
#include <vector>

namespace cf {
namespace {

// A 0.1 x 0.1 x 0.4 m column along z, one fragment.
const Fragments& column() {
    static const Fragments f =
        find_fragments(level_set_from_mesh(testmesh::box(Vec3(-0.05, -0.05, -0.2), Vec3(0.05, 0.05, 0.2)), 0.01));
    return f;
}

struct Silhouette {
    int width = 0, height = 0;  // of the box around the pixels that are not background [pixels]
};

Silhouette render(const PreviewOptions& opt, const std::string& name) {
    const auto png = std::filesystem::temp_directory_path() / ("crackflow_preview_" + name + ".png");
    render_fragments_preview(png, column(), opt);
    png_image img{};
    img.version = PNG_IMAGE_VERSION;
    EXPECT_TRUE(png_image_begin_read_from_file(&img, png.c_str())) << img.message;
    img.format = PNG_FORMAT_RGB;
    std::vector<unsigned char> rgb(PNG_IMAGE_SIZE(img));
    EXPECT_TRUE(png_image_finish_read(&img, nullptr, rgb.data(), 0, nullptr)) << img.message;
    std::filesystem::remove(png);
    EXPECT_EQ(int(img.width), opt.width);
    EXPECT_EQ(int(img.height), opt.height);
    // Background (0.93, 0.94, 0.96) is ~(237, 240, 245); the shaded column is warm (red > blue).
    int x0 = opt.width, x1 = -1, y0 = opt.height, y1 = -1;
    for (int y = 0; y < int(img.height); ++y)
        for (int x = 0; x < int(img.width); ++x) {
            const unsigned char* p = &rgb[3 * (std::size_t(y) * img.width + x)];
            if (int(p[0]) - int(p[2]) < 20) continue;
            x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
        }
    Silhouette s;
    if (x1 >= 0) s = {x1 - x0 + 1, y1 - y0 + 1};
    return s;
}

TEST(PreviewRender, UpAxisIsDrawnUpwards) {
    PreviewOptions z_up;  // defaults: up z, view (0.5, -1.2, 0.7)
    z_up.width = z_up.height = 160;
    const Silhouette tall = render(z_up, "z_up");
    PreviewOptions x_up = z_up;
    x_up.up = Vec3(1, 0, 0);
    x_up.view = Vec3(0.7, -1.2, 0.5);
    const Silhouette wide = render(x_up, "x_up");
    ASSERT_GT(tall.width, 0) << "the column must be visible";
    ASSERT_GT(wide.width, 0) << "the column must be visible";
    // Seen from these directions the 4:1 column projects to about 2.8:1 standing (z up) and 2:1
    // lying (x up, foreshortened along the view); swapped axes would give the inverse ratios.
    EXPECT_GT(tall.height, 1.5 * tall.width) << tall.width << " x " << tall.height;
    EXPECT_GT(wide.width, 1.5 * wide.height) << wide.width << " x " << wide.height;
}

TEST(PreviewRender, ViewParallelToUpOrZeroIsRejected) {
    const auto png = std::filesystem::temp_directory_path() / "crackflow_preview_bad.png";
    PreviewOptions o;
    o.view = Vec3(0, 0, 2);
    EXPECT_THROW(render_fragments_preview(png, column(), o), std::invalid_argument);
    o.view = Vec3(0.5, -1.2, 0.7);
    o.up = Vec3::Zero();
    EXPECT_THROW(render_fragments_preview(png, column(), o), std::invalid_argument);
    EXPECT_FALSE(std::filesystem::exists(png));
}

// The per-step crack preview: a unit cube seen along +y (one view, 200 x 200 pixels) with a thin
// crack slab |x|, |z| <= 0.3, |y| <= 0.01 in it. The cube's near wall is cut away, so the centre shows
// the crack's front face in crack 0's colour; between the crack and the cube's rim the far wall
// (y = +0.5, drawn from inside) shows in grey; outside the cube the background. Hand values: view
// d = (0, -1, 0), up u = z, right r = x; light = (-r + u + 1.5 d) / |.| = (-1, -1.5, 1) / sqrt(4.25);
// both faces seen face -y, n.light = 1.5 / sqrt(4.25); shade = 0.3 + 0.7 n.light. Scale: 0.48 x 200
// pixels over the cube's half diagonal sqrt(3)/2 m, so the cube spans +-55.4 pixels, the crack +-33.3.
TEST(CrackSheet, CrackShowsThroughTheCutAwayObjectInItsColour) {
    const SurfaceMesh cube = testmesh::box(Vec3::Constant(-0.5), Vec3::Constant(0.5));
    const std::vector<SurfaceMesh> cracks{testmesh::box(Vec3(-0.3, -0.01, -0.3), Vec3(0.3, 0.01, 0.3))};
    SheetOptions o;
    o.width = o.height = 200;
    o.contact_sheet = false;
    o.view = Vec3(0, -1, 0);
    int w = 0, h = 0;
    const std::vector<unsigned char> rgb = render_crack_sheet(cube, cracks, o, &w, &h);
    ASSERT_EQ(w, 200);
    ASSERT_EQ(h, 200);
    const double shade = 0.3 + 0.7 * 1.5 / std::sqrt(4.25);
    auto expect_pixel = [&](int x, int y, const Vec3& colour, const char* what) {
        const unsigned char* px = &rgb[(std::size_t(y) * 200 + std::size_t(x)) * 3];
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(px[k], std::lround(255 * std::min(1.0, colour[k])), 1) << what << " channel " << k;
    };
    expect_pixel(100, 100, shade * fragment_colour(0), "crack");
    expect_pixel(100 + 45, 100, shade * Vec3(0.78, 0.78, 0.8), "far wall");
    expect_pixel(100, 100 - 45, shade * Vec3(0.78, 0.78, 0.8), "far wall above the crack");
    expect_pixel(100 + 70, 100, Vec3(0.93, 0.94, 0.96), "background");
    // Without cracks only the far walls; an empty object is refused.
    const std::vector<unsigned char> empty = render_crack_sheet(cube, {}, o);
    const unsigned char* px = &empty[(100 * 200 + 100) * 3];
    EXPECT_NEAR(px[0], std::lround(255 * shade * 0.78), 1);
    EXPECT_THROW(render_crack_sheet(SurfaceMesh{}, cracks, o), std::invalid_argument);
}

}  // namespace
}  // namespace cf
