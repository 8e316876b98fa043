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

// 1-D real array of length n, every entry finite; `names` name the entries.
Array checked_vector(py::handle obj, const char* arg, const std::vector<std::string>& names);

// A fresh C-contiguous float64 array of shape (rows,) or, with cols >= 0,
// (rows, cols), made with numpy's C API directly: pybind11's shape
// containers would cost heap allocations on every call.
py::array_t<double> fresh_array(py::ssize_t rows, py::ssize_t cols = -1);

// 2-D real array of shape (rows, cols), finite; `row_names` name the rows.
Array checked_matrix(py::handle obj, const char* arg, py::ssize_t cols, const std::vector<std::string>& row_names);

}  // namespace soadyn_py
