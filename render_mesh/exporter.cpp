#include "render_mesh/exporter.hpp"

#include <assimp/Exporter.hpp>
#include <assimp/material.h>
#include <assimp/scene.h>

#include <memory>
#include <stdexcept>

#include "render_mesh/atomic_write.hpp"

namespace shellfrac::render_mesh {

const std::vector<ExportFormat>& export_formats() {
  static const std::vector<ExportFormat> formats = [] {
    std::vector<ExportFormat> out;
    Assimp::Exporter exporter;
    for (size_t i = 0; i < exporter.GetExportFormatCount(); ++i) {
      const aiExportFormatDesc* d = exporter.GetExportFormatDescription(i);
      out.push_back({d->id, d->fileExtension, d->description});
    }
    return out;
  }();
  return formats;
}

bool is_export_format(const std::string& id) {
  for (const auto& f : export_formats())
    if (f.id == id) return true;
  return false;
}

const ExportFormat& export_format(const std::string& id) {
  for (const auto& f : export_formats())
    if (f.id == id) return f;
  throw std::invalid_argument("unknown mesh export format \"" + id + "\"");
}

namespace {

aiMesh* to_ai_mesh(const PolyMesh& m) {
  auto* out = new aiMesh();
  out->mName = aiString(m.name);
  out->mMaterialIndex = 0;
  const auto nv = static_cast<unsigned>(m.num_vertices());
  out->mNumVertices = nv;
  out->mVertices = new aiVector3D[nv];
  for (unsigned i = 0; i < nv; ++i) {
    const Vec3& p = m.positions[i];
    out->mVertices[i] = aiVector3D(static_cast<ai_real>(p.x()), static_cast<ai_real>(p.y()),
                                   static_cast<ai_real>(p.z()));
  }
  if (m.normals.size() == nv) {
    out->mNormals = new aiVector3D[nv];
    for (unsigned i = 0; i < nv; ++i) {
      const Vec3& n = m.normals[i];
      out->mNormals[i] = aiVector3D(static_cast<ai_real>(n.x()), static_cast<ai_real>(n.y()),
                                    static_cast<ai_real>(n.z()));
    }
  }
  if (m.uvs.size() == nv) {
    out->mTextureCoords[0] = new aiVector3D[nv];
    out->mNumUVComponents[0] = 2;
    for (unsigned i = 0; i < nv; ++i)
      out->mTextureCoords[0][i] =
          aiVector3D(static_cast<ai_real>(m.uvs[i].x()), static_cast<ai_real>(m.uvs[i].y()), 0);
  }
  const auto nf = static_cast<unsigned>(m.num_faces());
  out->mNumFaces = nf;
  out->mFaces = new aiFace[nf];
  unsigned types = 0;
  for (unsigned f = 0; f < nf; ++f) {
    const int b = m.face_offsets[f], e = m.face_offsets[f + 1];
    aiFace& face = out->mFaces[f];
    face.mNumIndices = static_cast<unsigned>(e - b);
    face.mIndices = new unsigned[face.mNumIndices];
    for (int k = b; k < e; ++k) face.mIndices[k - b] = static_cast<unsigned>(m.face_vertices[k]);
    types |= face.mNumIndices == 1   ? aiPrimitiveType_POINT
             : face.mNumIndices == 2 ? aiPrimitiveType_LINE
             : face.mNumIndices == 3 ? aiPrimitiveType_TRIANGLE
                                     : aiPrimitiveType_POLYGON;
  }
  out->mPrimitiveTypes = types;
  return out;
}

// An aiScene owning one node per mesh and one default material (several exporters need one).
std::unique_ptr<aiScene> to_ai_scene(const std::vector<PolyMesh>& meshes) {
  auto scene = std::make_unique<aiScene>();
  scene->mNumMaterials = 1;
  scene->mMaterials = new aiMaterial*[1];
  scene->mMaterials[0] = new aiMaterial();
  aiString material_name("shell");
  scene->mMaterials[0]->AddProperty(&material_name, AI_MATKEY_NAME);

  const auto n = static_cast<unsigned>(meshes.size());
  scene->mNumMeshes = n;
  scene->mMeshes = new aiMesh*[n];
  scene->mRootNode = new aiNode("root");
  scene->mRootNode->mNumChildren = n;
  scene->mRootNode->mChildren = new aiNode*[n];
  for (unsigned i = 0; i < n; ++i) {
    scene->mMeshes[i] = to_ai_mesh(meshes[i]);
    auto* node = new aiNode(meshes[i].name);
    node->mParent = scene->mRootNode;
    node->mNumMeshes = 1;
    node->mMeshes = new unsigned[1]{i};
    scene->mRootNode->mChildren[i] = node;
  }
  return scene;
}

}  // namespace

std::filesystem::path export_meshes(const std::vector<PolyMesh>& meshes,
                                    const std::filesystem::path& directory, const std::string& stem,
                                    const std::string& format_id) {
  const ExportFormat& format = export_format(format_id);
  const std::string file_name = stem + "." + format.extension;
  const std::unique_ptr<aiScene> scene = to_ai_scene(meshes);
  StagingDirectory staging(directory);
  Assimp::Exporter exporter;
  const std::string staged = (staging.path() / file_name).string();
  if (exporter.Export(scene.get(), format.id, staged) != aiReturn_SUCCESS)
    throw std::runtime_error("cannot export " + (directory / file_name).string() + " as " +
                             format.id + ": " + exporter.GetErrorString());
  return staging.commit(file_name).back();
}

}  // namespace shellfrac::render_mesh
