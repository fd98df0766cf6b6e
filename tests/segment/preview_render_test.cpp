// The exploded preview (ch. 6.4): the camera's `up` decides which scene axis is drawn upwards,
// so a column standing along z looks tall with up = z and wide with up = x; bad cameras throw.
#include "nodes/levelset/level_set.hpp"
#include "nodes/segment/fragments.hpp"
#include "nodes/segment/preview_render.hpp"
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

}  // namespace
}  // namespace cf
