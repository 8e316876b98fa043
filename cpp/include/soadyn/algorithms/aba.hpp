// Forward dynamics by the articulated-body algorithm: Jain & Rodriguez's algorithm
// with every hinge regular, whatever the model's flags say.
#pragma once
#include "soadyn/sweeps/body_updates.hpp"

namespace soadyn {

// data.qdd = M^-1 (tau - h + J' f_ext). Returns the DOF whose articulated
// inertia D is singular, or a non-finite result, as a Status; never throws.
template <class S>
Status forward_dynamics(const ModelTpl<S>& model, DataTpl<S>& data, const ConstVecRef<S>& q, const ConstVecRef<S>& v,
                        const ConstVecRef<S>& tau, const S* f_ext = nullptr);

}  // namespace soadyn
