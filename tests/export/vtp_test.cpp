// The .vtp writer: structure ParaView expects (VTK XML PolyData, ascii inline data), region
// ids as Int32 cell data, extra point/cell arrays read back bit-exactly, bad arrays rejected.
#include "nodes/export/vtp_writer.hpp"
#include "tests/import/mesh_fixtures.hpp"
#include "tests/harness/expect_error.hpp"

#include <gtest/gtest.h>

#include <sstream>

namespace cf::testing {
namespace {

// The text between the opening tag containing `marker` and the next closing tag.
std::string element_text(const std::string& xml, const std::string& marker) {
    const auto at = xml.find(marker);
    if (at == std::string::npos) return "<missing " + marker + ">";
    const auto open_end = xml.find('>', at) + 1;
    return xml.substr(open_end, xml.find("</", open_end) - open_end);
}

std::vector<double> numbers(const std::string& text) {
    std::istringstream in(text);
    std::vector<double> r;
    std::string tok;
    while (in >> tok) r.push_back(std::strtod(tok.c_str(), nullptr));
    return r;
}

SurfaceMesh regioned_cube() {
    SurfaceMesh m = transformed(unit_cube(), 0.1, Vec3(1.0 / 3.0, 0.2, -0.7));
    m.region.assign(12, 0);
    for (int t = 4; t < 12; ++t) m.region[t] = t < 8 ? 1 : 2;
    return m;
}

TEST(Vtp, GeometryAndRegions) {
    const SurfaceMesh m = regioned_cube();
    std::ostringstream os;
    write_vtp(os, m);
    const std::string xml = os.str();
    EXPECT_EQ(xml.rfind("<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\"", 0), 0u);
    EXPECT_NE(xml.find("<Piece NumberOfPoints=\"8\" NumberOfVerts=\"0\" NumberOfLines=\"0\" NumberOfStrips=\"0\" "
                       "NumberOfPolys=\"12\">"),
              std::string::npos);
    const auto points = numbers(element_text(xml, "NumberOfComponents=\"3\" format=\"ascii\">"));
    ASSERT_EQ(points.size(), 24u);
    for (int v = 0; v < 8; ++v)
        for (int k = 0; k < 3; ++k) EXPECT_EQ(points[3 * v + k], m.vertices[v][k]);  // bit-exact text
    const auto conn = numbers(element_text(xml, "Name=\"connectivity\""));
    ASSERT_EQ(conn.size(), 36u);
    for (int t = 0; t < 12; ++t)
        for (int k = 0; k < 3; ++k) EXPECT_EQ(conn[3 * t + k], m.triangles[t][k]);
    const auto offsets = numbers(element_text(xml, "Name=\"offsets\""));
    ASSERT_EQ(offsets.size(), 12u);
    for (int t = 0; t < 12; ++t) EXPECT_EQ(offsets[t], 3 * (t + 1));
    EXPECT_NE(xml.find("<DataArray type=\"Int32\" Name=\"region\" format=\"ascii\">"), std::string::npos);
    const auto region = numbers(element_text(xml, "Name=\"region\""));
    ASSERT_EQ(region.size(), 12u);
    for (int t = 0; t < 12; ++t) EXPECT_EQ(region[t], m.region[t]);
    // Every opened element is closed, in order (a cheap well-formedness check).
    std::vector<std::string> stack;
    for (std::size_t i = xml.find("<VTKFile"); i != std::string::npos; i = xml.find('<', i + 1)) {
        const std::size_t end = xml.find_first_of(" >", i);
        if (xml[i + 1] == '/') {
            ASSERT_FALSE(stack.empty());
            EXPECT_EQ(stack.back(), xml.substr(i + 2, end - i - 2));
            stack.pop_back();
        } else {
            stack.push_back(xml.substr(i + 1, end - i - 1));
        }
    }
    EXPECT_TRUE(stack.empty());
}

TEST(Vtp, ExtraPointAndCellArrays) {
    const SurfaceMesh m = regioned_cube();
    VtpFields f;
    VtpArray disp{"displacement", 3, {}};
    for (const Vec3& p : m.vertices)
        for (int k = 0; k < 3; ++k) disp.values.push_back(std::sin(7 * p[k] + k));
    VtpArray stress{"max principal stress <Pa>", 1, {}};
    for (int t = 0; t < 12; ++t) stress.values.push_back(1e6 * std::exp(-t / 3.0));
    f.point_data.push_back(disp);
    f.cell_data.push_back(stress);
    std::ostringstream os;
    write_vtp(os, m, f);
    const std::string xml = os.str();
    EXPECT_NE(xml.find("<DataArray type=\"Float64\" Name=\"displacement\" NumberOfComponents=\"3\""), std::string::npos);
    EXPECT_EQ(numbers(element_text(xml, "Name=\"displacement\"")), disp.values);
    // The name is XML-escaped.
    EXPECT_EQ(numbers(element_text(xml, "Name=\"max principal stress &lt;Pa&gt;\"")), stress.values);
    // Point arrays inside PointData, cell arrays inside CellData.
    EXPECT_LT(xml.find("<PointData>"), xml.find("Name=\"displacement\""));
    EXPECT_LT(xml.find("Name=\"displacement\""), xml.find("</PointData>"));
    EXPECT_LT(xml.find("<CellData"), xml.find("Name=\"max principal"));
    EXPECT_LT(xml.find("Name=\"max principal"), xml.find("</CellData>"));
}

TEST(Vtp, BadArraysAreRejected) {
    const SurfaceMesh m = regioned_cube();
    auto expect_bad = [&](VtpFields f, const std::string& fragment) {
        std::ostringstream os;
        EXPECT_TRUE(cf::testing::throws<std::invalid_argument>([&] { write_vtp(os, m, f); }, {fragment}));
    };
    VtpFields short_points;
    short_points.point_data.push_back({"u", 3, std::vector<double>(23, 0.0)});
    expect_bad(short_points, "point array 'u' has 23 values, expected 3 x 8");
    VtpFields two;
    two.cell_data.push_back({"c", 2, std::vector<double>(24, 0.0)});
    expect_bad(two, "cell array 'c' has 2 components; use 1 (scalar) or 3 (vector)");
    VtpFields dup;
    dup.point_data.push_back({"a", 1, std::vector<double>(8, 0.0)});
    dup.cell_data.push_back({"a", 1, std::vector<double>(12, 0.0)});
    expect_bad(dup, "two arrays are named 'a'");
    VtpFields reserved;
    reserved.cell_data.push_back({"region", 1, std::vector<double>(12, 0.0)});
    expect_bad(reserved, "'region' is reserved");
    VtpFields unnamed;
    unnamed.cell_data.push_back({"", 1, std::vector<double>(12, 0.0)});
    expect_bad(unnamed, "has no name");
}

}  // namespace
}  // namespace cf::testing
