#include "errors.hpp"

#include <cmath>

#include "soadyn/algorithms/force_elements.hpp"
#include "soadyn/constraints/loop_assembly.hpp"
#include "soadyn/model/loop.hpp"

namespace soadyn_py {

namespace {

const std::string& name_of(const std::vector<std::string>& names, int k) {
  static const std::string unknown = "?";
  return k >= 0 && static_cast<std::size_t>(k) < names.size() ? names[static_cast<std::size_t>(k)] : unknown;
}

// The first body whose pose, velocity, momentum or first moment of mass is
// not finite, or -1.
int body_at_fault(const soadyn::Model& m, const soadyn::Data& d, bool with_velocity) {
  for (int i = 0; i < m.nbodies(); ++i) {
    const auto k = static_cast<std::size_t>(i);
    const soadyn::Transform<double>& X = d.pose_in_world[k];
    if (!X.rotation.allFinite() || !X.translation.allFinite()) return i;
    if (!(m.mass[k] * X.translation).allFinite()) return i;
    if (!with_velocity) continue;
    const soadyn::Vec6<double>& V = d.body_velocity[k];
    if (!V.allFinite()) return i;
    const soadyn::Vec6<double> h = m.inertia[k] * V;
    if (!h.allFinite() || !std::isfinite(V.dot(h)) || !X.force_to_parent(h).allFinite()) return i;
  }
  return -1;
}

// The body with the largest share of a total that overflowed though every
// share is finite.
int largest_share(const soadyn::Model& m, const soadyn::Data& d, bool with_velocity) {
  int best = -1;
  double largest = -1;
  for (int i = 0; i < m.nbodies(); ++i) {
    const auto k = static_cast<std::size_t>(i);
    const double share = with_velocity ? (m.inertia[k] * d.body_velocity[k]).norm()
                                       : m.mass[k] * d.pose_in_world[k].translation.norm();
    if (share > largest) {
      largest = share;
      best = i;
    }
  }
  return best;
}

}  // namespace

void raise_on(const soadyn::Status& s, const soadyn::Model& m, const char* what) {
  if (s.ok()) return;
  if (s.code == soadyn::StatusCode::loop_not_closed) {
    const std::string loop = s.index >= 0 && s.index < m.nloops() ? m.loops[static_cast<std::size_t>(s.index)].name : "?";
    throw DynamicsError(std::string(what) + ": loop '" + loop +
                        "' does not close: its residual stays above the tolerance (the mechanism cannot reach a closed "
                        "configuration from here with the DOFs allowed to move)");
  }
  if (s.code == soadyn::StatusCode::loop_assembly_stalled) {
    const std::string loop = s.index >= 0 && s.index < m.nloops() ? m.loops[static_cast<std::size_t>(s.index)].name : "?";
    throw soadyn::LoopError(std::string(what) + ": loop '" + loop + "' cannot be closed from here: its residual " +
                            "stopped falling (" + std::to_string(soadyn::assembly_stall_steps) +
                            " Gauss-Newton steps in a row, each halved down to 2^-20 of its length, gained nothing, or " +
                            std::to_string(soadyn::assembly_halving_steps) +
                            " steps did not halve it): the DOFs allowed to move cannot close it (every DOF of the loop "
                            "held, a configuration out of their reach, or a singular one)");
  }
  const std::string& dof = name_of(m.dof_names, s.index);
  if (s.code == soadyn::StatusCode::inconsistent_loop_equations) {
    const std::string loop = s.index >= 0 && static_cast<std::size_t>(s.index) < m.loops.size()
                                 ? m.loops[static_cast<std::size_t>(s.index)].name
                                 : std::string("?");
    throw DynamicsError(std::string(what) + ": the closure equations of loop '" + loop +
                        "' cannot be met: the prescribed accelerations are inconsistent with the loops, or the "
                        "mechanism is at a singular configuration (a dead centre)");
  }
  if (s.code == soadyn::StatusCode::singular_articulated_inertia)
    throw DynamicsError(std::string(what) + ": the articulated inertia D of regular DOF '" + dof +
                        "' is singular: nothing with mass or inertia moves with this DOF");
  throw DynamicsError(std::string(what) + ": the result for DOF '" + dof +
                      "' is not finite (an input is too large for floating point)");
}

void refuse_non_finite(const char* what, const char* quantity, const double* x, std::size_t items, std::size_t stride,
                       const std::vector<std::string>& names) {
  for (std::size_t k = 0; k < items * stride; ++k)
    if (!std::isfinite(x[k]))
      throw DynamicsError(std::string(what) + ": the " + quantity + " of '" + name_of(names, static_cast<int>(k / stride)) +
                          "' is not finite (an input is too large for floating point)");
}

void refuse_non_finite_rows(const std::string& what, const std::string& quantity,
                            const Eigen::Ref<const Eigen::MatrixXd>& x, const std::vector<std::string>& row_names) {
  if (x.allFinite()) return;
  for (Eigen::Index r = 0; r < x.rows(); ++r)
    if (!x.row(r).allFinite())
      throw DynamicsError(what + ": the " + quantity + " of '" + name_of(row_names, static_cast<int>(r)) +
                          "' is not finite (an input is too large for floating point)");
}

std::vector<std::string> loop_equation_names(const soadyn::Model& m) {
  std::vector<std::string> names;
  for (const auto& loop : m.loops)
    for (int i = 0; i < loop.rows(); ++i) names.push_back(loop.name + "[" + std::to_string(i) + "]");
  return names;
}

std::vector<std::string> state_names(const soadyn::Model& m) {
  std::vector<std::string> names;
  for (const auto& dof : m.dof_names) names.push_back(dof + " (position)");
  for (const auto& dof : m.dof_names) names.push_back(dof + " (velocity)");
  return names;
}

void raise_non_finite_total(const char* what, const soadyn::Model& m, const soadyn::Data& d, bool with_velocity) {
  const int body = body_at_fault(m, d, with_velocity);
  const std::string where =
      body >= 0 ? "body '" + name_of(m.body_names, body) + "' gives a non-finite " +
                      (with_velocity ? "pose, velocity or momentum" : "pose or first moment of mass")
                : "body '" + name_of(m.body_names, largest_share(m, d, with_velocity)) +
                      "' has the largest share of a sum that overflows";
  throw DynamicsError(std::string(what) + " is not finite: " + where + " (an input is too large for floating point)");
}

void raise_non_finite_force_element(const char* what, const soadyn::Model& m, soadyn::Data& d,
                                    const Eigen::Ref<const Eigen::VectorXd>& q, const double* v) {
  const double total = v ? soadyn::force_element_dissipation<double>(m, d, q, Eigen::Map<const Eigen::VectorXd>(v, m.nv))
                         : soadyn::force_element_potential<double>(m, d, q);
  if (std::isfinite(total)) return;  // the force elements' own sum is finite: not theirs to blame
  const int k = soadyn::force_element_at_fault<double>(m, d, q, v);
  if (k < 0) return;
  const auto& joint_springs = m.force_elements.joint_springs;
  const std::size_t n_joint = joint_springs.size(), index = static_cast<std::size_t>(k);
  const std::string& name =
      index < n_joint ? joint_springs[index].name : m.force_elements.point_springs[index - n_joint].name;
  throw DynamicsError(std::string(what) + " is not finite: force element '" + name + "' has " +
                      (v ? "the largest dissipated power" : "the largest potential") +
                      " (its constants or the state are too large for floating point)");
}

}  // namespace soadyn_py
