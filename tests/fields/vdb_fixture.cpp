#include "vdb_fixture.hpp"

#include <openvdb/openvdb.h>

namespace cf::testing {

void write_vec3_grid(const std::filesystem::path& file, const std::string& name) {
    openvdb::initialize();
    auto g = openvdb::Vec3SGrid::create(openvdb::Vec3s(0));
    g->setName(name);
    g->tree().setValue(openvdb::Coord(0, 0, 0), openvdb::Vec3s(1, 2, 3));
    openvdb::io::File(file.string()).write({g});
}

void write_linear_float_grid(const std::filesystem::path& file, const std::string& name, double h, int n, double c0,
                             double c1) {
    openvdb::initialize();
    auto g = openvdb::FloatGrid::create(static_cast<float>(c0));
    g->setName(name);
    g->setTransform(openvdb::math::Transform::createLinearTransform(h));
    auto acc = g->getAccessor();
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
            for (int k = 0; k < n; ++k)
                acc.setValue(openvdb::Coord(i, j, k), static_cast<float>(c0 + c1 * h * (i + 2 * j - k)));
    openvdb::io::File(file.string()).write({g});
}

}  // namespace cf::testing
