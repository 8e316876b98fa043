// The per-step dynamics calls on a model's preallocated Data, on raw
// checked buffers. Both the general pybind11 functions and the vectorcall
// fast path (fast_calls.cpp) run these, so the two cannot drift apart.
#pragma once
#include "arrays.hpp"
#include "model_handle.hpp"
#include "soadyn/status.hpp"

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

}  // namespace soadyn_py
