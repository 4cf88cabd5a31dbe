#include "python/arrays.hpp"

namespace shellfrac::python {

namespace {

constexpr py::ssize_t kD = static_cast<py::ssize_t>(sizeof(double));

py::array readonly(const double* data, std::vector<py::ssize_t> shape, std::vector<py::ssize_t> strides,
                   py::handle owner) {
  // An empty vector may have no storage: give NumPy a valid pointer anyway (nothing is read through it).
  static const double no_data = 0;
  py::array a(py::dtype::of<double>(), std::move(shape), std::move(strides), data ? data : &no_data, owner);
  a.attr("setflags")(py::arg("write") = false);
  return a;
}

}  // namespace

py::array view_vec3(const std::vector<Eigen::Vector3d>& v, py::handle owner) {
  static_assert(sizeof(Eigen::Vector3d) == 3 * sizeof(double), "Vector3d must be three packed doubles");
  return readonly(v.empty() ? nullptr : v[0].data(), {static_cast<py::ssize_t>(v.size()), 3}, {3 * kD, kD}, owner);
}

py::array view_vec2(const std::vector<Eigen::Vector2d>& v, py::handle owner) {
  static_assert(sizeof(Eigen::Vector2d) == 2 * sizeof(double), "Vector2d must be two packed doubles");
  return readonly(v.empty() ? nullptr : v[0].data(), {static_cast<py::ssize_t>(v.size()), 2}, {2 * kD, kD}, owner);
}

py::array view_scalars(const std::vector<double>& v, py::handle owner, long layers) {
  const auto n = static_cast<py::ssize_t>(v.size());
  if (layers <= 0) return readonly(v.data(), {n}, {kD}, owner);
  const auto l = static_cast<py::ssize_t>(layers);
  return readonly(v.data(), {n / l, l}, {l * kD, kD}, owner);
}

py::array view_mat3(const std::vector<Eigen::Matrix3d>& v, py::handle owner) {
  static_assert(sizeof(Eigen::Matrix3d) == 9 * sizeof(double), "Matrix3d must be nine packed doubles");
  // Element (r, c) of matrix k sits at k * 9 + c * 3 + r doubles (column-major).
  return readonly(v.empty() ? nullptr : v[0].data(), {static_cast<py::ssize_t>(v.size()), 3, 3}, {9 * kD, kD, 3 * kD},
                  owner);
}

py::array copy_mat3(const std::vector<Eigen::Matrix3d>& v, long layers) {
  const auto n = static_cast<py::ssize_t>(v.size());
  std::vector<py::ssize_t> shape = {n, 3, 3};
  if (layers > 0) shape = {n / layers, static_cast<py::ssize_t>(layers), 3, 3};
  py::array_t<double> a(shape);
  double* out = a.mutable_data();
  for (size_t k = 0; k < v.size(); ++k)
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) out[k * 9 + static_cast<size_t>(r * 3 + c)] = v[k](r, c);
  return a;
}

}  // namespace shellfrac::python
