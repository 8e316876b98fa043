// Forward kinematics: body poses in the world and body velocities.
#pragma once
#include "soadyn/sweeps/body_updates.hpp"

namespace soadyn {

// Fills pose_in_parent, pose_in_world and subspace; with `v` also velocity
// and coriolis. `v` may be null.
template <class S>
void forward_kinematics(const ModelTpl<S>& model, DataTpl<S>& data, const S* q, const S* v);

// pose_in_world of every body from pose_in_parent (after any sweep).
template <class S>
void update_world_poses(const ModelTpl<S>& model, DataTpl<S>& data);

}  // namespace soadyn
