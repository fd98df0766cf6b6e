// Scene preview images (nodes/rigid/scene_preview.hpp) against hand-computed truth: a unit cube
// seen face-on covers the square the pinhole model predicts, in its shaded colour; hidden pieces
// are not drawn; the z-buffer, not the piece order, decides occlusion; the ground shows 1 m
// squares; near-plane clipping; identical bytes for repeated runs and 1 or 2 threads; camera
// problems named; the PNG file.
#include "nodes/rigid/scene_preview.hpp"
#include "nodes/domain/fragment_palette.hpp"
#include "nodes/shape/box.hpp"
#include "nodes/shape/icosphere.hpp"

#include <gtest/gtest.h>

#include <tbb/global_control.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <memory>
#include <stdexcept>
#include <unistd.h>  // getpid

using namespace cf;
using namespace cf::rigid;
namespace fs = std::filesystem;

namespace {

constexpr double kPi = 3.14159265358979323846;

std::shared_ptr<const SurfaceMesh> cube(double size = 1, int subdivisions = 4) {
    BoxSpec spec;
    spec.size = Vec3::Constant(size);
    spec.subdivisions = subdivisions;  // > 1: interior edges, where a rasteriser could leave cracks
    return std::make_shared<const SurfaceMesh>(make_box(spec));
}

int add_piece(Animation& a, const std::string& name, std::shared_ptr<const SurfaceMesh> mesh, int parent = -1) {
    AnimationPiece p;
    p.name = name;
    p.parent = parent;
    p.rest_mesh = std::move(mesh);
    a.pieces.push_back(p);
    return int(a.pieces.size()) - 1;
}

PiecePose at(const Vec3& position, const Eigen::Quaterniond& rotation = Eigen::Quaterniond::Identity()) {
    PiecePose pose;
    pose.position = position;
    pose.rotation = rotation;
    return pose;
}

// The camera on the +x axis at distance d looking at the origin, z up.
SceneCamera from_plus_x(double d) {
    SceneCamera c;
    c.position = Vec3(d, 0, 0);
    c.target = Vec3::Zero();
    c.up = Vec3::UnitZ();
    return c;
}

std::vector<unsigned char> render(const Animation& a, std::size_t f, const SceneCamera& c, bool ground = false,
                                  const Vec3& ground_point = Vec3::Zero(), const Vec3& ground_normal = Vec3::UnitZ()) {
    return render_scene_image(a, f, c, ground_point, ground_normal, ground);
}

// The image of an empty frame: sky only.
std::vector<unsigned char> background(const SceneCamera& c) {
    Animation empty;
    empty.frames.resize(1);
    return render(empty, 0, c);
}

struct Rgb {
    int r, g, b;
};
Rgb pixel(const std::vector<unsigned char>& image, const SceneCamera& c, int x, int y) {
    const std::size_t p = 3 * (std::size_t(y) * std::size_t(c.width) + std::size_t(x));
    return {image[p], image[p + 1], image[p + 2]};
}
bool same_pixel(const std::vector<unsigned char>& a, const std::vector<unsigned char>& b, const SceneCamera& c, int x,
                int y) {
    const Rgb pa = pixel(a, c, x, y), pb = pixel(b, c, x, y);
    return pa.r == pb.r && pa.g == pb.g && pa.b == pb.b;
}

// What the renderer promises for a face with unit normal n facing the camera.
Rgb expected_shade(const Vec3& colour, double n_dot_light) {
    const double s = kSceneAmbient + kSceneDiffuse * std::max(0.0, n_dot_light);
    auto byte = [&](double v) { return int(std::lround(255 * std::clamp(v * s, 0.0, 1.0))); };
    return {byte(colour.x()), byte(colour.y()), byte(colour.z())};
}

void expect_near(const Rgb& got, const Rgb& want, int tolerance, const std::string& what) {
    EXPECT_NEAR(got.r, want.r, tolerance) << what;
    EXPECT_NEAR(got.g, want.g, tolerance) << what;
    EXPECT_NEAR(got.b, want.b, tolerance) << what;
}

// Pinhole projection by hand: pixel (column, row) of world point x.
std::pair<int, int> project(const SceneCamera& c, const Vec3& x) {
    const Vec3 forward = (c.target - c.position).normalized();
    const Vec3 right = forward.cross(c.up.normalized()).normalized();
    const Vec3 up = right.cross(forward);
    const Vec3 d = x - c.position;
    const double f = 0.5 * c.height / std::tan(0.5 * c.fov_degrees * kPi / 180);
    const double sx = 0.5 * c.width + f * d.dot(right) / d.dot(forward);
    const double sy = 0.5 * c.height - f * d.dot(up) / d.dot(forward);
    return {int(std::floor(sx)), int(std::floor(sy))};
}

double hue_degrees(const Vec3& rgb) {
    const double mx = rgb.maxCoeff(), mn = rgb.minCoeff(), c = mx - mn;
    if (c <= 0) return 0;
    double h;
    if (mx == rgb.x()) h = std::fmod((rgb.y() - rgb.z()) / c, 6.0);
    else if (mx == rgb.y()) h = (rgb.z() - rgb.x()) / c + 2;
    else h = (rgb.x() - rgb.y()) / c + 4;
    h *= 60;
    return h < 0 ? h + 360 : h;
}
double hue_distance(double a, double b) {
    const double d = std::abs(a - b);
    return std::min(d, 360 - d);
}

// A scene of many pieces of two kinds, deterministic positions and rotations.
Animation crowd(int pieces, std::shared_ptr<const SurfaceMesh> a, std::shared_ptr<const SurfaceMesh> b) {
    Animation anim;
    anim.frames.resize(1);
    for (int i = 0; i < pieces; ++i) {
        const int parent = i >= 10 ? i % 10 : -1;  // 10 bodies and their fragments
        const std::string name = parent < 0 ? "body" + std::to_string(i)
                                            : anim.pieces[std::size_t(parent)].name + "." + std::to_string(i);
        add_piece(anim, name, i % 2 ? a : b, parent);
        const double u = std::fmod(0.5 + i * 0.7548776662466927, 1.0), v = std::fmod(0.5 + i * 0.5698402909980532, 1.0);
        const double w = std::fmod(0.5 + i * 0.6180339887498949, 1.0);
        const Eigen::Quaterniond q(Eigen::AngleAxisd(6.283 * w, Vec3(u, v, 1 - w).normalized()));
        anim.frames[0].poses.emplace_back(i, at(Vec3(3 * u - 1.5, 3 * v - 1.5, 1.2 * w), q));
    }
    return anim;
}

}  // namespace

