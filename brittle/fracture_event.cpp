#include "brittle/fracture_event.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>
#include <nlohmann/json.hpp>

#include "brittle/errors.hpp"

namespace shellfrac::brittle {

FractureEvent fracture_event(const BrittleSolid& solid, const TriMesh& domain, const FractureEventOptions& o,
                             const std::string& source) {
  require_closed_solid(domain, source);
  FractureEvent ev;
  ev.damaged_particles = solid.count_damaged(o.crack.grid.damage_threshold);
  ev.breakage_order = o.breakage.enabled;
  FragmentOptions fo = o.fragments;
  fo.density = o.density > 0 ? o.density : solid.material.density;
  CrackExtractionOptions co = o.crack;
  bounding_box(domain, co.cover_lo, co.cover_hi);  // the regions must cover the whole mesh
  const std::vector<double> history = solid.damage_history();
  for (int attempt = 0;; ++attempt) {
    const auto t0 = std::chrono::steady_clock::now();
    ev.crack = extract_crack(solid.rest, history, co);
    ev.regions = find_regions(ev.crack.diagram, ev.crack.crack_face);
    if (o.breakage.enabled) {
      // The sheets between intact parts, split further along the valleys of the damage time.
      ev.crack = damage_time_crack(solid.rest, solid.damage, co, o.breakage.dynamics, {&ev.crack, &ev.regions});
      ev.regions = find_regions(ev.crack.diagram, ev.crack.crack_face);
      split_regions_at_empty_cells(ev.crack.diagram, ev.crack.crack_face, ev.regions, solid.rest);
    }
    if (o.breakage.enabled && o.breakage.min_share > 0) {
      const int before = ev.regions.count;
      merge_small_regions(ev.crack.diagram, ev.regions, points_per_region(ev.crack.diagram, ev.regions, solid.rest),
                          o.breakage.min_share);
      ev.merged_regions = before - ev.regions.count;
    }
    if (o.breakage.enabled && o.breakage.smoothing.passes > 0)
      // Every basin boundary (merged ones too: they stay in the crack surface as partial cracks).
      ev.smoothing = smooth_crack_faces(ev.crack.diagram, ev.crack.crack_face, co.grid.spacing, o.breakage.smoothing);
    const auto t1 = std::chrono::steady_clock::now();
    try {
      ev.fragments = cut_fragments(domain, ev.crack.diagram, ev.regions, fo, source);
      if (o.breakage.enabled && o.breakage.min_share > 0) {
        // The share is judged on the particles (nearest lattice site) before the sheets are smoothed;
        // a fragment is region n object (thesis sec. 3.5) cut from the smoothed cells, and the smoothing
        // shrinks small convex pieces (corner chips of 1.2-1.7 % of the particles came out 0.7-1.4 % of
        // the volume). So the merge is checked once more on the cut volumes of the regions, and the
        // regions are cut again if a region under the share had to join its neighbour.
        std::vector<double> volume(static_cast<size_t>(ev.regions.count), 0.0);
        for (const Fragment& f : ev.fragments.fragments)
          if (f.region >= 0) volume[static_cast<size_t>(f.region)] += f.properties.volume;
        const double input = ev.fragments.input_volume;
        bool small = false;
        for (double v : volume) small = small || (v > 0 && v < o.breakage.min_share * input);
        if (small && ev.regions.count > 1 && input > 0) {
          // Volumes as counts in units of 1e-9 of the input (merge_small_regions compares shares).
          std::vector<size_t> units(volume.size());
          for (size_t r = 0; r < volume.size(); ++r) units[r] = static_cast<size_t>(std::llround(1e9 * std::max(volume[r], 0.0) / input));
          const int before = ev.regions.count;
          merge_small_regions(ev.crack.diagram, ev.regions, units, o.breakage.min_share);
          if (ev.regions.count != before) {
            ev.merged_regions += before - ev.regions.count;
            ev.fragments = cut_fragments(domain, ev.crack.diagram, ev.regions, fo, source);
          }
        }
      }
      ev.seconds_extract += std::chrono::duration<double>(t1 - t0).count();
      ev.seconds_cut += std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
      break;
    } catch (const NumericalError&) {
      // A region boundary that does not close comes from a near-degenerate Voronoi vertex; other site
      // jitter removes it.
      if (attempt + 1 >= o.attempts) throw;
      co.seed += 7919;
    }
  }
  // The chevron detail moves the fragments' crack faces (the crack surface output below stays flat).
  ev.detail = add_fracture_detail(ev.fragments, solid.rest, solid.damage, o.detail, fo.density);
  const auto t2 = std::chrono::steady_clock::now();
  ev.crack_surface = crack_surface_mesh(ev.crack);
  const double clip_voxel = o.clip_voxel > 0 ? o.clip_voxel : 0.25 * co.grid.spacing;
  ev.crack_surface_clipped = clip_to_domain(ev.crack_surface, domain, clip_voxel);
  if (o.gap_width > 0) ev.gap_fragments = cut_thickened_crack(domain, ev.crack_surface, o.gap_width, fo, source);
  ev.seconds_cut += std::chrono::duration<double>(std::chrono::steady_clock::now() - t2).count();
  return ev;
}

namespace {

nlohmann::json fragments_json(const FragmentSet& set) {
  nlohmann::json list = nlohmann::json::array();
  for (const Fragment& f : set.fragments) {
    const MassProperties& p = f.properties;
    nlohmann::json inertia = nlohmann::json::array();
    for (int r = 0; r < 3; ++r) inertia.push_back({p.inertia(r, 0), p.inertia(r, 1), p.inertia(r, 2)});
    list.push_back({{"name", f.mesh.name},
                    {"volume", p.volume},
                    {"centroid", {p.centroid.x(), p.centroid.y(), p.centroid.z()}},
                    {"mass", p.mass},
                    {"inertia", inertia},
                    {"triangles", f.mesh.triangles.size()},
                    {"crack_triangles", f.crack_triangles}});
  }
  return {{"cutter", to_string(set.cutter)},
          {"voxel", set.voxel},
          {"count", set.fragments.size()},
          {"input_volume", set.input_volume},
          {"total_volume", set.total_volume()},
          {"volume_change", set.volume_change()},
          {"fragments", list}};
}

}  // namespace

nlohmann::json fracture_summary(const FractureEvent& ev) {
  const CrackExtraction& c = ev.crack;
  nlohmann::json j = {{"damaged_particles", ev.damaged_particles},
                      {"node_sets", {{"D", c.count_D}, {"B", c.count_B}, {"B_dilated", c.count_Bd}, {"S", c.count_S},
                                     {"V", c.count_V}, {"I", c.count_I}, {"E", c.count_E}, {"N", c.count_N}}},
                      {"voronoi_cells", c.diagram.num_cells()},
                      {"crack_faces", {{"interior", c.interior_faces}, {"extension", c.extension_faces}}},
                      {"crack_area_inside", surface_area(ev.crack_surface_clipped)},
                      {"regions", ev.regions.count},
                      {"seconds", {{"extract", ev.seconds_extract}, {"cut", ev.seconds_cut}, {"detail", ev.detail.seconds}}},
                      {"fragments", fragments_json(ev.fragments)}};
  if (!ev.gap_fragments.fragments.empty()) j["gap_fragments"] = fragments_json(ev.gap_fragments);
  if (ev.breakage_order)
    j["breakage_order"] = {{"merged_regions", ev.merged_regions},
                           {"smoothing", {{"sheet_corners", ev.smoothing.sheet_corners},
                                          {"curve_corners", ev.smoothing.curve_corners},
                                          {"fixed_corners", ev.smoothing.fixed_corners},
                                          {"rejected_moves", ev.smoothing.rejected_moves},
                                          {"max_displacement", ev.smoothing.max_displacement}}}};
  if (ev.detail.crack_vertices > 0)
    j["detail"] = {{"edge", ev.detail.edge}, {"crack_vertices", ev.detail.crack_vertices}, {"timed_vertices", ev.detail.timed_vertices},
                   {"lines", ev.detail.lines},                   {"enhanced_lines", ev.detail.enhanced_lines},
                   {"longest_line", ev.detail.longest_line},     {"moved_vertices", ev.detail.moved_vertices},
                   {"max_displacement", ev.detail.max_displacement}, {"folded_triangles", ev.detail.folded_triangles}};
  return j;
}

}  // namespace shellfrac::brittle
