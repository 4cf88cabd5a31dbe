// shellfrac command-line tool: run, validate, verify coupling, benchmark scene files, preview runs.
// Exit codes (core/exit_code.hpp): 0 success, 2 bad input, 3 numerical failure, 4 a verify check
// failed, 1 anything else; `run` stopped by a signal exits 128 + the signal (apps/shellfrac/run_command.cpp).
#include <CLI/CLI.hpp>

#include <string>
#include <vector>

#include "apps/shellfrac/command.hpp"
#include "core/exit_code.hpp"
#include "core/version.hpp"

int main(int argc, char** argv) {
  using namespace shellfrac;
  CLI::App app{"shellfrac: tears and fractures thin shells (Kirchhoff-Love NURBS shells simulated with "
               "MPM) and writes render meshes with the cracks in them."};
  app.set_version_flag("--version", std::string("shellfrac ") + kVersion);
  app.require_subcommand(1);
  const std::vector<app::Command> commands = {app::add_run_command(app), app::add_validate_command(app),
                                              app::add_verify_command(app), app::add_bench_command(app),
                                              app::add_preview_command(app)};
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? core::to_int(core::ExitCode::ok) : core::to_int(core::ExitCode::bad_input);
  }
  for (const app::Command& command : commands)
    if (const auto code = command()) return *code;
  return core::to_int(core::ExitCode::other);
}
