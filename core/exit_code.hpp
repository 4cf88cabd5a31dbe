#pragma once
// Process exit codes of every shellfrac command (docs/cli.md).

namespace shellfrac::core {

enum class ExitCode : int {
  ok = 0,
  other = 1,           // I/O failure, a missing tool, anything unexpected
  bad_input = 2,       // a scene, option or file the user gave is wrong (the message names where)
  numerical = 3,       // the simulation failed numerically (NaN, blow-up, inverted element)
  verify_failed = 4,   // a `verify` check did not pass
};

inline int to_int(ExitCode c) { return static_cast<int>(c); }

}  // namespace shellfrac::core
