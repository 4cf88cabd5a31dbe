#include "sim/fracture_setup.hpp"

#include <cmath>
#include <sstream>
#include <string>

#include "core/weibull.hpp"
#include "scene/scene_error.hpp"

namespace shellfrac::sim {

namespace {

// Crossing-number point-in-polygon test in the parameter plane.
bool inside_polygon(const Eigen::Vector2d& p, const std::vector<Eigen::Vector2d>& poly) {
  bool inside = false;
  for (size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const Eigen::Vector2d &a = poly[i], &b = poly[j];
    if ((a.y() > p.y()) != (b.y() > p.y()) && p.x() < a.x() + (p.y() - a.y()) * (b.x() - a.x()) / (b.y() - a.y()))
      inside = !inside;
  }
  return inside;
}

// H from sigma_f, G_f, E and l_ch (thesis sec. 2.3.1), or a SceneError at `json_path` when G_f is below
// the least fracture energy linear softening allows on this grid.
double brittleness_or_fail(double sigma_f, double g_f, double youngs_modulus, double l_ch, const std::string& source,
                           const std::string& json_path) {
  const double h = shell::brittleness(sigma_f, g_f, youngs_modulus, l_ch);
  if (h > 0) return h;
  const double minimum = sigma_f * sigma_f * l_ch / (2.0 * youngs_modulus);
  std::ostringstream os;
  os << "fracture energy " << g_f << " J/m^2 is too small for the failure stress " << sigma_f
     << " Pa and this grid: linear softening needs G_f > sigma_f^2 l_ch / (2 E) = " << minimum
     << " J/m^2 (l_ch = sqrt(3) dx = " << l_ch << " m); raise fracture_energy or refine the grid";
  throw scene::SceneError(source, json_path, os.str());
}

void init_shell_fracture(const scene::Model& model, size_t i, shell::ShellPatch& patch, double l_ch) {
  const scene::model::Shell& s = model.shells[i];
  const scene::model::FractureSpec& f = s.material.fracture;
  const double E = s.material.youngs_modulus;
  const std::string path = "/shells/" + std::to_string(i) + "/material/fracture";
  const double material_h =
      brittleness_or_fail(f.failure_stress, f.fracture_energy, E, l_ch, model.source, path + "/fracture_energy");
  patch.set_brittleness(material_h);
  // Regions in the parameter plane override sigma_f; later regions win (thesis Fig. 4.23b). A region keeps
  // the material's softening shape (its H) unless it gives its own fracture energy.
  for (size_t k = 0; k < f.regions.size(); ++k) {
    const scene::model::FailureRegion& r = f.regions[k];
    const double h = r.fracture_energy ? brittleness_or_fail(r.failure_stress, *r.fracture_energy, E, l_ch, model.source,
                                                             path + "/regions/" + std::to_string(k) + "/fracture_energy")
                                       : material_h;
    for (size_t q = 0; q < patch.num_inplane_points(); ++q)
      if (inside_polygon(patch.parameter(q), r.polygon)) patch.set_failure_stress(q, r.failure_stress, h);
  }
  // Heterogeneous strength: each in-plane point's sigma_f (material or region) times its own seeded Weibull
  // factor. H stays the point's, as for a region without its own fracture energy, so G_f scales with
  // sigma_f^2 and no draw can fall below the grid's minimum fracture energy.
  if (f.weibull.enabled)
    for (size_t q = 0; q < patch.num_inplane_points(); ++q)
      patch.set_failure_stress(q, patch.failure_stress(q) * core::weibull_factor(f.weibull, q), patch.brittleness(q));
}

}  // namespace

void init_fracture(const scene::Model& model, World& world, double grid_dx) {
  // Characteristic length of the damage law: l_ch = sqrt(3 h^2) with h the grid spacing (sec. 2.3.1).
  const double l_ch = std::sqrt(3.0) * grid_dx;
  for (size_t i = 0; i < world.num_shells(); ++i)
    if (model.shells[i].material.fracture.enabled) init_shell_fracture(model, i, world.shell(i), l_ch);
}

}  // namespace shellfrac::sim
