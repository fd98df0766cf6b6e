#include "nodes/fields/grid_fields.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace cf {

namespace {

const GranularSettings& checked(const GranularSettings& s) {
    if (!(s.grain_size > 0) || !std::isfinite(s.grain_size))
        throw std::invalid_argument("granular field: grain_size must be > 0 [m]");
    if (!(s.rise > -1) || !std::isfinite(s.rise)) throw std::invalid_argument("granular field: rise must be > -1");
    if (!(s.interior_depth > 0)) throw std::invalid_argument("granular field: interior_depth must be > 0");
    if (s.voxels_per_grain < 2) throw std::invalid_argument("granular field: voxels_per_grain must be >= 2");
    if (!std::isfinite(s.boundary_value)) throw std::invalid_argument("granular field: boundary value is not finite");
    return s;
}

}  // namespace

GranularField::GranularField(const GranularSettings& s)
    : s_(checked(s)),
      grains_(s.grain_size * std::cbrt(static_cast<double>(s.grains_per_tile)), s.grains_per_tile, s.seed),
      saturation_(s.interior_depth * s.grain_size) {
    const int res = std::max(2, static_cast<int>(std::ceil(grains_.tile() / s.grain_size * s.voxels_per_grain - 1e-9)));
    distance_ = VoxelGrid::periodic(grains_.tile(), res, [this](const Vec3& p) { return grains_.boundary_distance(p); });
}

double GranularField::value(const Vec3& p) const {
    const double d = distance_.sample(p);
    return s_.boundary_value * (1 + s_.rise * std::min(d / saturation_, 1.0));
}

Vec3 GranularField::gradient(const Vec3& p) const {
    const double d = distance_.sample(p);
    if (d >= saturation_) return Vec3::Zero();
    return s_.boundary_value * s_.rise / saturation_ * distance_.gradient(p);
}

double GranularField::lower_bound() const {
    // Interpolated distances lie in [0, max distance]; the factor is monotone in d.
    return std::min(s_.boundary_value, s_.boundary_value * (1 + s_.rise));
}

std::string GranularField::description() const {
    std::ostringstream os;
    os << "granular(boundary " << s_.boundary_value << ", rise " << s_.rise << ", grain " << s_.grain_size << " m, "
       << s_.grains_per_tile << " grains per tile, seed " << s_.seed << ")";
    return os.str();
}

VdbFileField::VdbFileField(const std::filesystem::path& file, const std::string& grid_name, double scale)
    : file_(file.string()), grid_name_(grid_name), scale_(scale), grid_(VoxelGrid::read(file, grid_name)) {
    if (!std::isfinite(scale)) throw std::invalid_argument("vdb field: scale is not finite");
}

double VdbFileField::lower_bound() const {
    return scale_ >= 0 ? scale_ * grid_.min_value() : scale_ * grid_.max_value();
}

std::string VdbFileField::description() const {
    std::ostringstream os;
    os << "grid '" << grid_name_ << "' of '" << file_ << "' x " << scale_;
    return os.str();
}

}  // namespace cf
