#include "output/scene_description.hpp"

#include <sstream>

namespace shellfrac::output {

std::string describe_scene(const scene::Model& scene) {
  std::ostringstream os;
  int control_points = 0;
  for (const scene::model::Shell& s : scene.shells) control_points += s.surface.num_u() * s.surface.num_v();
  os << "scene \"" << scene.name << "\": " << scene.shells.size() << " shell(s), " << control_points
     << " control points, " << scene.solids.size() << " solid(s), " << scene.colliders.size() << " collider(s), "
     << scene.pins.size() << " pin(s), " << scene.loads.size() << " load(s), " << scene.output.probes.size()
     << " probe(s), end time "
     << scene.time.end << " s" << (scene.time.until_rest ? " (or until rest)" : "") << " at " << scene.time.frame_rate << " frames/s, output " << scene.output.format << " at "
     << scene.output.resolution_u << " x " << scene.output.resolution_v << " quads per patch\n";
  for (const scene::model::Shell& s : scene.shells) {
    os << "  " << s.name << ": " << s.shape << " patch, " << s.surface.num_u() << " x " << s.surface.num_v()
       << " control points (degree " << s.surface.knots_u().degree() << " x " << s.surface.knots_v().degree() << ", "
       << s.surface.knots_u().num_spans() << " x " << s.surface.knots_v().num_spans() << " cells)"
       << (s.surface.is_rational() ? ", rational" : "") << ", thickness " << s.thickness << " m, "
       << s.material.model << " E=" << s.material.youngs_modulus << " nu=" << s.material.poisson_ratio
       << " rho=" << s.material.density << (s.material.plasticity.enabled ? ", plastic" : "")
       << (s.material.fracture.enabled ? ", fracturing (sigma_f=" : "");
    if (s.material.fracture.enabled)
      os << s.material.fracture.failure_stress << " Pa, G_f=" << s.material.fracture.fracture_energy << " J/m^2, "
         << (s.material.fracture.rule == shell::DamageRule::Monotone ? "monotone" : "healing") << " damage)";
    os << (s.cuts.empty() ? "" : ", " + std::to_string(s.cuts.size()) + " prescribed cut(s)") << "\n";
  }
  for (const scene::model::SolidBody& b : scene.solids)
    os << "  " << b.name << ": " << b.shape << " solid, particle spacing " << b.spacing << " m ("
       << (b.poisson_disk ? "Poisson disk" : "jittered grid") << "), E=" << b.material.youngs_modulus
       << " nu=" << b.material.poisson_ratio << " rho=" << b.material.density << "\n";
  return os.str();
}

}  // namespace shellfrac::output
