// The only translation unit of nodes/fields that includes OpenVDB.
#include "nodes/fields/voxel_grid.hpp"

#include "graph/atomic_write.hpp"
#include "nodes/levelset/vdb_write.hpp"

#include <openvdb/openvdb.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace cf {

struct VoxelGridData {
    openvdb::FloatGrid::Ptr grid;
    bool periodic = false;
    int period = 0;         // voxels per tile edge when periodic
    double voxel = 0;       // [m]
    double min = 0, max = 0;
};

namespace {

void initialise_openvdb() {
    static std::once_flag once;
    std::call_once(once, [] { openvdb::initialize(); });
}

void compute_range(VoxelGridData& d) {
    float lo = d.grid->background(), hi = d.grid->background();
    for (auto it = d.grid->cbeginValueAll(); it; ++it) {
        lo = std::min(lo, *it);
        hi = std::max(hi, *it);
    }
    d.min = lo;
    d.max = hi;
}

int wrap_index(int i, int n) {
    const int r = i % n;
    return r < 0 ? r + n : r;
}

// Eight corner values of the cell containing index-space point x, and the local coordinates.
struct Cell {
    double v[2][2][2];
    Vec3 t;
};

Cell cell_at(const VoxelGridData& d, const Vec3& p) {
    const openvdb::Vec3d x = d.grid->transform().worldToIndex(openvdb::Vec3d(p.x(), p.y(), p.z()));
    Cell c;
    int i0[3];
    for (int k = 0; k < 3; ++k) {
        const double f = std::floor(x[k]);
        i0[k] = static_cast<int>(f);
        c.t[k] = x[k] - f;
    }
    // Unregistered (no insertion into the tree's hash map per lookup: a field is sampled per
    // marker per sub-step); the grid is immutable once built.
    const openvdb::tree::ValueAccessor<const openvdb::FloatTree, false> acc(d.grid->tree());
    for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b)
            for (int e = 0; e < 2; ++e) {
                int i = i0[0] + a, j = i0[1] + b, k = i0[2] + e;
                if (d.periodic) {
                    i = wrap_index(i, d.period);
                    j = wrap_index(j, d.period);
                    k = wrap_index(k, d.period);
                }
                c.v[a][b][e] = acc.getValue(openvdb::Coord(i, j, k));
            }
    return c;
}

}  // namespace

VoxelGrid VoxelGrid::periodic(double tile, int res, const std::function<double(const Vec3&)>& f) {
    if (res < 2) throw std::invalid_argument("voxel grid: resolution must be >= 2 voxels per tile edge");
    if (static_cast<double>(res) * res * res > 1.3e8)
        throw std::invalid_argument("voxel grid: " + std::to_string(res) + "^3 voxels exceed the 1.3e8 limit; lower the resolution");
    if (!(tile > 0)) throw std::invalid_argument("voxel grid: tile size must be > 0 [m]");
    initialise_openvdb();
    const double h = tile / res;
    const std::size_t n = static_cast<std::size_t>(res);
    std::vector<float> values(n * n * n);
    tbb::parallel_for(std::size_t(0), n, [&](std::size_t i) {
        for (std::size_t j = 0; j < n; ++j)
            for (std::size_t k = 0; k < n; ++k)
                values[(i * n + j) * n + k] = static_cast<float>(f(Vec3(i * h, j * h, k * h)));
    });
    auto data = std::make_shared<VoxelGridData>();
    data->grid = openvdb::FloatGrid::create(0.0f);
    data->grid->setTransform(openvdb::math::Transform::createLinearTransform(h));
    auto acc = data->grid->getAccessor();
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = 0; j < n; ++j)
            for (std::size_t k = 0; k < n; ++k)
                acc.setValue(openvdb::Coord(int(i), int(j), int(k)), values[(i * n + j) * n + k]);
    data->periodic = true;
    data->period = res;
    data->voxel = h;
    compute_range(*data);
    VoxelGrid g;
    g.data_ = std::move(data);
    return g;
}

VoxelGrid VoxelGrid::read(const std::filesystem::path& file, const std::string& grid_name) {
    initialise_openvdb();
    const std::string where = "'" + file.string() + "'";
    if (!std::filesystem::exists(file)) throw std::invalid_argument("field file " + where + " does not exist");
    openvdb::GridBase::Ptr base;
    std::string names;
    try {
        openvdb::io::File f(file.string());
        f.open();
        for (auto it = f.beginName(); it != f.endName(); ++it) names += (names.empty() ? "" : ", ") + it.gridName();
        if (f.hasGrid(grid_name)) base = f.readGrid(grid_name);
        f.close();
    } catch (const std::exception& e) {
        throw std::invalid_argument("cannot read field file " + where + " as OpenVDB: " + e.what());
    }
    if (!base)
        throw std::invalid_argument("field file " + where + " has no grid named '" + grid_name + "' (grids: " +
                                    (names.empty() ? "none" : names) + "); set the grid parameter to one of them");
    auto grid = openvdb::gridPtrCast<openvdb::FloatGrid>(base);
    if (!grid)
        throw std::invalid_argument("grid '" + grid_name + "' in " + where + " has value type '" + base->valueType() +
                                    "'; a scalar field needs a float grid");
    if (!grid->transform().isLinear())
        throw std::invalid_argument("grid '" + grid_name + "' in " + where +
                                    " has a non-linear (frustum) transform; resample it to a linear transform");
    auto data = std::make_shared<VoxelGridData>();
    data->grid = grid;
    data->voxel = grid->transform().voxelSize()[0];
    compute_range(*data);
    VoxelGrid g;
    g.data_ = std::move(data);
    return g;
}

void VoxelGrid::write(const std::filesystem::path& file, const std::string& grid_name) const {
    auto copy = data_->grid->deepCopy();
    copy->setName(grid_name);
    openvdb::GridPtrVec grids{copy};
    write_vdb_file_checked(file, grids);
}

double VoxelGrid::sample(const Vec3& p) const {
    const Cell c = cell_at(*data_, p);
    const Vec3& t = c.t;
    double v = 0;
    for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b)
            for (int e = 0; e < 2; ++e)
                v += c.v[a][b][e] * (a ? t[0] : 1 - t[0]) * (b ? t[1] : 1 - t[1]) * (e ? t[2] : 1 - t[2]);
    return v;
}

Vec3 VoxelGrid::gradient(const Vec3& p) const {
    const Cell c = cell_at(*data_, p);
    const Vec3& t = c.t;
    Vec3 g = Vec3::Zero();
    for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b)
            for (int e = 0; e < 2; ++e) {
                const double wx = a ? t[0] : 1 - t[0], wy = b ? t[1] : 1 - t[1], wz = e ? t[2] : 1 - t[2];
                const double sx = a ? 1 : -1, sy = b ? 1 : -1, sz = e ? 1 : -1;
                g += c.v[a][b][e] * Vec3(sx * wy * wz, wx * sy * wz, wx * wy * sz);
            }
    // Index-space gradient to world space: inverse Jacobian transpose of the (linear) transform.
    const openvdb::Vec3d w = data_->grid->transform().baseMap()->applyIJT(openvdb::Vec3d(g.x(), g.y(), g.z()));
    return Vec3(w[0], w[1], w[2]);
}

double VoxelGrid::min_value() const { return data_->min; }
double VoxelGrid::max_value() const { return data_->max; }
double VoxelGrid::voxel_size() const { return data_->voxel; }
bool VoxelGrid::is_periodic() const { return data_->periodic; }
std::size_t VoxelGrid::active_voxel_count() const { return data_->grid->activeVoxelCount(); }

}  // namespace cf
