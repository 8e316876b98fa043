// Vectorcall entry points for forward_dynamics, inverse_dynamics,
// hybrid_dynamics and constrained_dynamics.
//
// A stepping loop calls them as f(model, q, v, x) with float64 arrays of the
// right length. pybind11's general dispatch (argument vectors, casters,
// defaults) and array conversion are then a large share of a small model's
// call (docs/performance.md). These entry points take
// exactly that call shape straight from CPython's vectorcall protocol and
// read the arrays in place. Every other call (keywords, f_ext, lists, other
// dtypes or layouts) and every failure (a non-finite entry, a non-unit
// quaternion, a singular inertia) goes to the general pybind11 function: it
// converts, checks and raises the error that names the item at fault (a
// failing call is thus computed twice; only failures pay). Both run the same
// dynamics_calls. The private pybind11 fields they read are reached only
// through pybind11_private.hpp, which checks them.
#include <cmath>
#include <cstdint>
#include <string>

#include "arrays.hpp"
#include "dynamics_calls.hpp"
#include "pybind11_private.hpp"
#include "soadyn/soadyn.hpp"

namespace soadyn_py {

namespace {

// Entries of an aligned, native-order, C-contiguous 1-D float64 ndarray of
// length n whose entries are all finite; nullptr for anything else.
const double* finite_vector(PyObject* obj, py::ssize_t n) {
  if (!pybind11_private::is_ndarray(obj)) return nullptr;
  const pybind11_private::ArrayFields a = pybind11_private::array_fields(obj);
  constexpr int layout = pybind11_private::kCContiguousAndAligned;
  if (a.ndim != 1 || a.shape[0] != n || a.type_num != pybind11_private::kNpyDouble || a.byteorder == '>' ||
      (a.flags & layout) != layout)
    return nullptr;
  const auto* x = reinterpret_cast<const double*>(a.data);
  return all_finite(x, n) ? x : nullptr;
}

// The Python type of pybind11's Model class, looked up once. A per-call
// py::isinstance or caster would go through the metaclass's
// __instancecheck__ or pybind11's type registry.
PyTypeObject* model_type = nullptr;

// The ModelHandle inside a Model (or a Python subclass of it), or nullptr.
// Model is a single C++ class without multiple inheritance.
ModelHandle* model_handle(PyObject* obj) {
  if (!PyObject_TypeCheck(obj, model_type)) return nullptr;
  return static_cast<ModelHandle*>(pybind11_private::instance_value(obj));
}

// The model and checked state of a (model, q, v, x) call, when it has the fast shape.
struct FastArgs {
  ModelHandle* handle = nullptr;
  StateBuffers state{};

