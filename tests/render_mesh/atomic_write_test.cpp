#include "render_mesh/atomic_write.hpp"

#include <gtest/gtest.h>
#include <sched.h>
#include <sys/mount.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>

#include "render_mesh/exporter.hpp"

namespace shellfrac::render_mesh {
namespace {

namespace fs = std::filesystem;

fs::path fresh_dir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("shellfrac-test-" + name + "-" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

size_t entries(const fs::path& d) {
  return static_cast<size_t>(std::distance(fs::directory_iterator(d), fs::directory_iterator{}));
}

TEST(AtomicWrite, WritesAndReplacesWithoutLeftovers) {
  const fs::path d = fresh_dir("atomic");
  const std::string big(1 << 20, 'x');
  write_file_atomically(d / "a.txt", "first");
  EXPECT_EQ(slurp(d / "a.txt"), "first");
  write_file_atomically(d / "a.txt", big);
  EXPECT_EQ(slurp(d / "a.txt").size(), big.size());
  EXPECT_EQ(entries(d), 1u);  // no temporary file remains
  fs::remove_all(d);
}

TEST(AtomicWrite, FailureLeavesOldFileIntact) {
  const fs::path d = fresh_dir("atomic-fail");
  write_file_atomically(d / "keep.txt", "old");
  // Writing over a directory cannot be renamed into place: the old content and directory stay.
  fs::create_directories(d / "sub");
  EXPECT_THROW(write_file_atomically(d / "sub", "new"), std::runtime_error);
  EXPECT_EQ(slurp(d / "keep.txt"), "old");
  EXPECT_EQ(entries(d), 2u);
  EXPECT_THROW(write_file_atomically(d / "missing-dir" / "x.txt", "new"), std::runtime_error);
  EXPECT_EQ(entries(d), 2u);
  fs::remove_all(d);
}

TEST(StagingDirectory, CommitsPrimaryLastAndCleansUp) {
  const fs::path d = fresh_dir("staging");
  {
    StagingDirectory s(d);
    std::ofstream(s.path() / "f.obj") << "main";
    std::ofstream(s.path() / "f.mtl") << "side";
    const auto moved = s.commit("f.obj");
    ASSERT_EQ(moved.size(), 2u);
    EXPECT_EQ(moved.back().filename(), "f.obj");
  }
  EXPECT_EQ(slurp(d / "f.obj"), "main");
  EXPECT_EQ(slurp(d / "f.mtl"), "side");
  EXPECT_EQ(entries(d), 2u);  // the staging directory is gone
  {
    StagingDirectory s(d);
    std::ofstream(s.path() / "g.obj") << "never committed";
  }
  EXPECT_FALSE(fs::exists(d / "g.obj"));
  EXPECT_EQ(entries(d), 2u);
  fs::remove_all(d);
}

TEST(StagingDirectory, RefusesAnEmptyFileAndMovesNothing) {
  const fs::path d = fresh_dir("staging-empty");
  {
    StagingDirectory s(d);
    std::ofstream(s.path() / "f.mtl") << "side";
    std::ofstream(s.path() / "f.obj");  // 0 bytes: the mark of a failed unchecked write
    EXPECT_THROW(s.commit("f.obj"), std::runtime_error);
  }
  EXPECT_TRUE(fs::is_empty(d));
  fs::remove_all(d);
}

// Runs `body` in a forked child inside a private mount namespace (mounts made there are seen by no other
// process and go away with the child). Returns the body's exit code, or -1 when this machine refuses the
// namespace or the mount (no CAP_SYS_ADMIN, a seccomp filter), which the caller reports as a skip.
template <class Body>
int in_private_mount_namespace(Body body) {
  const pid_t child = ::fork();
  if (child == 0) {
    if (::unshare(CLONE_NEWNS) != 0) ::_exit(100);
    if (::mount(nullptr, "/", nullptr, MS_REC | MS_PRIVATE, nullptr) != 0) ::_exit(101);  // nothing propagates out
    ::_exit(body());
  }
  int status = 0;
  ::waitpid(child, &status, 0);
  if (!WIFEXITED(status)) return -2;
  const int code = WEXITSTATUS(status);
  return code == 100 || code == 101 || code == 102 ? -1 : code;
}

// What a write that must fail threw, recorded by the child for the parent's assertions.
int record_failure(const fs::path& log, const std::function<void()>& write) {
  try {
    write();
  } catch (const std::runtime_error& e) {
    std::ofstream(log, std::ios::app) << e.what() << "\n";
    return 0;
  }
  std::ofstream(log, std::ios::app) << "no exception\n";
  return 1;
}

TEST(WriteFileDurably, FullDeviceThrowsWithThePathAndTheReason) {
  // /dev/full fails every write with ENOSPC, as a full disk does. The device itself must survive.
  if (fs::exists("/dev/full")) {
    try {
      write_file_durably("/dev/full", "some bytes");
      ADD_FAILURE() << "no exception";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("/dev/full"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(std::strerror(ENOSPC)), std::string::npos) << e.what();
    }
    EXPECT_TRUE(fs::is_character_file("/dev/full"));
    return;
  }
  // Without /dev/full: a one-page tmpfs (4 KiB) in a private mount namespace, and 64 KiB to write into it.
  const fs::path d = fresh_dir("full-tmpfs"), mnt = d / "mnt", log = d / "log";
  fs::create_directories(mnt);
  const int code = in_private_mount_namespace([&] {
    if (::mount("tmpfs", mnt.c_str(), "tmpfs", MS_NOSUID | MS_NODEV, "size=4k") != 0) return 102;
    const int r = record_failure(log, [&] { write_file_durably(mnt / "big.bin", std::string(64 << 10, 'x')); });
    // The failed file is removed again: the tmpfs is empty.
    return r + (fs::is_empty(mnt) ? 0 : 2);
  });
  if (code == -1) GTEST_SKIP() << "no /dev/full and no tmpfs mount allowed here";
  const std::string what = slurp(log);
  EXPECT_EQ(code, 0) << what;  // 1: no exception, 2: a partial file left
  EXPECT_NE(what.find((mnt / "big.bin").string()), std::string::npos) << what;
  EXPECT_NE(what.find(std::strerror(ENOSPC)), std::string::npos) << what;
  fs::remove_all(d);
}

TEST(WriteFileDurably, ReadOnlyDirectoryThrows) {
  const fs::path d = fresh_dir("read-only"), log = fresh_dir("read-only-log") / "log";
  // Both writes must throw and leave the directory empty; `expected` is the reason they must give.
  std::string expected;
  if (::geteuid() != 0) {
    fs::permissions(d, fs::perms::owner_read | fs::perms::owner_exec);
    const int r = record_failure(log, [&] { write_file_atomically(d / "summary.json", "{}"); }) +
                  2 * record_failure(log, [&] { export_meshes({}, d, "frame_00000", "obj"); });
    fs::permissions(d, fs::perms::owner_all);
    EXPECT_EQ(r, 0) << slurp(log);  // 1: the atomic write did not throw, 2: the export did not
    expected = std::strerror(EACCES);
  } else {
    // Root writes through permission bits, so the directory is made read-only the way a read-only disk
    // is: bound onto itself read-only (MS_RDONLY), in a private mount namespace.
    const int code = in_private_mount_namespace([&] {
      if (::mount(d.c_str(), d.c_str(), nullptr, MS_BIND, nullptr) != 0) return 102;
      if (::mount(nullptr, d.c_str(), nullptr, MS_BIND | MS_REMOUNT | MS_RDONLY, nullptr) != 0) return 102;
      return record_failure(log, [&] { write_file_atomically(d / "summary.json", "{}"); }) +
             2 * record_failure(log, [&] { export_meshes({}, d, "frame_00000", "obj"); });
    });
    if (code == -1) GTEST_SKIP() << "running as root and no read-only bind mount allowed here";
    EXPECT_EQ(code, 0) << slurp(log);  // 1: the atomic write did not throw, 2: the export did not
    expected = std::strerror(EROFS);
  }
  // Each message names the reason the system gave (the atomic write's also its file).
  const std::string what = slurp(log);
  EXPECT_NE(what.find(expected), std::string::npos) << what;
  EXPECT_NE(what.find((d / "summary.json").string()), std::string::npos) << what;
  EXPECT_TRUE(fs::is_empty(d));
  fs::remove_all(d);
  fs::remove_all(log.parent_path());
}

// A sheet big enough that its OBJ, PLY or glTF file is well above 4 KiB.
PolyMesh big_sheet() {
  PolyMesh m;
  m.name = "sheet";
  const int n = 30;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      m.positions.emplace_back(i / double(n), j / double(n), 0.0);
      m.normals.emplace_back(0.0, 0.0, 1.0);
      m.uvs.emplace_back(i / double(n), j / double(n));
    }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = i + (n + 1) * j;
      m.add_face({a, a + 1, a + n + 2, a + n + 1});
    }
  return m;
}

// In a forked child, frame 0 is written, then the file size limit (RLIMIT_FSIZE, with SIGXFSZ ignored,
// so write() fails with EFBIG as on a full disk) is set to 4 KiB and frame 1 must fail with the path
// and the reason. The parent checks that frame 0 is intact and nothing of frame 1 or the staging
// directory is left.
TEST(ExportFailure, FileSizeLimitLeavesNoPartialFileAndKeepsEarlierFrames) {
  for (const char* format : {"obj", "ply", "glb2", "gltf2", "collada"}) {
    SCOPED_TRACE(format);
    const fs::path d = fresh_dir(std::string("fsize-") + format);
    const std::vector<PolyMesh> big{big_sheet()};
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
      int code = 0;
      try {
        export_meshes(big, d, "frame_00000", format);
        std::signal(SIGXFSZ, SIG_IGN);
        const rlimit limit{4096, 4096};
        if (::setrlimit(RLIMIT_FSIZE, &limit) != 0) ::_exit(10);
        export_meshes(big, d, "frame_00001", format);
        code = 11;  // no exception
      } catch (const std::runtime_error& e) {
        const std::string what = e.what();
        if (what.find((d / "frame_00001").string()) == std::string::npos) code = 12;
        if (what.find(std::strerror(EFBIG)) == std::string::npos) code = 13;
        if (what.find(".staging") != std::string::npos) code = 14;  // the final path is named
      } catch (...) {
        code = 15;
      }
      ::_exit(code);
    }
    int status = 0;
    ASSERT_EQ(::waitpid(child, &status, 0), child);
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 0) << "10 setrlimit, 11 no exception, 12 path, 13 reason, 14 staging named";
    // Frame 0 complete (the same bytes as a fresh export), frame 1 and the staging directory gone.
    const fs::path reference_dir = fresh_dir(std::string("fsize-ref-") + format);
    const fs::path reference = export_meshes(big, reference_dir, "frame_00000", format);
    const fs::path frame0 = d / reference.filename();
    if (std::string(format) != "collada")  // COLLADA carries a time stamp; compare the size class instead
      EXPECT_EQ(slurp(frame0), slurp(reference));
    else
      EXPECT_NEAR(static_cast<double>(fs::file_size(frame0)), static_cast<double>(fs::file_size(reference)), 64.0);
    for (const auto& e : fs::directory_iterator(d)) {
      const std::string name = e.path().filename().string();
      EXPECT_EQ(name.rfind("frame_00000", 0), 0u) << name;
      EXPECT_GT(fs::file_size(e.path()), 0u) << name;
    }
    fs::remove_all(d);
    fs::remove_all(reference_dir);
  }
}

}  // namespace
}  // namespace shellfrac::render_mesh
