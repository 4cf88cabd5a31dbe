#pragma once
// Counters of the crack machinery over a run (summary.json metrics.cracks, docs/cli.md; Python's
// Simulation.metrics()["cracks"]). `visit` names each counter once, for every writer and reader.
#include <cstddef>

namespace shellfrac::sim {

struct CrackCounters {
  long extractions = 0;            // consistent crack extractions run (all patches)
  size_t subset_violations = 0;    // extractions whose graph did not contain the previous one (must be 0)
  size_t crack_segments = 0;       // segments in all crack graphs now
  size_t mls_points = 0;           // in-plane points with MLS bases now
  size_t mls_failures = 0;         // points left without a basis although their piece could carry one
  size_t max_split_nodes = 0;      // largest number of grid nodes with phantom copies in one step
  size_t contact_pairs = 0;        // pairwise fragment contacts resolved (Eq. 4.23-4.26), all steps
  double max_contact_residual = 0; // largest approaching velocity left after contact
  size_t seam_continuations = 0;   // cracks continued across a coupled seam into the neighbour patch

  // Calls visitor(name, member pointer) for every counter, in the order summary.json lists them.
  template <class Visitor>
  static void visit(Visitor&& visitor) {
    visitor("extractions", &CrackCounters::extractions);
    visitor("subset_violations", &CrackCounters::subset_violations);
    visitor("crack_segments", &CrackCounters::crack_segments);
    visitor("mls_points", &CrackCounters::mls_points);
    visitor("mls_failures", &CrackCounters::mls_failures);
    visitor("max_split_nodes", &CrackCounters::max_split_nodes);
    visitor("contact_pairs", &CrackCounters::contact_pairs);
    visitor("max_contact_residual", &CrackCounters::max_contact_residual);
    visitor("seam_continuations", &CrackCounters::seam_continuations);
  }
};

}  // namespace shellfrac::sim
