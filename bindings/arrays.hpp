// Checked conversion of Python arguments to contiguous float64 arrays.
// Errors name the argument and the item at fault (DOF, coordinate, body).
#pragma once
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <string>
#include <vector>

namespace soadyn_py {

namespace py = pybind11;
using Array = py::array_t<double, py::array::c_style>;

// Real numeric input as a C-contiguous float64 array (no copy when it
// already is one). Complex, object, string and boolean data are refused
// with a TypeError naming `arg`.
Array as_float_array(py::handle obj, const char* arg);

// "(2, 3)" or "(4,)": the shape of `a` as Python prints it.
std::string shape_text(const py::array& a);

// Raises ValueError "<arg> has shape (..), expected (n,) (<size_name>)"
// unless `a` is 1-D of length n.
void require_vector_shape(const py::array& a, const std::string& arg, py::ssize_t n, const char* size_name = nullptr);

// Whether all n entries of x are finite: a branch-free scan, for the checks
// common case (the caller then looks for the entry to name only when not).
bool all_finite(const double* x, py::ssize_t n);

// 1-D real array of length n, every entry finite; `names` name the entries.
Array checked_vector(py::handle obj, const char* arg, const std::vector<std::string>& names);

// A fresh C-contiguous float64 array of shape (rows,) or, with cols >= 0,
// (rows, cols), made with numpy's C API directly: pybind11's shape
// containers would cost heap allocations on every call.
py::array_t<double> fresh_array(py::ssize_t rows, py::ssize_t cols = -1);

// 2-D real array of shape (rows, cols), finite; `row_names` name the rows.
Array checked_matrix(py::handle obj, const char* arg, py::ssize_t cols, const std::vector<std::string>& row_names);

// Scalar arguments taken as Python objects, so that a wrong type names the
// argument (pybind11's own conversion would answer with its signature list):
// a real number (int or float, not bool), TypeError otherwise;
double checked_real(py::handle obj, const char* arg);
// an integer (not bool) in [low, high], TypeError or ValueError otherwise;
long long checked_integer(py::handle obj, const char* arg, long long low, long long high);
// a str;
std::string checked_text(py::handle obj, const char* arg);
// a bool (or numpy bool).
bool checked_flag(py::handle obj, const char* arg);

}  // namespace soadyn_py
