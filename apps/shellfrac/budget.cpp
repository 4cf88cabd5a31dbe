#include "apps/shellfrac/budget.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/error.hpp"
#include "core/memory_limits.hpp"

namespace shellfrac::app {

void add_budget_options(CLI::App* command, BudgetArguments& args, bool with_force, bool with_frames) {
  command->add_option("--max-memory", args.max_memory,
                      "Refuse scenes estimated to need more memory than this (e.g. 8G, 512M; default: the "
                      "available memory)");
  command->add_option("--max-steps", args.max_steps, "Step budget (more needs --force)")->capture_default_str();
  if (with_frames)
    command->add_option("--max-frames", args.max_frames, "Frame budget (more needs --force)")->capture_default_str();
  if (with_force)
    command->add_flag("--force", args.force,
                      with_frames ? "Allow a run over the step, frame or free-disk budget (never over memory)"
                                  : "Allow a run over the step budget (never over memory)");
}

double parse_memory_size(const std::string& text) {
  char* end = nullptr;
  const double number = std::strtod(text.c_str(), &end);
  std::string suffix = end ? std::string(end) : std::string();
  if (!suffix.empty() && (suffix.back() == 'B' || suffix.back() == 'b')) suffix.pop_back();
  if (!suffix.empty() && suffix.back() == 'i') suffix.pop_back();
  double factor = 1;
  if (suffix == "K" || suffix == "k")
    factor = 1024.0;
  else if (suffix == "M" || suffix == "m")
    factor = 1024.0 * 1024;
  else if (suffix == "G" || suffix == "g")
    factor = 1024.0 * 1024 * 1024;
  else if (suffix == "T" || suffix == "t")
    factor = 1024.0 * 1024 * 1024 * 1024;
  else if (!suffix.empty())
    factor = -1;
  if (end == text.c_str() || factor < 0 || !(number > 0) || !std::isfinite(number))
    throw core::InputError("--max-memory: \"" + text + "\" is not a memory size (examples: 8G, 512M, 2000000000)");
  return number * factor;
}

scene::ResourceBudget make_budget(const BudgetArguments& args, const std::string& out_dir, int threads) {
  scene::ResourceBudget b;
  if (!args.max_memory.empty()) b.memory_bytes = parse_memory_size(args.max_memory);
  core::MemoryLimitSources sources;
  sources.threads = threads;
  for (const core::MemoryLimit& l : core::memory_limits(sources)) {
    if (!l.hard && !args.max_memory.empty()) continue;  // --max-memory replaces the available memory
    const double left = std::max(1.0, l.headroom);       // 0 would mean "no limit"
    if (b.memory_bytes > 0 && left >= b.memory_bytes) continue;
    b.memory_bytes = left;
    b.memory_source = l.hard ? "what is left under " + l.name + " of " + scene::format_bytes(l.limit) +
                                   ", which --max-memory cannot raise"
                             : "";
  }
  b.max_steps = args.max_steps;
  b.max_frames = args.max_frames;
  b.force = args.force;
  if (!out_dir.empty()) {
    std::filesystem::path p = std::filesystem::absolute(out_dir);
    std::error_code ec;
    while (!p.empty() && !std::filesystem::exists(p, ec) && p != p.parent_path()) p = p.parent_path();
    const std::filesystem::space_info space = std::filesystem::space(p, ec);
    if (!ec) b.free_disk_bytes = static_cast<double>(space.available);
  }
  return b;
}

}  // namespace shellfrac::app
