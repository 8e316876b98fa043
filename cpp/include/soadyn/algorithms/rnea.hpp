// Inverse dynamics by the recursive Newton-Euler algorithm (Jain & Rodriguez 1993, Eqs. 1-4).
#pragma once
#include "soadyn/sweeps/body_updates.hpp"

namespace soadyn {

// data.tau = M(q) qdd + h(q, v) - J' f_ext; data.hinge_force holds every
// joint reaction wrench. `f_ext`: nbodies x 6 body-frame wrenches, or null.
// Returns non_finite_result naming the first DOF whose force is not finite.
template <class S>
Status inverse_dynamics(const ModelTpl<S>& model, DataTpl<S>& data, const ConstVecRef<S>& q, const ConstVecRef<S>& v,
                      const ConstVecRef<S>& qdd, const S* f_ext = nullptr);

// data.tau = h(q, v): Coriolis, centrifugal and gravity forces (Status as above).
template <class S>
Status bias_forces(const ModelTpl<S>& model, DataTpl<S>& data, const ConstVecRef<S>& q, const ConstVecRef<S>& v);

}  // namespace soadyn