TEST(ScenePreview, UnitCubeFaceOnCoversThePinholeSquareInItsShadedColour) {
    Animation a;
    add_piece(a, "cube", cube());
    a.frames.resize(1);
    a.frames[0].poses.emplace_back(0, at(Vec3::Zero()));
    const double d = 4;
    const SceneCamera c = from_plus_x(d);
    const std::vector<unsigned char> image = render(a, 0, c), sky = background(c);
    ASSERT_EQ(image.size(), std::size_t(3 * 640 * 480));

    // The face x = +0.5 at depth d - 0.5 is the silhouette (the back edges project smaller).
    const double f = 0.5 * c.height / std::tan(0.5 * c.fov_degrees * kPi / 180);
    const double h = f * 0.5 / (d - 0.5);  // half-width [pixels], 94.2 here
    long covered = 0;
    int misplaced = 0;
    for (int y = 0; y < c.height; ++y)
        for (int x = 0; x < c.width; ++x) {
            const bool drawn = !same_pixel(image, sky, c, x, y);
            covered += drawn;
            const double r = std::max(std::abs(x + 0.5 - 0.5 * c.width), std::abs(y + 0.5 - 0.5 * c.height));
            if ((r < h - 1 && !drawn) || (r > h + 1 && drawn)) ++misplaced;
        }
    EXPECT_EQ(misplaced, 0) << "pixels more than one pixel inside the square not drawn, or outside it drawn";
    EXPECT_GE(covered, long(std::pow(2 * (h - 1), 2)));
    EXPECT_LE(covered, long(std::pow(2 * (h + 1), 2)));

    // Light by hand: right = +y, up = +z, back = +x, so light = (1.5, -1, 1) / sqrt(4.25).
    const Vec3 light = scene_light_direction(c);
    EXPECT_NEAR((light - Vec3(1.5, -1, 1) / std::sqrt(4.25)).norm(), 0, 1e-12);
    const double n_dot_light = 1.5 / std::sqrt(4.25);  // face normal +x
    expect_near(pixel(image, c, 320, 240), expected_shade(scene_piece_colours(a)[0], n_dot_light), 1, "centre pixel");

    // Corners are sky: the same as an empty frame's, bluer at the top than at the bottom.
    for (const auto& [x, y] : {std::pair{0, 0}, {639, 0}, {0, 479}, {639, 479}})
        EXPECT_TRUE(same_pixel(image, sky, c, x, y)) << x << ", " << y;
    EXPECT_GT(pixel(sky, c, 0, 0).b - pixel(sky, c, 0, 0).r, pixel(sky, c, 0, 479).b - pixel(sky, c, 0, 479).r);
}

