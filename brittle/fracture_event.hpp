#pragma once
#include <nlohmann/json_fwd.hpp>
#include <string>

#include "brittle/breakage_order.hpp"
#include "brittle/brittle_solid.hpp"
#include "brittle/crack_surface.hpp"
#include "brittle/fracture_detail.hpp"
#include "brittle/fragments.hpp"

namespace shellfrac::brittle {

struct FractureEventOptions {
  CrackExtractionOptions crack;   // h_v (crack.grid.spacing) etc.
  FragmentOptions fragments;      // cutter, voxel, UV scale (its density is replaced, see below)
  double density = 0;             // of the fragments' mass; 0 = the solid's material density
  double gap_width = 0;           // > 0: also cut the crack surface as a hairline gap (partial cracks)
  double clip_voxel = 0;          // voxel of the clipped crack surface; 0 = h_v / 4
  int attempts = 3;               // new site jitter seeds tried when a region boundary does not close
  BreakageOrderOptions breakage;  // crack along the valleys of the damage time (off by default)
  FractureDetailOptions detail;   // chevron marks on the crack faces (sec. 3.7; off by default)
};

// Everything one fracture event produces (thesis sec. 3.3-3.5), in the object's material space.
struct FractureEvent {
  size_t damaged_particles = 0;
  bool breakage_order = false;    // the crack follows the damage time (BreakageOrderOptions)
  int merged_regions = 0;         // regions under breakage.min_share merged into a neighbour
  CrackSmoothingReport smoothing; // what smoothing the damage-time crack faces did
  CrackExtraction crack;
  Regions regions;
  TriMesh crack_surface;          // all crack faces (interior and extension), possibly non-manifold
  TriMesh crack_surface_clipped;  // the part inside the object
  FragmentSet fragments;          // region n object
  FragmentSet gap_fragments;      // object minus the thickened crack (only with gap_width > 0)
  FractureDetailReport detail;    // what the chevron detail did (zeros when off)
  double seconds_extract = 0, seconds_cut = 0;
};

// Extracts the crack from the solid's damage history and cuts the fragments out of `domain` (the object's
// closed mesh, named by `source` in errors). Throws InputError / NumericalError as the stages do.
FractureEvent fracture_event(const BrittleSolid& solid, const TriMesh& domain, const FractureEventOptions& options,
                             const std::string& source);

// The event for summary.json: counts, per fragment name, volume, centroid, mass, inertia tensor, the
// total volume against the input's, and the stage seconds.
nlohmann::json fracture_summary(const FractureEvent& event);

}  // namespace shellfrac::brittle
