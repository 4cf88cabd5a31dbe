#include "render_mesh/assimp_export.hpp"

#include <assimp/Exporter.hpp>
#include <assimp/IOStream.hpp>
#include <assimp/IOSystem.hpp>
#include <assimp/material.h>
#include <assimp/scene.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <limits>
#include <memory>
#include <sstream>
#include <vector>
#include <stdexcept>

#include "render_mesh/atomic_write.hpp"
#include "render_mesh/object_name.hpp"

namespace shellfrac::render_mesh {

namespace fs = std::filesystem;

namespace {

aiMesh* to_ai_mesh(const PolyMesh& m, const std::string& name) {
  auto* out = new aiMesh();
  out->mName = aiString(name);
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

// An aiScene owning one node per mesh and one default material (several exporters need one). The scene
// is not flagged AI_SCENE_FLAGS_NON_VERBOSE_FORMAT, so assimp does not expand it to one vertex per face
// corner before exporting.
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
    const std::string name = export_object_name(meshes[i].name, "mesh" + std::to_string(i));
    scene->mMeshes[i] = to_ai_mesh(meshes[i], name);
    auto* node = new aiNode(name);
    node->mParent = scene->mRootNode;
    node->mNumMeshes = 1;
    node->mMeshes = new unsigned[1]{i};
    scene->mRootNode->mChildren[i] = node;
  }
  return scene;
}

// The first I/O failure of an export, shared by the I/O system and its streams (which assimp may
// delete directly instead of closing them through the system).
struct IoFailure {
  std::string reason;
  void record(const std::string& r) {
    if (reason.empty()) reason = r;
  }
};

// A file assimp writes: the bytes are kept in memory (assimp may seek) and go to disk, checked, when
// the stream ends. Read streams serve an existing file's bytes.
class CheckedStream : public Assimp::IOStream {
 public:
  CheckedStream(std::string path, fs::path reported_as, bool writing, std::string content, IoFailure* failure)
      : path_(std::move(path)), reported_as_(std::move(reported_as)), writing_(writing), data_(std::move(content)),
        failure_(failure) {}
  ~CheckedStream() override {
    if (!writing_) return;
    try {
      write_file_durably(path_, data_, reported_as_);
    } catch (const std::exception& e) {
      failure_->record(e.what());
    }
  }
  size_t Read(void* buffer, size_t size, size_t count) override {
    if (size == 0) return 0;
    const size_t n = std::min(count, (data_.size() - std::min(pos_, data_.size())) / size);
    std::memcpy(buffer, data_.data() + pos_, n * size);
    pos_ += n * size;
    return n;
  }
  size_t Write(const void* buffer, size_t size, size_t count) override {
    if (!writing_) return 0;
    const size_t bytes = size * count;
    if (pos_ + bytes > data_.size()) data_.resize(pos_ + bytes);
    std::memcpy(&data_[pos_], buffer, bytes);
    pos_ += bytes;
    return count;
  }
  aiReturn Seek(size_t offset, aiOrigin origin) override {
    const size_t base = origin == aiOrigin_SET ? 0 : origin == aiOrigin_CUR ? pos_ : data_.size();
    if (offset > std::numeric_limits<size_t>::max() - base) return aiReturn_FAILURE;
    pos_ = base + offset;
    return aiReturn_SUCCESS;
  }
  size_t Tell() const override { return pos_; }
  size_t FileSize() const override { return data_.size(); }
  void Flush() override {}

 private:
  std::string path_;
  fs::path reported_as_;
  bool writing_;
  std::string data_;
  size_t pos_ = 0;
  IoFailure* failure_;
};

class CheckedIoSystem : public Assimp::IOSystem {
 public:
  CheckedIoSystem(IoFailure* failure, fs::path final_dir) : failure_(failure), final_dir_(std::move(final_dir)) {}
  bool Exists(const char* file) const override { return fs::exists(file); }
  const std::vector<std::string>& written() const { return written_; }
  char getOsSeparator() const override { return '/'; }
  Assimp::IOStream* Open(const char* file, const char* mode) override {
    const std::string m = mode ? mode : "rb";
    const bool writing = m.find_first_of("wa") != std::string::npos;
    std::string content;
    if (!writing || m.find('a') != std::string::npos) {
      std::ifstream in(file, std::ios::binary);
      if (!in) {
        if (!writing) return nullptr;
      } else {
        std::ostringstream ss;
        ss << in.rdbuf();
        content = ss.str();
      }
    }
    if (writing) written_.push_back(fs::path(file).filename().string());
    return new CheckedStream(file, final_dir_ / fs::path(file).filename(), writing, std::move(content), failure_);
  }
  void Close(Assimp::IOStream* stream) override { delete stream; }

 private:
  IoFailure* failure_;
  fs::path final_dir_;
  std::vector<std::string> written_;
};

}  // namespace

void export_with_assimp(const std::vector<PolyMesh>& meshes, const std::string& format_id,
                        const fs::path& staged_file, const fs::path& final_dir) {
  const std::unique_ptr<aiScene> scene = to_ai_scene(meshes);
  IoFailure failure;
  aiReturn status;
  std::string assimp_error;
  std::vector<std::string> written;
  {
    Assimp::Exporter exporter;
    auto* io = new CheckedIoSystem(&failure, final_dir);
    exporter.SetIOHandler(io);  // the exporter owns and deletes it
    status = exporter.Export(scene.get(), format_id.c_str(), staged_file.c_str());
    if (status != aiReturn_SUCCESS) assimp_error = exporter.GetErrorString();
    written = io->written();
  }
  if (!failure.reason.empty()) throw std::runtime_error(failure.reason);
  // A file that did not pass through the checked I/O (an exporter writing on its own) cannot be vouched
  // for: refuse it rather than commit something possibly truncated.
  for (const auto& entry : fs::directory_iterator(staged_file.parent_path()))
    if (std::find(written.begin(), written.end(), entry.path().filename().string()) == written.end())
      throw std::runtime_error("cannot export " + (final_dir / entry.path().filename()).string() + " as " + format_id +
                               ": the exporter wrote it past shellfrac's checked I/O");
  if (status != aiReturn_SUCCESS)
    throw std::runtime_error("cannot export " + (final_dir / staged_file.filename()).string() + " as " +
                             format_id + ": " + assimp_error);
}

}  // namespace shellfrac::render_mesh