// A fracture face (region "inside") is drawn in the inside shade of the piece's colour, the rest of
// the piece in the colour itself: the cube seen from +x with its +x face's upper half tagged.
TEST(ScenePreview, FractureFacesAreDrawnInTheInsideShade) {
    auto m = std::make_shared<SurfaceMesh>(*cube());
    m->region.assign(m->num_triangles(), 0);
    m->region_names = {"outside", "inside"};
    for (std::size_t t = 0; t < m->num_triangles(); ++t)
        if (triangle_normal(*m, t).x() > 0.99 && triangle_centroid(*m, t).z() > 0) m->region[t] = 1;
    Animation a;
    add_piece(a, "cube", m);
    a.frames.resize(1);
    a.frames[0].poses.emplace_back(0, at(Vec3::Zero()));
    const SceneCamera c = from_plus_x(4);
    const std::vector<unsigned char> image = render(a, 0, c);
    const double n_dot_light = 1.5 / std::sqrt(4.25);  // face normal +x, as in the face-on test
    const Vec3 colour = scene_piece_colours(a)[0];
    expect_near(pixel(image, c, 320, 200), expected_shade(inside_shade(colour), n_dot_light), 1, "upper half: inside");
    expect_near(pixel(image, c, 320, 280), expected_shade(colour, n_dot_light), 1, "lower half: outside");
}

TEST(ScenePreview, PieceWithoutPoseInTheFrameIsNotDrawn) {
    Animation a;
    add_piece(a, "stays", cube());
    add_piece(a, "leaves", cube());
    a.pieces[1].last_frame = 0;
    a.frames.resize(2);
    a.frames[1].time = 0.04;
    a.frames[0].poses = {{0, at(Vec3::Zero())}, {1, at(Vec3(0, 2, 0))}};
    a.frames[1].poses = {{0, at(Vec3::Zero())}};
    const SceneCamera c = from_plus_x(6);
    const std::vector<unsigned char> sky = background(c);
    const auto [bx, by] = project(c, Vec3(0.5, 2, 0));  // centre of the piece's front face
    ASSERT_LT(bx, c.width - 20);
    const std::vector<unsigned char> frame0 = render(a, 0, c), frame1 = render(a, 1, c);
    expect_near(pixel(frame0, c, bx, by), expected_shade(scene_piece_colours(a)[1], 1.5 / std::sqrt(4.25)), 1,
                "frame 0: the piece is there");
    EXPECT_TRUE(same_pixel(frame1, sky, c, bx, by)) << "frame 1: the piece has no pose and must not be drawn";
    EXPECT_TRUE(same_pixel(frame0, frame1, c, 320, 240)) << "the other piece is drawn in both";
    EXPECT_FALSE(same_pixel(frame1, sky, c, 320, 240));
}