  bool load(PyObject* const* args) {
    handle = model_handle(args[0]);
    if (!handle) return false;
    const soadyn::Model& m = handle->model;
    state.model_version = m.version;
    state.q = finite_vector(args[1], m.nq);
    state.v = finite_vector(args[2], m.nv);
    state.x = finite_vector(args[3], m.nv);
    state.f_ext = nullptr;
    if (!state.q || !state.v || !state.x) return false;
    return soadyn::first_non_unit_quaternion<double>(m, Eigen::Map<const Eigen::VectorXd>(state.q, m.nq),
                                                     kQuaternionTolerance, nullptr) < 0;
  }
};

enum class Call { forward, inverse, hybrid, constrained };

// The result of a fast call, or nullptr (no Python error set) to hand the
// call to the general function.
template <Call kind>
PyObject* fast_result(const FastArgs& a) {
  const py::ssize_t nv = a.handle->model.nv;
  if constexpr (kind == Call::hybrid) {
    auto qdd = fresh_array(nv), tau = fresh_array(nv);
    if (!hybrid_dynamics_into(*a.handle, a.state, qdd.mutable_data(), tau.mutable_data(), nullptr).ok())
      return nullptr;
    return py::make_tuple(std::move(qdd), std::move(tau)).release().ptr();
  } else if constexpr (kind == Call::constrained) {
    auto qdd = fresh_array(nv), tau = fresh_array(nv), wrenches = fresh_array(a.handle->model.nloops(), 6);
    if (!constrained_dynamics_into(*a.handle, a.state, qdd.mutable_data(), tau.mutable_data(), wrenches.mutable_data(),
                                   nullptr)
             .ok())
      return nullptr;
    return py::make_tuple(std::move(qdd), std::move(tau), std::move(wrenches)).release().ptr();
  } else {
    auto out = fresh_array(nv);
    if constexpr (kind == Call::forward) {
      if (!forward_dynamics_into(*a.handle, a.state, out.mutable_data()).ok()) return nullptr;
    } else {
      if (!inverse_dynamics_into(*a.handle, a.state, out.mutable_data(), nullptr).ok()) return nullptr;
    }
    return out.release().ptr();
  }
}

// METH_FASTCALL | METH_KEYWORDS entry; `general` is the pybind11 function.
template <Call kind>
PyObject* fast_entry(PyObject* general, PyObject* const* args, Py_ssize_t nargs, PyObject* kwnames) {
  if (nargs == 4 && kwnames == nullptr) {
    try {
      FastArgs a;
      if (a.load(args))
        if (PyObject* result = fast_result<kind>(a)) return result;
    } catch (py::error_already_set& e) {
      e.restore();
      return nullptr;
    } catch (...) {
      // The general function reports it.
    }
  }
  return PyObject_Vectorcall(general, args, static_cast<size_t>(nargs), kwnames);
}

// Replaces mod.<name> (a pybind11 function) with a fast entry that hands
// every other call to it. `signature` is the text signature shown by help().
template <Call kind>
void install(py::module_& mod, const char* name, const char* signature) {
  py::object general = mod.attr(name);
  const std::string doc = py::str(general.attr("__doc__"));
  const auto body = doc.find("\n\n");  // pybind11's own signature line comes first
  static std::string text;             // one per kind: the method definition points into it
  text = std::string(name) + signature + "\n--\n\n" + (body == std::string::npos ? doc : doc.substr(body + 2));
  static PyMethodDef def{name, reinterpret_cast<PyCFunction>(reinterpret_cast<void (*)()>(&fast_entry<kind>)),
                         METH_FASTCALL | METH_KEYWORDS, text.c_str()};
  py::object module_name = mod.attr("__name__");
  PyObject* fn = PyCFunction_NewEx(&def, general.ptr(), module_name.ptr());
  if (!fn) throw py::error_already_set();
  mod.attr(name) = py::reinterpret_steal<py::object>(fn);
}

// Probes of the private pybind11 uses, for tests/test_fast_calls.py: what
// the fast entry reads from an array and from a model, to be compared with
// numpy's own view and with pybind11's public cast.
void add_private_api_probes(py::module_& mod) {
  mod.attr("_pybind11_version") = std::to_string(PYBIND11_VERSION_MAJOR) + "." +
                                  std::to_string(PYBIND11_VERSION_MINOR) + "." +
                                  std::to_string(PYBIND11_VERSION_PATCH);
  mod.def("_probe_array_fields", [](py::handle obj) -> py::object {
    if (!pybind11_private::is_ndarray(obj.ptr())) return py::none();
    const pybind11_private::ArrayFields a = pybind11_private::array_fields(obj.ptr());
    py::list shape;
    for (int k = 0; k < a.ndim; ++k) shape.append(a.shape[k]);
    py::dict out;
    out["data"] = reinterpret_cast<std::uintptr_t>(a.data);
    out["shape"] = py::tuple(shape);
    out["c_contiguous_and_aligned"] =
        (a.flags & pybind11_private::kCContiguousAndAligned) == pybind11_private::kCContiguousAndAligned;
    out["float64"] = a.type_num == pybind11_private::kNpyDouble;
    out["big_endian"] = a.byteorder == '>';
    return out;
  });
  mod.def("_probe_model_handles", [](py::handle obj) {
    // (the fast entry's ModelHandle address, pybind11's public cast's address); 0 for no model
    const ModelHandle* fast = model_handle(obj.ptr());
    const ModelHandle* general = py::isinstance<ModelHandle>(obj) ? &obj.cast<const ModelHandle&>() : nullptr;
    return py::make_tuple(reinterpret_cast<std::uintptr_t>(fast), reinterpret_cast<std::uintptr_t>(general));
  });
}

}  // namespace

void add_fast_paths(py::module_& mod) {
  model_type = pybind11_private::bound_type<ModelHandle>();
  install<Call::forward>(mod, "forward_dynamics", "(model, q, v, tau, f_ext=None)");
  install<Call::inverse>(mod, "inverse_dynamics", "(model, q, v, qdd, f_ext=None)");
  install<Call::hybrid>(mod, "hybrid_dynamics", "(model, q, v, u, f_ext=None, joint_wrenches=False)");
  install<Call::constrained>(mod, "constrained_dynamics", "(model, q, v, u, f_ext=None, joint_wrenches=False)");
  add_private_api_probes(mod);
}

}  // namespace soadyn_py
