// Which bodies have a constant inertia in their tree frame (templated
// implementation of ModelTpl::refresh_constant_tree_inertia, model.hpp).
//
// The forward and hybrid dynamics sweeps and the CRBA express a tree whose
// root joint has a constant body-frame subspace (free, revolute or
// prismatic about a coordinate axis, fixed) in the root's body frame
// (sweeps/tree_frame_updates.hpp), so a rigid body's inertia there is the
// body's own inertia carried by its pose relative to the root. That pose is
// constant for the root itself and for every rigid body joined to it by
// fixed joints (welded: a spacecraft's instruments and booms, a robot's
// base plate). A body whose revolute joint turns it about a coordinate axis
// of its own frame, on a welded parent, moves, but its inertia does not when
// its mass is symmetric about that axis: centre of mass on the axis, and the
// rotational inertia about it diagonal with equal moments about the two
// other axes (a reaction wheel, a turntable, a gimbal ring of uniform mass).
// Those bodies' ten inertia parameters are formed here, once, and the sweeps
// read them instead of forming them per call. The symmetry is tested
// exactly, as the inertia is given: a rotor whose two transverse moments
// differ in the last bit is formed per call, as before. A flexible
// appendage welded to such a root has its modal integrals formed here in
// the root's frame, once (ModelTpl::root_frame_integrals).
#pragma once
#include <type_traits>
#include "soadyn/linalg/small_cholesky.hpp"
#include "soadyn/model/model.hpp"

namespace soadyn {

namespace detail {

// Whether rotations about e_axis leave a body's inertia (centre of mass
// `com`, rotational inertia `inertia_com` about it, body frame) unchanged.
template <class S>
bool mass_symmetric_about_axis(int axis, const Vec3<S>& com, const Mat3<S>& inertia_com) {
  const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
  const S zero(0);
  return com[a1] == zero && com[a2] == zero && inertia_com(a1, a1) == inertia_com(a2, a2) &&
         inertia_com(a1, a2) == zero && inertia_com(a2, a1) == zero && inertia_com(a1, axis) == zero &&
         inertia_com(axis, a1) == zero && inertia_com(a2, axis) == zero && inertia_com(axis, a2) == zero;
}

}  // namespace detail

template <class S>
void ModelTpl<S>::refresh_constant_tree_inertia() {
  const std::size_t n = parent.size();
  derived.constant_tree_inertia.assign(n, 0);
  derived.tree_inertia_parameters.resize(n);
  derived.welded_to_root.assign(n, 0);
  derived.pose_in_root.resize(n);
  derived.appendage_in_root_frame.assign(n, 0);
  derived.root_frame_integrals.resize(flexible_bodies.size());
  derived.constant_leaf_hinge.assign(n, 0);
  derived.leaf_hinge_terms.resize(n);
  derived.leaf_plus_presummed.assign(n, 0);
  derived.leaf_presum_slot.assign(n, -1);
  derived.placement_axes.assign(n, PlacementAxes<S>());
  derived.diagonal_inertia_com.assign(n, 0);
  if constexpr (!is_real_scalar_v<S>) return;
  for (std::size_t i = 0; i < n; ++i) {
    derived.placement_axes[i] = placement_axes_of(placement[i].rotation);
    derived.diagonal_inertia_com[i] = detail::is_diagonal(inertia_com[i]);
  }
  // Per body: bit 1, some body is its child; bit 2, on one of its nodes.
  derived.has_children.assign(n, 0);
  for (std::size_t i = 0; i < n; ++i)
    if (parent[i] >= 0) derived.has_children[static_cast<std::size_t>(parent[i])] |= attachment_node[i] >= 0 ? 3 : 1;
  for (std::size_t i = 0; i < n; ++i) {
    const int p = parent[i];
    const JointFastPath path = joint_fast_path[i];
    const int flexible = flexible_index[i];
    if (flexible >= 0 && p >= 0 && attachment_node[i] < 0 && !(derived.has_children[i] & 2) &&
        joint_is_weld(path) && derived.welded_to_root[static_cast<std::size_t>(p)]) {  // a welded appendage
      derived.appendage_in_root_frame[i] = 1;
      derived.pose_in_root[i] = derived.pose_in_root[static_cast<std::size_t>(p)] * placement[i];
      const std::size_t f = static_cast<std::size_t>(flexible);
      flexible_bodies[f].modal_integrals().in_frame(derived.pose_in_root[i], derived.root_frame_integrals[f]);
    }
    if (flexible >= 0 || attachment_node[i] >= 0) continue;  // rigid bodies on a body frame only
    if (p < 0) {
      if (!joint_has_constant_body_subspace(path)) continue;
      derived.welded_to_root[i] = 1;
      derived.pose_in_root[i] = Transform<S>();
    } else {
      const std::size_t pp = static_cast<std::size_t>(p);
      if (!derived.welded_to_root[pp]) continue;
      const bool welded = joint_is_weld(path);
      const int axis = joint_turning_axis(path);
      if (!welded && !(axis >= 0 && detail::mass_symmetric_about_axis(axis, com[i], inertia_com[i]))) continue;
      derived.welded_to_root[i] = welded ? 1 : 0;
      derived.pose_in_root[i] = derived.pose_in_root[pp] * placement[i];  // a turning body's at angle 0: the same inertia
    }
    derived.constant_tree_inertia[i] = 1;
    inertia_parameters_in_frame(derived.pose_in_root[i], mass[i], com[i], inertia_com[i], derived.tree_inertia_parameters[i]);
  }
  refresh_constant_leaf_hinges();
}

// Among those bodies, the leaves that turn: their hinge terms
// (constant_hinge_terms.hpp), from the subspace [w; t x w] of the revolute
// tree update (joints/revolute.hpp), constant here, and the leaf's P, its inertia.
template <class S>
void ModelTpl<S>::refresh_constant_leaf_hinges() {
  const std::size_t n = parent.size();
  for (std::size_t i = 0; i < n; ++i) {  // has_children: refresh_constant_tree_inertia's
    const JointFastPath path = joint_fast_path[i];
    const int axis = joint_turning_axis(path);
    if (!derived.constant_tree_inertia[i] || derived.has_children[i] || parent[i] < 0 || axis < 0) continue;
    const Transform<S>& pose = derived.pose_in_root[i];  // at angle 0; the axis and its point do not move
    const Vec3<S> w = pose.rotation.col(axis) * axis_sign[i];
    Vec6<S> subspace;
    subspace << w, pose.translation.cross(w);
    Mat6<S> P;
    assign_spatial_inertia(derived.tree_inertia_parameters[i], P);
    const Vec6<S> u = P * subspace;
    const S D = subspace.dot(u);
    if (!(D > detail::singular_pivot_threshold(P))) continue;  // left to the general update, which names the DOF
    ConstantHingeTerms<S>& terms = derived.leaf_hinge_terms[i];
    terms.articulated_d = D;
    terms.inverse_d = S(1) / D;
    terms.gain = u * terms.inverse_d;
    terms.articulated_plus = P;
    terms.articulated_plus.noalias() -= terms.gain * u.transpose();
    terms.subspace = subspace;
    terms.origin = pose.translation;
    derived.constant_leaf_hinge[i] = 1;
  }
  // A slot for each welded rigid body with a leaf child that has DOFs:
  // those leaves are the ones whose terms can be constant (above), so the
  // slots depend on the structure alone and a change of inertia or flags
  // refills them without allocating.
  int slots = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const int p = parent[i];
    if (p < 0 || derived.has_children[i] || nv_body[i] == 0 || flexible_index[i] >= 0 || attachment_node[i] >= 0) continue;
    const std::size_t pp = static_cast<std::size_t>(p);
    if (derived.welded_to_root[pp] && derived.leaf_presum_slot[pp] < 0) derived.leaf_presum_slot[pp] = slots++;
  }
  derived.leaf_presum_flags.resize(static_cast<std::size_t>(slots));
  derived.leaf_presum_regular.resize(static_cast<std::size_t>(slots));
  refresh_leaf_presums();
}

