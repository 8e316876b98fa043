#pragma once
#include "soadyn/data.hpp"

namespace soadyn {

template <class S>
DataTpl<S>::DataTpl(const ModelTpl<S>& model) : model_version(model.version) {
  const std::size_t n = static_cast<std::size_t>(model.nbodies());
  pose_in_parent.resize(n);
  pose_in_world.resize(n);
  subspace.resize(n);
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
    regular_subspace[i].setZero(6, nv);
    gain[i].setZero(6, nv);
    innovation[i].setZero(nv);
  }
  qdd.setZero(model.nv);
  tau.setZero(model.nv);
  mass_matrix.setZero(model.nv, model.nv);
}

}  // namespace soadyn
