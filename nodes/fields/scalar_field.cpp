#include "nodes/fields/scalar_field.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace cf {

const char* quantity_name(FieldQuantity q) { return q == FieldQuantity::toughness ? "toughness" : "strength"; }
const char* quantity_unit(FieldQuantity q) { return q == FieldQuantity::toughness ? "Pa*sqrt(m)" : "Pa"; }

FieldQuantity parse_quantity(const std::string& s) {
    if (s == "toughness") return FieldQuantity::toughness;
    if (s == "strength") return FieldQuantity::strength;
    throw std::invalid_argument("unknown field quantity '" + s + "': use 'toughness' or 'strength'");
}

ScalarField make_field(std::shared_ptr<const FieldSource> source, FieldQuantity quantity, double compressive_factor) {
    if (!source) throw std::invalid_argument(std::string(quantity_name(quantity)) + " field has no source");
    if (!std::isfinite(compressive_factor) || compressive_factor <= 0) {
        std::ostringstream os;
        os << "compressive_factor f_c = " << compressive_factor << " must be finite and > 0 (ratio of compressive to tensile "
           << quantity_name(quantity) << ", usually >= 1)";
        throw std::invalid_argument(os.str());
    }
    const double lo = source->lower_bound();
    if (!(lo >= 0)) {  // also catches NaN
        std::ostringstream os;
        os << quantity_name(quantity) << " field " << source->description() << " reaches " << lo << " "
           << quantity_unit(quantity) << " somewhere; a " << quantity_name(quantity)
           << " must be >= 0 everywhere (raise the mean or lower the amplitude)";
        throw std::invalid_argument(os.str());
    }
    ScalarField f;
    f.source = std::move(source);
    f.quantity = quantity;
    f.compressive_factor = compressive_factor;
    return f;
}

}  // namespace cf
