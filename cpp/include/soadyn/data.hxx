#pragma once
#include "soadyn/data.hpp"

namespace soadyn {

template <class S>
FlexibleBodyData<S>::FlexibleBodyData(int n)
    : mass(MatX<S>::Zero(6 + n, 6 + n)),
      second_moment_rates(MatX<S>::Zero(3, 3 * n)),
      bias(VecX<S>::Zero(6 + n)),
      modal_bias(VecX<S>::Zero(n)),
      coupling(Mat6X<S>::Zero(6, n)),
      modal_inertia(MatX<S>::Zero(n, n)),
      gain_transpose(MatX<S>::Zero(n, 6)),
      innovation(VecX<S>::Zero(n)) {}

template <class S>
DataTpl<S>::DataTpl(const ModelTpl<S>& model) : model_version(model.version) {
  const std::size_t n = static_cast<std::size_t>(model.nbodies());
  pose_in_parent.resize(n);
  pose_in_world.resize(n);
  subspace.resize(n);
  tree_pose.resize(n);
  tree_subspace.resize(n);
  joint_bias.assign(n, Vec6<S>::Zero());
  velocity.assign(n, Vec6<S>::Zero());
  coriolis.assign(n, Vec6<S>::Zero());
  bias_force.assign(n, Vec6<S>::Zero());
  acceleration.assign(n, Vec6<S>::Zero());
  hinge_force.assign(n, Vec6<S>::Zero());
  articulated_inertia.assign(n, Mat6<S>::Zero());
  articulated_bias.assign(n, Vec6<S>::Zero());
  regular_subspace.resize(n);
  gain.resize(n);
  innovation.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    joint_init_subspace(model.joints[i], subspace[i]);
    const Eigen::Index nv = subspace[i].cols();
    tree_subspace[i].setZero(6, nv);
    regular_subspace[i].setZero(6, nv);
    gain[i].setZero(6, nv);
    innovation[i].setZero(nv);
  }
  for (const FlexibleBodyTpl<S>& body : model.flexible_bodies) flexible.emplace_back(body.n_modes());
  attachment_subspace.resize(n);
  attachment_bias.assign(n, Vec6<S>::Zero());
  for (std::size_t i = 0; i < n; ++i)
    if (model.attachment_node[i] >= 0) attachment_subspace[i].setZero(6, model.n_modes[static_cast<std::size_t>(model.parent[i])]);
  if (model.has_flexible_bodies() || model.reach_checks_needed) unit_acceleration.setZero(model.nv);
  qdd.setZero(model.nv);
  tau.setZero(model.nv);
  mass_matrix.setZero(model.nv, model.nv);
}

}  // namespace soadyn
