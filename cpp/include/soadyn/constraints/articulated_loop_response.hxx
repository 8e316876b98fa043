// The response of the hybrid algorithm's articulated-body factorisation to
// the loops' multipliers: Y = M_rr^-1 C_r' (the change of the regular
// accelerations per unit multiplier) without forming M, and the solved loop
// forces entered into the sweeps.
//
// A multiplier lambda_c of loop l acts on the tree as the wrench W_c
// (loop_directions) on frame A's body and -W_c on frame B's body: C' e_c is
// their generalized force. The sweeps are linear in the external forces, so
// with the articulated inertias P, gains G and D of the hybrid sweeps already
// in `data` (tree frames, tree_frame_sweeps.hxx), the change they cause obeys
// the same recursions with the velocity, gravity and torque terms removed
// (Jain & Rodriguez 1993, Eqs. 28, 29):
//   inward, on the loop bodies' root paths only:
//     dz = sum of the children's dz+ - (applied wrench),
//     deps = -H_r dz,  dz+ = dz + G deps,
//   outward, over the same bodies:
//     dqdd_r = D^-1 deps - G' dalpha+,  dqdd_p = 0,  dalpha = dalpha+ + H*_r dqdd_r.
// All m multipliers are carried at once as load cases (a 6 x m block per
// body, an n x m block per hinge) on the loaded bodies (L of them: the loop
// bodies and their ancestors). Once the multipliers are known, the loop
// forces enter the loaded bodies' z and nu, and the hybrid algorithm's own
// outward sweep, run once, gives qdd and tau with them. The cost is
// O(N + L m) for N bodies, against O(N d^2) for factoring M on a tree of
// depth d; the Delassus matrix is then K = C_r Y (m x m). This is the
// operational-space inverse inertia of Kreutz-Delgado, Jain & Rodriguez,
// "Recursive formulation of operational space control" (IJRR 11(4), 1992),
// for the loops' cut-joint wrenches, in the hybrid setting.
#pragma once
#include <algorithm>
#include "soadyn/constraints/loop_closure.hxx"
#include "soadyn/linalg/small_cholesky.hpp"
#include "soadyn/sweeps/tree_frame_sweeps.hxx"

