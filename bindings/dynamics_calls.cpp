#include "dynamics_calls.hpp"

#include "soadyn/soadyn.hpp"

namespace soadyn_py {

namespace {

using Map = Eigen::Map<const Eigen::VectorXd>;
using VectorOut = Eigen::Map<Eigen::VectorXd>;

}  // namespace

void copy_wrenches(const soadyn::Data& d, double* out) {
  for (std::size_t i = 0; i < d.hinge_force.size(); ++i) Eigen::Map<soadyn::Vec6<double>>(out + 6 * i) = d.hinge_force[i];
}

Array q_arg(const ModelHandle& h, py::handle q) {
  Array a = checked_vector(q, "q", h.model.coordinate_names);
  double norm = 0;
  const int body = soadyn::first_non_unit_quaternion<double>(h.model, Map(a.data(), a.size()), kQuaternionTolerance, &norm);
  if (body >= 0)
    throw py::value_error("q: the quaternion of joint '" + h.model.joint_names[static_cast<std::size_t>(body)] +
                          "' has norm " + std::to_string(norm) + "; it must be 1 within 1e-6");
  return a;
}
Array v_arg(const ModelHandle& h, py::handle v, const char* name) { return checked_vector(v, name, h.model.dof_names); }

soadyn::Status forward_dynamics_into(ModelHandle& h, const StateBuffers& s, double* qdd) {
  soadyn::Status status;
  run_locked(h, s.model_version, [&](const soadyn::Model& m, soadyn::Data& d) {
    status = soadyn::forward_dynamics<double>(m, d, Map(s.q, m.nq), Map(s.v, m.nv), Map(s.x, m.nv), s.f_ext);
    VectorOut(qdd, m.nv) = d.qdd;
  });
  return status;
}

soadyn::Status inverse_dynamics_into(ModelHandle& h, const StateBuffers& s, double* tau, double* wrenches) {
  soadyn::Status status;
  run_locked(h, s.model_version, [&](const soadyn::Model& m, soadyn::Data& d) {
    status = soadyn::inverse_dynamics<double>(m, d, Map(s.q, m.nq), Map(s.v, m.nv), Map(s.x, m.nv), s.f_ext);
    if (tau) VectorOut(tau, m.nv) = d.tau;
    if (wrenches) copy_wrenches(d, wrenches);
  });
  return status;
}

namespace {

// Runs `algorithm` (hybrid_dynamics or constrained_dynamics: the same
// arguments) on the model's Data under its lock and copies qdd, tau, the
// joint wrenches when `wrenches` is not nullptr, and whatever `more` copies.
template <class Algorithm, class More>
soadyn::Status hybrid_shaped_into(ModelHandle& h, const StateBuffers& s, double* qdd, double* tau, double* wrenches,
                                  Algorithm&& algorithm, More&& more) {
  soadyn::Status status;
  run_locked(h, s.model_version, [&](const soadyn::Model& m, soadyn::Data& d) {
    status = algorithm(m, d, Map(s.q, m.nq), Map(s.v, m.nv), Map(s.x, m.nv), s.f_ext,
                       soadyn::DynamicsOutputs{wrenches != nullptr});
    VectorOut(qdd, m.nv) = d.qdd;
    VectorOut(tau, m.nv) = d.tau;
    if (wrenches) copy_wrenches(d, wrenches);
    more(d);
  });
  return status;
}

}  // namespace

soadyn::Status hybrid_dynamics_into(ModelHandle& h, const StateBuffers& s, double* qdd, double* tau,
                                    double* wrenches) {
  return hybrid_shaped_into(
      h, s, qdd, tau, wrenches, [](auto&&... args) { return soadyn::hybrid_dynamics<double>(args...); },
      [](const soadyn::Data&) {});
}

soadyn::Status constrained_dynamics_into(ModelHandle& h, const StateBuffers& s, double* qdd, double* tau,
                                         double* loop_wrenches, double* joint_wrenches) {
  return hybrid_shaped_into(
      h, s, qdd, tau, joint_wrenches, [](auto&&... args) { return soadyn::constrained_dynamics<double>(args...); },
      [&](const soadyn::Data& d) {
        for (std::size_t l = 0; l < d.loops.wrench.size(); ++l)
          Eigen::Map<soadyn::Vec6<double>>(loop_wrenches + 6 * l) = d.loops.wrench[l];
      });
}

const double* f_ext_arg(const ModelHandle& h, py::handle f, py::object& keep) {
  if (f.is_none()) return nullptr;
  Array checked = checked_matrix(f, "f_ext", 6, h.model.body_names);
  const double* data = checked.data();
  keep = std::move(checked);
  return data;
}

}  // namespace soadyn_py
