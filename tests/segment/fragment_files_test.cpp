// The surface mesher's files read back by independent readers (VTK's OBJ, PLY and glTF readers,
// the Khronos glTF validator), and the preview's colours: the textured box of textured_box.hpp
// cut into four fragments and written by export_fragments.
#include "nodes/domain/fragment_palette.hpp"
#include "nodes/import/read_mesh.hpp"
#include "nodes/levelset/crack_grids.hpp"
#include "nodes/segment/fragment_export.hpp"
#include "nodes/segment/fragment_sheet.hpp"
#include "nodes/segment/preview_render.hpp"
#include "nodes/segment/surface_fragments.hpp"
#include "tests/segment/textured_box.hpp"

#include "tests/harness/shell_command.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>

namespace cf {
namespace {

namespace fs = std::filesystem;
using namespace textured_box;
using testing::CommandResult;
using testing::run_command;
using testing::shell_quote;

struct Cut {
    SurfaceMesh input;
    Fragments fragments;
    std::vector<SurfaceMesh> meshes;  // by the surface mesher, as export_fragments writes them
};

const Cut& cut() {
    static const Cut c = [] {
        Cut k;
        const fs::path dir = fs::temp_directory_path() / "crackflow-tests" / "fragment_files";
        fs::create_directories(dir);
        std::ofstream(dir / "box.obj") << box_obj();
        ImportOptions io;
        io.weld_tolerance = 1e-9;
        k.input = read_mesh(dir / "box.obj", io);
        const CrackLevelSets cracks{kRf, 3, {planar_disk_crack(kP1, kN1, 1.0, kRf), planar_disk_crack(kP2, kN2, 1.0, kRf)}};
        const LevelSet object = level_set_from_mesh(k.input, kRf);
        k.fragments = find_fragments(broken_object(object, cracks));
        k.fragments.object = object;  // as segment.fragments sets it: the surface mesher offsets it
        FragmentMesherOptions o;
        o.kind = FragmentMesherKind::surface;
        o.surface = &k.input;
        const FragmentMesher mesher(k.fragments, o);
        for (std::size_t i = 0; i < k.fragments.fragments.size(); ++i) k.meshes.push_back(mesher.mesh(i));
        return k;
    }();
    return c;
}



fs::path export_dir(const std::string& format) {
    const fs::path d = fs::temp_directory_path() / "crackflow-tests" / ("fragment_files_" + format);
    fs::remove_all(d);
    fs::create_directories(d);
    FragmentExportOptions o;
    o.format = mesh_format_from_name(format);
    o.binary = false;
    o.vdb = false;
    o.preview = false;
    o.mesher.kind = FragmentMesherKind::surface;
    o.mesher.surface = &cut().input;
    const FragmentExportResult r = export_fragments(d, cut().fragments, o);
    EXPECT_EQ(r.fallback_fragments, 0u);
    return d;
}

// One JSON line per file from read_fragment_files.py, as text (checked with plain finds).
std::vector<std::string> read_with_vtk(const fs::path& dir, const std::string& ext) {
    std::string cmd = shell_quote(CRACKFLOW_VTK_PYTHON) + " " +
                      shell_quote(std::string(CRACKFLOW_SOURCE_DIR) + "/tests/segment/read_fragment_files.py");
    for (std::size_t i = 0; i < cut().meshes.size(); ++i) {
        char name[64];
        std::snprintf(name, sizeof name, "fragment_%03zu.%s", i, ext.c_str());
        cmd += " " + shell_quote((dir / name).string());
    }
    const CommandResult r = run_command(cmd);
    EXPECT_EQ(r.exit_code, 0) << r.output << "\n(needs Debian's python3-vtk9 for " << CRACKFLOW_VTK_PYTHON << ")";
    std::vector<std::string> lines;
    std::size_t at = 0;
    while (at < r.output.size()) {
        const std::size_t nl = r.output.find('\n', at);
        const std::string line = r.output.substr(at, nl - at);
        if (line.rfind("{", 0) == 0) lines.push_back(line);
        at = nl == std::string::npos ? r.output.size() : nl + 1;
    }
    EXPECT_EQ(lines.size(), cut().meshes.size()) << r.output;
    return lines;
}

std::map<std::string, std::size_t> region_counts(const SurfaceMesh& m) {
    std::map<std::string, std::size_t> n;
    for (std::size_t t = 0; t < m.num_triangles(); ++t) ++n[m.region_name(m.region_of(t))];
    return n;
}

bool has(const std::string& line, const std::string& part) { return line.find(part) != std::string::npos; }

TEST(FragmentFiles, ObjWithMaterialLibraryReadsBackInVtk) {
    const fs::path d = export_dir("obj");
    ASSERT_TRUE(fs::exists(d / "fragments.mtl"));
    const auto lines = read_with_vtk(d, "obj");
    for (std::size_t i = 0; i < lines.size(); ++i) {
        const SurfaceMesh& m = cut().meshes[i];
        EXPECT_TRUE(has(lines[i], "\"cells\": " + std::to_string(m.num_triangles()))) << lines[i];
        EXPECT_TRUE(has(lines[i], "\"tcoords\": true")) << lines[i];
        for (const auto& [name, count] : region_counts(m))
            EXPECT_TRUE(has(lines[i], "\"" + name + "\": " + std::to_string(count))) << name << ": " << lines[i];
    }
}

TEST(FragmentFiles, PlyCarriesTheInsideFacePropertyAndReadsBackInVtk) {
    const fs::path d = export_dir("ply");
    const auto lines = read_with_vtk(d, "ply");
    for (std::size_t i = 0; i < lines.size(); ++i) {
        const SurfaceMesh& m = cut().meshes[i];
        EXPECT_TRUE(has(lines[i], "\"cells\": " + std::to_string(m.num_triangles()))) << lines[i];
        EXPECT_TRUE(has(lines[i], "\"tcoords\": true")) << lines[i];
        EXPECT_TRUE(has(lines[i], "\"normals\": true")) << lines[i];
        EXPECT_TRUE(has(lines[i], "\"inside\": " + std::to_string(region_counts(m)[kInsideRegion]))) << lines[i];
    }
}

TEST(FragmentFiles, GlbPassesTheKhronosValidatorAndReadsBackInVtk) {
    const fs::path d = export_dir("glb");
    const auto lines = read_with_vtk(d, "glb");
    for (std::size_t i = 0; i < lines.size(); ++i) {
        EXPECT_TRUE(has(lines[i], "\"cells\": " + std::to_string(cut().meshes[i].num_triangles()))) << lines[i];
        EXPECT_TRUE(has(lines[i], "\"tcoords\": true")) << lines[i];
    }
    const fs::path tools = CRACKFLOW_GLTF_TOOLS_DIR;
    ASSERT_TRUE(fs::exists(tools / "node_modules" / "gltf-validator" / "package.json"))
        << "build the target gltf_tools (npm ci from tests/tools/package-lock.json)";
    for (std::size_t i = 0; i < cut().meshes.size(); ++i) {
        char name[64];
        std::snprintf(name, sizeof name, "fragment_%03zu.glb", i);
        const CommandResult r = run_command(shell_quote(CRACKFLOW_NODE) + " " + shell_quote((tools / "validate_gltf.mjs").string()) +
                                            " " + shell_quote((d / name).string()));
        EXPECT_EQ(r.exit_code, 0) << r.output;
    }
}

// Which fragment's palette colour (outer or inside shade) a pixel is a shaded copy of: rgb = s c
// for one of them with s in [0.25, 1] (ambient 0.3 x outline 0.7 .. 1), to within the byte
// rounding; -1 for none or more than one.
int palette_match(const unsigned char* px, std::size_t n, bool inside) {
    int found = -1;
    for (std::size_t i = 0; i < n; ++i) {
        const Vec3 c = inside ? fragment_inside_colour(i) : fragment_colour(i);
        const Vec3 p(px[0] / 255.0, px[1] / 255.0, px[2] / 255.0);
        const double s = p.dot(c) / c.dot(c);
        if (s < 0.25 || s > 1.0 + 1e-9 || (p - s * c).cwiseAbs().maxCoeff() > 1.01 / 255) continue;
        if (found >= 0) return -1;
        found = int(i);
    }
    return found;
}

TEST(FragmentPreview, EachFragmentHasItsOwnColourAndFractureFacesAShadeOfIt) {
    const Cut& c = cut();
    std::vector<Vec3> centroids;
    for (const Fragment& f : c.fragments.fragments) centroids.push_back(f.centroid);
    SheetOptions o;
    o.width = 640;
    o.height = 480;
    int w = 0, h = 0;
    const std::vector<unsigned char> rgb = render_fragment_sheet(c.meshes, centroids, o, &w, &h);
    ASSERT_EQ(w, 640);
    ASSERT_EQ(h, 480);
    const std::size_t n = c.meshes.size();
    // Per view (quadrant) and fragment: pixels in the fragment's outer colour and inside shade.
    std::vector<std::vector<int>> outer(4, std::vector<int>(n, 0)), inside(4, std::vector<int>(n, 0));
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const unsigned char* px = &rgb[(std::size_t(y) * std::size_t(w) + std::size_t(x)) * 3];
            const int view = (y >= 240) * 2 + (x >= 320);
            if (const int i = palette_match(px, n, false); i >= 0) ++outer[std::size_t(view)][std::size_t(i)];
            if (const int i = palette_match(px, n, true); i >= 0) ++inside[std::size_t(view)][std::size_t(i)];
        }
    write_png_rgb(fs::temp_directory_path() / "crackflow-tests" / "fragment_files_preview.png", w, h, rgb.data());
    // Front, side and top hide a piece behind another; the oblique view and at least two of the
    // others show every piece.
    for (std::size_t i = 0; i < n; ++i) {
        int seen_inside = 0, views = 0;
        for (int v = 0; v < 4; ++v) {
            views += outer[std::size_t(v)][i] > 200;
            seen_inside += inside[std::size_t(v)][i];
        }
        EXPECT_GT(outer[0][i], 200) << "fragment " << i << " in the oblique view";
        EXPECT_GE(views, 3) << "fragment " << i;
        // The explode opens the cracks: every piece shows fracture faces in some view.
        EXPECT_GT(seen_inside, 100) << "fragment " << i;
    }
    // The palette itself: the first 64 colours pairwise apart (no two read alike).
    for (std::size_t i = 0; i < 64; ++i)
        for (std::size_t j = 0; j < i; ++j)
            EXPECT_GT((fragment_colour(i) - fragment_colour(j)).cwiseAbs().maxCoeff(), 0.04) << i << " vs " << j;
}

}  // namespace
}  // namespace cf
