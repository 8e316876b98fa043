// Hybrid dynamics of a tree whose DOFs are each regular (torque given,
// acceleration unknown) or prescribed (acceleration given, torque unknown):
// the O(N) algorithm of Jain & Rodriguez 1993 (Eqs. 14, 28, 29, Lemma 8), on trees, with
// multi-DOF hinges whose DOFs may mix modes (ibid., conclusion 5).
//
// Bodies on whose root path every hinge is prescribed need no articulated
// inertia: their accelerations are known in the first sweep and their hinge
// forces come from the Newton-Euler inward sweep, as in inverse dynamics.
// With every flag prescribed the algorithm is RNEA; with every flag regular
// it is the articulated-body algorithm: a tree with no prescribed DOF runs the
// very sweeps of forward_dynamics (aba.hpp), so it never costs more; a tree
// with every DOF prescribed runs inverse dynamics (rnea.hpp). Rigid models and
// models whose flexible bodies carry nothing on a node run in tree frames
// (tree_frame_sweeps.hxx), the others in body frames (body_frame_sweeps.hxx);
// dynamics_path.hxx chooses.
#pragma once
#include "soadyn/sweeps/body_updates.hpp"

namespace soadyn {

// `u` holds, per DOF, the torque of a regular DOF or the acceleration of a
// prescribed one (model.prescribed). On return data.qdd and data.tau hold
// every DOF's acceleration and generalized force (given entries copied
// through). Allocation free; never throws.
template <class S>
Status hybrid_dynamics(const ModelTpl<S>& model, DataTpl<S>& data, const ConstVecRef<S>& q, const ConstVecRef<S>& v,
                       const ConstVecRef<S>& u, const S* f_ext = nullptr, DynamicsOutputs outputs = {});

// The same algorithm in impulse form, for impacts (locking a moving hinge):
// velocities and gravity drop out, `u` holds the generalized impulse of each
// regular DOF and the velocity jump of each prescribed one; on return
// data.qdd holds every velocity jump and data.tau every generalized impulse.
template <class S>
Status hybrid_impulse(const ModelTpl<S>& model, DataTpl<S>& data, const ConstVecRef<S>& q, const ConstVecRef<S>& u);

}  // namespace soadyn
