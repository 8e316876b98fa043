// ModelTpl::add_joint_spring / add_point_spring and their checks
// (force_elements.hpp). Included by model.hxx.
#pragma once
#include <cmath>
#include "soadyn/model/add_loop.hxx"
#include "soadyn/model/model.hpp"

namespace soadyn {

namespace detail {
[[noreturn]] inline void force_element_fail(const std::string& element, const std::string& what) {
  throw std::invalid_argument("force element '" + element + "': " + what);
}

template <class S>
void check_spring_constant(const std::string& element, const char* what, S value) {
  if (!std::isfinite(static_cast<double>(value)) || value < S(0))
    force_element_fail(element, std::string(what) + " must be finite and non-negative (got " +
                                    std::to_string(static_cast<double>(value)) + ")");
}

template <class S>
void check_new_force_element(const ModelTpl<S>& m, const std::string& element, S stiffness, S damping) {
  if (element.empty()) throw std::invalid_argument("a force element needs a name");
  if (m.force_elements.has_name(element)) force_element_fail(element, "the name is already used");
  check_spring_constant(element, "stiffness", stiffness);
  check_spring_constant(element, "damping", damping);
}

// The body carrying point `point` of `frame` ("" or "world": -1) and the point
// in that body's frame; refuses unknown frames and flexible bodies.
template <class S>
int resolve_force_element_point(const ModelTpl<S>& m, const std::string& element, const std::string& frame,
                                const Vec3<S>& point, const char* which, Vec3<S>& in_body) {
  if (!point.allFinite()) force_element_fail(element, std::string(which) + " point is not finite");
  in_body = point;
  if (frame.empty() || frame == "world") return -1;
  int body = m.body_index(frame);
  if (body < 0) {
    const int f = m.frame_index(frame);
    if (f < 0) force_element_fail(element, std::string(which) + " '" + frame + "' is neither a body nor a frame");
    const Frame<S>& fr = m.frames[static_cast<std::size_t>(f)];
    body = fr.body;
    in_body = fr.placement.apply_point(point);
  }
  for (int j = body; j >= 0; j = m.parent[static_cast<std::size_t>(j)])
    if (m.is_flexible(j))
      force_element_fail(element, std::string(which) + " '" + frame + "' is on flexible body '" +
                                      m.body_names[static_cast<std::size_t>(j)] +
                                      "' or carried by it; point springs on flexible bodies are not supported");
  return body;
}
}  // namespace detail

template <class S>
int ModelTpl<S>::add_joint_spring(const std::string& name, int dof, S stiffness, S damping, S rest) {
  detail::check_new_force_element(*this, name, stiffness, damping);
  if (dof < 0 || dof >= nv) detail::force_element_fail(name, "DOF index " + std::to_string(dof) + " is out of range");
  if (!std::isfinite(static_cast<double>(rest))) detail::force_element_fail(name, "rest is not finite");
  const std::string& dof_name = dof_names[static_cast<std::size_t>(dof)];
  if (is_modal(dof)) detail::force_element_fail(name, "DOF '" + dof_name + "' is modal: its stiffness is the flexible body's");
  const int body = dof_body[static_cast<std::size_t>(dof)];
  if (!joint_has_scalar_coordinates(joints[static_cast<std::size_t>(body)]))
    detail::force_element_fail(name, "DOF '" + dof_name + "' has no scalar coordinate (planar, spherical or free "
                                     "joint); joint springs need one with q' = v");
  JointSpringTpl<S> spring;
  spring.name = name;
  spring.dof = dof;
  spring.coordinate = q_index[static_cast<std::size_t>(body)] + (dof - v_index[static_cast<std::size_t>(body)]);
  spring.stiffness = stiffness;
  spring.damping = damping;
  spring.rest = rest;
  force_elements.joint_springs.push_back(spring);
  ++version;
  return static_cast<int>(force_elements.joint_springs.size()) - 1;
}

template <class S>
int ModelTpl<S>::add_point_spring(const std::string& name, const std::string& frame_a, const std::string& frame_b,
                                  const Vec3<S>& point_a, const Vec3<S>& point_b, S stiffness, S damping,
                                  const S* rest_length, const std::vector<S>& law_lengths,
                                  const std::vector<S>& law_forces) {
  detail::check_new_force_element(*this, name, stiffness, damping);
  PointSpringTpl<S> spring;
  spring.name = name;
  spring.body_a = detail::resolve_force_element_point(*this, name, frame_a, point_a, "frame_a", spring.point_a);
  spring.body_b = detail::resolve_force_element_point(*this, name, frame_b, point_b, "frame_b", spring.point_b);
  if (spring.body_a == spring.body_b)
    detail::force_element_fail(name, "frame_a '" + frame_a + "' and frame_b '" + frame_b +
                                         "' are on the same body: the spring would exert no force");
  spring.stiffness = stiffness;
  spring.damping = damping;
  if (rest_length) {
    if (!std::isfinite(static_cast<double>(*rest_length)) || *rest_length < S(0))
      detail::force_element_fail(name, "rest_length must be finite and non-negative");
    spring.rest_length = *rest_length;
  } else {  // the length at the neutral configuration
    VecX<S> neutral = VecX<S>::Zero(nq);
    for (std::size_t i = 0; i < static_cast<std::size_t>(nbodies()); ++i)
      joint_neutral(joints[i], neutral.data() + q_index[i]);
    const Vec3<S> a = detail::rigid_body_pose_at(*this, spring.body_a, neutral.data()).apply_point(spring.point_a);
    const Vec3<S> b = detail::rigid_body_pose_at(*this, spring.body_b, neutral.data()).apply_point(spring.point_b);
    spring.rest_length = (b - a).norm();
  }
  if (!law_lengths.empty() || !law_forces.empty()) {
    spring.force_law.length = law_lengths;
    spring.force_law.force = law_forces;
    spring.force_law.build(std::string("force element '") + name + "'");
  }
  force_elements.point_springs.push_back(spring);
  ++version;
  return static_cast<int>(force_elements.point_springs.size()) - 1;
}

}  // namespace soadyn
