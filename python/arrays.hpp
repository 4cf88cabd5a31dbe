#pragma once
// NumPy arrays over the solver's own storage. A view shares the memory of a std::vector that is never
// resized while its owner lives (World keeps its arrays fixed: sim/world.hpp), is kept alive by that
// owner (a reference on the Python object) and is read-only: writing to it raises ValueError.
#include <pybind11/numpy.h>

#include <Eigen/Core>
#include <vector>

#include "python/bindings.hpp"

namespace shellfrac::python {

// (n, 3) view of 3-vectors (Eigen::Vector3d is 3 packed doubles: row stride 24 bytes).
py::array view_vec3(const std::vector<Eigen::Vector3d>& v, py::handle owner);
// (n, 2) view of 2-vectors.
py::array view_vec2(const std::vector<Eigen::Vector2d>& v, py::handle owner);
// (n,) view of doubles, or (n, layers) when layers > 0.
py::array view_scalars(const std::vector<double>& v, py::handle owner, long layers = 0);
// (n, 3, 3) view of 3x3 matrices (Eigen stores them column-major: strides 72, 8, 24 bytes).
py::array view_mat3(const std::vector<Eigen::Matrix3d>& v, py::handle owner);
// (n, [layers,] 3, 3) copy of 3x3 matrices, a fresh writable array.
py::array copy_mat3(const std::vector<Eigen::Matrix3d>& v, long layers = 0);

}  // namespace shellfrac::python
