// Every use this module makes of pybind11's private `pybind11::detail`
// namespace, in one place. pybind11 does not promise to keep these stable;
// the fast call entries (fast_calls.cpp) and the fresh output arrays
// (arrays.cpp) use them because the public API's argument vectors, type
// casters and shape containers dominate a small model's dynamics call. What
// is used, and why:
//
//   detail::npy_api                 numpy's C API table, loaded by pybind11:
//                                   PyArray_Check_, PyArray_DescrFromType_,
//                                   PyArray_NewFromDescr_, PyArray_Type_ and
//                                   the NPY_* constants (no import_array here).
//   detail::array_proxy,            an ndarray's and its dtype's C fields
//   detail::array_descriptor_proxy  (data, nd, dimensions, flags, descr;
//                                   type_num, byteorder) read without calling
//                                   into Python.
//   detail::instance,               the C++ object inside an instance of a
//   detail::get_type_info           bound class, and that class's Python type,
//                                   without pybind11's type caster.
//
// Checked here at compile time: the pybind11 version lies in the range this
// was written and tested against (pyproject.toml bounds the build
// requirement to the same range), and each field and function has the type
// used. tests/test_fast_calls.py checks the behaviour through the probes
// bound in fast_calls.cpp (the array fields against numpy's own view, the
// instance's C++ object against pybind11's public cast), so a change that
// keeps the types but not the meaning fails loudly too.
#pragma once
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <type_traits>
#include <typeinfo>
#include <utility>

// 2.12 is the first release whose dtype proxy reads type_num at the same
// offset under numpy 1 and numpy 2; 3.x is the newest major tested.
static_assert(PYBIND11_VERSION_HEX >= 0x020C0000 && PYBIND11_VERSION_MAJOR < 4,
              "bindings/pybind11_private.hpp was checked against pybind11 2.12 to 3.x: check each private use "
              "below against the new version, then widen this range and pyproject.toml's bound together");

namespace soadyn_py::pybind11_private {

namespace py = pybind11;
namespace pd = pybind11::detail;

static_assert(std::is_same_v<decltype(pd::PyArray_Proxy::data), char*> &&
                  std::is_same_v<decltype(pd::PyArray_Proxy::nd), int> &&
                  std::is_same_v<decltype(pd::PyArray_Proxy::dimensions), py::ssize_t*> &&
                  std::is_same_v<decltype(pd::PyArray_Proxy::descr), PyObject*> &&
                  std::is_same_v<decltype(pd::PyArray_Proxy::flags), int>,
              "pybind11's PyArray_Proxy fields changed");
static_assert(std::is_same_v<decltype(pd::PyArrayDescr_Proxy::type_num), int> &&
                  std::is_same_v<decltype(pd::PyArrayDescr_Proxy::byteorder), char>,
              "pybind11's PyArrayDescr_Proxy fields changed");
static_assert(std::is_same_v<decltype(pd::array_proxy(std::declval<const void*>())), const pd::PyArray_Proxy*> &&
                  std::is_same_v<decltype(pd::array_descriptor_proxy(std::declval<const PyObject*>())),
                                 const pd::PyArrayDescr_Proxy*>,
              "pybind11's array proxies changed");
static_assert(std::is_same_v<decltype(pd::get_type_info(std::declval<const std::type_info&>(), true)),
                             pd::type_info*>,
              "pybind11's get_type_info changed");
static_assert(std::is_same_v<decltype(std::declval<pd::instance&>().get_value_and_holder().value_ptr()), void*&>,
              "pybind11's instance::get_value_and_holder changed");

// numpy constants as pybind11 names them.
constexpr int kNpyDouble = pd::npy_api::NPY_DOUBLE_;
constexpr int kCContiguousAndAligned = pd::npy_api::NPY_ARRAY_C_CONTIGUOUS_ | pd::npy_api::NPY_ARRAY_ALIGNED_;

// The C fields of an ndarray that a fast call reads.
struct ArrayFields {
  const char* data;
  int ndim;
  const py::ssize_t* shape;
  int flags;
  int type_num;
  char byteorder;  // '>' is big-endian; '<', '=' and '|' are native here
};

// True when `obj` is an ndarray (or a subclass); no Python call.
inline bool is_ndarray(PyObject* obj) { return pd::npy_api::get().PyArray_Check_(obj); }

// The fields of ndarray `obj` (is_ndarray(obj) must hold).
inline ArrayFields array_fields(PyObject* obj) {
  const pd::PyArray_Proxy* a = pd::array_proxy(static_cast<const void*>(obj));
  const pd::PyArrayDescr_Proxy* d = pd::array_descriptor_proxy(static_cast<const PyObject*>(a->descr));
  return ArrayFields{a->data, a->nd, a->dimensions, a->flags, d->type_num, d->byteorder};
}

// A new, uninitialised C-order float64 ndarray of `ndim` (1 or 2)
// dimensions, as a new reference; nullptr with a Python error set on failure.
inline PyObject* new_double_array(int ndim, Py_intptr_t* dims) {
  const auto& api = pd::npy_api::get();
  PyObject* descr = api.PyArray_DescrFromType_(kNpyDouble);
  if (!descr) return nullptr;
  // NewFromDescr takes over the reference to descr; no strides and flags 0: C order.
  return api.PyArray_NewFromDescr_(api.PyArray_Type_, descr, ndim, dims, nullptr, nullptr, 0, nullptr);
}

// The Python type of bound C++ class T (throws if T is not bound).
template <class T>
PyTypeObject* bound_type() {
  return pd::get_type_info(typeid(T), /*throw_if_missing=*/true)->type;
}

// The C++ object inside `obj`, an instance of a bound class registered as
// a single C++ type (no multiple inheritance), or of a Python subclass of it:
// the instance's first value.
inline void* instance_value(PyObject* obj) {
  return reinterpret_cast<pd::instance*>(obj)->get_value_and_holder().value_ptr();
}

}  // namespace soadyn_py::pybind11_private
