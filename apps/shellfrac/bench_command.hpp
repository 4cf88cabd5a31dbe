#pragma once
#include <CLI/CLI.hpp>

#include <functional>
#include <optional>

namespace shellfrac::app {

// Adds `bench sweep` and `bench stability` ([--config tiny|full] [--out DIR] [--threads N] [--no-charts])
// to `app`. Returns the function to call after app.parse(): no value when `bench` was not given,
// otherwise the exit code (0 done, 1 anything else, e.g. gnuplot missing: the CSV files are written).
std::function<std::optional<int>()> add_bench_command(CLI::App& app);

}  // namespace shellfrac::app
