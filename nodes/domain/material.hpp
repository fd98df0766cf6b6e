#pragma once
// Isotropic linear-elastic brittle material. SI units.
#include "graph/value.hpp"

#include <stdexcept>
#include <string>

namespace cf {

struct Material {
    double E = 3.1e9;                 // Young's modulus [Pa]
    double nu = 0.327;                // Poisson's ratio [-], in (0, 0.5)
    double rho = 1200;                // density [kg/m^3]
    double tensile_strength = 7.6e7;  // [Pa]
    double toughness = 1.0e6;         // fracture toughness K_c [Pa*sqrt(m)]
    double compressive_factor = 2;    // f_c: compressive strength/toughness = f_c * tensile [-]

    double mu() const { return E / (2 * (1 + nu)); }                           // shear modulus [Pa]
    double lambda() const { return E * nu / ((1 + nu) * (1 - 2 * nu)); }       // Lame's first [Pa]
};

// Throws std::invalid_argument naming the offending parameter and the allowed range.
void validate(const Material& m);

}  // namespace cf

CF_GRAPH_TYPE(cf::Material, "Material");
