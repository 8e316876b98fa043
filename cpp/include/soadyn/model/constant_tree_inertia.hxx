// Which bodies have a constant inertia in their tree frame (templated
// implementation of ModelTpl::refresh_constant_tree_inertia, model.hpp).
//
// The forward and hybrid dynamics sweeps and the CRBA express a tree whose
// root joint has a constant body-frame subspace (free, revolute or
// prismatic about a coordinate axis, fixed) in the root's body frame
// (sweeps/tree_frame_steps.hpp), so a rigid body's inertia there is the
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
  constant_tree_inertia.assign(n, 0);
  tree_inertia_parameters.resize(n);
  welded_to_root_.assign(n, 0);
  pose_in_root_.resize(n);
  appendage_in_root_frame.assign(n, 0);
  root_frame_integrals.resize(flexible_bodies.size());
  constant_leaf_hinge.assign(n, 0);
  leaf_hinge_terms.resize(n);
  leaf_plus_presummed.assign(n, 0);
  leaf_presum_slot.assign(n, -1);
  placement_axes.assign(n, PlacementAxes<S>());
  diagonal_inertia_com.assign(n, 0);
  if constexpr (!std::is_floating_point_v<S>) return;
  for (std::size_t i = 0; i < n; ++i) {
    placement_axes[i] = placement_axes_of(placement[i].rotation);
    diagonal_inertia_com[i] = detail::is_diagonal(inertia_com[i]);
  }
  // Per body: bit 1, some body is its child; bit 2, on one of its nodes.
  has_children_.assign(n, 0);
  for (std::size_t i = 0; i < n; ++i)
    if (parent[i] >= 0) has_children_[static_cast<std::size_t>(parent[i])] |= attachment_node[i] >= 0 ? 3 : 1;
  for (std::size_t i = 0; i < n; ++i) {
    const int p = parent[i];
    const JointKernel kernel = joint_kernel[i];
    const int flexible = flexible_index[i];
    if (flexible >= 0 && p >= 0 && attachment_node[i] < 0 && !(has_children_[i] & 2) &&
        kernel == JointKernel::fixed && welded_to_root_[static_cast<std::size_t>(p)]) {  // a welded appendage
      appendage_in_root_frame[i] = 1;
      pose_in_root_[i] = pose_in_root_[static_cast<std::size_t>(p)] * placement[i];
      const std::size_t f = static_cast<std::size_t>(flexible);
      flexible_bodies[f].modal_integrals().in_frame(pose_in_root_[i], root_frame_integrals[f]);
    }
    if (flexible >= 0 || attachment_node[i] >= 0) continue;  // rigid bodies on a body frame only
    if (p < 0) {
      if (!joint_has_constant_body_subspace(kernel)) continue;
      welded_to_root_[i] = 1;
      pose_in_root_[i] = Transform<S>();
    } else {
      const std::size_t pp = static_cast<std::size_t>(p);
      if (!welded_to_root_[pp]) continue;
      const bool welded = kernel == JointKernel::fixed;
      const int axis = static_cast<int>(kernel) - static_cast<int>(JointKernel::revolute_x);
      const bool coordinate_axis = kernel == JointKernel::revolute_x || kernel == JointKernel::revolute_y ||
                                   kernel == JointKernel::revolute_z;
      if (!welded && !(coordinate_axis && detail::mass_symmetric_about_axis(axis, com[i], inertia_com[i]))) continue;
      welded_to_root_[i] = welded ? 1 : 0;
      pose_in_root_[i] = pose_in_root_[pp] * placement[i];  // a turning body's at angle 0: the same inertia
    }
    constant_tree_inertia[i] = 1;
    inertia_parameters_in_frame(pose_in_root_[i], mass[i], com[i], inertia_com[i], tree_inertia_parameters[i]);
  }
  refresh_constant_leaf_hinges();
}