TEST(ScenePreview, NearerPieceOccludesFartherWhateverTheOrder) {
    const SceneCamera c = from_plus_x(6);
    for (const bool near_first : {true, false}) {
        // The far cube is larger, so it shows around the near one; poses go in piece order, so
        // the second case draws the near cube first.
        Animation a;
        int n, far;
        if (near_first) {
            n = add_piece(a, "near", cube());
            far = add_piece(a, "far", cube(1.5));
        } else {
            far = add_piece(a, "far", cube(1.5));
            n = add_piece(a, "near", cube());
        }
        a.frames.resize(1);
        for (int i = 0; i < 2; ++i) a.frames[0].poses.emplace_back(i, at(i == n ? Vec3(1, 0, 0) : Vec3(-1, 0, 0)));
        const std::vector<Vec3> colours = scene_piece_colours(a);
        const Vec3 near_colour = colours[std::size_t(n)], far_colour = colours[std::size_t(far)];
        ASSERT_GT((near_colour - far_colour).cwiseAbs().maxCoeff(), 0.1) << "pick names with different colours";
        const std::vector<unsigned char> image = render(a, 0, c);
        const double s = 1.5 / std::sqrt(4.25);
        expect_near(pixel(image, c, 320, 240), expected_shade(near_colour, s), 1, "centre: the near cube");
        // Beyond the near cube's silhouette (half-width f * 0.5 / 4.5 = 73 px) but inside the far
        // one's (f * 0.75 / 6.25 = 79 px): the far cube.
        expect_near(pixel(image, c, 320 + 76, 240), expected_shade(far_colour, s), 1, "the far cube around it");
    }
}

TEST(ScenePreview, GroundShowsMetreSquaresAndHidesWhatIsBelowIt) {
    Animation a;
    add_piece(a, "sunk", cube());
    a.frames.resize(1);
    a.frames[0].poses.emplace_back(0, at(Vec3(0, 0, 0)));  // half below the ground z = 0
    SceneCamera c;
    c.position = Vec3(6, 0, 2);
    c.target = Vec3(0, 0, 0);
    const std::vector<unsigned char> with = render(a, 0, c, true), without = render(a, 0, c, false);
    // Above the ground: the cube's top half is drawn the same either way.
    const auto [ux, uy] = project(c, Vec3(0.5, 0, 0.25));
    EXPECT_TRUE(same_pixel(with, without, c, ux, uy));
    // Its lower half is below the ground: ground there, grey (r, g, b within a few percent).
    const auto [lx, ly] = project(c, Vec3(0.5, 0, -0.25));
    EXPECT_FALSE(same_pixel(with, without, c, lx, ly));
    const Rgb g = pixel(with, c, lx, ly);
    EXPECT_LT(std::max({g.r, g.g, g.b}) - std::min({g.r, g.g, g.b}), 12);
    // Squares of 1 m from the ground point, light where floor(x) + floor(y) is even: (1.5, -0.5)
    // and (2.5, 0.5) light, (1.5, 0.5) and (2.5, -0.5) dark.
    auto at_ground = [&](double x, double y) {
        const auto [px, py] = project(c, Vec3(x, y, 0));
        const Rgb p = pixel(with, c, px, py);
        return p.r + p.g + p.b;
    };
    const int light1 = at_ground(1.5, -0.5), light2 = at_ground(2.5, 0.5);
    const int dark1 = at_ground(1.5, 0.5), dark2 = at_ground(2.5, -0.5);
    EXPECT_GT(std::min(light1, light2), std::max(dark1, dark2) + 15) << light1 << " " << light2 << " " << dark1 << " "
                                                                       << dark2;
    // The sky at the top is untouched.
    EXPECT_TRUE(same_pixel(with, without, c, 320, 0));
}