namespace soadyn {
namespace detail {

// loops.tree_origin (the world position of each body's tree origin: its
// root body's origin) and pose_in_world from the tree-frame poses.
template <class S>
void set_world_poses_from_tree_frames(const ModelTpl<S>& m, DataTpl<S>& d, const S* q) {
  LoopData<S>& ld = d.loops;
  for (std::size_t i = 0; i < static_cast<std::size_t>(m.nbodies()); ++i) {
    const int p = m.parent[i];
    if (p >= 0) {
      ld.tree_origin[i] = ld.tree_origin[static_cast<std::size_t>(p)];
    } else {  // a root's tree pose keeps the rotation of placement * joint and drops its translation
      const Transform<S>& X = m.placement[i];
      ld.tree_origin[i] = X.translation;
      if (joint_translates(m.joints[i])) {
        Transform<S> joint_pose;
        Mat6N<S> s;
        Vec6<S> bias;
        joint_init_subspace(m.joints[i], s);
        joint_calc(m.joints[i], q + m.q_index[i], static_cast<const S*>(nullptr), joint_pose, s, bias);
        ld.tree_origin[i] += X.rotation * joint_pose.translation;
      }
    }
    d.pose_in_world[i].rotation = d.sweep.tree_pose[i].rotation;
    d.pose_in_world[i].translation = d.sweep.tree_pose[i].translation + ld.tree_origin[i];
  }
}

// Marks the bodies on a loop body's root path (the loaded bodies): the loop
// bodies and their ancestors.
template <class S>
void mark_loop_paths(const ModelTpl<S>& m, LoopData<S>& ld) {
  std::fill(ld.on_loop_path.begin(), ld.on_loop_path.end(), std::uint8_t(0));
  for (const LoopTpl<S>& loop : m.loops)
    for (const int body : {loop.body_a, loop.body_b})
      if (body >= 0) ld.on_loop_path[static_cast<std::size_t>(body)] = 1;
  for (std::size_t i = static_cast<std::size_t>(m.nbodies()); i-- > 0;)
    if (ld.on_loop_path[i] && m.parent[i] >= 0) ld.on_loop_path[static_cast<std::size_t>(m.parent[i])] = 1;
}

// Loads the unit multipliers' wrenches into R.z, one load case per loop
// equation, on the loaded bodies (their other entries cleared): W's column k
// of loop l (world axes, about frame A's origin) on frame A's body as case
// first_row + k, its opposite on frame B's body at the point P whose velocity
// C compares (B's origin; A's for a prismatic loop), both where the loop
// equations left them (loops.point_a, point_p). In z, as an external force:
// dz = -(the wrench) in the body's tree frame, about its origin:
// [torque + (point - origin) x force; force].
template <class S>
void load_unit_multipliers(const ModelTpl<S>& m, DataTpl<S>& d, ArticulatedResponse<S>& R) {
  LoopData<S>& ld = d.loops;
  for (std::size_t i = 0; i < static_cast<std::size_t>(m.nbodies()); ++i)
    if (ld.on_loop_path[i]) R.z_of(i).setZero();
  const auto apply = [&](int body, const Vec3<S>& point, S sign, const Mat6<S>& W, int first, int rows) {
    if (body < 0) return;
    const std::size_t b = static_cast<std::size_t>(body);
    const Vec3<S> arm = point - ld.tree_origin[b];
    auto dz = R.z_of(b).middleCols(first - R.first_case[b], rows);
    for (int k = 0; k < rows; ++k) {
      const auto w = W.col(k);
      dz.col(k).template head<3>() -= sign * (w.template head<3>() + arm.cross(w.template tail<3>()));
      dz.col(k).template tail<3>() -= sign * w.template tail<3>();
    }
  };
  for (std::size_t l = 0; l < m.loops.size(); ++l) {
    const LoopTpl<S>& loop = m.loops[l];
    apply(loop.body_a, ld.point_a[l], S(1), ld.directions[l], loop.first_row, loop.rows());
    apply(loop.body_b, ld.point_p[l], S(-1), ld.directions[l], loop.first_row, loop.rows());
  }
}

// Whether body i's hinge has a gain G and its eps: an articulated inertia, a
// regular DOF, and not the free root solved outright (free_root_inward).
template <class S>
bool hinge_has_gain(const ModelTpl<S>& m, std::size_t i) {
  const HingeModes& h = m.modes[i];
  return h.needs_articulated_inertia && h.n_regular > 0 && !is_regular_free_root<ModePolicy::model_flags>(m, i);
}

template <class S>
const Mat6N<S>& regular_tree_subspace(const ModelTpl<S>& m, const DataTpl<S>& d, std::size_t i) {
  return m.modes[i].n_prescribed > 0 ? d.sweep.tree_regular_subspace[i] : d.sweep.tree_subspace[i];
}

// One hinge's part of the response, per load case c, for N regular DOFs
// (N fixed at compile time for 1, 2, 3 and 6, Eigen::Dynamic otherwise):
// inward  eps_c = -H_r dz_c,  dz+_c = dz_c + G eps_c;
// outward qdd_c = D^-1 eps_c - G' dalpha+_c,  dalpha_c = dalpha+_c + H*_r qdd_c,
// with D = H_r P H*_r + armature (Eq. 28) as the inward sweep left it
// factored (hinge_factor); the outward step leaves dnu = D^-1 eps in place
// of eps.
template <int N, class S>
struct HingeResponse {
  using Mat6n = Eigen::Matrix<S, 6, N, 0, 6, (N == Eigen::Dynamic ? 6 : N)>;
  using Matn = Eigen::Matrix<S, N, N, 0, (N == Eigen::Dynamic ? 6 : N), (N == Eigen::Dynamic ? 6 : N)>;
  using Vecn = Eigen::Matrix<S, N, 1, 0, (N == Eigen::Dynamic ? 6 : N), 1>;

  // eps into rows [v, v + n) of `eps`; dz+ added to dz_parent (null: a root).
  template <class Z, class Eps, class ZParent>
  static void inward(const Mat6N<S>& Sr, const Mat6N<S>& G, const Z& dz, Eps& eps, int v, ZParent* dz_parent) {
    const Mat6n s = Sr, g = G;
    const Eigen::Index n = s.cols();
    for (Eigen::Index c = 0; c < dz.cols(); ++c) {
      const Vecn e = -(s.transpose() * dz.col(c));
      eps.col(c).segment(v, n) = e;
      if (dz_parent) dz_parent->col(c) += dz.col(c) + g * e;
    }
  }

