#pragma once
// Fields defined in closed form, with analytic gradients (thesis ch. 4.5.3).
#include "nodes/fields/scalar_field.hpp"

namespace cf {

// The same value everywhere.
class HomogeneousField final : public FieldSource {
public:
    explicit HomogeneousField(double value);
    double value(const Vec3&) const override { return value_; }
    Vec3 gradient(const Vec3&) const override { return Vec3::Zero(); }
    double lower_bound() const override { return value_; }
    std::string description() const override;

private:
    double value_;
};

// "Layered" material of fig. 19: K(p) = a - b cos(f p.l), with l the unit layer normal
// (normalised here), f the spatial frequency [rad/m]; layers repeat every 2 pi / f.
// Gradient: b f sin(f p.l) l. Extremes a - |b| and a + |b|.
class LayeredField final : public FieldSource {
public:
    // Throws std::invalid_argument when l is zero or not finite, or f < 0.
    LayeredField(double a, double b, double f, const Vec3& l);
    double value(const Vec3& p) const override;
    Vec3 gradient(const Vec3& p) const override;
    double lower_bound() const override;
    std::string description() const override;

private:
    double a_, b_, f_;
    Vec3 l_;
};

}  // namespace cf
