#pragma once
// What a scene will cost before anything big is allocated: particle, quadrature point, grid,
// render and level-set counts with their memory, the number of steps and frames, and the disk a run
// writes. Everything comes from the scene's numbers and cheap geometry (patch sizes, knot spans, mesh
// bounds and areas read from the mesh file, no level set), so `validate` and `run` can refuse a scene
// that would exhaust the machine at no cost. The counts are estimates (docs/cli.md, "Resource estimate");
// the shell counts are exact for flat, cylinder and cone patches and control nets, and so are the grid
// nodes of shells with up to 2e6 grid particles and 2e5 blocks (counted from their positions).
#include <optional>
#include <string>
#include <vector>

#include "scene/scene.hpp"

namespace shellfrac::scene {

// One kind of array a run allocates: how many elements, how many bytes, and the JSON pointer of the
// scene value that sets the count (so a refusal can say what to change).
struct ResourceItem {
  std::string what;  // "shell quadrature points", "grid nodes", ...
  double count = 0;
  double bytes = 0;
  std::string json_path;
};

struct ResourceEstimate {
  std::vector<ResourceItem> memory;  // the big arrays, in scene order
  double memory_bytes = 0;           // their sum plus a fixed base for the program itself
  double grid_dx = 0;                // the grid spacing the run will use [m]
  double dt = 0;                     // the step the run will take [s] (the stability bound, or time.dt)
  double steps = 0;                  // time.end / dt
  std::string steps_path;            // the value that makes steps large
  double frames = 0;                 // frames written, frame 0 included
  std::string frames_path;
  double frame_bytes = 0;            // one frame's mesh files on disk
  double disk_bytes = 0;             // all frames
  double work = 0;                   // steps x (particles + quadrature points): the cost of the run
  // The item with the most bytes (memory is never empty for a valid scene).
  const ResourceItem& largest() const;
};

// Estimates a scene's resources. Validates it first (SceneError as build() would give), applies its
// quality preset, and reads the mesh files of mesh solids and colliders (SceneError at their "file"
// key when a mesh cannot be read or is not a closed surface). Throws SceneError at /grid/dx when the
// grid spacing is too small for the scene's extent (the sparse grid's coordinates would overflow).
ResourceEstimate estimate_resources(const Scene& scene);

// What a run may use. Steps, frames and disk may be exceeded with `force`; memory never.
struct ResourceBudget {
  double memory_bytes = 0;                  // 0: no memory limit
  double max_steps = 1e8;
  double max_frames = 1e5;
  std::optional<double> free_disk_bytes;    // free space where the frames go, when known
  bool force = false;
  std::string memory_source;                // what set memory_bytes, for the message ("": --max-memory)
};

// Throws SceneError (file = source, path = the driving value, exit code 2) when the estimate is over
// the budget; the message gives the estimate, the budget and how to lift it. A frame count above the
// largest int is refused even with `force`.
void check_budget(const ResourceEstimate& estimate, const ResourceBudget& budget, const std::string& source);

// The problems check_budget would report with force = false that force lifts, one line each (for
// `validate`, which warns about them).
std::vector<std::string> budget_warnings(const ResourceEstimate& estimate, const ResourceBudget& budget);

// The estimate as indented lines for `validate` ("  memory  1.2 GiB (...)").
std::string describe_estimate(const ResourceEstimate& estimate);

// "1.5 GiB", "320 MiB", "12 KiB", "512 B".
std::string format_bytes(double bytes);

}  // namespace shellfrac::scene
