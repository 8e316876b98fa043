#include "arrays.hpp"

#include <cmath>
#include <cstring>

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

bool all_finite(const double* x, py::ssize_t n) {
  // x - x is 0 for a finite x and NaN for an infinite or NaN one, so the sums
  // stay 0 exactly when every entry is finite. Four sums of two lanes each
  // keep the additions independent.
  typedef double Pair __attribute__((vector_size(16)));
  Pair sums[4] = {};
  py::ssize_t k = 0;
  for (; k + 8 <= n; k += 8)
    for (int s = 0; s < 4; ++s) {
      Pair p;
      std::memcpy(&p, x + k + 2 * s, sizeof p);
      sums[s] += p - p;
    }
  double total = 0;
  for (; k < n; ++k) total += x[k] - x[k];
  const Pair all = (sums[0] + sums[1]) + (sums[2] + sums[3]);
  return total + all[0] + all[1] == 0;
}

namespace {

void check_finite(const double* x, py::ssize_t n, py::ssize_t cols, const char* arg,
                  const std::vector<std::string>& names) {
  if (all_finite(x, n)) return;
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

std::string shape_text(const py::array& a) {
  std::string shape = "(";
  for (py::ssize_t k = 0; k < a.ndim(); ++k) shape += (k ? ", " : "") + std::to_string(a.shape(k));
  return shape + (a.ndim() == 1 ? ",)" : ")");
}

void require_vector_shape(const py::array& a, const std::string& arg, py::ssize_t n, const char* size_name) {
  if (a.ndim() == 1 && a.shape(0) == n) return;
  throw py::value_error(arg + " has shape " + shape_text(a) + ", expected (" + std::to_string(n) + ",)" +
                        (size_name ? std::string(" (") + size_name + ")" : std::string()));
}

Array checked_vector(py::handle obj, const char* arg, const std::vector<std::string>& names) {
  Array a = as_float_array(obj, arg);
  const py::ssize_t n = static_cast<py::ssize_t>(names.size());
  require_vector_shape(a, arg, n);
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
                          std::to_string(cols) + "), got " + shape_text(a));
  check_finite(a.data(), rows * cols, cols, arg, row_names);
  return a;
}

namespace {

// The type's name as Python prints it: "float", "NoneType", "numpy.bool".
std::string type_name(py::handle obj) {
  const py::handle type = py::type::handle_of(obj);
  const std::string module = py::str(type.attr("__module__")).cast<std::string>();
  const std::string name = py::str(type.attr("__qualname__")).cast<std::string>();
  return module == "builtins" ? name : module + "." + name;
}

[[noreturn]] void wrong_type(const char* arg, const char* expected, py::handle obj) {
  throw py::type_error(std::string(arg) + " must be " + expected + ", got " + type_name(obj));
}

// Python's bool or numpy's (which is no int subclass, but converts to one).
bool is_bool(py::handle obj) {
  if (PyBool_Check(obj.ptr())) return true;
  static const py::handle numpy_bool = py::object(py::module_::import("numpy").attr("bool_")).release();  // kept for the process
  return py::isinstance(obj, numpy_bool);
}

}  // namespace

double checked_real(py::handle obj, const char* arg) {
  if (is_bool(obj) || !(PyFloat_Check(obj.ptr()) || PyIndex_Check(obj.ptr()) || py::hasattr(obj, "__float__")) ||
      PyComplex_Check(obj.ptr()))
    wrong_type(arg, "a real number", obj);
  const double x = PyFloat_AsDouble(obj.ptr());
  if (x == -1.0 && PyErr_Occurred()) {
    PyErr_Clear();
    throw py::value_error(std::string(arg) + " cannot be represented as a float64 (" +
                          py::repr(obj).cast<std::string>() + ")");
  }
  return x;
}

long long checked_integer(py::handle obj, const char* arg, long long low, long long high) {
  if (is_bool(obj) || !PyIndex_Check(obj.ptr())) wrong_type(arg, "an integer", obj);
  int overflow = 0;
  const py::object index = py::reinterpret_steal<py::object>(PyNumber_Index(obj.ptr()));
  if (!index) throw py::error_already_set();
  const long long x = PyLong_AsLongLongAndOverflow(index.ptr(), &overflow);
  if (overflow != 0 || x < low || x > high)
    throw py::value_error(std::string(arg) + " must be in [" + std::to_string(low) + ", " + std::to_string(high) +
                          "], got " + py::repr(obj).cast<std::string>());
  return x;
}

std::string checked_text(py::handle obj, const char* arg) {
  if (!py::isinstance<py::str>(obj)) wrong_type(arg, "a str", obj);
  return obj.cast<std::string>();
}

bool checked_flag(py::handle obj, const char* arg) {
  if (!is_bool(obj)) wrong_type(arg, "a bool", obj);
  return PyObject_IsTrue(obj.ptr()) == 1;
}

}  // namespace soadyn_py
