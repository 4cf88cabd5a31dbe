#include "apps/shellfrac/bench_verify.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <iostream>

namespace shellfrac::app {

int exec_course_runner(const std::vector<std::string>& args) {
#if defined(SHELLFRAC_PYTHON_EXECUTABLE) && defined(SHELLFRAC_PYTHON_PACKAGE_DIR)
  std::string path = SHELLFRAC_PYTHON_PACKAGE_DIR;
  if (const char* old = std::getenv("PYTHONPATH"); old != nullptr && *old != '\0') path += std::string(":") + old;
  ::setenv("PYTHONPATH", path.c_str(), 1);
  std::vector<std::string> words{SHELLFRAC_PYTHON_EXECUTABLE, "-m", "shellfrac.verify_course"};
  words.insert(words.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& w : words) argv.push_back(w.data());
  argv.push_back(nullptr);
  ::execv(argv[0], argv.data());
  std::cerr << "error: bench verify: cannot start " << SHELLFRAC_PYTHON_EXECUTABLE << ": " << std::strerror(errno)
            << "\n";
  return 2;
#else
  (void)args;
  std::cerr << "error: bench verify needs the Python module, which this build does not have (it needs "
               "pybind11-dev and python3-dev: scripts/setup.sh, then rebuild)\n";
  return 2;
#endif
}

}  // namespace shellfrac::app