// The sums of constant leaf terms per parent (leaf_presum_slot), under the
// model's flags and with every DOF regular. A leaf is summed when its
// parent's sweep forms a P (under the flags: some regular hinge on the
// parent's path) and either its hinge terms are constant and apply (every
// DOF regular, no armature, which would change D) or, under the flags
// only, none of its DOFs is regular and its inertia is constant.
template <class S>
void ModelTpl<S>::refresh_leaf_presums() {
  const std::size_t n = parent.size();
  if (derived.leaf_presum_slot.size() != n || modes.size() != n) return;  // during construction: refreshed once sized
  for (Mat6<S>& sum : derived.leaf_presum_flags) sum.setZero();
  for (Mat6<S>& sum : derived.leaf_presum_regular) sum.setZero();
  for (std::size_t i = 0; i < n; ++i) {
    derived.leaf_plus_presummed[i] = 0;
    const int p = parent[i];
    if (p < 0 || derived.leaf_presum_slot[static_cast<std::size_t>(p)] < 0 || derived.has_children[i] || nv_body[i] == 0 ||
        !derived.constant_tree_inertia[i])
      continue;
    const std::size_t slot = static_cast<std::size_t>(derived.leaf_presum_slot[static_cast<std::size_t>(p)]);
    const HingeModes& h = modes[i];
    const bool constant_terms = derived.constant_leaf_hinge[i] && !h.has_armature;
    if (constant_terms) {
      derived.leaf_presum_regular[slot] += derived.leaf_hinge_terms[i].articulated_plus;
      derived.leaf_plus_presummed[i] |= 2;
    }
    if (!modes[static_cast<std::size_t>(p)].needs_articulated_inertia) continue;  // under the flags, no P to start
    if (constant_terms && h.n_prescribed == 0) {
      derived.leaf_presum_flags[slot] += derived.leaf_hinge_terms[i].articulated_plus;
      derived.leaf_plus_presummed[i] |= 1;
    } else if (h.n_regular == 0) {
      Mat6<S> P;
      assign_spatial_inertia(derived.tree_inertia_parameters[i], P);
      derived.leaf_presum_flags[slot] += P;
      derived.leaf_plus_presummed[i] |= 1;
    }
  }
}

}  // namespace soadyn