  // qdd into rows dof(k) of `qdd` (k < n); dalpha holds dalpha+ on entry
  // (`has_parent`; zero otherwise) and dalpha on return.
  template <class Eps, class A, class Qdd, class Dof>
  static void outward(const Mat6N<S>& Sr, const Mat6N<S>& G, const Mat6<S>& factor, Eps& eps, int v,
                      bool has_parent, A& dalpha, Qdd& qdd, Dof&& dof) {
    const Mat6n s = Sr, g = G;
    const Eigen::Index n = s.cols();
    const Matn L = factor.topLeftCorner(n, n);
    // One DOF: the factor holds D itself; its solve is rounded as the 1 x 1
    // Cholesky solve (two products with 1 / sqrt(D)), the arithmetic the
    // float-versus-double test of the loops was validated with.
    using std::sqrt;
    const S inverse_root = N == 1 ? S(1) / sqrt(L(0, 0)) : S(0);
    for (Eigen::Index c = 0; c < dalpha.cols(); ++c) {
      Vecn r = eps.col(c).segment(v, n);
      if constexpr (N == 1)
        r[0] = r[0] * inverse_root * inverse_root;
      else
        cholesky_solve_in_place(L, r);
      eps.col(c).segment(v, n) = r;  // dnu = D^-1 deps, kept for the update of nu (add_loop_forces_to_sweeps)
      if (has_parent) r.noalias() -= g.transpose() * dalpha.col(c);
      dalpha.col(c) += s * r;
      for (Eigen::Index k = 0; k < n; ++k) qdd(dof(static_cast<int>(k)), c) = r[k];
    }
  }
};

// Calls fn(HingeResponse<N, S>{}) with N = n when n is 1, 2, 3 or 6.
template <class S, class Fn>
decltype(auto) with_hinge_size(int n, Fn&& fn) {
  switch (n) {
    case 1: return fn(HingeResponse<1, S>{});
    case 2: return fn(HingeResponse<2, S>{});
    case 3: return fn(HingeResponse<3, S>{});
    case 6: return fn(HingeResponse<6, S>{});
    default: return fn(HingeResponse<Eigen::Dynamic, S>{});
  }
}

// The inward half over the loaded bodies: eps of each hinge with a gain and
// dz+ into its parent.
template <class S>
void loop_response_inward(const ModelTpl<S>& m, DataTpl<S>& d, ArticulatedResponse<S>& R) {
  const LoopData<S>& ld = d.loops;
  for (std::size_t i = static_cast<std::size_t>(m.nbodies()); i-- > 0;) {
    if (!ld.on_loop_path[i]) continue;
    const auto dz = R.z_of(i);
    const int p = m.parent[i];
    auto dz_parent = R.z_of(p >= 0 ? static_cast<std::size_t>(p) : i);
    if (!hinge_has_gain(m, i)) {  // z+ = z: a hinge without regular DOFs, a Newton-Euler region
      if (p >= 0) dz_parent += dz;
      continue;
    }
    auto eps = R.eps_of(i);
    with_hinge_size<S>(m.modes[i].n_regular, [&](auto kernel) {
      kernel.inward(regular_tree_subspace(m, d, i), d.sweep.tree_gain[i], dz, eps, m.v_index[i],
                    p >= 0 ? &dz_parent : nullptr);
    });
  }
}

// The outward half over the loaded bodies: dqdd and dalpha per load case.
template <class S>
void loop_response_outward(const ModelTpl<S>& m, DataTpl<S>& d, ArticulatedResponse<S>& R) {
  const LoopData<S>& ld = d.loops;
  for (std::size_t i = 0; i < static_cast<std::size_t>(m.nbodies()); ++i) {
    if (!ld.on_loop_path[i]) continue;
    const int vi = m.v_index[i], ni = m.nv_body[i];
    const HingeModes& h = m.modes[i];
    const int p = m.parent[i];
    const Mat6N<S>& s = d.sweep.tree_subspace[i];
    auto qdd = R.qdd_of(i);
    auto eps = R.eps_of(i);
    auto dqdd = qdd.middleRows(vi, ni);
    auto dalpha = R.alpha_of(i);
    if (!h.needs_articulated_inertia) {  // accelerations given from the world in
      dalpha.setZero();
      dqdd.setZero();
      continue;
    }
    if (is_regular_free_root<ModePolicy::model_flags>(m, i)) {  // alpha = P^-1 (H^-* T - z) (free_root_inward)
      const Mat6<S>& factor = d.sweep.hinge_factor[i];  // P = L D L' (spd_factor6.hpp)
      const auto dz = R.z_of(i);
      for (Eigen::Index c = 0; c < dalpha.cols(); ++c)  // fixed-size solves: no heap temporary
        dalpha.col(c) = -spd_solve6(factor, Vec6<S>(dz.col(c)));
      dqdd.topRows(3).noalias() = s.template topLeftCorner<3, 3>().transpose() * dalpha.template topRows<3>();
      dqdd.bottomRows(3).noalias() = s.template bottomRightCorner<3, 3>().transpose() * dalpha.template bottomRows<3>();
      continue;
    }
    if (p >= 0)
      dalpha = R.alpha_of(static_cast<std::size_t>(p));
    else
      dalpha.setZero();
    for (int k = 0; k < h.n_prescribed; ++k) dqdd.row(h.prescribed[k]).setZero();
    if (h.n_regular == 0) continue;
    with_hinge_size<S>(h.n_regular, [&](auto kernel) {
      kernel.outward(regular_tree_subspace(m, d, i), d.sweep.tree_gain[i], d.sweep.hinge_factor[i], eps, vi, p >= 0,
                     dalpha, qdd, [&](int k) { return vi + (h.n_prescribed > 0 ? h.regular[k] : k); });
    });
  }
}

// After the inward sweeps of hybrid dynamics in tree frames (their P, G and
// poses in `data`), with the loaded bodies marked (mark_loop_paths) and
// pose_in_world, loops.tree_origin and loops.directions current: the loaded
// bodies' dqdd per unit multiplier, in loops.unit_response.qdd (the loaded
// DOFs' rows of Y = M_rr^-1 C_r'), and their dz, dalpha and dnu.
template <class S>
void unit_multiplier_response(const ModelTpl<S>& m, DataTpl<S>& d) {
  LoopData<S>& ld = d.loops;
  load_unit_multipliers(m, d, ld.unit_response);
  loop_response_inward(m, d, ld.unit_response);
  loop_response_outward(m, d, ld.unit_response);
}

// Then, with the multipliers lambda solved: the loop forces C_r' lambda
// entered into the sweeps' quantities of the loaded bodies, so that the
// outward sweep (tree_frame_outward_sweep) gives qdd and tau with them:
// z += dz lambda and nu += dnu lambda on hinges with a gain (Eq. 28), the
// free root's alpha += dalpha lambda (solved in the inward sweep), and in a
// Newton-Euler region, which the outward sweep leaves alone, T += H dz lambda.
template <class S>
void add_loop_forces_to_sweeps(const ModelTpl<S>& m, DataTpl<S>& d) {
  LoopData<S>& ld = d.loops;
  ArticulatedResponse<S>& U = ld.unit_response;
  const VecX<S>& lambda = ld.multipliers;
  for (std::size_t i = 0; i < static_cast<std::size_t>(m.nbodies()); ++i) {
    if (!ld.on_loop_path[i]) continue;
    const int vi = m.v_index[i];
    const HingeModes& h = m.modes[i];
    const auto lambda_i = lambda.segment(U.first_case[i], U.case_count[i]);
    const Vec6<S> dz = U.z_of(i) * lambda_i;
    if (!h.needs_articulated_inertia) {
      d.tau.segment(vi, m.nv_body[i]).noalias() += d.sweep.tree_subspace[i].transpose() * dz;
      continue;
    }
    if (is_regular_free_root<ModePolicy::model_flags>(m, i)) {
      d.sweep.tree_acceleration[i].noalias() += U.alpha_of(i) * lambda_i;
      continue;
    }
    d.sweep.tree_bias_and_children_z[i] += dz;
    if (hinge_has_gain(m, i))  // nu's first n_r entries: a hinge step may leave it longer (the readers take n_r)
      d.sweep.innovation[i].head(h.n_regular).noalias() += U.eps_of(i).middleRows(vi, h.n_regular) * lambda_i;
  }
}

}  // namespace detail
}  // namespace soadyn
