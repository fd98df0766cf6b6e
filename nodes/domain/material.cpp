#include "material.hpp"

#include "graph/diagnostics.hpp"

#include <cmath>

namespace cf {

void validate(const Material& m) {
    auto need = [](bool ok, const std::string& what) {
        if (!ok) throw std::invalid_argument(what);
    };
    need(std::isfinite(m.E) && m.E > 0, "material: E (Young's modulus, Pa) must be > 0, got " + graph::format_quantity(m.E, "Pa"));
    need(std::isfinite(m.nu) && m.nu > 0 && m.nu < 0.5,
         "material: nu (Poisson's ratio) must lie in (0, 0.5), got " + graph::format_number(m.nu));
    need(std::isfinite(m.rho) && m.rho > 0, "material: rho (density, kg/m^3) must be > 0, got " + graph::format_quantity(m.rho, "kg/m^3"));
    need(std::isfinite(m.tensile_strength) && m.tensile_strength > 0,
         "material: tensile_strength (Pa) must be > 0, got " + graph::format_quantity(m.tensile_strength, "Pa"));
    need(std::isfinite(m.toughness) && m.toughness > 0,
         "material: toughness (Pa*sqrt(m)) must be > 0, got " + graph::format_quantity(m.toughness, "Pa*sqrt(m)"));
    need(std::isfinite(m.compressive_factor) && m.compressive_factor >= 1,
         "material: compressive_factor must be >= 1, got " + graph::format_number(m.compressive_factor));
}

}  // namespace cf
