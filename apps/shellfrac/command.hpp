#pragma once
// What every command of the CLI shares: how it registers, and how its errors become exit codes.
#include <CLI/CLI.hpp>

#include <functional>
#include <optional>
#include <string>

#include "scene/scene.hpp"

namespace shellfrac::app {

// Returned by each add_*_command: after CLI parsing, the command runs if it was chosen and returns its
// exit code; otherwise it returns no value.
using Command = std::function<std::optional<int>()>;

Command add_run_command(CLI::App& app);
Command add_validate_command(CLI::App& app);
Command add_verify_command(CLI::App& app);
Command add_bench_command(CLI::App& app);
Command add_preview_command(CLI::App& app);  // preview_command.hpp

// Runs `body` and returns its exit code; any exception is printed to stderr ("error: ..." or
// "numerical failure: ...") and mapped to the exit code of its kind (core::exit_code_for: 2 bad input,
// 3 numerical failure, 1 anything else).
int run_guarded(const std::function<int()>& body);

// The scene file, or the built-in default when `path` is empty.
scene::Scene load_scene_or_default(const std::string& path);

}  // namespace shellfrac::app
