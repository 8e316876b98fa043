// The hinge's own part of the hybrid algorithm's sweeps (Jain & Rodriguez
// 1993, Eqs. 28, 29, Lemma 8), shared by the body-frame sweeps (aba.hxx) and
// the tree-frame sweeps (tree_frame_sweeps.hxx): `F` names the frames their
// P, z, alpha and H* are expressed in (body_updates.hpp, frame_subspace and the
// like). `AllRegular` treats every DOF as regular whatever the model's flags
// say (forward dynamics). Both updates are inlined into the sweeps, whatever
// the mode: a call per body would make mixed masks dearer than all-regular.
#pragma once
#include "soadyn/sweeps/body_updates.hpp"

namespace soadyn {
namespace detail {

// Whose flags the sweeps follow: the model's (bodies without an articulated
// inertia handled as in RNEA), the model's when every body has one (a regular
// hinge at every root: no Newton-Euler branches compiled in), or none (every
// DOF regular: forward dynamics, the articulated-body algorithm).
enum class ModePolicy { model_flags, model_flags_articulated, all_regular };

template <ModePolicy Modes, class S>
inline bool needs_articulated_inertia(const ModelTpl<S>& m, std::size_t i) {
  if constexpr (Modes != ModePolicy::model_flags) return true;
  return m.modes[i].needs_articulated_inertia;
}

// Whether body i's hinge has no prescribed DOF: its updates then run the
// articulated-body code with the DOF count fixed by the joint (no gather of
// regular columns, no mode branches), as forward dynamics does.
template <ModePolicy Modes, class S>
inline bool regular_hinge(const ModelTpl<S>& m, std::size_t i) {
  return Modes == ModePolicy::all_regular || m.modes[i].n_prescribed == 0;
}

// H*_p qdd_p: the known hinge acceleration of the prescribed DOFs of body i.
template <class S>
inline Vec6<S> prescribed_hinge_acceleration(const ModelTpl<S>& m, const Mat6N<S>& s, std::size_t i, const S* u) {
  const HingeModes& h = m.modes[i];
  const S* ui = u + m.v_index[i];
  if (h.n_regular == 0) return detail::subspace_times(s, ui);
  Vec6<S> a = Vec6<S>::Zero();
  for (int k = 0; k < h.n_prescribed; ++k) a += s.col(h.prescribed[k]) * ui[h.prescribed[k]];
  return a;
}

// Tip-to-base update of a hinge with no regular DOF (Eq. 28, Lemma 8):
// z+ = z = z_children + b + P (H* qdd + a) and P+ = P, passed on by pointer
// (P_out points at body i's articulated inertia). 36 multiplications.
template <Frames F, class S>
SOADYN_ALWAYS_INLINE void prescribed_hinge_inward(const ModelTpl<S>& m, const DataTpl<S>& d, std::size_t i, const S* u,
                                                  Vec6<S>& z_plus, const Mat6<S>*& P_out) {
  P_out = &frame_articulated_inertia<F>(d)[i];
  if (F == Frames::tree && frame_subspace<F>(d)[i].cols() == 0) {  // no DOF: a = 0 in tree frames, so z+ = z
    z_plus = frame_bias_and_children_z<F>(d)[i];
    return;
  }
  const Vec6<S> hinge_acc = frame_coriolis<F>(d)[i] + detail::subspace_times(frame_subspace<F>(d)[i], u + m.v_index[i]);
  z_plus = frame_bias_and_children_z<F>(d)[i];
  z_plus.noalias() += frame_articulated_inertia<F>(d)[i] * hinge_acc;
}

// Base-to-tip update of a hinge with no regular DOF (Eq. 29) once alpha+
// is known: qdd = the given accelerations, alpha = alpha+ + H* qdd + a,
// f = P alpha + z and T = H f. 36 + 6 n multiplications (none for a hinge
// without DOFs unless `want_force`).
template <Frames F, class S>
SOADYN_ALWAYS_INLINE void prescribed_hinge_outward(const ModelTpl<S>& m, DataTpl<S>& d, std::size_t i, const S* u,
                                                   const Vec6<S>& alpha_plus, bool want_force) {
  const Mat6N<S>& s = frame_subspace<F>(d)[i];
  Vec6<S>& alpha = frame_acceleration<F>(d)[i];
  Vec6<S>& f = frame_hinge_force<F>(d)[i];
  const int vi = m.v_index[i];
  const S* given = u + vi;
  alpha = alpha_plus + frame_coriolis<F>(d)[i];
  if (s.cols() > 0)
    alpha += detail::subspace_times(s, given);
  else if (!want_force)
    return;
  f = frame_bias_and_children_z<F>(d)[i];
  f.noalias() += frame_articulated_inertia<F>(d)[i] * alpha;
  for (Eigen::Index k = 0; k < s.cols(); ++k) {
    d.qdd[vi + k] = given[k];
    d.tau[vi + k] = s.col(k).dot(f);
  }
  detail::add_armature_torques(m, i, d.qdd.data(), d.tau.data());
}

// Tip-to-base hinge update of a body with an articulated inertia (Eq. 28):
// z = z_children + b + P (H*_p qdd_p + a); the regular DOFs then give P+ and
// z+ (articulated_hinge_update) in P_plus (as `Mode` says: with
// PlusMode::add or none, P_out is null on return) and z_plus; a hinge with no
// regular DOF passes P on (P_out points at body i's articulated inertia) and
// z in z_plus. Returns the DOF of a singular D, or -1.
template <Frames F, bool AllRegular, detail::PlusMode Mode = detail::PlusMode::store, class S>
SOADYN_ALWAYS_INLINE int hinge_inward(const ModelTpl<S>& m, DataTpl<S>& d, std::size_t i, const S* u,
                                      Mat6<S>& P_plus, Vec6<S>& z_plus, const Mat6<S>*& P_out) {
  const HingeModes& h = m.modes[i];
  const int n_prescribed = AllRegular ? 0 : h.n_prescribed;
  const int n_regular = AllRegular ? m.nv_body[i] : h.n_regular;
  const Mat6N<S>& s = frame_subspace<F>(d)[i];
  const Mat6<S>& P = frame_articulated_inertia<F>(d)[i];
  if (n_regular == 0) {
    prescribed_hinge_inward<F>(m, d, i, u, z_plus, P_out);
    return -1;
  }
  Vec6<S> hinge_acc = frame_coriolis<F>(d)[i];
  if (n_prescribed > 0) hinge_acc += prescribed_hinge_acceleration(m, s, i, u);
  Vec6<S> z = frame_bias_and_children_z<F>(d)[i];
  z.noalias() += P * hinge_acc;
  P_out = Mode == detail::PlusMode::store ? &P_plus : nullptr;  // add: already in the parent; none: not formed
  const S* ui = u + m.v_index[i];
  VecN<S> torque(n_regular);
  const Mat6N<S>* Sr = &s;
  S regular_armature[6];
  if (n_prescribed > 0) {  // mixed hinge: gather the regular columns and torques
    Mat6N<S>& gathered = frame_regular_subspace<F>(d)[i];
    gathered.resize(6, n_regular);
    for (int k = 0; k < n_regular; ++k) {
      gathered.col(k) = s.col(h.regular[k]);
      torque[k] = ui[h.regular[k]];
    }
    Sr = &gathered;
  } else {
    torque = Eigen::Map<const VecN<S>>(ui, n_regular);
  }
  if (h.has_armature)
    for (int k = 0; k < n_regular; ++k)
      regular_armature[k] = m.armature[static_cast<std::size_t>(m.v_index[i] + (n_prescribed > 0 ? h.regular[k] : k))];
  const int bad = detail::articulated_hinge_update<Mode>(P, *Sr, z, torque, h.has_armature ? regular_armature : nullptr,
                                               frame_gain<F>(d)[i], d.sweep.innovation[i], d.sweep.hinge_factor[i],
                                               P_plus, z_plus);
  if (bad < 0) return -1;
  return m.v_index[i] + (n_prescribed > 0 ? h.regular[bad] : bad);
}

// P+ alpha for body i after its hinge update ran with PlusMode::none, without
// forming P+: with P+ = P - G S_r' P (Eq. 28; P symmetric),
// P+ alpha = w - G (S_r' w), w = P alpha.
template <Frames F, bool AllRegular, class S>
SOADYN_ALWAYS_INLINE Vec6<S> articulated_plus_times(const ModelTpl<S>& m, const DataTpl<S>& d, std::size_t i,
                                                    const Vec6<S>& alpha) {
  const HingeModes& h = m.modes[i];
  const Mat6N<S>& s = frame_subspace<F>(d)[i];
  const Mat6N<S>& G = frame_gain<F>(d)[i];
  const int n_regular = AllRegular ? m.nv_body[i] : h.n_regular;
  const bool gathered = !AllRegular && h.n_prescribed > 0;  // mixed hinge: regular columns only
  Vec6<S> w;
  w.noalias() = frame_articulated_inertia<F>(d)[i] * alpha;
  Vec6<S> out = w;
  for (int k = 0; k < n_regular; ++k) out -= G.col(k) * s.col(gathered ? h.regular[k] : k).dot(w);
  return out;
}

// Base-to-tip hinge update (Eq. 29) once alpha+ (the parent's acceleration
// in this body's frame) is known: regular qdd = nu - G* alpha+, prescribed
// qdd copied; alpha = alpha+ + H* qdd + a; f = P alpha + z and the prescribed
// torques T_p = H f. The hinge force f is computed only when a prescribed DOF
// needs it or `want_force` asks for it.
template <Frames F, bool AllRegular, class S>
SOADYN_ALWAYS_INLINE void hinge_outward(const ModelTpl<S>& m, DataTpl<S>& d, std::size_t i, const S* u,
                                        const Vec6<S>& alpha_plus, bool want_force) {
  const HingeModes& h = m.modes[i];
  const int n_prescribed = AllRegular ? 0 : h.n_prescribed;
  if (!AllRegular && h.n_regular == 0) return prescribed_hinge_outward<F>(m, d, i, u, alpha_plus, want_force);
  const Mat6N<S>& s = frame_subspace<F>(d)[i];
  const Mat6N<S>& G = frame_gain<F>(d)[i];
  const VecN<S>& nu = d.sweep.innovation[i];
  Vec6<S>& alpha = frame_acceleration<F>(d)[i];
  const int vi = m.v_index[i], ni = m.nv_body[i];
  S* qdd = d.qdd.data() + vi;
  S* tau = d.tau.data() + vi;
  if (n_prescribed == 0) {  // the articulated-body case: no gather, no scatter
    for (int k = 0; k < ni; ++k) qdd[k] = nu[k] - G.col(k).dot(alpha_plus);
    for (int k = 0; k < ni; ++k) tau[k] = u[vi + k];
  } else {
    for (int k = 0; k < h.n_regular; ++k) {
      qdd[h.regular[k]] = nu[k] - G.col(k).dot(alpha_plus);
      tau[h.regular[k]] = u[vi + h.regular[k]];
    }
    for (int k = 0; k < n_prescribed; ++k) qdd[h.prescribed[k]] = u[vi + h.prescribed[k]];
  }
  alpha = alpha_plus + frame_coriolis<F>(d)[i];
  if (ni > 0) alpha += detail::subspace_times(s, qdd);
  if (n_prescribed > 0 || want_force) {
    Vec6<S>& f = frame_hinge_force<F>(d)[i];
    f = frame_bias_and_children_z<F>(d)[i];
    f.noalias() += frame_articulated_inertia<F>(d)[i] * alpha;
    for (int k = 0; k < n_prescribed; ++k) {
      const int p = h.prescribed[k];
      tau[p] = s.col(p).dot(f);
      if (h.has_armature) tau[p] += m.armature[static_cast<std::size_t>(vi + p)] * qdd[p];
    }
  }
}

}  // namespace detail
}  // namespace soadyn
