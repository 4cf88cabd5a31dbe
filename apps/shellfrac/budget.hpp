#pragma once
// The resource budget of `run` and `validate`: --max-memory (default: the memory available
// to this process, within its cgroup and rlimits), the step and frame budgets and --force, and the free
// disk where the frames go.
#include <CLI/CLI.hpp>

#include <memory>
#include <string>

#include "scene/estimate.hpp"

namespace shellfrac::app {

struct BudgetArguments {
  std::string max_memory;  // "8G", "512M", "1.5e9"; empty: available memory
  double max_steps = 1e8;
  double max_frames = 1e5;
  bool force = false;
};

// Adds --max-memory, --max-steps, (with_frames) --max-frames and (with_force) --force to a command.
void add_budget_options(CLI::App* command, BudgetArguments& args, bool with_force, bool with_frames = true);

// Bytes of memory this process may use: MemAvailable of /proc/meminfo, lowered by a cgroup limit
// (memory.max) when one is set. 0 when neither can be read.
double available_memory_bytes();

// "8G" -> 8 GiB, "512M", "64K", plain bytes. Throws core::InputError naming --max-memory.
double parse_memory_size(const std::string& text);

// The budget for a run writing into out_dir with `threads` workers (0: all cores). Memory: --max-memory,
// or by default what is available (MemAvailable); either way no more than what is left under the hard
// limits the process runs under (cgroup memory limits, RLIMIT_AS, RLIMIT_DATA: core/memory_limits.hpp),
// so a scene that would be killed or fail an allocation is refused instead. Free disk is measured at
// out_dir or its nearest existing parent.
scene::ResourceBudget make_budget(const BudgetArguments& args, const std::string& out_dir, int threads = 0);

}  // namespace shellfrac::app
