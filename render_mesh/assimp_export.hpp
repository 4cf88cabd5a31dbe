#pragma once
// Export through assimp for the formats shellfrac does not write itself (exporter.hpp decides).
#include <filesystem>
#include <string>
#include <vector>

#include "render_mesh/poly_mesh.hpp"

namespace shellfrac::render_mesh {

// Writes the meshes with assimp's exporter `format_id` to `staged_file` (inside a staging directory),
// with no post-processing beyond what that exporter itself enforces. Object names go through
// export_object_name. Every file assimp opens goes through a checked I/O layer: bytes are collected in
// memory and written, fsynced and closed with write_file_durably when assimp closes the stream.
// Throws std::runtime_error naming `final_dir`/<file> and the reason (assimp's or the OS's).
void export_with_assimp(const std::vector<PolyMesh>& meshes, const std::string& format_id,
                        const std::filesystem::path& staged_file, const std::filesystem::path& final_dir);

}  // namespace shellfrac::render_mesh
