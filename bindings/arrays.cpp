#include "arrays.hpp"

#include <cmath>

#include "pybind11_private.hpp"

namespace soadyn_py {

Array as_float_array(py::handle obj, const char* arg) {
  if (py::isinstance<Array>(obj)) {
    auto a = py::reinterpret_borrow<py::array>(obj);
    if (a.flags() & py::array::c_style) return py::reinterpret_borrow<Array>(obj);
  }
  py::array a;
  try {
    a = py::array::ensure(obj);
  } catch (py::error_already_set&) {
  }
  if (!a) throw py::type_error(std::string(arg) + " must be an array of real numbers");
  const char kind = a.dtype().kind();
  if (kind != 'f' && kind != 'i' && kind != 'u')
    throw py::type_error(std::string(arg) + " must be an array of real numbers, got dtype " +
                         py::str(a.dtype()).cast<std::string>());
  // forcecast: long double and float128 inputs are rounded to double as
  // np.asarray(x, float) would (without it numpy refuses the unsafe cast).
  using Cast = py::array_t<double, py::array::c_style | py::array::forcecast>;
  Cast converted = Cast::ensure(a);
  if (!converted) throw py::type_error(std::string(arg) + " cannot be converted to float64");
  return py::reinterpret_steal<Array>(converted.release());
}

namespace {

void check_finite(const double* x, py::ssize_t n, py::ssize_t cols, const char* arg,
                  const std::vector<std::string>& names) {
  for (py::ssize_t k = 0; k < n; ++k) {
    if (std::isfinite(x[k])) continue;
    const py::ssize_t item = cols > 0 ? k / cols : k;
    std::string where = std::string(arg) + "[" + std::to_string(item);
    if (cols > 0) where += ", " + std::to_string(k % cols);
    where += "]";
    if (static_cast<std::size_t>(item) < names.size()) where += " ('" + names[static_cast<std::size_t>(item)] + "')";
    throw py::value_error(where + " is " + (std::isnan(x[k]) ? "NaN" : "infinite"));
  }
}

}  // namespace

Array checked_vector(py::handle obj, const char* arg, const std::vector<std::string>& names) {
  Array a = as_float_array(obj, arg);
  const py::ssize_t n = static_cast<py::ssize_t>(names.size());
  if (a.ndim() != 1 || a.shape(0) != n) {
    std::string shape = "(";
    for (py::ssize_t k = 0; k < a.ndim(); ++k) shape += (k ? ", " : "") + std::to_string(a.shape(k));
    throw py::value_error(std::string(arg) + " has shape " + shape + (a.ndim() == 1 ? ",)" : ")") +
                          ", expected (" + std::to_string(n) + ",)");
  }
  check_finite(a.data(), n, 0, arg, names);
  return a;
}

py::array_t<double> fresh_array(py::ssize_t rows, py::ssize_t cols) {
  Py_intptr_t dims[2] = {rows, cols};
  PyObject* array = pybind11_private::new_double_array(cols < 0 ? 1 : 2, dims);
  if (!array) throw py::error_already_set();
  return py::reinterpret_steal<py::array_t<double>>(array);
}

Array checked_matrix(py::handle obj, const char* arg, py::ssize_t cols, const std::vector<std::string>& row_names) {
  Array a = as_float_array(obj, arg);
  const py::ssize_t rows = static_cast<py::ssize_t>(row_names.size());
  if (a.ndim() != 2 || a.shape(0) != rows || a.shape(1) != cols)
    throw py::value_error(std::string(arg) + " must have shape (" + std::to_string(rows) + ", " +
                          std::to_string(cols) + ")");
  check_finite(a.data(), rows * cols, cols, arg, row_names);
  return a;
}

}  // namespace soadyn_py
