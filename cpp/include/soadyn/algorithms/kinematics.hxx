#pragma once
#include "soadyn/sweeps/flexible_updates.hpp"
#include "soadyn/algorithms/kinematics.hpp"

namespace soadyn {

template <class S>
void update_world_poses(const ModelTpl<S>& m, DataTpl<S>& d) {
  for (std::size_t i = 0; i < static_cast<std::size_t>(m.nbodies()); ++i) {
    const int p = m.parent[i];
    d.pose_in_world[i] = p >= 0 ? d.pose_in_world[static_cast<std::size_t>(p)] * d.pose_in_parent[i] : d.pose_in_parent[i];
  }
}

namespace detail {
template <bool Flex, class S>
void kinematic_sweep(const ModelTpl<S>& m, DataTpl<S>& d, const S* q, const S* v) {
  for (std::size_t i = 0; i < static_cast<std::size_t>(m.nbodies()); ++i) {
    body_joint_update<Flex>(m, d, i, q, v);
    if (v) body_velocity_update<Flex>(m, d, i, v);
  }
}
}  // namespace detail

template <class S>
void forward_kinematics(const ModelTpl<S>& m, DataTpl<S>& d, const S* q, const S* v) {
  if (m.has_flexible_bodies())
    detail::kinematic_sweep<true>(m, d, q, v);
  else
    detail::kinematic_sweep<false>(m, d, q, v);
  update_world_poses(m, d);
}

}  // namespace soadyn
