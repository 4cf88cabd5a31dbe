#pragma once
// How much more memory this process may take before something stops it: the physical memory
// the kernel reports as available, the cgroup it runs in (v2 memory.max, or a v1 memory controller's
// limit_in_bytes, for the process's own group and every group above it), and its own address-space and
// data-segment limits (RLIMIT_AS, RLIMIT_DATA, as `prlimit --as` or `ulimit -v` set them). The resource
// budget of `run` and `validate` is the smallest of these, so a scene that would be killed is refused.
#include <string>
#include <vector>

namespace shellfrac::core {

// One limit and how much of it is left.
struct MemoryLimit {
  std::string name;     // "available memory", "cgroup memory.max", "RLIMIT_AS", ...
  double limit = 0;     // the limit itself [bytes]
  double headroom = 0;  // resident bytes this process may still add under it
  bool hard = true;     // exceeding it kills the process or fails allocations (all but the available memory)
};

// Where the limits are read from; the defaults are the live system. Tests point `root` at a folder
// holding a fake /proc and /sys and give the rlimits and the process's mapped size directly.
struct MemoryLimitSources {
  std::string root;                // prefix of every file path ("" for the live system)
  bool read_rlimits = true;        // getrlimit(); false: use the fields below
  double address_space_limit = 0;  // RLIMIT_AS when read_rlimits is false (0: none)
  double data_limit = 0;           // RLIMIT_DATA when read_rlimits is false (0: none)
  double mapped_bytes = -1;        // address space in use (VmSize); < 0: read /proc/self/status
  double data_bytes = -1;          // data segment in use (VmData); < 0: read /proc/self/status
  int threads = 0;                 // worker threads the run will start (0: the hardware's count)
};

// Address space a worker thread adds on top of the arrays the estimate counts: its stack and the malloc
// arena glibc reserves for it (64 MiB of address space, mostly never touched).
constexpr double kThreadAddressSpaceBytes = 72.0 * (1 << 20);

// Address space a run maps per byte it keeps resident: vectors grown by doubling, buffers reserved
// ahead and freed blocks malloc keeps. Measured 1.2 to 1.45 (peak VmSize over peak RSS, less the
// program's own, for box solids of 1e6 to 8e6 particles, a 200^2-cell sheet, level sets and renders).
// The headroom under RLIMIT_AS and RLIMIT_DATA is divided by it, so it compares with the estimate,
// which counts resident bytes.
constexpr double kAddressSpacePerResidentByte = 1.5;

// Every limit that is set, in the order above; the unlimited ones are left out.
std::vector<MemoryLimit> memory_limits(const MemoryLimitSources& sources = {});

// The limit with the least headroom, or nullptr when the list is empty.
const MemoryLimit* tightest(const std::vector<MemoryLimit>& limits);

}  // namespace shellfrac::core
