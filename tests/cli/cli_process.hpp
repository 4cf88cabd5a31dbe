#pragma once
// Running the shellfrac binary from end-to-end tests: its exit code and everything it printed, and a
// fresh scratch folder per test. SHELLFRAC_BIN is the binary's path, defined by the test target.
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <string>

namespace shellfrac::test {

struct Result {
  int exit_code;
  std::string output;  // stdout and stderr
};

// `PREFIX shellfrac ARGS` through the shell (PREFIX: a wrapper such as `prlimit --as=N`, or nothing);
// exit code -1 when it did not exit normally (a signal).
inline Result run_shellfrac_under(const std::string& prefix, const std::string& args) {
  const std::string cmd = prefix + (prefix.empty() ? "" : " ") + std::string(SHELLFRAC_BIN) + " " + args + " 2>&1";
  FILE* pipe = ::popen(cmd.c_str(), "r");
  if (!pipe) return {-1, "popen failed"};
  std::string out;
  char buf[4096];
  size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, pipe)) > 0) out.append(buf, n);
  const int status = ::pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

// `shellfrac ARGS` through the shell; exit code -1 when it did not exit normally (a signal).
inline Result run_shellfrac(const std::string& args) { return run_shellfrac_under("", args); }

// An empty folder TMP/shellfrac-<suite>-<name>-<pid>.
inline std::filesystem::path scratch_folder(const std::string& suite, const std::string& name) {
  const std::filesystem::path d =
      std::filesystem::temp_directory_path() / ("shellfrac-" + suite + "-" + name + "-" + std::to_string(::getpid()));
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d;
}

}  // namespace shellfrac::test
