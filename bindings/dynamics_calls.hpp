// The per-step dynamics calls on a model's preallocated Data, on raw
// checked buffers. Both the general pybind11 functions and the vectorcall
// fast path (fast_calls.cpp) run these, so the two cannot drift apart.
#pragma once
#include <utility>

#include "arrays.hpp"
#include "model_handle.hpp"
#include "soadyn/core/status.hpp"

namespace soadyn_py {

// How far from 1 a quaternion's norm in q may be.
constexpr double kQuaternionTolerance = 1e-6;

// q (nq): finite, with unit quaternions; v-sized vectors (nv): finite. Python
// errors name the coordinate or DOF at fault.
Array q_arg(const ModelHandle& h, py::handle q);
Array v_arg(const ModelHandle& h, py::handle v, const char* name);

// Checked inputs: q (nq), v (nv), x = tau, qdd or u (nv), f_ext (nbodies x 6,
// row-major) or nullptr.
// `model_version`: the model's version when they were checked (model_handle.hpp).
struct StateBuffers {
  const double* q;
  const double* v;
  const double* x;
  const double* f_ext;
  std::uint64_t model_version;
};

// qdd = forward dynamics (every DOF regular).
soadyn::Status forward_dynamics_into(ModelHandle& h, const StateBuffers& s, double* qdd);

// tau = inverse dynamics; wrenches (nbodies x 6) when not nullptr.
soadyn::Status inverse_dynamics_into(ModelHandle& h, const StateBuffers& s, double* tau, double* wrenches);

// (qdd, tau) = hybrid dynamics under the model's prescribed flags; the joint
// wrenches (nbodies x 6) when `wrenches` is not nullptr.
soadyn::Status hybrid_dynamics_into(ModelHandle& h, const StateBuffers& s, double* qdd, double* tau,
                                    double* wrenches);

// (qdd, tau, loop wrenches (nloops x 6)) = constrained dynamics under the
// model's prescribed flags; the joint wrenches (nbodies x 6) when
// `joint_wrenches` is not nullptr.
soadyn::Status constrained_dynamics_into(ModelHandle& h, const StateBuffers& s, double* qdd, double* tau,
                                         double* loop_wrenches, double* joint_wrenches);

// The joint wrenches of the last call on `d` (nbodies x 6, row-major) into `out`.
void copy_wrenches(const soadyn::Data& d, double* out);

// fn(model, data, q) on the model's Data with q checked (q_arg), under the
// model's lock (run_locked); returns fn's result (a value, not a view of Data).
template <class Fn>
auto at_configuration(ModelHandle& h, py::handle q, Fn&& fn) {
  using ConfigurationMap = Eigen::Map<const Eigen::VectorXd>;
  const std::uint64_t version = h.model.version;
  const Array qa = q_arg(h, q);
  decltype(fn(std::declval<const soadyn::Model&>(), std::declval<soadyn::Data&>(),
              std::declval<const ConfigurationMap&>())) result{};
  run_locked(h, version, [&](const soadyn::Model& m, soadyn::Data& d) { result = fn(m, d, ConfigurationMap(qa.data(), m.nq)); });
  return result;
}

// f_ext: None or (nbodies, 6) body-frame wrenches [torque; force] about the
// body origin; nullptr for None. (`keep` holds the checked array; a
// default-constructed Array would itself allocate an empty numpy array on
// every call.)
const double* f_ext_arg(const ModelHandle& h, py::handle f, py::object& keep);

// The checked (q, v, x, f_ext) of a dynamics call; x is tau, qdd or u.
// (The model's version is read first: converting an argument may run Python
// code, and so let another thread change the model.)
struct StateArgs {
  std::uint64_t model_version;
  Array q, v, x;
  py::object f;
  const double* f_ext = nullptr;
  StateArgs(const ModelHandle& h, py::handle q_in, py::handle v_in, py::handle x_in, const char* x_name,
            py::handle f_in)
      : model_version(h.model.version), q(q_arg(h, q_in)), v(v_arg(h, v_in, "v")), x(v_arg(h, x_in, x_name)) {
    f_ext = f_ext_arg(h, f_in, f);
  }
  StateBuffers buffers() const { return {q.data(), v.data(), x.data(), f_ext, model_version}; }
};

}  // namespace soadyn_py
