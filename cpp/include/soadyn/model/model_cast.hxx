// ModelTpl::cast (model.hpp): the same model in another scalar type. Every
// field is copied, numeric ones converted; nothing is recomputed, so the cast
// model runs exactly the sweeps the original runs (same dynamics path, joint
// fast paths, prescribed flags and tree-frame reach).
#pragma once
#include <type_traits>
#include "soadyn/model/model.hpp"

namespace soadyn {

namespace cast_detail {

template <class T, class S>
T scalar(const S& x) {
  return T(x);
}

template <class T, class Derived>
auto matrix(const Eigen::MatrixBase<Derived>& x) {
  return x.template cast<T>().eval();
}

template <class T, class S>
Transform<T> transform(const Transform<S>& X) {
  Transform<T> out;
  out.rotation = X.rotation.template cast<T>();
  out.translation = X.translation.template cast<T>();
  return out;
}

template <class J, class T>
struct rebind;
template <template <class> class J, class S, class T>
struct rebind<J<S>, T> {
  using type = J<T>;
};

template <class T, class V>
T member(const V& x) {
  if constexpr (std::is_arithmetic_v<V>)
    return T(x);
  else
    return x.template cast<typename T::Scalar>();
}

// A joint is an aggregate of its Parameters, in member order (joint_base.hpp).
template <class T, class S>
JointModel<T> joint(const JointModel<S>& j) {
  return std::visit(
      [](const auto& alternative) -> JointModel<T> {
        using In = std::decay_t<decltype(alternative)>;
        using Out = typename rebind<In, T>::type;
        using Parameters = typename Out::Parameters;
        constexpr std::size_t n = std::tuple_size_v<Parameters>;
        static_assert(n <= 2, "joint_cast: a joint with more than two parameters");
        if constexpr (n == 0) {
          return Out{};
        } else if constexpr (n == 1) {
          const auto& [a] = alternative;
          return Out{member<std::tuple_element_t<0, Parameters>>(a)};
        } else {
          const auto& [a, b] = alternative;
          return Out{member<std::tuple_element_t<0, Parameters>>(a), member<std::tuple_element_t<1, Parameters>>(b)};
        }
      },
      j);
}

template <class T, class S>
std::vector<T> scalars(const std::vector<S>& x) {
  return std::vector<T>(x.begin(), x.end());
}

}  // namespace cast_detail

template <class S>
template <class T>
ModelTpl<T> ModelTpl<S>::cast() const {
  namespace c = cast_detail;
  ModelTpl<T> out;
  out.body_names = body_names;
  out.joint_names = joint_names;
  out.parent = parent;
  for (const auto& j : joints) out.joints.push_back(c::joint<T>(j));
  for (const auto& X : placement) out.placement.push_back(c::transform<T>(X));
  for (const auto& M : inertia) out.inertia.push_back(M.template cast<T>());
  out.mass = c::scalars<T>(mass);
  for (const auto& x : com) out.com.push_back(x.template cast<T>());
  for (const auto& x : inertia_com) out.inertia_com.push_back(x.template cast<T>());
  out.joint_fast_path = joint_fast_path;
  out.axis_sign = c::scalars<T>(axis_sign);
  out.angle_slot = angle_slot;
  out.angle_coordinates = angle_coordinates;
  out.angle_signs = c::scalars<T>(angle_signs);
  out.q_index = q_index;
  out.v_index = v_index;
  out.nq_body = nq_body;
  out.nv_body = nv_body;
  out.modes = modes;
  out.flexible_index = flexible_index;
  for (const FlexibleBodyTpl<S>& body : flexible_bodies) out.flexible_bodies.push_back(body.template converted<T>());
  out.n_modes = n_modes;
  out.attachment_node = attachment_node;
  out.nq = nq;
  out.nv = nv;
  out.dof_names = dof_names;
  out.coordinate_names = coordinate_names;
  out.dof_body = dof_body;
  out.dof_parent = dof_parent;
  out.dof_run_start = dof_run_start;
  out.prescribed = prescribed;
  out.modal_dof = modal_dof;
  out.armature = c::scalars<T>(armature);
  out.has_armature = has_armature;
  out.effort_limit = c::scalars<T>(effort_limit);
  out.n_prescribed = n_prescribed;
  out.prescribed_dofs = prescribed_dofs;
  out.has_newton_euler_region = has_newton_euler_region;
  out.derived.tree_frame_reach_squared = c::scalars<T>(derived.tree_frame_reach_squared);
  out.derived.check_tree_frame_reach = derived.check_tree_frame_reach;
  out.derived.reach_checks_needed = derived.reach_checks_needed;
  out.refresh_constant_tree_inertia();  // from the converted inertias (none cached for a non-floating-point T)
  out.dynamics_path = dynamics_path;
  out.tree_factor_work = tree_factor_work;
  for (const auto& f : frames) out.frames.push_back(Frame<T>{f.name, f.body, c::transform<T>(f.placement), f.node});
  for (const auto& l : loops) {
    LoopTpl<T> o;
    o.name = l.name;
    o.kind = l.kind;
    o.body_a = l.body_a;
    o.body_b = l.body_b;
    o.placement_a = c::transform<T>(l.placement_a);
    o.placement_b = c::transform<T>(l.placement_b);
    o.length = T(l.length);
    o.first_row = l.first_row;
    out.loops.push_back(o);
  }
  out.nloop_equations = nloop_equations;
  for (const auto& e : force_elements.joint_springs)
    out.force_elements.joint_springs.push_back(
        JointSpringTpl<T>{e.name, e.dof, e.coordinate, T(e.stiffness), T(e.damping), T(e.rest)});
  for (const auto& e : force_elements.point_springs) {
    PointSpringTpl<T> o;
    o.name = e.name;
    o.body_a = e.body_a;
    o.body_b = e.body_b;
    o.point_a = e.point_a.template cast<T>();
    o.point_b = e.point_b.template cast<T>();
    o.stiffness = T(e.stiffness);
    o.damping = T(e.damping);
    o.rest_length = T(e.rest_length);
    o.force_law.length = c::scalars<T>(e.force_law.length);
    o.force_law.force = c::scalars<T>(e.force_law.force);
    o.force_law.slope = c::scalars<T>(e.force_law.slope);
    o.force_law.integral_to_knot = c::scalars<T>(e.force_law.integral_to_knot);
    out.force_elements.point_springs.push_back(o);
  }
  out.gravity = gravity.template cast<T>();
  out.version = version;
  out.body_lookup_ = body_lookup_;
  out.dof_lookup_ = dof_lookup_;
  out.frame_lookup_ = frame_lookup_;
  return out;
}

}  // namespace soadyn
