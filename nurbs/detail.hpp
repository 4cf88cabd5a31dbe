#pragma once
// Private helpers shared by the nurbs/*.cpp files. Not part of the public API.
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace shellfrac::nurbs::detail {

// Shortest of "%.15g" / "%.17g" that reads back to the same double, so that messages show 0.3, not
// 0.29999999999999999, yet never hide a difference between two values.
inline std::string format_number(double x) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.15g", x);
  if (std::strtod(buf, nullptr) != x) std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}

// Scratch doubles: on the stack up to N, on the heap above (only for degrees above kStackDegree).
template <std::size_t N>
class ScratchBuffer {
 public:
  explicit ScratchBuffer(std::size_t size) {
    if (size <= N) {
      data_ = stack_;
    } else {
      heap_.resize(size);
      data_ = heap_.data();
    }
  }
  ScratchBuffer(const ScratchBuffer&) = delete;
  ScratchBuffer& operator=(const ScratchBuffer&) = delete;

  double* data() { return data_; }

 private:
  double stack_[N];
  std::vector<double> heap_;
  double* data_ = nullptr;
};

}  // namespace shellfrac::nurbs::detail
