#include "nodes/fields/closed_form_fields.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace cf {

HomogeneousField::HomogeneousField(double value) : value_(value) {
    if (!std::isfinite(value)) throw std::invalid_argument("homogeneous field value is not finite");
}

std::string HomogeneousField::description() const {
    std::ostringstream os;
    os << "homogeneous(" << value_ << ")";
    return os.str();
}

LayeredField::LayeredField(double a, double b, double f, const Vec3& l) : a_(a), b_(b), f_(f) {
    if (!std::isfinite(a) || !std::isfinite(b) || !std::isfinite(f) || f < 0)
        throw std::invalid_argument("layered field: a, b must be finite and the frequency f >= 0 [rad/m]");
    const double n = l.norm();
    if (!std::isfinite(n) || n == 0)
        throw std::invalid_argument("layered field: layer direction l must be a non-zero vector");
    l_ = l / n;
}

double LayeredField::value(const Vec3& p) const { return a_ - b_ * std::cos(f_ * p.dot(l_)); }

Vec3 LayeredField::gradient(const Vec3& p) const { return b_ * f_ * std::sin(f_ * p.dot(l_)) * l_; }

double LayeredField::lower_bound() const { return f_ == 0 ? a_ - b_ : a_ - std::abs(b_); }

std::string LayeredField::description() const {
    std::ostringstream os;
    os << "layered(a=" << a_ << ", b=" << b_ << ", f=" << f_ << " rad/m, l=(" << l_.x() << ", " << l_.y() << ", " << l_.z()
       << "))";
    return os.str();
}

}  // namespace cf
