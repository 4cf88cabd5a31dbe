#pragma once
#include <filesystem>
#include <string>
#include <vector>

namespace shellfrac::render_mesh {

// Every function here checks each write, fsync and close. A failure throws std::runtime_error that
// names the path and the OS reason (errno text), e.g. "cannot write out/frames/f.obj: No space left on
// device". Nothing partial is left under a final name, even on a full disk.

// Writes `content` to `path` so that readers only ever see the old file or the complete new one:
// the bytes go to a temporary file in the same directory, are fsynced, and are renamed over `path`;
// the directory is then fsynced so that the rename survives a crash. On failure the temporary file is
// removed and an existing `path` keeps its old content.
void write_file_atomically(const std::filesystem::path& path, const std::string& content);

// Creates (or truncates) `path` and writes `content`, then fsyncs and closes it, checking each call.
// On failure the file is removed before the exception leaves. Meant for files inside a staging
// directory, which reach their final name only by StagingDirectory::commit. Errors name `reported_as`
// when given (the final path of a staged file), else `path`.
void write_file_durably(const std::filesystem::path& path, const std::string& content,
                        const std::filesystem::path& reported_as = {});

// fsyncs a directory (makes renames and new entries in it durable). Throws on failure.
void sync_directory(const std::filesystem::path& dir);

// A private scratch directory next to the final files. Writers put complete files into it;
// commit() fsyncs them and renames them into the destination (the primary file last, so it never
// appears before the files it references), then fsyncs the destination directory. The directory and
// anything left in it are removed on destruction, so a failed export leaves no file behind.
class StagingDirectory {
 public:
  explicit StagingDirectory(const std::filesystem::path& destination_dir);
  ~StagingDirectory();
  StagingDirectory(const StagingDirectory&) = delete;
  StagingDirectory& operator=(const StagingDirectory&) = delete;

  const std::filesystem::path& path() const { return staging_; }
  const std::filesystem::path& destination() const { return destination_; }
  // Moves every file in the staging directory into the destination; `primary` (a file name) goes last.
  // Returns the final paths. A file of 0 bytes is refused (no exporter writes an empty mesh file; an
  // empty file is the mark of an unchecked failed write).
  std::vector<std::filesystem::path> commit(const std::string& primary);

 private:
  std::filesystem::path destination_, staging_;
};

}  // namespace shellfrac::render_mesh
