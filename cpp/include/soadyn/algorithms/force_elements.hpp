// Force elements in the dynamics (model/force_element.hpp): their
// forces, potential energy and dissipated power. Every dynamics entry point
// (inverse_dynamics, bias_forces, forward_dynamics, hybrid_dynamics,
// constrained_dynamics, loop_joint_wrenches, and through them the Simulator)
// evaluates them first: joint springs join the regular DOFs' torques, point
// springs the external wrenches, and the tree's sweeps run unchanged. The
// generalized forces these calls return are the actuators' (the springs'
// share removed): inverse dynamics gives M qdd + h - J' f_ext - Q, bias_forces
// h - Q, Q the force elements' generalized force. The equation terms
// (equation_terms.hpp: gravity_forces, coriolis_matrix, ...) are the tree's
// rigid terms and do not include them. A model without force elements pays
// one test per call.
#pragma once
#include "soadyn/sweeps/body_updates.hpp"

namespace soadyn {

// 1/2 sum k (q - rest)^2 over the joint springs plus each point spring's
// potential (force_elements.hpp). Uses data's kinematics scratch.
template <class S>
S force_element_potential(const ModelTpl<S>& model, DataTpl<S>& data, const ConstVecRef<S>& q);

// Power dissipated by the dampers at (q, v), >= 0: sum c v^2 + sum c L'^2.
template <class S>
S force_element_dissipation(const ModelTpl<S>& model, DataTpl<S>& data, const ConstVecRef<S>& q,
                            const ConstVecRef<S>& v);

// The force element (joint springs first, then point springs: the order of
// soadyn.force_elements) whose potential at q (v null) or dissipated power at
// (q, v) is not finite or, if every one is, the largest: the one to name when
// their sum overflows. -1 without force elements.
template <class S>
int force_element_at_fault(const ModelTpl<S>& model, DataTpl<S>& data, const ConstVecRef<S>& q, const S* v);

// Fills data.force_elements at (q, v) (v null: at rest): each joint spring's
// generalized force, each point spring's length, rate and tension, and
// body_wrench = f_ext (null: zero) plus the point springs' wrenches on their
// bodies, body frame about the body origin. Allocation free.
template <class S>
void evaluate_force_elements(const ModelTpl<S>& model, DataTpl<S>& data, const S* q, const S* v, const S* f_ext);

}  // namespace soadyn
