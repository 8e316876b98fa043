#pragma once
#include "soadyn/model/data.hpp"

namespace soadyn {

template <class S>
FlexibleBodyData<S>::FlexibleBodyData(int n)
    : mass(MatX<S>::Zero(6 + n, 6 + n)),
      second_moment_rates(MatX<S>::Zero(6, n)),
      bias(VecX<S>::Zero(6 + n)),
      modal_bias(VecX<S>::Zero(n)),
      modal_bias_and_children_z(VecX<S>::Zero(n)),
      modal_force(VecX<S>::Zero(n)),
      coupling(Mat6X<S>::Zero(6, n)),
      deformed_angular_coupling(Eigen::Matrix<S, 3, Eigen::Dynamic>::Zero(3, n)),
      modal_inertia(MatX<S>::Zero(n, n)),
      gain_transpose(MatX<S>::Zero(n, 6)),
      innovation(VecX<S>::Zero(n)) {}

template <class S>
DataTpl<S>::DataTpl(const ModelTpl<S>& model)
    : model_version(model.version), loops(model) {
  const std::size_t n = static_cast<std::size_t>(model.nbodies());
  SweepData<S>& w = sweep;
  pose_in_parent.resize(n);
  pose_in_world.resize(n);
  body_velocity.assign(n, Vec6<S>::Zero());
  body_acceleration.assign(n, Vec6<S>::Zero());
  hinge_force.assign(n, Vec6<S>::Zero());
  w.body_subspace.resize(n);
  w.body_joint_bias.assign(n, Vec6<S>::Zero());
  w.body_coriolis.assign(n, Vec6<S>::Zero());
  w.body_bias_force.assign(n, Vec6<S>::Zero());
  w.body_articulated_inertia.assign(n, Mat6<S>::Zero());
  w.body_bias_and_children_z.assign(n, Vec6<S>::Zero());
  w.body_regular_subspace.resize(n);
  w.body_gain.resize(n);
  w.tree_pose.resize(n);
  w.tree_subspace.resize(n);
  w.tree_velocity.assign(n, Vec6<S>::Zero());
  w.tree_coriolis.assign(n, Vec6<S>::Zero());
  w.tree_bias_force.assign(n, Vec6<S>::Zero());
  w.tree_acceleration.assign(n, Vec6<S>::Zero());
  w.tree_world_acceleration.assign(n, Vec6<S>::Zero());
  w.tree_hinge_force.assign(n, Vec6<S>::Zero());
  w.tree_articulated_inertia.assign(n, Mat6<S>::Zero());
  w.tree_composite_inertia.assign(n, InertiaParameters<S>{Eigen::Matrix<S, 10, 1>::Zero()});
  w.tree_bias_and_children_z.assign(n, Vec6<S>::Zero());
  w.tree_regular_subspace.resize(n);
  w.tree_gain.resize(n);
  w.innovation.resize(n);
  w.hinge_factor.assign(n, Mat6<S>::Identity());
  for (std::size_t i = 0; i < n; ++i) {
    joint_init_subspace(model.joints[i], w.body_subspace[i]);
    const Eigen::Index nv = w.body_subspace[i].cols();
    w.tree_subspace[i].setZero(6, nv);
    w.body_regular_subspace[i].setZero(6, nv);
    w.tree_regular_subspace[i].setZero(6, nv);
    w.body_gain[i].setZero(6, nv);
    w.tree_gain[i].setZero(6, nv);
    w.innovation[i].setZero(nv);
  }
  for (const FlexibleBodyTpl<S>& body : model.flexible_bodies) w.flexible.emplace_back(body.n_modes());
  w.attachment_subspace.resize(n);
  w.attachment_bias.assign(n, Vec6<S>::Zero());
  for (std::size_t i = 0; i < n; ++i)
    if (model.attachment_node[i] >= 0)
      w.attachment_subspace[i].setZero(6, model.n_modes[static_cast<std::size_t>(model.parent[i])]);
  if (model.has_flexible_bodies() || model.derived.reach_checks_needed) w.unit_acceleration.setZero(model.nv);
  w.tree_subspace_columns.setZero(6, model.nv);
  const Eigen::Index angle_slots = (static_cast<Eigen::Index>(model.angle_coordinates.size()) + 3) / 4 * 4;
  w.tree_joint_angle.setZero(angle_slots);
  w.tree_joint_sine.setZero(angle_slots);
  w.tree_joint_cosine.setZero(angle_slots);
  qdd.setZero(model.nv);
  tau.setZero(model.nv);
  mass_matrix.setZero(model.nv, model.nv);
  if (model.has_force_elements()) {
    const Eigen::Index n_point = static_cast<Eigen::Index>(model.force_elements.point_springs.size());
    force_elements.joint_force.setZero(static_cast<Eigen::Index>(model.force_elements.joint_springs.size()));
    force_elements.length.setZero(n_point);
    force_elements.length_rate.setZero(n_point);
    force_elements.tension.setZero(n_point);
    force_elements.body_wrench.setZero(6 * model.nbodies());
    force_elements.input.setZero(model.nv);
  }
}

}  // namespace soadyn