// Among those bodies, the leaves that turn: their hinge terms
// (constant_hinge_terms.hpp), from the subspace [w; t x w] of the revolute
// tree step (joints/revolute.hpp), constant here, and the leaf's P, its inertia.
template <class S>
void ModelTpl<S>::refresh_constant_leaf_hinges() {
  const std::size_t n = parent.size();
  for (std::size_t i = 0; i < n; ++i) {  // has_children_: refresh_constant_tree_inertia's
    const JointKernel kernel = joint_kernel[i];
    const bool turns = kernel == JointKernel::revolute_x || kernel == JointKernel::revolute_y ||
                       kernel == JointKernel::revolute_z;
    if (!constant_tree_inertia[i] || has_children_[i] || parent[i] < 0 || !turns) continue;
    const int axis = static_cast<int>(kernel) - static_cast<int>(JointKernel::revolute_x);
    const Transform<S>& pose = pose_in_root_[i];  // at angle 0; the axis and its point do not move
    const Vec3<S> w = pose.rotation.col(axis) * axis_sign[i];
    Vec6<S> subspace;
    subspace << w, pose.translation.cross(w);
    Mat6<S> P;
    assign_spatial_inertia(tree_inertia_parameters[i], P);
    const Vec6<S> u = P * subspace;
    const S D = subspace.dot(u);
    if (!(D > detail::singular_pivot_threshold(P))) continue;  // left to the general step, which names the DOF
    ConstantHingeTerms<S>& terms = leaf_hinge_terms[i];
    terms.articulated_d = D;
    terms.inverse_d = S(1) / D;
    terms.gain = u * terms.inverse_d;
    terms.articulated_plus = P;
    terms.articulated_plus.noalias() -= terms.gain * u.transpose();
    terms.subspace = subspace;
    terms.origin = pose.translation;
    constant_leaf_hinge[i] = 1;
  }
  // A slot for each welded rigid body with a leaf child that has DOFs:
  // those leaves are the ones whose terms can be constant (above), so the
  // slots depend on the structure alone and a change of inertia or flags
  // refills them without allocating.
  int slots = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const int p = parent[i];
    if (p < 0 || has_children_[i] || nv_body[i] == 0 || flexible_index[i] >= 0 || attachment_node[i] >= 0) continue;
    const std::size_t pp = static_cast<std::size_t>(p);
    if (welded_to_root_[pp] && leaf_presum_slot[pp] < 0) leaf_presum_slot[pp] = slots++;
  }
  leaf_presum_flags.resize(static_cast<std::size_t>(slots));
  leaf_presum_regular.resize(static_cast<std::size_t>(slots));
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
  if (leaf_presum_slot.size() != n || modes.size() != n) return;  // during construction: refreshed once sized
  for (Mat6<S>& sum : leaf_presum_flags) sum.setZero();
  for (Mat6<S>& sum : leaf_presum_regular) sum.setZero();
  for (std::size_t i = 0; i < n; ++i) {
    leaf_plus_presummed[i] = 0;
    const int p = parent[i];
    if (p < 0 || leaf_presum_slot[static_cast<std::size_t>(p)] < 0 || has_children_[i] || nv_body[i] == 0 ||
        !constant_tree_inertia[i])
      continue;
    const std::size_t slot = static_cast<std::size_t>(leaf_presum_slot[static_cast<std::size_t>(p)]);
    const HingeModes& h = modes[i];
    const bool constant_terms = constant_leaf_hinge[i] && !h.has_armature;
    if (constant_terms) {
      leaf_presum_regular[slot] += leaf_hinge_terms[i].articulated_plus;
      leaf_plus_presummed[i] |= 2;
    }
    if (!modes[static_cast<std::size_t>(p)].needs_articulated_inertia) continue;  // under the flags, no P to start
    if (constant_terms && h.n_prescribed == 0) {
      leaf_presum_flags[slot] += leaf_hinge_terms[i].articulated_plus;
      leaf_plus_presummed[i] |= 1;
    } else if (h.n_regular == 0) {
      Mat6<S> P;
      assign_spatial_inertia(tree_inertia_parameters[i], P);
      leaf_presum_flags[slot] += P;
      leaf_plus_presummed[i] |= 1;
    }
  }
}

}  // namespace soadyn
