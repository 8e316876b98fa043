// Model construction and validation (templated implementation of model.hpp).
#pragma once
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include "soadyn/model/modal_rule.hpp"
#include "soadyn/model/model.hpp"
#include "soadyn/model/constant_tree_inertia.hxx"
#include "soadyn/model/tree_frame_reach.hxx"
#include "soadyn/core/validation.hpp"
#include "soadyn/model/add_loop.hxx"
#include "soadyn/model/add_force_element.hxx"

namespace soadyn {

namespace detail {

template <class S>
S model_tolerance() {
  return validation_tolerance<S>();
}

[[noreturn]] inline void fail(const std::string& what) { throw std::invalid_argument(what); }

template <class S>
std::string str(const S& x) {
  return to_text(x);
}

template <class S>
void check_placement(const Transform<S>& X, const std::string& body) {
  if (!X.rotation.allFinite() || !X.translation.allFinite())
    fail("body '" + body + "': placement is not finite");
  const S err = (X.rotation.transpose() * X.rotation - Mat3<S>::Identity()).cwiseAbs().maxCoeff();
  if (err > model_tolerance<S>() || X.rotation.determinant() < S(0))
    fail("body '" + body + "': placement rotation is not a proper rotation matrix (|R'R - I| = " + str(err) +
         ")");
}

// Finite parameters, mass >= 0, symmetric inertia: required of every part.
template <class S>
void check_mass_parameters(S mass, const Vec3<S>& com, const Mat3<S>& I, const std::string& body) {
  if (!std::isfinite(static_cast<double>(mass))) fail("body '" + body + "': mass is not finite");
  if (mass < S(0)) fail("body '" + body + "': mass " + str(mass) + " is negative");
  if (!com.allFinite()) fail("body '" + body + "': centre of mass is not finite");
  if (!I.allFinite()) fail("body '" + body + "': inertia is not finite");
  const S tol = model_tolerance<S>() * std::max(I.cwiseAbs().maxCoeff(), S(std::numeric_limits<S>::min()));
  if ((I - I.transpose()).cwiseAbs().maxCoeff() > tol) fail("body '" + body + "': inertia is not symmetric");
}

// The scale of a body's rotational inertia for the rounding allowance of the
// physical tests below (sqrt(eps) of it): the larger of the inertia's largest
// entry and m r^2 with r = point_mass_radius (1 mm), so that a point mass
// printed with a product of inertia of 1e-20 is a point mass. An inertia
// given about the centre of mass is judged on this scale wherever the centre
// of mass lies: diag(-1, 1, 1) is refused at com 1e9 as at com 0.
constexpr double point_mass_radius = 1e-3;

template <class S>
S inertia_scale(S mass, const Mat3<S>& I) {
  return std::max({I.cwiseAbs().maxCoeff(), mass * S(point_mass_radius * point_mass_radius),
                   S(std::numeric_limits<S>::min())});
}

// The scale of an inertia about the centre of mass that was computed from one
// about the frame origin (a merge of welded parts): its rounding is relative
// to the parallel-axis term m |c|^2 as well.
template <class S>
S merged_inertia_scale(S mass, const Vec3<S>& com, const Mat3<S>& I) {
  return std::max(inertia_scale(mass, I), mass * com.squaredNorm());
}

// What makes a rigid body impossible (none: it is physical): inertia about
// the centre of mass not positive semidefinite, principal moments violating
// the triangle inequality, or inertia without mass, each beyond `tolerance`.
// Semidefinite inertias (point masses, thin rods) are physical.
enum class InertiaDefect { none, indefinite, triangle_inequality, massless_with_inertia };

template <class S>
InertiaDefect inertia_defect(S mass, const Mat3<S>& I, S tolerance, Vec3<S>* principal_moments = nullptr) {
  const Vec3<S> m = Eigen::SelfAdjointEigenSolver<Mat3<S>>(I, Eigen::EigenvaluesOnly).eigenvalues();
  if (principal_moments) *principal_moments = m;
  if (m.minCoeff() < -tolerance) return InertiaDefect::indefinite;
  for (int k = 0; k < 3; ++k)
    if (m[k] > m[(k + 1) % 3] + m[(k + 2) % 3] + tolerance) return InertiaDefect::triangle_inequality;
  if (mass == S(0) && m.maxCoeff() > tolerance) return InertiaDefect::massless_with_inertia;
  return InertiaDefect::none;
}

// Throws NonphysicalInertiaError naming `who` unless the body is physical
// (inertia_defect, with sqrt(eps) of `scale` as the rounding allowance).
// Required of every body of the tree under InertiaPolicy::require_physical; a
// part welded to a body by a fixed joint only has to leave that body physical
// (CAD exports split bodies into pieces that are not bodies on their own).
template <class S>
void check_physical_inertia(S mass, const Mat3<S>& I, S scale, const std::string& who) {
  Vec3<S> m;
  switch (inertia_defect(mass, I, model_tolerance<S>() * scale, &m)) {
    case InertiaDefect::none: return;
    case InertiaDefect::indefinite:
      throw NonphysicalInertiaError(who + ": inertia is not positive semidefinite (principal moment " +
                                    str(m.minCoeff()) + ")");
    case InertiaDefect::triangle_inequality:
      throw NonphysicalInertiaError(who + ": principal moments " + str(m[0]) + ", " + str(m[1]) + ", " +
                                    str(m[2]) + " violate the triangle inequality");
    case InertiaDefect::massless_with_inertia:
      throw NonphysicalInertiaError(who + ": massless body with nonzero inertia");
  }
}

// The spatial inertia about the frame origin (M(k) of Jain & Rodriguez 1993) must be finite:
// mass * com and mass * |com|^2 overflow long before mass or com do.
template <class S>
void check_finite_spatial_inertia(const Mat6<S>& M, const std::string& who) {
  if (!M.allFinite())
    fail(who + ": spatial inertia about the body frame origin is not finite (mass * com or mass * |com|^2 "
               "overflows)");
}

}  // namespace detail

template <class S>
ModelTpl<S>::ModelTpl() : gravity(S(0), S(0), S(-9.81)) {}

template <class S>
int ModelTpl<S>::body_index(const std::string& name) const {
  const auto it = body_lookup_.find(name);
  return it == body_lookup_.end() ? -1 : it->second;
}
template <class S>
int ModelTpl<S>::dof_index(const std::string& name) const {
  const auto it = dof_lookup_.find(name);
  return it == dof_lookup_.end() ? -1 : it->second;
}
template <class S>
int ModelTpl<S>::frame_index(const std::string& name) const {
  const auto it = frame_lookup_.find(name);
  return it == frame_lookup_.end() ? -1 : it->second;
}

template <class S>
int ModelTpl<S>::add_body(const std::string& name, const std::string& parent_name, const JointModel<S>& joint,
                          const Transform<S>& X, S m, const Vec3<S>& c, const Mat3<S>& I,
                          const std::string& joint_name, InertiaPolicy policy) {
  if (parent_name.empty() || parent_name == "world")
    return add_body(name, -1, joint, X, m, c, I, joint_name, policy);
  const int b = body_index(parent_name);
  if (b >= 0) return add_body(name, b, joint, X, m, c, I, joint_name, policy);
  const int f = frame_index(parent_name);
  if (f < 0) detail::fail("body '" + name + "': parent '" + parent_name + "' does not exist");
  const Frame<S> frame = frames[static_cast<std::size_t>(f)];
  if (frame.node >= 0) {
    if (joint_is_fixed(joint))
      detail::fail("body '" + name + "': cannot be welded to flexible body '" +
                   body_names[static_cast<std::size_t>(frame.body)] + "'; give its mass to a node instead");
    detail::check_placement(X, name);
    return add_resolved(name, frame.body, frame.node, joint, frame.placement * X, m, c, I, joint_name, nullptr,
                        policy);
  }
  return add_body(name, frame.body, joint, frame.placement * X, m, c, I, joint_name, policy);
}

template <class S>
int ModelTpl<S>::add_body(const std::string& name, int parent_body, const JointModel<S>& joint,
                          const Transform<S>& X, S m, const Vec3<S>& c, const Mat3<S>& I,
                          const std::string& joint_name, InertiaPolicy policy) {
  if (joint_is_fixed(joint) && parent_body >= 0 && parent_body < nbodies() && is_flexible(parent_body))
    detail::fail("body '" + name + "': cannot be welded to flexible body '" +
                 body_names[static_cast<std::size_t>(parent_body)] + "'; give its mass to a node instead");
  return add_resolved(name, parent_body, -1, joint, X, m, c, I, joint_name, nullptr, policy);
}

template <class S>
int ModelTpl<S>::add_flexible_body(const std::string& name, const std::string& parent_name,
                                   const JointModel<S>& joint, const Transform<S>& X, const FlexibleBodyTpl<S>& body,
                                   const std::string& joint_name) {
  int parent_body = -1, node = -1;
  Transform<S> placement = X;
  if (!(parent_name.empty() || parent_name == "world")) {
    parent_body = body_index(parent_name);
    if (parent_body < 0) {
      const int f = frame_index(parent_name);
      if (f < 0) detail::fail("body '" + name + "': parent '" + parent_name + "' does not exist");
      const Frame<S>& frame = frames[static_cast<std::size_t>(f)];
      detail::check_placement(X, name);
      parent_body = frame.body;
      node = frame.node;
      placement = frame.placement * X;
    }
  }
  for (const auto& [attachment, j] : body.attachments()) {
    const std::string frame_name = name + ":" + attachment;
    if (body_index(frame_name) >= 0 || frame_index(frame_name) >= 0)
      detail::fail("flexible body '" + name + "': attachment frame '" + frame_name + "' clashes with an existing name");
  }
  const ModalIntegrals<S>& mi = body.modal_integrals();
  const Vec3<S> com = mi.mass > S(0) ? Vec3<S>(mi.first_moment / mi.mass) : Vec3<S>::Zero();
  // Rotational inertia about the centre of mass of the undeformed body.
  const Mat3<S> inertia_origin = mi.second_moment.trace() * Mat3<S>::Identity() - mi.second_moment + mi.rotary_inertia;
  const Mat3<S> inertia_com = inertia_origin - mi.mass * (com.squaredNorm() * Mat3<S>::Identity() - com * com.transpose());
  const int index = add_resolved(name, parent_body, node, joint, placement, mi.mass, com,
                                 S(0.5) * (inertia_com + inertia_com.transpose()), joint_name, &body,
                                 InertiaPolicy::require_physical);
  for (const auto& [attachment, j] : body.attachments()) {
    frame_lookup_[name + ":" + attachment] = static_cast<int>(frames.size());
    frames.push_back(Frame<S>{name + ":" + attachment, index, Transform<S>::Identity(), j});
  }
  return index;
}

template <class S>
int ModelTpl<S>::add_resolved(const std::string& name, int parent_body, int node, const JointModel<S>& joint_in,
                              const Transform<S>& X, S m, const Vec3<S>& c, const Mat3<S>& I,
                              const std::string& joint_name_in, const FlexibleBodyTpl<S>* flexible,
                              InertiaPolicy policy) {
  if (name.empty()) detail::fail("body name is empty");
  if (name == "world") detail::fail("body name 'world' is reserved for the ground");
  if (body_index(name) >= 0 || frame_index(name) >= 0) detail::fail("duplicate body name '" + name + "'");
  if (parent_body < -1 || parent_body >= nbodies())
    detail::fail("body '" + name + "': parent index " + std::to_string(parent_body) + " does not exist");
  const std::string jname = joint_name_in.empty() ? name : joint_name_in;
  const bool welded = joint_is_fixed(joint_in) && flexible == nullptr;
  if (!joint_name_in.empty())
    for (const auto& other : joint_names)
      if (other == jname) detail::fail("duplicate joint name '" + jname + "'");
  JointModel<S> joint = joint_in;
  check_joint(joint, jname);
  detail::check_placement(X, name);
  detail::check_mass_parameters(m, c, I, name);
  const bool physical = policy == InertiaPolicy::require_physical;
  if (!welded && physical) detail::check_physical_inertia(m, I, detail::inertia_scale(m, I), "body '" + name + "'");
  const Mat6<S> body_inertia = spatial_inertia(m, c, I);
  detail::check_finite_spatial_inertia(body_inertia, "body '" + name + "'");

  if (welded) {  // weld: merge into the parent, keep the name as a frame
    if (parent_body >= 0) {
      const std::size_t p = static_cast<std::size_t>(parent_body);
      const Mat6<S> merged = inertia[p] + X.inertia_to_parent(body_inertia);
      S merged_mass;
      Vec3<S> merged_com;
      Mat3<S> merged_inertia_com;
      decompose_spatial_inertia(merged, merged_mass, merged_com, merged_inertia_com);
      const std::string who = "body '" + body_names[p] + "' with '" + name + "' welded to it";
      detail::check_finite_spatial_inertia(merged, who);
      if (!merged_com.allFinite() || !merged_inertia_com.allFinite())
        detail::fail(who + ": centre of mass or inertia is not finite (a nearly massless merge)");
      if (physical)
        detail::check_physical_inertia(merged_mass, merged_inertia_com,
                                       detail::merged_inertia_scale(merged_mass, merged_com, merged_inertia_com), who);
      inertia[p] = merged;
      mass[p] = merged_mass;
      com[p] = merged_com;
      inertia_com[p] = merged_inertia_com;
    }
    frame_lookup_[name] = static_cast<int>(frames.size());
    frames.push_back(Frame<S>{name, parent_body, X, -1});
    refresh_derived_caches();
    refresh_dynamics_path();
    ++version;
    return -1;
  }

  const int jq = joint_nq(joint), jv = joint_nv(joint);
  const int nm = flexible ? flexible->n_modes() : 0;
  const char* const* qs = joint_coordinate_suffixes(joint);
  const char* const* vs = joint_velocity_suffixes(joint);
  std::vector<std::string> new_dofs;
  for (int k = 0; k < jv; ++k) new_dofs.push_back(jv == 1 ? jname : jname + ":" + vs[k]);
  for (int k = 0; k < nm; ++k) new_dofs.push_back(name + ":mode" + std::to_string(k + 1));
  for (std::size_t k = 0; k < new_dofs.size(); ++k) {
    if (dof_index(new_dofs[k]) >= 0) detail::fail("duplicate DOF name '" + new_dofs[k] + "'");
    for (std::size_t l = 0; l < k; ++l)
      if (new_dofs[l] == new_dofs[k]) detail::fail("duplicate DOF name '" + new_dofs[k] + "'");
  }
  // Checked: from here on nothing throws, so a refused body leaves no trace.
  const int index = nbodies();
  body_names.push_back(name);
  joint_names.push_back(jname);
  parent.push_back(parent_body);
  joints.push_back(joint);
  placement.push_back(X);
  inertia.push_back(body_inertia);
  mass.push_back(m);
  com.push_back(c);
  inertia_com.push_back(I);
  S sign;
  joint_fast_path.push_back(classify_joint(joint, sign));
  axis_sign.push_back(sign);
  const std::vector<S> angle_signs_of_joint = tabulated_angle_signs(joint, joint_fast_path.back(), sign);
  angle_slot.push_back(angle_signs_of_joint.empty() ? -1 : static_cast<int>(angle_coordinates.size()));
  for (std::size_t k = 0; k < angle_signs_of_joint.size(); ++k) {
    angle_coordinates.push_back(nq + static_cast<int>(k));
    angle_signs.push_back(angle_signs_of_joint[k]);
  }
  q_index.push_back(nq);
  v_index.push_back(nv);
  nq_body.push_back(jq);
  nv_body.push_back(jv);
  n_modes.push_back(nm);
  attachment_node.push_back(node);
  flexible_index.push_back(flexible ? static_cast<int>(flexible_bodies.size()) : -1);
  if (flexible) flexible_bodies.push_back(*flexible);
  for (int k = 0; k < jq; ++k) coordinate_names.push_back(jq == 1 ? jname : jname + ":" + qs[k]);
  for (int k = 0; k < nm; ++k) coordinate_names.push_back(new_dofs[static_cast<std::size_t>(jv + k)]);
  int ancestor = parent_body;  // the nearest ancestor with DOFs: its last DOF precedes this body's first
  while (ancestor >= 0 && nv_body[static_cast<std::size_t>(ancestor)] + n_modes[static_cast<std::size_t>(ancestor)] == 0)
    ancestor = parent[static_cast<std::size_t>(ancestor)];
  const int ancestor_last_dof =
      ancestor < 0 ? -1 : modal_v_index(ancestor) + n_modes[static_cast<std::size_t>(ancestor)] - 1;
  for (int k = 0; k < jv + nm; ++k) {
    dof_parent.push_back(k == 0 ? ancestor_last_dof : nv + k - 1);
    const bool continues_run = dof_parent.back() >= 0 && dof_parent.back() == nv + k - 1;
    dof_run_start.push_back(continues_run ? dof_run_start[static_cast<std::size_t>(nv + k - 1)] : nv + k);
    dof_lookup_[new_dofs[static_cast<std::size_t>(k)]] = nv + k;
    dof_names.push_back(new_dofs[static_cast<std::size_t>(k)]);
    dof_body.push_back(index);
    prescribed.push_back(0);
    armature.push_back(S(0));
    effort_limit.push_back(std::numeric_limits<S>::infinity());
    prescribed_dofs.push_back(0);
    modal_dof.push_back(k >= jv ? 1 : 0);
  }
  nq += jq + nm;
  nv += jv + nm;
  body_lookup_[name] = index;
  modes.emplace_back();
  refresh_body_modes(index);
  refresh_modes();
  refresh_derived_caches();
  refresh_dynamics_path();
  ++version;
  return index;
}

template <class S>
void ModelTpl<S>::refresh_body_modes(int body) {
  HingeModes& h = modes[static_cast<std::size_t>(body)];
  h.n_regular = h.n_prescribed = 0;
  const int v0 = v_index[static_cast<std::size_t>(body)];
  for (int k = 0; k < nv_body[static_cast<std::size_t>(body)]; ++k) {
    if (prescribed[static_cast<std::size_t>(v0 + k)])
      h.prescribed[h.n_prescribed++] = static_cast<std::uint8_t>(k);
    else
      h.regular[h.n_regular++] = static_cast<std::uint8_t>(k);
  }
}

template <class S>
void ModelTpl<S>::refresh_dynamics_path() {
  const bool on_nodes = std::any_of(attachment_node.begin(), attachment_node.end(), [](int node) { return node >= 0; });
  dynamics_path = on_nodes               ? DynamicsPath::body_frames
                  : has_flexible_bodies() ? DynamicsPath::appendage_tree_frames
                                          : DynamicsPath::rigid_tree_frames;
  std::vector<std::size_t> depth(static_cast<std::size_t>(nv));  // ancestors-or-self of each DOF (a parent's index is lower)
  tree_factor_work = 0;
  for (std::size_t k = 0; k < depth.size(); ++k) {
    const int p = dof_parent[k];
    depth[k] = p >= 0 ? depth[static_cast<std::size_t>(p)] + 1 : 1;
    tree_factor_work += depth[k] * depth[k];
  }
}

template <class S>
void ModelTpl<S>::refresh_modes() {
  n_prescribed = 0;
  for (std::size_t d = 0; d < prescribed.size(); ++d)
    if (prescribed[d]) prescribed_dofs[static_cast<std::size_t>(n_prescribed++)] = static_cast<int>(d);
  has_newton_euler_region = false;
  for (int i = 0; i < nbodies(); ++i) {
    const int p = parent[static_cast<std::size_t>(i)];
    HingeModes& h = modes[static_cast<std::size_t>(i)];
    // Modal DOFs are regular: a flexible body always needs one.
    h.needs_articulated_inertia = h.n_regular > 0 || flexible_index[static_cast<std::size_t>(i)] >= 0 ||
                                  (p >= 0 && modes[static_cast<std::size_t>(p)].needs_articulated_inertia);
    has_newton_euler_region = has_newton_euler_region || !h.needs_articulated_inertia;
  }
  refresh_derived_caches(DerivedChange::flags);
}

template <class S>
void ModelTpl<S>::set_prescribed(int dof, bool flag) {
  const std::size_t d = static_cast<std::size_t>(dof);
  if (flag) require_regular_modal_dof(*this, dof);
  if (prescribed[d] == static_cast<std::uint8_t>(flag)) return;
  prescribed[d] = static_cast<std::uint8_t>(flag);
  refresh_body_modes(dof_body[d]);
  refresh_modes();
}

namespace detail {
inline void check_dof_index(const char* what, int dof, int nv) {
  if (dof < 0 || dof >= nv)
    throw std::invalid_argument(std::string(what) + ": DOF index " + std::to_string(dof) + " is out of range (nv = " +
                                std::to_string(nv) + ")");
}
}  // namespace detail

template <class S>
void ModelTpl<S>::set_effort_limit(int dof, S value) {
  detail::check_dof_index("set_effort_limit", dof, nv);
  const std::size_t d = static_cast<std::size_t>(dof);
  if (!(value > S(0)))
    throw std::invalid_argument("DOF '" + dof_names[d] + "': effort limit must be positive (+inf: none), got " +
                                std::to_string(static_cast<double>(value)));
  effort_limit[d] = value;
}

template <class S>
void ModelTpl<S>::set_armature(int dof, S value) {
  detail::check_dof_index("set_armature", dof, nv);
  const std::size_t d = static_cast<std::size_t>(dof);
  if (!(std::isfinite(value) && value >= S(0)))
    throw std::invalid_argument("DOF '" + dof_names[d] + "': armature must be finite and non-negative");
  if (modal_dof[d] && value != S(0))
    throw std::invalid_argument("DOF '" + dof_names[d] + "' is a modal coordinate: it has no armature");
  armature[d] = value;
  const int body = dof_body[d];
  const int v0 = v_index[static_cast<std::size_t>(body)];
  bool body_has = false;
  for (int k = 0; k < nv_body[static_cast<std::size_t>(body)]; ++k)
    body_has = body_has || armature[static_cast<std::size_t>(v0 + k)] != S(0);
  modes[static_cast<std::size_t>(body)].has_armature = body_has;
  has_armature = std::any_of(armature.begin(), armature.end(), [](const S& a) { return a != S(0); });
  refresh_derived_caches(DerivedChange::flags);
}

template <class S>
void ModelTpl<S>::set_all_prescribed(bool flag) {
  for (std::size_t d = 0; d < prescribed.size(); ++d) prescribed[d] = static_cast<std::uint8_t>(flag && !modal_dof[d]);
  for (int i = 0; i < nbodies(); ++i) refresh_body_modes(i);
  refresh_modes();
}

}  // namespace soadyn
