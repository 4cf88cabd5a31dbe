#pragma once
#include <filesystem>
#include <string>
#include <vector>

namespace shellfrac::render_mesh {

// Writes `content` to `path` so that readers only ever see the old file or the complete new one:
// the bytes go to a temporary file in the same directory, are flushed, and are renamed over `path`.
// Throws std::runtime_error (naming the path and the OS reason) on failure; no partial file remains.
void write_file_atomically(const std::filesystem::path& path, const std::string& content);

// A private scratch directory next to the final files. Writers put complete files into it;
// commit() renames them into the destination (the primary file last, so it never appears before the
// files it references). The directory and anything left in it are removed on destruction.
class StagingDirectory {
 public:
  explicit StagingDirectory(const std::filesystem::path& destination_dir);
  ~StagingDirectory();
  StagingDirectory(const StagingDirectory&) = delete;
  StagingDirectory& operator=(const StagingDirectory&) = delete;

  const std::filesystem::path& path() const { return staging_; }
  // Moves every file in the staging directory into the destination; `primary` (a file name) goes last.
  // Returns the final paths.
  std::vector<std::filesystem::path> commit(const std::string& primary);

 private:
  std::filesystem::path destination_, staging_;
};

}  // namespace shellfrac::render_mesh
