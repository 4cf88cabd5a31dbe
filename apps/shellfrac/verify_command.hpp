#pragma once
#include <CLI/CLI.hpp>

#include <functional>
#include <optional>

namespace shellfrac::app {

// Exit code of `shellfrac verify coupling` when the run completed but a seam check failed.
constexpr int kExitCheckFailed = 4;

// Adds `verify coupling SCENE [--out DIR] [--threads N]` to `app`: runs the scene like `run` (frames
// and summary.json with metrics.interfaces), then prints a pass/fail table per interface. Returns the
// function to call after app.parse(): it returns no value when `verify` was not given, otherwise the
// exit code (0 all checks pass, 4 a check failed, 2 bad input, 3 numerical failure, 1 anything else).
std::function<std::optional<int>()> add_verify_command(CLI::App& app);

}  // namespace shellfrac::app
