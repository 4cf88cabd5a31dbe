// The crack stages of Simulation: set-up of damage and prescribed cuts, consistent crack extraction
// (thesis sec. 4.4.2) with MLS basis updates (sec. 4.6), and the phantom-node partition (sec. 4.7.1).
#include <algorithm>
#include <cmath>
#include <sstream>

#include "sim/scene_error.hpp"
#include "sim/simulation.hpp"

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

}  // namespace

void Simulation::init_cracks() {
  mls_settings_.max_factor = scene_.cracks.max_support;
  cracks_.resize(patches_.size());
  damaged_count_.assign(patches_.size(), 0);
  // Characteristic length of the damage law: l_ch = sqrt(3 h^2) with h the grid spacing (sec. 2.3.1).
  const double l_ch = std::sqrt(3.0) * grid_.dx();
  for (size_t i = 0; i < patches_.size(); ++i) {
    const Shell& s = scene_.shells[i];
    shell::ShellPatch& patch = patches_[i];
    const FractureSpec& f = s.material.fracture;
    const std::string path = "/shells/" + std::to_string(i);
    if (f.enabled) {
      // H follows from sigma_f, G_f, E and l_ch (thesis sec. 2.3.1).
      auto brittleness_or_fail = [&](double sigma_f, double g_f, const std::string& json_path) {
        const double h = shell::brittleness(sigma_f, g_f, s.material.youngs_modulus, l_ch);
        if (h > 0) return h;
        const double minimum = sigma_f * sigma_f * l_ch / (2.0 * s.material.youngs_modulus);
        std::ostringstream os;
        os << "fracture energy " << g_f << " J/m^2 is too small for the failure stress " << sigma_f
           << " Pa and this grid: linear softening needs G_f > sigma_f^2 l_ch / (2 E) = " << minimum
           << " J/m^2 (l_ch = sqrt(3) dx = " << l_ch << " m); raise fracture_energy or refine the grid";
        throw SceneError(scene_.source, json_path, os.str());
      };
      const double material_h = brittleness_or_fail(f.failure_stress, f.fracture_energy, path + "/material/fracture/fracture_energy");
      patch.set_brittleness(material_h);
      // Regions in the parameter plane override sigma_f; later regions win (thesis Fig. 4.23b). A region
      // keeps the material's softening shape (its H) unless it gives its own fracture energy.
      for (size_t k = 0; k < f.regions.size(); ++k) {
        const FailureRegion& r = f.regions[k];
        const double h = r.fracture_energy
                             ? brittleness_or_fail(r.failure_stress, *r.fracture_energy,
                                                   path + "/material/fracture/regions/" + std::to_string(k) + "/fracture_energy")
                             : material_h;
        for (size_t q = 0; q < patch.num_inplane_points(); ++q)
          if (inside_polygon(patch.parameter(q), r.polygon)) patch.set_failure_stress(q, r.failure_stress, h);
      }
    }
    if (!f.enabled && s.cuts.empty()) continue;
    const auto& ku = s.surface.knots_u();
    const auto& kv = s.surface.knots_v();
    const crack2d::Box domain{{ku.domain_begin(), kv.domain_begin()}, {ku.domain_end(), kv.domain_end()}};
    cracks_[i] = std::make_unique<crack2d::ConsistentCrackExtractor>(domain, patch.parameter_spacing());
    for (size_t c = 0; c < s.cuts.size(); ++c) {
      try {
        cracks_[i]->add_prescribed_cut(s.cuts[c].points, s.cuts[c].closed);
      } catch (const crack2d::CutError& e) {
        throw SceneError(scene_.source, path + "/cuts/" + std::to_string(c) + "/points", e.what());
      }
    }
    if (cracks_[i]->graph().num_edges() > 0) {
      const shell::CrackUpdate u = patch.update_crack(cracks_[i]->index(), 0, mls_settings_);
      if (crack_stats_.first_mls_failure.empty() && !u.first_failure.empty())
        crack_stats_.first_mls_failure = "shell \"" + s.name + "\" " + u.first_failure;
    }
  }
  count_crack_state();
}

void Simulation::stage_cracks() {
  bool any = false;
  for (const auto& c : cracks_) any = any || c;
  if (!any) return;
  auto scope = timer_.time("cracks");
  const size_t edges_before = crack_stats_.crack_edges;
  crack_stats_.crack_edges = crack_stats_.mls_points = crack_stats_.mls_failures = 0;
  for (size_t i = 0; i < patches_.size(); ++i) {
    if (!cracks_[i]) continue;
    shell::ShellPatch& patch = patches_[i];
    // The fully damaged set only grows (c_his is a running maximum): an unchanged count means an
    // unchanged set, and the extraction would add nothing.
    const std::vector<unsigned char> damaged =
        patch.fractures() ? patch.fully_damaged_points() : std::vector<unsigned char>{};
    const size_t count = static_cast<size_t>(std::count(damaged.begin(), damaged.end(), 1));
    if (patch.fractures() && count != damaged_count_[i]) {
      damaged_count_[i] = count;
      const size_t first = cracks_[i]->graph().num_edges();
      const crack2d::ExtractionStats st = cracks_[i]->extract(patch.inplane_parameters(), damaged);
      ++crack_stats_.extractions;
      crack_stats_.subset_violations += st.subset_violations;
      // Only points whose support the new segments touch are rebuilt (thesis sec. 4.6).
      if (cracks_[i]->graph().num_edges() > first) {
        const shell::CrackUpdate u = patch.update_crack(cracks_[i]->index(), first, mls_settings_);
        if (crack_stats_.first_mls_failure.empty() && !u.first_failure.empty())
          crack_stats_.first_mls_failure = "shell \"" + scene_.shells[i].name + "\" " + u.first_failure;
      }
    }
    crack_stats_.crack_edges += cracks_[i]->graph().num_edges();
    crack_stats_.mls_points += patch.num_mls_points();
    crack_stats_.mls_failures += patch.num_mls_failures();
  }
  if (crack_stats_.crack_edges != edges_before && !scene_.interfaces.empty()) {
    update_seam_cracks();  // may continue a crack into a coupled neighbour
    count_crack_state();
  }
}

