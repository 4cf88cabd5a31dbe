#include "render_mesh/atomic_write.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace shellfrac::render_mesh {

namespace fs = std::filesystem;

namespace {

std::string unique_suffix() {
  static std::atomic<unsigned> counter{0};
  return std::to_string(::getpid()) + "-" + std::to_string(counter.fetch_add(1));
}

[[noreturn]] void fail(const fs::path& path, const std::string& what) {
  throw std::runtime_error("cannot write " + path.string() + ": " + what);
}

std::string os_reason() { return std::strerror(errno); }

// Writes all of `content` to fd, retrying short writes and EINTR. Returns an empty string or the reason.
std::string write_all(int fd, const std::string& content) {
  size_t done = 0;
  while (done < content.size()) {
    const ssize_t n = ::write(fd, content.data() + done, content.size() - done);
    if (n < 0) {
      if (errno == EINTR) continue;
      return os_reason();
    }
    if (n == 0) return "the write made no progress";
    done += static_cast<size_t>(n);
  }
  return {};
}

// Writes, fsyncs and closes fd; returns the first failure's reason or an empty string. fd is closed in
// every case.
std::string finish_file(int fd, const std::string& content) {
  std::string why = write_all(fd, content);
  if (why.empty() && ::fsync(fd) != 0) why = os_reason();
  if (::close(fd) != 0 && why.empty()) why = os_reason();
  return why;
}

void fsync_path(const fs::path& path, int flags) {
  const int fd = ::open(path.c_str(), flags | O_CLOEXEC);
  if (fd < 0) fail(path, os_reason());
  if (::fsync(fd) != 0) {
    const std::string why = os_reason();
    ::close(fd);
    fail(path, why);
  }
  if (::close(fd) != 0) fail(path, os_reason());
}

}  // namespace

void write_file_durably(const fs::path& path, const std::string& content, const fs::path& reported_as) {
  const fs::path& name = reported_as.empty() ? path : reported_as;
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) fail(name, os_reason());
  // Only a regular file is removed on failure: a device such as /dev/full must survive a failed write.
  struct stat st {};
  const bool regular = ::fstat(fd, &st) == 0 && S_ISREG(st.st_mode);
  const std::string why = finish_file(fd, content);
  if (!why.empty()) {
    if (regular) ::unlink(path.c_str());
    fail(name, why);
  }
}

void sync_directory(const fs::path& dir) {
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) fail(dir, os_reason());
  // EINVAL: the file system cannot sync a directory (some network and FUSE mounts); the renamed files
  // themselves were synced, so this is not a write failure.
  std::string why;
  if (::fsync(fd) != 0 && errno != EINVAL) why = os_reason();
  if (::close(fd) != 0 && why.empty()) why = os_reason();
  if (!why.empty()) fail(dir, why);
}

void write_file_atomically(const fs::path& path, const std::string& content) {
  const fs::path dir = path.has_parent_path() ? path.parent_path() : fs::path(".");
  const fs::path tmp = dir / ("." + path.filename().string() + ".tmp-" + unique_suffix());
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd < 0) fail(path, os_reason());
  std::string why = finish_file(fd, content);
  if (why.empty() && ::rename(tmp.c_str(), path.c_str()) != 0) why = os_reason();
  if (!why.empty()) {
    ::unlink(tmp.c_str());
    fail(path, why);
  }
  sync_directory(dir);
}

StagingDirectory::StagingDirectory(const fs::path& destination_dir)
    : destination_(destination_dir),
      staging_(destination_dir / (".staging-" + unique_suffix())) {
  std::error_code ec;
  fs::create_directories(staging_, ec);
  if (ec) fail(staging_, ec.message());
}

StagingDirectory::~StagingDirectory() {
  std::error_code ec;
  fs::remove_all(staging_, ec);  // best effort: never throw from a destructor
}

std::vector<fs::path> StagingDirectory::commit(const std::string& primary) {
  // Check every file before the first rename, so that a refused export moves nothing.
  std::vector<fs::path> order;
  for (const auto& entry : fs::directory_iterator(staging_))
    if (entry.path().filename() != primary) order.push_back(entry.path());
  const fs::path main = staging_ / primary;
  if (!fs::exists(main)) fail(destination_ / primary, "the exporter produced no such file");
  order.push_back(main);
  for (const fs::path& from : order) {
    std::error_code ec;
    const auto size = fs::file_size(from, ec);
    if (ec) fail(destination_ / from.filename(), ec.message());
    if (size == 0) fail(destination_ / from.filename(), "the exporter wrote an empty file");
    fsync_path(from, O_RDONLY);  // writers that bypass write_file_durably (assimp's zip) are made durable here
  }
  std::vector<fs::path> moved;
  for (const fs::path& from : order) {
    const fs::path to = destination_ / from.filename();
    std::error_code ec;
    fs::rename(from, to, ec);
    if (ec) fail(to, ec.message());
    moved.push_back(to);
  }
  sync_directory(destination_);
  return moved;
}

}  // namespace shellfrac::render_mesh
