// Kinetic and potential energy, spatial momentum and centre of mass.
#pragma once
#include "soadyn/algorithms/kinematics.hpp"

namespace soadyn {

// 1/2 sum V' M V.
template <class S>
S kinetic_energy(const ModelTpl<S>& model, DataTpl<S>& data, const ConstVecRef<S>& q, const ConstVecRef<S>& v);

// -sum m g . c (zero at the world origin), plus the flexible bodies' strain
// energy and the force elements' potential (force_elements.hpp).
template <class S>
S potential_energy(const ModelTpl<S>& model, DataTpl<S>& data, const ConstVecRef<S>& q);

// kinetic_energy and potential_energy at one state, the same values bit for
// bit, from one kinematic sweep (the divergence guard's energy at each step).
template <class S>
void mechanical_energy(const ModelTpl<S>& model, DataTpl<S>& data, const ConstVecRef<S>& q, const ConstVecRef<S>& v,
                       S& kinetic, S& potential);

// Spatial momentum [angular about the world origin; linear], world frame.
template <class S>
Vec6<S> momentum(const ModelTpl<S>& model, DataTpl<S>& data, const ConstVecRef<S>& q, const ConstVecRef<S>& v);

// Total mass and centre of mass in the world frame.
template <class S>
Vec3<S> center_of_mass(const ModelTpl<S>& model, DataTpl<S>& data, const ConstVecRef<S>& q, S* total_mass = nullptr);

}  // namespace soadyn
