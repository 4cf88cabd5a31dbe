// The memory limits the budget honours (core/memory_limits.hpp), read from a fake /proc and /sys tree:
// MemAvailable, cgroup v2 memory.max of the process's group and its parents ("max" is none), a cgroup v1
// memory controller, and RLIMIT_AS / RLIMIT_DATA less what the process has mapped and its threads, in
// resident bytes (kAddressSpacePerResidentByte).
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "core/memory_limits.hpp"

namespace shellfrac::core {
namespace {

namespace fs = std::filesystem;

constexpr double kMiB = 1024.0 * 1024.0, kGiB = 1024.0 * kMiB;

class FakeSystem {
 public:
  FakeSystem() : root_(fs::temp_directory_path() / ("shellfrac-limits-" + std::to_string(::getpid()))) {
    fs::remove_all(root_);
    write("proc/meminfo", "MemTotal:       16000000 kB\nMemFree:         1000000 kB\nMemAvailable:    8000000 kB\n");
  }
  ~FakeSystem() { fs::remove_all(root_); }
  void write(const std::string& path, const std::string& text) {
    fs::create_directories((root_ / path).parent_path());
    std::ofstream(root_ / path) << text;
  }
  MemoryLimitSources sources() const {
    MemoryLimitSources s;
    s.root = root_.string();
    s.read_rlimits = false;
    s.threads = 2;
    return s;
  }

 private:
  fs::path root_;
};

const MemoryLimit* find(const std::vector<MemoryLimit>& limits, const std::string& part) {
  for (const MemoryLimit& l : limits)
    if (l.name.find(part) != std::string::npos) return &l;
  return nullptr;
}

TEST(MemoryLimits, AvailableMemoryAloneWhenNothingElseIsSet) {
  FakeSystem sys;
  const auto limits = memory_limits(sys.sources());
  ASSERT_EQ(limits.size(), 1u);
  EXPECT_DOUBLE_EQ(limits[0].headroom, 8000000 * 1024.0);
  EXPECT_FALSE(limits[0].hard);
}

TEST(MemoryLimits, CgroupV2LimitOfTheGroupOrAParentLessItsUse) {
  FakeSystem sys;
  sys.write("proc/self/mounts", "cgroup2 /sys/fs/cgroup cgroup2 rw,nosuid 0 0\n");
  sys.write("proc/self/cgroup", "0::/user.slice/job\n");
  sys.write("sys/fs/cgroup/memory.max", "max\n");
  sys.write("sys/fs/cgroup/user.slice/memory.max", std::to_string(static_cast<long long>(3 * kGiB)) + "\n");
  sys.write("sys/fs/cgroup/user.slice/memory.current", std::to_string(static_cast<long long>(1 * kGiB)) + "\n");
  // 256 MiB of the parent's use is inactive page cache: it does not count.
  sys.write("sys/fs/cgroup/user.slice/memory.stat", "anon 100\ninactive_file " + std::to_string(static_cast<long long>(256 * kMiB)) + "\n");
  sys.write("sys/fs/cgroup/user.slice/job/memory.max", "max\n");
  const auto limits = memory_limits(sys.sources());
  const MemoryLimit* cg = find(limits, "memory.max");
  ASSERT_NE(cg, nullptr);
  EXPECT_DOUBLE_EQ(cg->limit, 3 * kGiB);
  EXPECT_DOUBLE_EQ(cg->headroom, 3 * kGiB - (1 * kGiB - 256 * kMiB));
  EXPECT_TRUE(cg->hard);
  EXPECT_EQ(tightest(limits), cg);  // 2.25 GiB left, less than the 7.6 GiB available
}

TEST(MemoryLimits, UnlimitedCgroupsAddNothing) {
  FakeSystem sys;
  sys.write("proc/self/mounts", "cgroup2 /sys/fs/cgroup/unified cgroup2 rw 0 0\ncgroup /sys/fs/cgroup/memory cgroup rw,memory 0 0\n");
  sys.write("proc/self/cgroup", "4:memory:/jobs/a\n0::/\n");
  sys.write("sys/fs/cgroup/unified/memory.max", "max\n");
  sys.write("sys/fs/cgroup/memory/jobs/a/memory.limit_in_bytes", "9223372036854771712\n");
  EXPECT_EQ(memory_limits(sys.sources()).size(), 1u);
}

TEST(MemoryLimits, CgroupV1MemoryController) {
  FakeSystem sys;
  sys.write("proc/self/mounts", "cgroup /sys/fs/cgroup/memory cgroup rw,relatime,memory 0 0\n");
  sys.write("proc/self/cgroup", "5:cpu:/\n4:memory:/jobs/a\n");
  sys.write("sys/fs/cgroup/memory/jobs/a/memory.limit_in_bytes", std::to_string(static_cast<long long>(2 * kGiB)) + "\n");
  sys.write("sys/fs/cgroup/memory/jobs/a/memory.usage_in_bytes", std::to_string(static_cast<long long>(512 * kMiB)) + "\n");
  const MemoryLimit* cg = find(memory_limits(sys.sources()), "limit_in_bytes");
  ASSERT_NE(cg, nullptr);
  EXPECT_DOUBLE_EQ(cg->headroom, 1.5 * kGiB);
}

TEST(MemoryLimits, AddressSpaceLimitLessWhatIsMappedAndTheThreads) {
  FakeSystem sys;
  MemoryLimitSources s = sys.sources();
  s.address_space_limit = 4 * kGiB;
  s.mapped_bytes = 300 * kMiB;
  const auto limits = memory_limits(s);
  const MemoryLimit* as = find(limits, "RLIMIT_AS");
  ASSERT_NE(as, nullptr);
  EXPECT_DOUBLE_EQ(as->headroom, (4 * kGiB - 300 * kMiB - 2 * kThreadAddressSpaceBytes) / kAddressSpacePerResidentByte);
  EXPECT_EQ(tightest(limits), as);
  // The mapped size from /proc/self/status when not given.
  sys.write("proc/self/status", "Name:\tshellfrac\nVmPeak:\t  500000 kB\nVmSize:\t  400000 kB\nVmData:\t  100000 kB\n");
  s.mapped_bytes = -1;
  s.data_limit = 2 * kGiB;
  const auto read = memory_limits(s);
  EXPECT_DOUBLE_EQ(find(read, "RLIMIT_AS")->headroom,
                   (4 * kGiB - 400000 * 1024.0 - 2 * kThreadAddressSpaceBytes) / kAddressSpacePerResidentByte);
  EXPECT_DOUBLE_EQ(find(read, "RLIMIT_DATA")->headroom,
                   (2 * kGiB - 100000 * 1024.0 - 2 * kThreadAddressSpaceBytes) / kAddressSpacePerResidentByte);
}

TEST(MemoryLimits, TheLiveProcessHasAtLeastTheAvailableMemory) {
  const auto limits = memory_limits();
  ASSERT_FALSE(limits.empty());
  for (const MemoryLimit& l : limits) EXPECT_GE(l.headroom, 0.0) << l.name;
}

}  // namespace
}  // namespace shellfrac::core