TEST(ScenePreview, GeometryThroughTheCameraPlaneIsClipped) {
    // A 20 m slab of two triangles per face whose top face runs from behind the camera to far
    // in front of it: projecting without near-plane clipping would fold it across the image.
    Animation a;
    BoxSpec slab;
    slab.size = Vec3(20, 20, 0.1);
    slab.subdivisions = 1;
    add_piece(a, "slab", std::make_shared<const SurfaceMesh>(make_box(slab)));
    a.frames.resize(1);
    a.frames[0].poses.emplace_back(0, at(Vec3(0, 0, -0.05)));  // top face at z = 0
    SceneCamera c;
    c.position = Vec3(0, 0, 1);
    c.target = Vec3(5, 0, 0.5);
    const std::vector<unsigned char> image = render(a, 0, c), sky = background(c);
    // Below the horizon the top face (normal +z), above it the sky.
    const Vec3 light = scene_light_direction(c);
    expect_near(pixel(image, c, 320, 470), expected_shade(scene_piece_colours(a)[0], light.z()), 1, "slab top");
    EXPECT_TRUE(same_pixel(image, sky, c, 320, 5));
}

TEST(ScenePreview, BodiesTakeWellSeparatedHuesAndFragmentsShadesOfThem) {
    Animation a;
    const char* names[] = {"rock", "vase", "plate", "pillar", "block", "wall"};
    for (const char* name : names) add_piece(a, name, cube());
    for (int k = 0; k < 8; ++k) add_piece(a, "rock." + std::to_string(k), cube(), 0);
    for (int k = 0; k < 3; ++k) add_piece(a, "rock.3." + std::to_string(k), cube(), 6 + 3);  // of rock.3
    const std::vector<Vec3> colour = scene_piece_colours(a);
    ASSERT_EQ(colour.size(), a.pieces.size());
    // Six hues a golden angle apart are at least 32.5 degrees apart.
    for (int i = 0; i < 6; ++i)
        for (int j = 0; j < i; ++j)
            EXPECT_GE(hue_distance(hue_degrees(colour[i]), hue_degrees(colour[j])), 32) << names[i] << ", " << names[j];
    const double rock = hue_degrees(colour[0]);
    for (std::size_t i = 6; i < a.pieces.size(); ++i) {
        EXPECT_LE(hue_distance(hue_degrees(colour[i]), rock), 6 + 1e-9) << a.pieces[i].name;
        EXPECT_GT((colour[i] - colour[0]).cwiseAbs().maxCoeff(), 0.02) << a.pieces[i].name;
        for (std::size_t j = 6; j < i; ++j)
            EXPECT_GT((colour[i] - colour[j]).cwiseAbs().maxCoeff(), 0.02)
                << a.pieces[i].name << " vs " << a.pieces[j].name;
    }
    EXPECT_TRUE(scene_piece_colours(a) == colour) << "deterministic";
    a.pieces[7].parent = 7;
    EXPECT_THROW(scene_piece_colours(a), std::invalid_argument);
}

TEST(ScenePreview, BytesAreIdenticalForRepeatedRunsAndAnyThreadCount) {
    SphereSpec sphere;
    sphere.radius = 0.2;
    sphere.level = 3;
    BoxSpec box;
    box.size = Vec3(0.3, 0.2, 0.1);
    const Animation a = crowd(60, std::make_shared<const SurfaceMesh>(make_icosphere(sphere)),
                              std::make_shared<const SurfaceMesh>(make_box(box)));
    SceneCamera c;  // the default camera
    c.width = 320;
    c.height = 240;
    const std::vector<unsigned char> first = render(a, 0, c, true), second = render(a, 0, c, true);
    EXPECT_TRUE(first == second);
    std::vector<unsigned char> one, two;
    {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
        one = render(a, 0, c, true);
    }
    {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
        two = render(a, 0, c, true);
    }
    EXPECT_TRUE(one == first);
    EXPECT_TRUE(two == first);
    Animation empty;
    empty.frames.resize(1);
    EXPECT_FALSE(first == render(empty, 0, c, true)) << "the pieces are in view";
}

