// ModelTpl::cast (model.hpp): the same model in another scalar type;
// cast_into: several models of one structure as one model of packets, lane
// l holding model l's values; and cast_values_into: the values alone, taken
// again into such a cast without allocating. Every field is copied, numeric ones
// converted; nothing is recomputed but the constant tree-frame terms
// (refresh_constant_tree_inertia, from the converted values), so the cast
// model runs exactly the sweeps the original runs (same dynamics path,
// joint fast paths, prescribed flags and tree-frame reach).
#pragma once
#include <array>
#include <functional>
#include <type_traits>
#include "soadyn/model/model.hpp"

namespace soadyn {

namespace cast_detail {

template <class X>
struct is_std_vector : std::false_type {};
template <class X, class A>
struct is_std_vector<std::vector<X, A>> : std::true_type {};

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
Transform<T> transform(const Transform<S>& X) {
  Transform<T> out;
  out.rotation = X.rotation.template cast<T>();
  out.translation = X.translation.template cast<T>();
  return out;
}

// The field `member` of get(model): a getter for Sources.
template <class Get, class Member>
auto then(Get get, Member member) {
  return [get, member](const auto& model) -> const auto& { return std::invoke(member, std::invoke(get, model)); };
}

// The models a cast reads: one, whose values fill every lane of T, or one
// per lane of a packet T (T::lanes of them), lane l taking model l's values.
template <class S, std::size_t N>
class Sources {
 public:
  using Model = ModelTpl<S>;
  explicit Sources(const std::array<const Model*, N>& models) : models_(models) {}

  const Model& first() const { return *models_[0]; }

  // out = get(model) converted, lane l of each value from model l: a scalar,
  // an Eigen matrix, a Transform or a std::vector of them. `get` is a
  // member pointer or a function of the model.
  template <class Get, class Out>
  void values(Get&& get, Out& out) const {
    using In = std::decay_t<std::invoke_result_t<Get, const Model&>>;
    if constexpr (is_std_vector<In>::value) {
      const std::size_t n = std::invoke(get, first()).size();
      out.resize(n);
      for (std::size_t j = 0; j < n; ++j) values([&](const Model& m) -> const auto& { return std::invoke(get, m)[j]; }, out[j]);
    } else if constexpr (std::is_same_v<In, Transform<S>>) {
      values([&](const Model& m) -> const auto& { return std::invoke(get, m).rotation; }, out.rotation);
      values([&](const Model& m) -> const auto& { return std::invoke(get, m).translation; }, out.translation);
    } else if constexpr (std::is_arithmetic_v<In>) {
      out = Out(std::invoke(get, first()));
      if constexpr (N > 1)
        for (std::size_t l = 1; l < N; ++l) out[static_cast<int>(l)] = std::invoke(get, *models_[l]);
    } else {  // an Eigen matrix
      const In& x = std::invoke(get, first());
      out = x.template cast<typename Out::Scalar>();
      if constexpr (N > 1)
        for (std::size_t l = 1; l < N; ++l)
          for (Eigen::Index c = 0; c < x.cols(); ++c)
            for (Eigen::Index r = 0; r < x.rows(); ++r) out(r, c)[static_cast<int>(l)] = std::invoke(get, *models_[l])(r, c);
    }
  }

  // out = get(first()), a field that is not numeric; records whether every
  // model has the same (agree()).
  template <class Get, class Out>
  void same(Get&& get, Out& out) const {
    out = std::invoke(get, first());
    for (std::size_t l = 1; l < N; ++l)
      if (!(std::invoke(get, *models_[l]) == out)) agree_ = false;
  }

  bool agree() const { return agree_; }

