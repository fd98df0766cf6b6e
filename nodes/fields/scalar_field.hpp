#pragma once
// Spatially varying fracture parameters (thesis ch. 4.5.3): toughness K_c [Pa*sqrt(m)] steers
// crack propagation, strength [Pa] biases crack initiation (ch. 4.4). A field answers value and
// gradient at any point; the compressive factor f_c scales it for compressive fracture.
#include "graph/value.hpp"
#include "nodes/domain/surface_mesh.hpp"

#include <memory>
#include <string>

namespace cf {

// What a field describes; decides its unit in messages.
enum class FieldQuantity { toughness, strength };
const char* quantity_name(FieldQuantity q);  // "toughness" / "strength"
const char* quantity_unit(FieldQuantity q);  // "Pa*sqrt(m)" / "Pa"
// Parses "toughness"/"strength"; throws std::invalid_argument listing the choices otherwise.
FieldQuantity parse_quantity(const std::string& s);

// A scalar function of position with its gradient. Implementations are immutable and
// thread-safe (queried by parallel marker propagation).
class FieldSource {
public:
    virtual ~FieldSource() = default;
    virtual double value(const Vec3& p) const = 0;     // field units
    virtual Vec3 gradient(const Vec3& p) const = 0;    // field units per metre
    virtual double lower_bound() const = 0;            // no value anywhere is below this
    virtual std::string description() const = 0;      // one line, for errors and reports
};

// The value that flows between nodes: a shared source, what it means, and f_c.
struct ScalarField {
    std::shared_ptr<const FieldSource> source;
    FieldQuantity quantity = FieldQuantity::toughness;
    double compressive_factor = 1;  // f_c: compressive = f_c * tensile (ch. 4.4, 4.5.1) [-]

    double value(const Vec3& p) const { return source->value(p); }
    Vec3 gradient(const Vec3& p) const { return source->gradient(p); }
    double compressive_value(const Vec3& p) const { return compressive_factor * source->value(p); }
};

// Wraps a source after checking it: throws std::invalid_argument when the source is null, the
// field can be negative somewhere (naming the quantity, the bound and the description) or
// f_c is not finite and positive.
ScalarField make_field(std::shared_ptr<const FieldSource> source, FieldQuantity quantity, double compressive_factor);

}  // namespace cf

CF_GRAPH_TYPE(cf::ScalarField, "ScalarField");
