#pragma once
// `shellfrac bench verify`: the shell obstacle course as a speed-accuracy benchmark. The course runner is
// the Python module's shellfrac.verify_course (it also runs the variants on a Dask cluster, which has no
// C++ client), so this command hands its arguments to that module in Debian's python3 (docs/benchmarks.md).
#include <string>
#include <vector>

namespace shellfrac::app {

// Replaces this process by `python3 -m shellfrac.verify_course ARGS...` with the build's package first on
// PYTHONPATH. Returns only on failure (no Python module in this build, or exec failed): exit code 2
// after a message on stderr.
int exec_course_runner(const std::vector<std::string>& args);

}  // namespace shellfrac::app