 private:
  std::array<const Model*, N> models_;
  mutable bool agree_ = true;
};

}  // namespace cast_detail

template <class S>
template <class T, std::size_t N>
bool ModelTpl<S>::cast_into(const std::array<const ModelTpl<S>*, N>& models, ModelTpl<T>& out) {
  namespace c = cast_detail;
  using M = ModelTpl<S>;
  const c::Sources<S, N> in(models);
  const M& first = in.first();
  // Names, joints, flexible bodies, frames and loops are the first model's:
  // no parameter (parameters.hpp) changes them.
  out.body_names = first.body_names;
  out.joint_names = first.joint_names;
  for (const auto& j : first.joints) out.joints.push_back(c::joint<T>(j));
  for (const FlexibleBodyTpl<S>& body : first.flexible_bodies) out.flexible_bodies.push_back(body.template converted<T>());
  for (const auto& f : first.frames) out.frames.push_back(Frame<T>{f.name, f.body, c::transform<T>(f.placement), f.node});
  for (const auto& l : first.loops) {
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
  out.dof_names = first.dof_names;
  out.coordinate_names = first.coordinate_names;
  out.dof_body = first.dof_body;
  out.body_lookup_ = first.body_lookup_;
  out.dof_lookup_ = first.dof_lookup_;
  out.frame_lookup_ = first.frame_lookup_;
  // The force elements' places (their values: cast_values_into).
  for (const auto& e : first.force_elements.joint_springs)
    out.force_elements.joint_springs.push_back(JointSpringTpl<T>{e.name, e.dof, e.coordinate, T(), T(), T()});
  using PointSpring = PointSpringTpl<S>;
  for (std::size_t k = 0; k < first.force_elements.point_springs.size(); ++k) {
    const auto spring = [k](const M& m) -> const PointSpring& { return m.force_elements.point_springs[k]; };
    PointSpringTpl<T> o;
    o.name = spring(first).name;
    in.same(c::then(spring, &PointSpring::body_a), o.body_a);
    in.same(c::then(spring, &PointSpring::body_b), o.body_b);
    out.force_elements.point_springs.push_back(o);
  }
  const bool values_agree = cast_values_into<T, N>(models, out);
  return in.agree() && values_agree;
}

template <class S>
template <class T, std::size_t N>
bool ModelTpl<S>::cast_values_into(const std::array<const ModelTpl<S>*, N>& models, ModelTpl<T>& out) {
  namespace c = cast_detail;
  using M = ModelTpl<S>;
  const c::Sources<S, N> in(models);
  const M& first = in.first();
  // The values, lane by lane.
  in.values(&M::placement, out.placement);
  in.values(&M::inertia, out.inertia);
  in.values(&M::mass, out.mass);
  in.values(&M::com, out.com);
  in.values(&M::inertia_com, out.inertia_com);
  in.values(&M::axis_sign, out.axis_sign);
  in.values(&M::angle_signs, out.angle_signs);
  in.values(&M::armature, out.armature);
  in.values(&M::effort_limit, out.effort_limit);
  using Derived = DerivedCachesTpl<S>;
  in.values(c::then(&M::derived, &Derived::tree_frame_reach_squared), out.derived.tree_frame_reach_squared);
  in.values(&M::gravity, out.gravity);
  using JointSpring = JointSpringTpl<S>;
  using PointSpring = PointSpringTpl<S>;
  using ForceLaw = ForceLawTpl<S>;
  for (std::size_t k = 0; k < first.force_elements.joint_springs.size(); ++k) {
    const auto spring = [k](const M& m) -> const JointSpring& { return m.force_elements.joint_springs[k]; };
    JointSpringTpl<T>& o = out.force_elements.joint_springs[k];
    in.values(c::then(spring, &JointSpring::stiffness), o.stiffness);
    in.values(c::then(spring, &JointSpring::damping), o.damping);
    in.values(c::then(spring, &JointSpring::rest), o.rest);
  }
  for (std::size_t k = 0; k < first.force_elements.point_springs.size(); ++k) {
    const auto spring = [k](const M& m) -> const PointSpring& { return m.force_elements.point_springs[k]; };
    const auto law = c::then(spring, &PointSpring::force_law);
    PointSpringTpl<T>& o = out.force_elements.point_springs[k];
    in.values(c::then(spring, &PointSpring::point_a), o.point_a);
    in.values(c::then(spring, &PointSpring::point_b), o.point_b);
    in.values(c::then(spring, &PointSpring::stiffness), o.stiffness);
    in.values(c::then(spring, &PointSpring::damping), o.damping);
    in.values(c::then(spring, &PointSpring::rest_length), o.rest_length);
    in.values(c::then(law, &ForceLaw::length), o.force_law.length);
    in.values(c::then(law, &ForceLaw::force), o.force_law.force);
    in.values(c::then(law, &ForceLaw::slope), o.force_law.slope);
    in.values(c::then(law, &ForceLaw::integral_to_knot), o.force_law.integral_to_knot);
  }
  // The structure and the flags, which must be the same in every model (the
  // hinge modes follow from the prescribed flags).
  out.modes = first.modes;
  in.same(&M::parent, out.parent);
  in.same(&M::joint_fast_path, out.joint_fast_path);
  in.same(&M::angle_slot, out.angle_slot);
  in.same(&M::angle_coordinates, out.angle_coordinates);
  in.same(&M::q_index, out.q_index);
  in.same(&M::v_index, out.v_index);
  in.same(&M::nq_body, out.nq_body);
  in.same(&M::nv_body, out.nv_body);
  in.same(&M::flexible_index, out.flexible_index);
  in.same(&M::n_modes, out.n_modes);
  in.same(&M::attachment_node, out.attachment_node);
  in.same(&M::nq, out.nq);
  in.same(&M::nv, out.nv);
  in.same(&M::dof_parent, out.dof_parent);
  in.same(&M::dof_run_start, out.dof_run_start);
  in.same(&M::prescribed, out.prescribed);
  in.same(&M::modal_dof, out.modal_dof);
  in.same(&M::has_armature, out.has_armature);
  in.same(&M::n_prescribed, out.n_prescribed);
  in.same(&M::prescribed_dofs, out.prescribed_dofs);
  in.same(&M::has_newton_euler_region, out.has_newton_euler_region);
  in.same(c::then(&M::derived, &Derived::check_tree_frame_reach), out.derived.check_tree_frame_reach);
  in.same(c::then(&M::derived, &Derived::reach_checks_needed), out.derived.reach_checks_needed);
  in.same(&M::dynamics_path, out.dynamics_path);
  in.same(&M::tree_factor_work, out.tree_factor_work);
  in.same(&M::nloop_equations, out.nloop_equations);
  in.same(&M::version, out.version);
  out.refresh_constant_tree_inertia();  // from the converted inertias (none cached for a non-floating-point T)
  return in.agree();
}

template <class S>
template <class T>
ModelTpl<T> ModelTpl<S>::cast() const {
  ModelTpl<T> out;
  cast_into<T, 1>({this}, out);
  return out;
}

}  // namespace soadyn