TEST(ScenePreview, BadCamerasAndInputsAreNamed) {
    EXPECT_EQ(scene_camera_problem(SceneCamera{}), "");
    auto problem = [](auto change) {
        SceneCamera c;
        change(c);
        return scene_camera_problem(c);
    };
    const double nan = std::nan("");
    EXPECT_EQ(problem([&](SceneCamera& c) { c.position.x() = nan; }).rfind("position:", 0), 0u);
    EXPECT_EQ(problem([&](SceneCamera& c) { c.target.z() = INFINITY; }).rfind("target:", 0), 0u);
    EXPECT_EQ(problem([](SceneCamera& c) { c.target = c.position; }).rfind("target:", 0), 0u);
    EXPECT_EQ(problem([](SceneCamera& c) { c.up = Vec3::Zero(); }).rfind("up:", 0), 0u);
    EXPECT_EQ(problem([](SceneCamera& c) { c.up = 3 * (c.target - c.position); }),
              "up: parallel to the view direction");
    EXPECT_EQ(problem([](SceneCamera& c) { c.up = c.position - c.target; }), "up: parallel to the view direction");
    EXPECT_EQ(problem([](SceneCamera& c) { c.fov_degrees = 0; }).rfind("fov_degrees:", 0), 0u);
    EXPECT_EQ(problem([](SceneCamera& c) { c.fov_degrees = 180; }).rfind("fov_degrees:", 0), 0u);
    EXPECT_EQ(problem([&](SceneCamera& c) { c.fov_degrees = nan; }).rfind("fov_degrees:", 0), 0u);
    EXPECT_EQ(problem([](SceneCamera& c) { c.width = 0; }).rfind("width:", 0), 0u);
    EXPECT_EQ(problem([](SceneCamera& c) { c.height = 100000; }).rfind("height:", 0), 0u);

    Animation a;
    add_piece(a, "cube", cube());
    a.frames.resize(1);
    a.frames[0].poses.emplace_back(0, at(Vec3::Zero()));
    auto message = [&](auto call) {
        try {
            call();
        } catch (const std::invalid_argument& e) {
            return std::string(e.what());
        }
        return std::string("no exception");
    };
    SceneCamera bad;
    bad.up = Vec3::Zero();
    EXPECT_NE(message([&] { render(a, 0, bad); }).find("up: zero"), std::string::npos);
    EXPECT_NE(message([&] { render(a, 1, SceneCamera{}); }).find("frame 1: out of range"), std::string::npos);
    EXPECT_NE(message([&] { render(a, 0, SceneCamera{}, true, Vec3::Zero(), Vec3::Zero()); }).find("ground_normal"),
              std::string::npos);
    EXPECT_NO_THROW(render(a, 0, SceneCamera{}, false, Vec3::Zero(), Vec3::Zero())) << "no ground, not checked";
    Animation broken = a;
    auto mesh = std::make_shared<SurfaceMesh>(*a.pieces[0].rest_mesh);
    mesh->triangles[5][1] = 1000000;
    broken.pieces[0].rest_mesh = mesh;
    EXPECT_NE(message([&] { render(broken, 0, SceneCamera{}); }).find("frame 0: piece 0 ('cube'): triangle 5"),
              std::string::npos);
}

TEST(ScenePreview, WritesAPngFileAtomically) {
    Animation a;
    add_piece(a, "cube", cube());
    a.frames.resize(1);
    a.frames[0].poses.emplace_back(0, at(Vec3::Zero()));
    const fs::path dir = fs::temp_directory_path() / ("cf_scene_preview_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    const fs::path png = dir / "frames" / "frame_0000.png";
    render_scene_preview(a, 0, SceneCamera{}, png, Vec3(0, 0, -0.5), Vec3::UnitZ(), true);
    std::ifstream in(png, std::ios::binary);
    ASSERT_TRUE(in) << png;
    unsigned char signature[8] = {};
    in.read(reinterpret_cast<char*>(signature), 8);
    const unsigned char png_signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    EXPECT_TRUE(std::equal(signature, signature + 8, png_signature));
    EXPECT_GT(fs::file_size(png), 1000u);
    int files = 0;
    for ([[maybe_unused]] const auto& e : fs::directory_iterator(png.parent_path())) ++files;
    EXPECT_EQ(files, 1) << "no temporary file left beside the PNG";
    fs::remove_all(dir);
}

// Timing, not run by ctest (--gtest_also_run_disabled_tests): a 640x480 frame with ground of 400
// pieces of ~2000 triangles each (boxes with 13 x 13 cells per face: 2028 triangles).
