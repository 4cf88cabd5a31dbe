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
  bool own_writer = false;        // written by shellfrac (obj, objnomtl, ply, plyb, gltf2, glb2); else assimp
  // The format takes triangles only: frames are always triangulated (points and lines are kept, except
  // in stl, which cannot hold them: solids' particle clouds do not appear there).
  bool needs_triangles = false;
  // The file holds every PolyMesh vertex exactly once, in PolyMesh order (meshes one after the other),
  // so the vertex count and order stay fixed while the crack graph is unchanged (point caches, motion
  // blur). Set only where a test reads the file back and checks it (tessellation_export_test.cpp).
  bool keeps_vertices = false;
  bool double_precision = false;  // ExportOptions::double_precision is honoured
};

// Every format shellfrac can write: its own OBJ, PLY and glTF 2 writers and the other assimp exporters
// (left out: pbrt, whose assimp 5.2 exporter crashes, and 3mf, whose exporter writes past the checked
// I/O layer).
const std::vector<ExportFormat>& export_formats();
bool is_export_format(const std::string& id);
const ExportFormat& export_format(const std::string& id);  // throws std::invalid_argument if unknown

struct ExportOptions {
  // Triangulate every polygon (output.triangulate), with triangulate(): deterministic ear clipping in
  // the parameter plane, no vertex added or moved. Formats with needs_triangles do it regardless.
  bool triangulate = false;
  // 17 significant digits instead of 9 for positions, UVs and normals (output.precision "double");
  // only formats with double_precision honour it, the others ignore it.
  bool double_precision = false;
};

// Writes the meshes (one object each) to directory/stem.<extension>, atomically: the writer puts the
// files into a staging directory, every write, fsync and close is checked, and the files are renamed
// into place only when all are complete (side files such as OBJ's .mtl or glTF's .bin first), then the
// directory is fsynced. Returns the path of the main file.
// Throws std::invalid_argument for an unknown format, a stem that is not a plain file name or a mesh
// whose faces index outside its vertices; std::runtime_error naming the final path and the reason
// (errno text, or assimp's) when writing fails. On failure nothing new appears in `directory`, and
// files already there (earlier frames) are untouched.
std::filesystem::path export_meshes(const std::vector<PolyMesh>& meshes,
                                    const std::filesystem::path& directory, const std::string& stem,
                                    const std::string& format_id, const ExportOptions& options = {});

}  // namespace shellfrac::render_mesh
