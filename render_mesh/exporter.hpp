#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "render_mesh/poly_mesh.hpp"

namespace shellfrac::render_mesh {

struct ExportFormat {
  std::string id;           // e.g. "obj", "ply", "stl", "gltf2"
  std::string extension;    // file extension without the dot
  std::string description;
};

// Every format the linked assimp can write.
const std::vector<ExportFormat>& export_formats();
bool is_export_format(const std::string& id);
const ExportFormat& export_format(const std::string& id);  // throws std::invalid_argument if unknown

// Writes the meshes (one object each) to directory/stem.<extension> with assimp, atomically: the
// exporter writes into a staging directory and the files are renamed into place only when complete
// (side files such as OBJ's .mtl first). Returns the path of the main file.
// Throws std::runtime_error with assimp's reason on failure; nothing is left half-written.
std::filesystem::path export_meshes(const std::vector<PolyMesh>& meshes,
                                    const std::filesystem::path& directory, const std::string& stem,
                                    const std::string& format_id);

}  // namespace shellfrac::render_mesh
