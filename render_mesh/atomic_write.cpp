#include "render_mesh/atomic_write.hpp"

#include <fcntl.h>
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

}  // namespace

void write_file_atomically(const fs::path& path, const std::string& content) {
  const fs::path dir = path.has_parent_path() ? path.parent_path() : fs::path(".");
  const fs::path tmp = dir / ("." + path.filename().string() + ".tmp-" + unique_suffix());
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd < 0) fail(path, std::strerror(errno));
  size_t done = 0;
  while (done < content.size()) {
    const ssize_t n = ::write(fd, content.data() + done, content.size() - done);
    if (n < 0) {
      if (errno == EINTR) continue;
      const std::string why = std::strerror(errno);
      ::close(fd);
      ::unlink(tmp.c_str());
      fail(path, why);
    }
    done += static_cast<size_t>(n);
  }
  if (::fsync(fd) != 0 || ::close(fd) != 0) {
    const std::string why = std::strerror(errno);
    ::unlink(tmp.c_str());
    fail(path, why);
  }
  if (::rename(tmp.c_str(), path.c_str()) != 0) {
    const std::string why = std::strerror(errno);
    ::unlink(tmp.c_str());
    fail(path, why);
  }
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
  std::vector<fs::path> moved;
  auto move = [&](const fs::path& from) {
    const fs::path to = destination_ / from.filename();
    std::error_code ec;
    fs::rename(from, to, ec);
    if (ec) fail(to, ec.message());
    moved.push_back(to);
  };
  for (const auto& entry : fs::directory_iterator(staging_))
    if (entry.path().filename() != primary) move(entry.path());
  const fs::path main = staging_ / primary;
  if (!fs::exists(main)) fail(destination_ / primary, "the exporter produced no such file");
  move(main);
  return moved;
}

}  // namespace shellfrac::render_mesh
