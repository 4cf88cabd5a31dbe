#pragma once
#include <cstddef>
#include <string>
#include <vector>

namespace shellfrac::app {

// The `preview OUT_DIR [--frames LIST|last|all] [--size WxH] [--samples N] [--out PNG_DIR] [--threads N]`
// command (registered by add_preview_command, command.hpp) renders chosen frames of a finished run
// (OUT_DIR/summary.json "frames") to PNG with Blender in background mode (Cycles on the CPU), plus a contact
// sheet. Blender is found as $SHELLFRAC_BLENDER or `blender` on PATH; the Blender-side scripts
// (apps/shellfrac/blender/preview.py, shellfrac_mesh.py) are compiled into the binary. Exit codes: 0 rendered,
// 2 bad input, 1 Blender missing or failed.

// Frame numbers named by `spec` for a run of `frame_count` frames, ascending and without repeats:
// "last", "all", or a comma-separated list of numbers and inclusive ranges ("0,12,20-24").
// Throws std::invalid_argument naming the offending item.
std::vector<int> select_frames(const std::string& spec, std::size_t frame_count);

// A Python file Blender runs for `preview`, embedded at build time from apps/shellfrac/blender/.
struct BlenderScript {
  const char* name;  // file name; the first one is the script to run, the others are modules it imports
  const char* text;
};
const std::vector<BlenderScript>& blender_preview_scripts();

}  // namespace shellfrac::app