void Simulation::count_crack_state() {
  crack_stats_.crack_edges = crack_stats_.mls_points = crack_stats_.mls_failures = 0;
  for (size_t i = 0; i < patches_.size(); ++i)
    if (cracks_[i]) {
      crack_stats_.crack_edges += cracks_[i]->graph().num_edges();
      crack_stats_.mls_points += patches_[i].num_mls_points();
      crack_stats_.mls_failures += patches_[i].num_mls_failures();
    }
}

void Simulation::partition_phantom_nodes() {
  phantoms_ = mpm::PhantomLayout{};
  if (!scene_.cracks.phantom_nodes) return;
  bool any = false;
  for (const auto& p : patches_) any = any || p.num_mls_points() > 0;
  if (!any) return;
  auto scope = timer_.time("phantom_nodes");
  // sets_ holds, per shell, its control points then its shear particles; then one set per solid.
  std::vector<mpm::PartitionRole> roles;
  for (const auto& p : patches_) {
    roles.push_back({mpm::FieldKind::Shell, p.control_near_crack().data()});
    roles.push_back({mpm::FieldKind::Shell, p.shear_near_crack().data()});
  }
  for (size_t k = 0; k < solids_.size(); ++k) roles.push_back({mpm::FieldKind::Solid, nullptr});
  const size_t shell_sets = 2 * patches_.size();
  auto parameter = [&](uint32_t set, uint32_t particle) {
    const shell::ShellPatch& p = patches_[set / 2];
    return set % 2 == 0 ? p.control_parameter(particle) : p.shear_parameter(particle);
  };
  size_t segments = 0;
  for (const auto& c : cracks_) segments += c ? c->graph().num_edges() : 0;
  bool cacheable = shell_sets < (size_t{1} << 8);
  for (size_t s = 0; s < shell_sets; ++s) cacheable = cacheable && sets_[s].count < (size_t{1} << 24);
  if (!visibility_cache_ || segments != visibility_cache_segments_) {
    visibility_cache_ = std::make_unique<tbb::enumerable_thread_specific<VisibilityCache>>();
    visibility_cache_segments_ = segments;
  }
  // Two particles are on the same fragment side locally when they belong to the same body and, on a
  // shell, the parameter-space segment between them crosses no crack. Coupled patches are one body:
  // there the path runs through the seam (seam_connected).
  std::vector<unsigned char> coupled_patch(patches_.size(), 0);
  for (const InterfaceSpec& spec : scene_.interfaces)
    if (spec.coupled) coupled_patch[static_cast<size_t>(spec.coupling.leader_patch)] =
                          coupled_patch[static_cast<size_t>(spec.coupling.follower_patch)] = 1;
  auto visible = [&](uint32_t sa, uint32_t a, uint32_t sb, uint32_t b) {
    if (sa / 2 != sb / 2) return seam_connected(sa / 2, parameter(sa, a), sb / 2, parameter(sb, b));
    const crack2d::CrackIndex* index = patches_[sa / 2].crack();
    return !index || !index->crosses(parameter(sa, a), parameter(sb, b));
  };
  const mpm::Connectivity connected = [&](uint32_t sa, uint32_t a, uint32_t sb, uint32_t b) {
    if (sa >= shell_sets || sb >= shell_sets) return sa == sb;
    if (sa / 2 != sb / 2 && !(coupled_patch[sa / 2] && coupled_patch[sb / 2])) return false;
    if (sa / 2 == sb / 2 && !patches_[sa / 2].crack()) return true;
    if (!cacheable) return visible(sa, a, sb, b);
    // Key: the two (set, particle) ids, smaller first (sets < 2^8, particles < 2^24 per set).
    uint64_t ka = (uint64_t{sa} << 24) | a, kb = (uint64_t{sb} << 24) | b;
    if (ka > kb) std::swap(ka, kb);
    VisibilityCache& cache = visibility_cache_->local();
    const auto [it, inserted] = cache.try_emplace((ka << 32) | kb, false);
    if (inserted) it->second = visible(sa, a, sb, b);
    return it->second;
  };
  phantoms_ = mpm::partition_nodes(grid_, sets_, roles, connected);
  grid_.set_phantom_copies(phantoms_);
  crack_stats_.max_split_nodes = std::max(crack_stats_.max_split_nodes, phantoms_.split_nodes);
}

}  // namespace shellfrac::sim
