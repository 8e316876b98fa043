// Operations on configurations: neutral, random, integration on the joint
// manifolds, and the unit-quaternion check.
#pragma once
#include <cstdint>
#include <vector>
#include "soadyn/sweeps/body_updates.hpp"

namespace soadyn {

// Zero coordinates with identity quaternions.
template <class S>
void neutral_configuration(const ModelTpl<S>& model, VecRef<S> q);

// Angles uniform in [-pi, pi], translations uniform in [-1, 1], quaternions
// uniform on the unit sphere, modal coordinates uniform in [-0.1, 0.1];
// deterministic for a given seed.
template <class S>
void random_configuration(const ModelTpl<S>& model, std::uint64_t seed, VecRef<S> q);

// q_out = q (+) v dt, each joint on its manifold (q_out may alias q).
template <class S>
void integrate(const ModelTpl<S>& model, const ConstVecRef<S>& q, const ConstVecRef<S>& v, S dt,
               VecRef<S> q_out);

// The body of the first joint whose quaternion norm differs from 1 by more
// than `tolerance`, or -1.
template <class S>
int first_non_unit_quaternion(const ModelTpl<S>& model, const ConstVecRef<S>& q, S tolerance, S* norm = nullptr);

// The test first_non_unit_quaternion applies to each quaternion: whether the
// four values at `x` have a norm within `tolerance` of 1 (the norm in `norm`).
template <class S>
bool unit_quaternion(const S* x, S tolerance, S* norm = nullptr);

// Where the model's quaternions start in q, in body order: for checking
// many configurations of one model (batched calls).
template <class S>
std::vector<int> quaternion_coordinates(const ModelTpl<S>& model);

}  // namespace soadyn
