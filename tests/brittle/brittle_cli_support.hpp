#pragma once
// Shared by the brittle and shatter CLI tests: running the shellfrac binary on brittle scenes, scratch
// folders, and an OBJ reader of their own (no program code) for checking the written meshes.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <array>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "tests/cli/cli_process.hpp"

namespace shellfrac::test::brittle_cli {

namespace fs = std::filesystem;
using Json = nlohmann::json;


inline Result shellfrac(const std::string& args) { return shellfrac::test::run_shellfrac(args); }

inline fs::path scratch(const std::string& name) { return shellfrac::test::scratch_folder("brittle", name); }

inline fs::path scene_file(const std::string& name) { return fs::path(SHELLFRAC_SOURCE_DIR) / "scenes" / "brittle" / (name + ".json"); }

// Runs a shipped brittle scene and returns its summary.json (the run folder stays for the caller).
inline Json run_scene(const std::string& name, const fs::path& out) {
  const Result r = shellfrac("run " + scene_file(name).string() + " --out " + out.string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  std::ifstream in(out / "summary.json");
  return Json::parse(in);
}

// The fragment OBJ read back on its own, without the program's numbers: its objects ("o <name>") with
// their faces as position triples. The writer never merges vertices (each face corner has its own
// normal and UV), so vertices are matched by their printed position: two corners are the same point
// exactly when their "v" lines print the same coordinates.
struct ObjObject {
  std::string name;
  std::vector<std::vector<size_t>> faces;  // indices into ObjFile::points (one per distinct printed position)
};
struct ObjFile {
  std::vector<std::array<double, 3>> points;  // per distinct printed position
  std::vector<ObjObject> objects;
};

inline ObjFile read_obj(const fs::path& path) {
  ObjFile file;
  std::map<std::string, size_t> by_text;
  std::vector<size_t> vertex_point;  // OBJ vertex (1-based in the file) -> distinct position
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream ls(line);
    std::string tag;
    ls >> tag;
    if (tag == "o") {
      file.objects.emplace_back();
      ls >> file.objects.back().name;
    } else if (tag == "v") {
      std::string x, y, z;
      ls >> x >> y >> z;
      const auto [it, added] = by_text.emplace(x + " " + y + " " + z, file.points.size());
      if (added) file.points.push_back({std::stod(x), std::stod(y), std::stod(z)});
      vertex_point.push_back(it->second);
    } else if (tag == "f") {
      if (file.objects.empty()) file.objects.emplace_back();  // faces before any "o": an unnamed object
      std::vector<size_t> face;
      std::string corner;
      while (ls >> corner) {
        const long i = std::stol(corner.substr(0, corner.find('/')));  // "v/vt/vn": the position index
        const long k = i > 0 ? i - 1 : static_cast<long>(vertex_point.size()) + i;
        if (k < 0 || k >= static_cast<long>(vertex_point.size())) throw std::runtime_error(path.string() + ": bad index " + corner);
        face.push_back(vertex_point[static_cast<size_t>(k)]);
      }
      file.objects.back().faces.push_back(face);
    }
  }
  return file;
}

// A minimal brittle scene: one block with the given extra solid fields and fracture keys.
inline std::string brittle_scene(const std::string& solid_fields, const std::string& fracture = R"("stop": {"max_steps": 5})") {
  return R"({"gravity": [0, 0, 0], "solids": [{"name": "block", "spacing": 0.01,
    "material": {"E": 1e7, "nu": 0.2, "density": 1000, "failure_stress": 1e5, "fracture_energy": 100},
    "fracture": {)" + fracture + "}, " + solid_fields + "}]}";
}

}  // namespace shellfrac::test::brittle_cli
