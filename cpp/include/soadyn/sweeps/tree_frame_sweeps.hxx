// The hybrid algorithm's three sweeps in tree frames (tree_frame_updates.hpp):
// hybrid dynamics and its impulse form (the model's flags) and forward
// dynamics (every DOF regular: the articulated-body algorithm), for rigid
// models (Flex = false) and for models whose flexible bodies carry no body
// on a node (Flex = true: appendages such as booms, antennas and arrays).
// Models with bodies on nodes, and bodies beyond tree-frame reach, use the
// body-frame sweep (body_frame_sweeps.hxx); dynamics_path.hxx chooses.
// Inverse dynamics stays in body frames (rnea.hxx): without an articulated
// inertia to carry, body frames need fewer operations.
#pragma once
#include "soadyn/sweeps/hinge_updates.hpp"
#include "soadyn/linalg/spd_factor6.hpp"
#include "soadyn/sweeps/tree_frame_updates.hpp"

namespace soadyn {
namespace detail {

// A free root joint with every DOF regular. Its subspace in the tree frame,
// blockdiag(R, R), is invertible, so Eq. 28 gives P+ = 0 and the hinge
// equation H (P alpha + z) = T fixes the body's acceleration outright:
//   alpha = P^-1 (H^-* T - z),  H^-* = H (orthogonal blocks),
// with one solve with P = L D L' (spd_factor6.hpp) instead of D = H P H*, G
// and P+. Stores alpha in acceleration[i] and P's factor in hinge_factor[i];
// returns the DOF of a singular P, or -1. RootBodyFrames: the tree frame is
// the root's body frame, where H = 1 and alpha = P^-1 (T - z).
template <bool RootBodyFrames, class S>
inline int free_root_inward(const ModelTpl<S>& m, DataTpl<S>& d, std::size_t i, const S* u) {
  const Mat6N<S>& s = d.sweep.tree_subspace[i];
  const Mat6<S>& P = d.sweep.tree_articulated_inertia[i];
  Mat6<S>& factor = d.sweep.hinge_factor[i];
  const int bad = spd_factor6(P, detail::singular_pivot_threshold(P), factor);
  if (bad >= 0) return m.v_index[i] + bad;
  const Eigen::Map<const Vec6<S>> torque(u + m.v_index[i]);
  Vec6<S> residual;  // H^-* T - z
  if constexpr (RootBodyFrames)
    residual = torque;
  else
    residual << s.template topLeftCorner<3, 3>() * torque.template head<3>(),
        s.template bottomRightCorner<3, 3>() * torque.template tail<3>();
  residual -= d.sweep.tree_bias_and_children_z[i];
  d.sweep.tree_acceleration[i] = spd_solve6(factor, residual);
  return -1;
}

// Whether leaf i's hinge update reads its constant terms (RootBodyFrames:
// the tree frame is its root's body frame; ModelTpl::leaf_hinge_terms): its
// DOF regular, with no armature, which would change D.
template <ModePolicy Modes, bool RootBodyFrames, class S>
SOADYN_ALWAYS_INLINE bool constant_leaf_hinge(const ModelTpl<S>& m, std::size_t i) {
  return RootBodyFrames && m.derived.constant_leaf_hinge[i] && regular_hinge<Modes>(m, i) && !m.modes[i].has_armature;
}

// The bit of ModelTpl::leaf_plus_presummed that holds under `Modes`.
template <ModePolicy Modes>
constexpr std::uint8_t presum_bit() {
  return Modes == ModePolicy::all_regular ? 2 : 1;
}

// Whether leaf i's P+ (or passed-on P) is already in its parent's P, which
// the first sweep started with the sum of such terms (RootBodyFrames only:
// the terms are constant in the root's body frame).
template <ModePolicy Modes, bool RootBodyFrames, class S>
SOADYN_ALWAYS_INLINE bool leaf_plus_presummed(const ModelTpl<S>& m, std::size_t i) {
  return RootBodyFrames && (m.derived.leaf_plus_presummed[i] & presum_bit<Modes>());
}

// Body i's P starts as its own inertia plus its constant leaves' terms.
template <ModePolicy Modes, bool RootBodyFrames, class S>
SOADYN_ALWAYS_INLINE void add_presummed_leaves(const ModelTpl<S>& m, SweepData<S>& w, std::size_t i) {
  const int slot = RootBodyFrames ? m.derived.leaf_presum_slot[i] : -1;
  if (slot < 0) return;
  const auto& sums = Modes == ModePolicy::all_regular ? m.derived.leaf_presum_regular : m.derived.leaf_presum_flags;
  w.tree_articulated_inertia[i] += sums[static_cast<std::size_t>(slot)];
}

// Whether the inward sweep runs leaf i's update with its constant terms: into
// a parent that forms a P.
template <ModePolicy Modes, bool RootBodyFrames, class S>
SOADYN_ALWAYS_INLINE bool constant_leaf_update(const ModelTpl<S>& m, std::size_t i) {
  // The flag first: false for every body of most models (a leaf has a parent)
  return constant_leaf_hinge<Modes, RootBodyFrames>(m, i) &&
         needs_articulated_inertia<Modes>(m, static_cast<std::size_t>(m.parent[i]));
}

// Eq. 28 for such a leaf, with D, G and P+ read: z = b + P a,
// eps = T - H z, nu = D^-1 eps, z+ = z + G eps; P+ added to its parent's P
// unless the parent started with it (`presummed`).
template <class S>
SOADYN_ALWAYS_INLINE void constant_leaf_inward(const ModelTpl<S>& m, DataTpl<S>& d, std::size_t i, const S* u,
                                               bool presummed, Vec6<S>& z_plus) {
  const ConstantHingeTerms<S>& terms = m.derived.leaf_hinge_terms[i];
  SweepData<S>& w = d.sweep;
  Vec6<S> z = w.tree_bias_and_children_z[i];
  z += momentum(m.derived.tree_inertia_parameters[i], w.tree_coriolis[i]);  // P a, P its constant inertia
  const S e = u[m.v_index[i]] - w.tree_subspace[i].col(0).dot(z);
  w.tree_gain[i].col(0) = terms.gain;
  w.innovation[i][0] = e * terms.inverse_d;
  w.hinge_factor[i](0, 0) = terms.articulated_d;
  z_plus = z + terms.gain * e;
  if (!presummed) w.tree_articulated_inertia[static_cast<std::size_t>(m.parent[i])] += terms.articulated_plus;
}

// qdd = H^-1 (alpha - alpha+ - a) of that free root, H^-1 = H* (orthogonal
// blocks; RootBodyFrames: H = 1, a = 0 and alpha+ the world's acceleration in
// the root's frame).
template <bool RootBodyFrames, class S>
inline void free_root_outward(const ModelTpl<S>& m, DataTpl<S>& d, std::size_t i, const S* u, const Vec6<S>& world_acc,
                              bool want_force) {
  SweepData<S>& w = d.sweep;
  const Mat6N<S>& s = w.tree_subspace[i];
  const int vi = m.v_index[i];
  if constexpr (RootBodyFrames) {
    d.qdd.template segment<6>(vi) = w.tree_acceleration[i] - w.tree_world_acceleration[i];
  } else {
    const Vec6<S> relative = w.tree_acceleration[i] - world_acc - w.tree_coriolis[i];
    d.qdd.template segment<3>(vi) = s.template topLeftCorner<3, 3>().transpose() * relative.template head<3>();
    d.qdd.template segment<3>(vi + 3) = s.template bottomRightCorner<3, 3>().transpose() * relative.template tail<3>();
  }
  d.tau.template segment<6>(vi) = Eigen::Map<const Vec6<S>>(u + vi);
  if (want_force)
    w.tree_hinge_force[i] = w.tree_articulated_inertia[i] * w.tree_acceleration[i] + w.tree_bias_and_children_z[i];
}

// Hinge forces of the sweeps, from tree frames to the body-frame output.
template <class S>
inline void hinge_forces_to_body_frames(DataTpl<S>& d) {
  for (std::size_t i = 0; i < d.hinge_force.size(); ++i)
    d.hinge_force[i] = d.sweep.tree_pose[i].force_to_child(d.sweep.tree_hinge_force[i]);
}

template <ModePolicy Modes, class S>
inline bool is_regular_free_root(const ModelTpl<S>& m, std::size_t i) {
  return is_free_root(m, static_cast<int>(i)) && regular_hinge<Modes>(m, i) &&
         !m.modes[i].has_armature;  // armature: D = H P H* + A, the general update
}

// The acceleration a root's tree frame gives its parent, the world: [0; -g]
// in the world's orientation, or in the root's body frame (RootBodyFrames).
template <bool RootBodyFrames, class S>
SOADYN_ALWAYS_INLINE const Vec6<S>& root_world_acceleration(const ModelTpl<S>& m, const DataTpl<S>& d, std::size_t i,
                                                            const Vec6<S>& world_acc) {
  if (RootBodyFrames && joint_has_constant_body_subspace(m.joint_fast_path[i])) return d.sweep.tree_world_acceleration[i];
  return world_acc;
}

// The tree-frame hinge update of body i (Jain & Rodriguez 1993, Eq. 28): P+
// added to the parent's P as it is formed when the parent has one (Eq. 14
// with phi = 1), else not formed at all (`never_formed`).
template <bool AllRegular, class S>
SOADYN_ALWAYS_INLINE int tree_hinge_inward(const ModelTpl<S>& m, DataTpl<S>& d, std::size_t i, const S* u,
                                           bool into_parent, Mat6<S>& never_formed, Vec6<S>& z_plus,
                                           const Mat6<S>*& P_out) {
  constexpr Frames tree = Frames::tree;
  if (into_parent)
    return hinge_inward<tree, AllRegular, detail::PlusMode::add>(
        m, d, i, u, d.sweep.tree_articulated_inertia[static_cast<std::size_t>(m.parent[i])], z_plus, P_out);
  return hinge_inward<tree, AllRegular, detail::PlusMode::none>(m, d, i, u, never_formed, z_plus, P_out);
}

// The first two sweeps in tree frames: base to tip V, a, M, b (Eq. 1) and
// the accelerations of all-prescribed regions; tip to base P, z, G, nu
// (Eq. 28). `v` null means zero velocity. Returns TreeFrameStatus::beyond,
// having changed no output, when a body lies too far from its tree origin
// for tree frames (the caller then uses body frames). RootBodyFrames: a
// root's tree frame is its body frame where its joint allows
// (tree_frame_updates.hpp); `poses_wanted` false: the orientations of
// leaves with constant hinge terms are not needed afterwards
// (tree_velocity_update), nor their P as a matrix (the hinge force's).
template <ModePolicy Modes, bool Flex, bool RootBodyFrames = false, class S>
TreeFrameStatus tree_frame_inward_sweeps(const ModelTpl<S>& m, DataTpl<S>& d, const S* q, const S* v, const S* u,
                                const S* f_ext, const Vec6<S>& world_acc, bool poses_wanted = true) {
  const std::size_t n = static_cast<std::size_t>(m.nbodies());
  SweepData<S>& w = d.sweep;
  // Constant leaves and their parents' sums: every such leaf's parent has a
  // slot (ModelTpl::leaf_presum_slot), so a model without slots (most
  // robots) tests nothing per body.
  const bool leaf_terms = RootBodyFrames && !m.derived.leaf_presum_flags.empty();
  tabulate_joint_angles(m, w, q);
  for (std::size_t i = 0; i < n; ++i) {  // base to tip: V, a, M, b (Eq. 1); all-prescribed regions' accelerations
    if (RootBodyFrames && is_body_frame_root(m, static_cast<int>(i)))
      root_body_frame_update(m, d, i, q, v, world_acc);
    else
      tree_velocity_update<RootBodyFrames>(m, d, i, q, v, poses_wanted || f_ext);
    if (beyond_tree_frame_reach(m, d, i)) return TreeFrameStatus::beyond(static_cast<int>(i));
    if constexpr (Flex) {
      if (m.is_flexible(static_cast<int>(i))) {  // modal DOFs always regular: P^ and z^ at once
        tree_flexible_body_update<RootBodyFrames>(m, d, i, q, v, u, f_ext);
        continue;
      }
    }
    InertiaParameters<S> inertia;
    tree_rigid_body_update<RootBodyFrames>(m, d, i, v, f_ext, inertia);
    // A leaf with constant hinge terms needs its P as a matrix only for its
    // hinge force (the outward sweep, when wanted); its inward update reads
    // its constant inertia's parameters.
    if (poses_wanted || !(leaf_terms && constant_leaf_update<Modes, RootBodyFrames>(m, i)))
      assign_spatial_inertia(inertia, w.tree_articulated_inertia[i]);  // the start of P
    if (leaf_terms) add_presummed_leaves<Modes, RootBodyFrames>(m, w, i);
    if (!needs_articulated_inertia<Modes>(m, i)) {  // Newton-Euler: alpha = alpha+ + H* qdd + a, f = M alpha + b
      const int p = m.parent[i];
      w.tree_acceleration[i] = (p >= 0 ? w.tree_acceleration[static_cast<std::size_t>(p)]
                                       : root_world_acceleration<RootBodyFrames>(m, d, i, world_acc)) +
                               w.tree_coriolis[i];
      w.tree_acceleration[i] += detail::subspace_times(w.tree_subspace[i], u + m.v_index[i]);
      w.tree_hinge_force[i] = w.tree_bias_force[i] + momentum(inertia, w.tree_acceleration[i]);
    }
  }
  Mat6<S> never_formed;  // P+ is added to the parent as it is formed, or only applied (articulated_plus_times)
  Vec6<S> z_plus;
  for (std::size_t i = n; i-- > 0;) {  // tip to base (Eq. 28)
    const int p = m.parent[i];
    const std::size_t pp = static_cast<std::size_t>(p);
    if (!needs_articulated_inertia<Modes>(m, i)) {  // T = H f, f(parent) += f
      const int vi = m.v_index[i], ni = m.nv_body[i];
      for (int k = 0; k < ni; ++k) d.qdd[vi + k] = u[vi + k];
      detail::subspace_transpose_times(w.tree_subspace[i], w.tree_hinge_force[i], d.tau.segment(vi, ni));
      detail::add_armature_torques(m, i, u, d.tau.data());
      if (p >= 0) w.tree_hinge_force[pp] += w.tree_hinge_force[i];
      continue;
    }
    if (is_regular_free_root<Modes>(m, i)) {
      const int bad = free_root_inward<RootBodyFrames>(m, d, i, u);
      if (bad >= 0) return Status{StatusCode::singular_articulated_inertia, bad};
      continue;
    }
    const Mat6<S>* P_out = nullptr;
    const bool into_parent = p >= 0 && needs_articulated_inertia<Modes>(m, pp);
    if (leaf_terms && constant_leaf_update<Modes, RootBodyFrames>(m, i)) {
      constant_leaf_inward(m, d, i, u, leaf_plus_presummed<Modes, RootBodyFrames>(m, i), z_plus);
      w.tree_bias_and_children_z[pp] += z_plus;
      continue;
    }
    const bool regular = regular_hinge<Modes>(m, i);
    const int bad = regular ? tree_hinge_inward<true>(m, d, i, u, into_parent, never_formed, z_plus, P_out)
                            : tree_hinge_inward<false>(m, d, i, u, into_parent, never_formed, z_plus, P_out);
    if (bad >= 0) return Status{StatusCode::singular_articulated_inertia, bad};
    if (p < 0) continue;
    if (into_parent) {
      if (P_out && !(leaf_terms && leaf_plus_presummed<Modes, RootBodyFrames>(m, i)))  // no regular DOF: P passed on
        w.tree_articulated_inertia[pp] += *P_out;
      w.tree_bias_and_children_z[pp] += z_plus;
    } else {  // the parent's acceleration is already known: f = P+ alpha(parent) + z+
      Vec6<S>& f = w.tree_hinge_force[pp];
      const Vec6<S>& alpha = w.tree_acceleration[pp];
      f += z_plus;
      if (P_out)
        f.noalias() += *P_out * alpha;
      else
        f += regular ? articulated_plus_times<Frames::tree, true>(m, d, i, alpha)
                     : articulated_plus_times<Frames::tree, false>(m, d, i, alpha);
    }
  }
  return {};
}

// The third sweep's update for body i (Eq. 29), its parent's acceleration known.
template <ModePolicy Modes, bool Flex, bool RootBodyFrames = false, class S>
SOADYN_ALWAYS_INLINE void tree_outward_update(const ModelTpl<S>& m, DataTpl<S>& d, std::size_t i, const S* u,
                                            const Vec6<S>& world_acc, bool want_force) {
  if (!needs_articulated_inertia<Modes>(m, i)) return;
  const int p = m.parent[i];
  const Vec6<S>& alpha_plus = p >= 0 ? d.sweep.tree_acceleration[static_cast<std::size_t>(p)]
                                     : root_world_acceleration<RootBodyFrames>(m, d, i, world_acc);
  if (is_regular_free_root<Modes>(m, i))
    free_root_outward<RootBodyFrames>(m, d, i, u, world_acc, want_force);
  else if (regular_hinge<Modes>(m, i))
    hinge_outward<Frames::tree, true>(m, d, i, u, alpha_plus, want_force);
  else  // some DOF prescribed
    hinge_outward<Frames::tree, false>(m, d, i, u, alpha_plus, want_force);
  if constexpr (Flex)
    if (m.is_flexible(static_cast<int>(i)))
      modal_accelerations(m, d, i, u,
                          appendage_eliminated_in_tree_frame<RootBodyFrames>(m, i)
                              ? d.sweep.tree_acceleration[i]
                              : Vec6<S>(d.sweep.tree_pose[i].motion_to_child(d.sweep.tree_acceleration[i])));
}

// The third sweep (base to tip, Eq. 29) and the outputs' checks; `want_force`
// also leaves every hinge force in data.hinge_force (body frame).
template <ModePolicy Modes, bool Flex, bool RootBodyFrames = false, class S>
Status tree_frame_outward_sweep(const ModelTpl<S>& m, DataTpl<S>& d, const S* u, const Vec6<S>& world_acc,
                                bool want_force) {
  for (std::size_t i = 0; i < static_cast<std::size_t>(m.nbodies()); ++i)
    tree_outward_update<Modes, Flex, RootBodyFrames>(m, d, i, u, world_acc, want_force);
  if (want_force) hinge_forces_to_body_frames(d);
  const Status s = detail::check_finite(d.qdd);
  if constexpr (Modes == ModePolicy::all_regular) return s;  // tau is the given torque
  return s.ok() ? detail::check_prescribed_finite(m, d.tau) : s;
}

// The three sweeps in tree frames (arguments as above), roots in their body
// frames where their joints allow: these sweeps' outputs are joint-space (and hinge forces in
// body frames), so no caller sees the tree frame's orientation.
template <ModePolicy Modes, bool Flex, class S>
TreeFrameStatus tree_frame_sweeps(const ModelTpl<S>& m, DataTpl<S>& d, const S* q, const S* v, const S* u,
                                  const S* f_ext, const Vec6<S>& world_acc, bool want_force) {
  const TreeFrameStatus inward = tree_frame_inward_sweeps<Modes, Flex, true>(m, d, q, v, u, f_ext, world_acc, want_force);
  if (!inward.ok()) return inward;
  return tree_frame_outward_sweep<Modes, Flex, true>(m, d, u, world_acc, want_force);
}

}  // namespace detail
}  // namespace soadyn
