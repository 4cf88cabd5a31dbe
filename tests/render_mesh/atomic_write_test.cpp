#include "render_mesh/atomic_write.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

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

}  // namespace
}  // namespace shellfrac::render_mesh
