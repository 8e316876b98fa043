#include "errors.hpp"

#include <cmath>

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
  const std::string& dof = name_of(m.dof_names, s.index);
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

void raise_non_finite_total(const char* what, const soadyn::Model& m, const soadyn::Data& d, bool with_velocity) {
  const int body = body_at_fault(m, d, with_velocity);
  const std::string where =
      body >= 0 ? "body '" + name_of(m.body_names, body) + "' gives a non-finite " +
                      (with_velocity ? "pose, velocity or momentum" : "pose or first moment of mass")
                : "body '" + name_of(m.body_names, largest_share(m, d, with_velocity)) +
                      "' has the largest share of a sum that overflows";
  throw DynamicsError(std::string(what) + " is not finite: " + where + " (an input is too large for floating point)");
}

}  // namespace soadyn_py
