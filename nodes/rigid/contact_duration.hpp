#pragma once
// Hertzian contact duration (thesis ch. 7.2): two elastic bodies meeting at speed v behave like a
// sphere of effective radius R, modulus E and mass m on a rigid plane, and stay in contact for
//   t_c = 2.87 (m^2 / (E^2 R v))^(1/5),
// with E = 1 / sum_i (1 - nu_i^2) / E_i, R = 1 / sum_i |H_i| (H the surface mean curvature at the
// contact; R_i = 1 / |H_i|), m = 1 / sum_i 1 / m_i (a static body contributes no 1/m). A flat contact
// (H = 0) would give R = infinity and t_c = 0, an approach speed of 0 t_c = infinity: R is capped at
// `max_radius` and v raised to `min_speed`, so t_c stays finite and positive. SI units.
#include "nodes/domain/surface_mesh.hpp"

#include <vector>

namespace cf::rigid {

struct ContactBody {
    double E = 0;                // Young's modulus [Pa]
    double nu = 0;               // Poisson's ratio
    double mass = 0;             // [kg]; 0: static or kinematic (infinite mass)
    double mean_curvature = 0;   // |H| at the contact [1/m]
};

struct ContactDurationLimits {
    double max_radius = 1.0;     // [m] cap of the effective radius (flat contacts)
    double min_speed = 1e-3;     // [m/s] floor of the approach speed
};

struct ContactDuration {
    double seconds = 0;          // t_c
    double E = 0, R = 0, m = 0, v = 0;  // the effective quantities used
    bool radius_capped = false, speed_raised = false;
};

// Throws std::invalid_argument when both bodies are static, a modulus is not positive, or nu is
// outside [0, 0.5).
ContactDuration hertz_contact_duration(const ContactBody& a, const ContactBody& b, double approach_speed,
                                       const ContactDurationLimits& limits = {});

// Unsigned mean curvature |H| [1/m] per vertex of a closed mesh, from the cotangent Laplacian,
// |H| = |Delta x| / 2 with mixed Voronoi areas (Meyer et al. 2003); and per triangle, the mean of its
// vertices'. 1/R on a sphere of radius R, 0 on a plane.
std::vector<double> vertex_mean_curvature(const SurfaceMesh& mesh);
std::vector<double> triangle_mean_curvature(const SurfaceMesh& mesh);

}  // namespace cf::rigid
