#pragma once
#include <limits>

namespace shellfrac::brittle {

// One of two bodies in a Hertzian impact (thesis sec. 3.6.2). A plane or a fixed body has an infinite
// radius or mass.
struct HertzBody {
  double youngs_modulus = 0;  // E_s [Pa]
  double poisson_ratio = 0;   // nu_s
  double radius = std::numeric_limits<double>::infinity();  // R_s [m]
  double mass = std::numeric_limits<double>::infinity();    // m_s [kg]
};

double hertz_effective_modulus(const HertzBody& a, const HertzBody& b);  // Eq. 3.8
double hertz_effective_radius(const HertzBody& a, const HertzBody& b);   // Eq. 3.9
double hertz_effective_mass(const HertzBody& a, const HertzBody& b);     // Eq. 3.10
// Contact duration t_c = 2.87 (m^2 / (E^2 R v))^(1/5) (Eq. 3.11) at relative normal speed v. Throws
// InputError when a modulus, radius, mass or the speed is not positive, or both radii/masses are infinite.
double hertz_contact_time(const HertzBody& a, const HertzBody& b, double relative_speed);

}  // namespace shellfrac::brittle
