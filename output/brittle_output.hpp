#pragma once
// What the run writes for brittle solids (docs/brittle.md, docs/cli.md): per fracture event the fragments
// as one mesh file with one named object per fragment (through render_mesh's exporter, in the scene's
// output format), the crack surface inside the object, the particles as OpenVDB Points, and the typed
// "brittle" section of summary.json.
#include <filesystem>
#include <string>
#include <vector>

#include "output/summary.hpp"
#include "render_mesh/poly_mesh.hpp"
#include "scene/model.hpp"
#include "sim/simulation.hpp"

namespace shellfrac::output {

// A brittle triangle mesh as an exportable polygon mesh (normals and UVs when the mesh has them).
render_mesh::PolyMesh poly_mesh(const brittle::TriMesh& m);

class BrittleWriter {
 public:
  BrittleWriter(const scene::Model& model, std::filesystem::path out_dir);

  // Writes the files of every fracture event that appeared since the last call (atomically, each file
  // complete or absent). Throws std::runtime_error naming the file when a write fails.
  void write_new_events(const sim::Simulation& sim);
  // The brittle section of the summary: every brittle solid, with its event once it happened.
  std::vector<BrittleSolidReport> reports(const sim::Simulation& sim) const;

 private:
  const scene::Model& model_;
  std::filesystem::path out_dir_;
  std::vector<bool> written_;
  std::vector<std::array<std::string, 3>> files_;  // fragments, crack, particles (relative)
};

}  // namespace shellfrac::output
