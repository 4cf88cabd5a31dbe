#pragma once
#include <cstddef>

namespace shellfrac::sim {

// A fixed-size window onto particle state owned by the simulation: elements may be read and written,
// the array cannot be resized (the grid's particle views point into it).
template <class T>
class Span {
 public:
  Span(T* data, std::size_t size) : data_(data), size_(size) {}
  T* data() const { return data_; }
  std::size_t size() const { return size_; }
  T& operator[](std::size_t i) const { return data_[i]; }
  T* begin() const { return data_; }
  T* end() const { return data_ + size_; }

 private:
  T* data_;
  std::size_t size_;
};

}  // namespace shellfrac::sim
