#include "core/memory_limits.hpp"

#include <sys/resource.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

namespace shellfrac::core {

namespace {

namespace fs = std::filesystem;

// Values at or above this are "no limit" (cgroup v1 writes 2^63 rounded down to a page for none).
constexpr double kNoLimit = 1e18;

// The first whitespace-separated word of a file, or "" when it cannot be read.
std::string first_word(const fs::path& file) {
  std::ifstream in(file);
  std::string word;
  in >> word;
  return word;
}

// A file holding one number of bytes; < 0 when missing, "max" or not a number.
double read_bytes(const fs::path& file) {
  const std::string word = first_word(file);
  if (word.empty() || word == "max") return -1;
  char* end = nullptr;
  const double v = std::strtod(word.c_str(), &end);
  return end && *end == '\0' && v >= 0 ? v : -1;
}

// The value of `key` in a "key value" file (memory.stat), 0 when absent.
double stat_value(const fs::path& file, const std::string& key) {
  std::ifstream in(file);
  std::string k;
  double v = 0;
  while (in >> k >> v)
    if (k == key) return v;
  return 0;
}

// "Key:   1234 kB" of /proc/meminfo or /proc/self/status, in bytes; < 0 when absent.
double kib_field(const fs::path& file, const std::string& key) {
  std::ifstream in(file);
  std::string line;
  while (std::getline(in, line)) {
    if (line.compare(0, key.size(), key) != 0 || line.size() <= key.size() || line[key.size()] != ':') continue;
    return std::strtod(line.c_str() + key.size() + 1, nullptr) * 1024.0;
  }
  return -1;
}

struct CgroupMount {
  std::string v2, v1_memory;  // mount points, "" when not mounted
};

CgroupMount cgroup_mounts(const std::string& root) {
  CgroupMount out;
  std::ifstream in(root + "/proc/self/mounts");
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream fields(line);
    std::string device, point, type, options;
    if (!(fields >> device >> point >> type >> options)) continue;
    if (type == "cgroup2" && out.v2.empty()) out.v2 = point;
    if (type == "cgroup" && out.v1_memory.empty()) {
      std::istringstream opts(options);
      for (std::string o; std::getline(opts, o, ',');)
        if (o == "memory") out.v1_memory = point;
    }
  }
  return out;
}

// The limits of one cgroup hierarchy: the process's group and each group above it up to the mount
// point (a parent's limit caps its children). The group path comes from /proc/self/cgroup; inside a
// cgroup namespace the mount point itself is the process's group, so a path that does not exist
// under the mount falls back to the mount point.
void add_cgroup_limits(const std::string& root, const std::string& mount, const std::string& group, bool v2,
                       std::vector<MemoryLimit>& out) {
  if (mount.empty()) return;
  const fs::path top = fs::path(root + mount).lexically_normal();
  fs::path dir = (top / fs::path(group).relative_path()).lexically_normal();
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) dir = top;
  const std::string limit_file = v2 ? "memory.max" : "memory.limit_in_bytes";
  const std::string usage_file = v2 ? "memory.current" : "memory.usage_in_bytes";
  const std::string cache_key = v2 ? "inactive_file" : "total_inactive_file";
  double best_headroom = -1;
  MemoryLimit best;
  for (;;) {
    const double limit = read_bytes(dir / limit_file);
    if (limit >= 0 && limit < kNoLimit) {
      // Page cache the kernel would drop first does not count against what is left.
      const double used = std::max(0.0, read_bytes(dir / usage_file) - stat_value(dir / "memory.stat", cache_key));
      const double headroom = std::max(0.0, limit - used);
      if (best_headroom < 0 || headroom < best_headroom) {
        best_headroom = headroom;
        best = {v2 ? "the cgroup's memory.max" : "the cgroup's memory.limit_in_bytes", limit, headroom};
      }
    }
    if (dir == top || !dir.has_relative_path() || dir.parent_path() == dir) break;
    dir = dir.parent_path();
    if (dir.string().size() < top.string().size()) break;
  }
  if (best_headroom >= 0) out.push_back(best);
}

void add_cgroups(const std::string& root, std::vector<MemoryLimit>& out) {
  const CgroupMount mounts = cgroup_mounts(root);
  std::ifstream in(root + "/proc/self/cgroup");
  std::string line;
  while (std::getline(in, line)) {
    // hierarchy-id:controllers:path
    const size_t a = line.find(':'), b = a == std::string::npos ? a : line.find(':', a + 1);
    if (b == std::string::npos) continue;
    const std::string id = line.substr(0, a), controllers = line.substr(a + 1, b - a - 1), path = line.substr(b + 1);
    if (id == "0" && controllers.empty()) {
      add_cgroup_limits(root, mounts.v2, path, true, out);
      continue;
    }
    std::istringstream list(controllers);
    for (std::string c; std::getline(list, c, ',');)
      if (c == "memory") add_cgroup_limits(root, mounts.v1_memory, path, false, out);
  }
}

}  // namespace

std::vector<MemoryLimit> memory_limits(const MemoryLimitSources& s) {
  std::vector<MemoryLimit> out;
  const double available = kib_field(s.root + "/proc/meminfo", "MemAvailable");
  if (available >= 0) out.push_back({"the available memory (MemAvailable)", kib_field(s.root + "/proc/meminfo", "MemTotal"), available, false});
  add_cgroups(s.root, out);

  double as = s.address_space_limit, data = s.data_limit;
  if (s.read_rlimits) {
    rlimit r{};
    as = ::getrlimit(RLIMIT_AS, &r) == 0 && r.rlim_cur != RLIM_INFINITY ? static_cast<double>(r.rlim_cur) : 0;
    data = ::getrlimit(RLIMIT_DATA, &r) == 0 && r.rlim_cur != RLIM_INFINITY ? static_cast<double>(r.rlim_cur) : 0;
  }
  const int threads = s.threads > 0 ? s.threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  const double thread_bytes = threads * kThreadAddressSpaceBytes;
  auto add_rlimit = [&](const char* name, double limit, double used, const char* field) {
    if (!(limit > 0) || limit >= kNoLimit) return;
    if (used < 0) used = std::max(0.0, kib_field(s.root + "/proc/self/status", field));
    out.push_back({name, limit, std::max(0.0, (limit - used - thread_bytes) / kAddressSpacePerResidentByte)});
  };
  add_rlimit("the address-space limit (RLIMIT_AS)", as, s.mapped_bytes, "VmSize");
  add_rlimit("the data-segment limit (RLIMIT_DATA)", data, s.data_bytes, "VmData");
  return out;
}

const MemoryLimit* tightest(const std::vector<MemoryLimit>& limits) {
  const MemoryLimit* best = nullptr;
  for (const MemoryLimit& l : limits)
    if (!best || l.headroom < best->headroom) best = &l;
  return best;
}

}  // namespace shellfrac::core
