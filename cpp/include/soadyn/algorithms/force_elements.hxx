#pragma once
#include "soadyn/algorithms/force_elements.hpp"
#include "soadyn/algorithms/kinematics.hxx"

#include <cmath>
#include <limits>

namespace soadyn {

namespace detail {

// Point A or B of a point spring in the world, and its velocity there (after
// forward_kinematics; v null: zero).
template <class S>
void spring_end_in_world(const DataTpl<S>& d, int body, const Vec3<S>& point, bool with_velocity, Vec3<S>& position,
                         Vec3<S>& velocity) {
  velocity.setZero();
  if (body < 0) {
    position = point;
    return;
  }
  const Transform<S>& X = d.pose_in_world[static_cast<std::size_t>(body)];
  position = X.apply_point(point);
  if (with_velocity) {
    const Vec6<S>& V = d.body_velocity[static_cast<std::size_t>(body)];
    velocity = X.rotation * (V.template tail<3>() + V.template head<3>().cross(point));
  }
}

// Adds world force `f` at `point` of `body` to its body-frame wrench.
template <class S>
void add_point_force(const DataTpl<S>& d, S* wrenches, int body, const Vec3<S>& point, const Vec3<S>& f) {
  if (body < 0) return;
  const Vec3<S> f_body = d.pose_in_world[static_cast<std::size_t>(body)].rotation.transpose() * f;
  Eigen::Map<Vec6<S>> w(wrenches + 6 * body);
  w.template head<3>() += point.cross(f_body);
  w.template tail<3>() += f_body;
}

// Potential of point spring `s` at length L.
template <class S>
S point_spring_potential(const PointSpringTpl<S>& s, S L) {
  const S stretch = L - s.rest_length;
  S energy = S(0.5) * s.stiffness * stretch * stretch;
  if (!s.force_law.empty()) {
    S integral;
    s.force_law.value(L, nullptr, &integral);
    energy += integral;
  }
  return energy;
}

// Tension of point spring `s` at length L and rate L'.
template <class S>
S point_spring_tension(const PointSpringTpl<S>& s, S L, S rate) {
  S T = s.stiffness * (L - s.rest_length) + s.damping * rate;
  if (!s.force_law.empty()) T += s.force_law.value(L);
  return T;
}

// Lengths and length rates of the point springs into d.force_elements
// (forward kinematics first); the unit vectors B - A are not kept.
template <class S>
void point_spring_geometry(const ModelTpl<S>& m, DataTpl<S>& d, const S* q, const S* v) {
  forward_kinematics<S>(m, d, q, v);
  ForceElementDataTpl<S>& fd = d.force_elements;
  for (std::size_t k = 0; k < m.force_elements.point_springs.size(); ++k) {
    const PointSpringTpl<S>& s = m.force_elements.point_springs[k];
    Vec3<S> a, b, va, vb;
    spring_end_in_world(d, s.body_a, s.point_a, v != nullptr, a, va);
    spring_end_in_world(d, s.body_b, s.point_b, v != nullptr, b, vb);
    const Vec3<S> ab = b - a;
    const S L = ab.norm();
    const Eigen::Index ks = static_cast<Eigen::Index>(k);
    fd.length[ks] = L;
    fd.length_rate[ks] = L > S(0) ? ab.dot(vb - va) / L : S(0);
  }
}

// Which rows of a dynamics call's input u are generalized forces that the
// joint springs join: none (inverse dynamics), every row (forward dynamics),
// or the regular rows (hybrid and constrained dynamics; prescribed rows are
// accelerations).
enum class SpringInputRows { none, all, regular };

}  // namespace detail

template <class S>
void evaluate_force_elements(const ModelTpl<S>& m, DataTpl<S>& d, const S* q, const S* v, const S* f_ext);

namespace detail {

// Runs `rigid(u, f_ext)`, a dynamics call on the tree without force elements,
// with the force elements folded into its inputs: the joint springs' Q added
// to u's force rows, the point springs' wrenches to f_ext. Afterwards the
// generalized forces in data.tau are the actuators': the given u on its force
// rows, the sweeps' result minus Q elsewhere.
template <class S, class RigidCall>
Status with_force_elements(const ModelTpl<S>& m, DataTpl<S>& d, const S* q, const S* v, const S* u,
                           const S* f_ext, SpringInputRows rows, RigidCall&& rigid) {
  evaluate_force_elements(m, d, q, v, f_ext);
  ForceElementDataTpl<S>& fd = d.force_elements;
  const auto given_force = [&](int dof) {
    return rows == SpringInputRows::all || (rows == SpringInputRows::regular && !m.is_prescribed(dof));
  };
  if (rows != SpringInputRows::none) {
    fd.input = Eigen::Map<const VecX<S>>(u, m.nv);
    for (std::size_t k = 0; k < m.force_elements.joint_springs.size(); ++k) {
      const int dof = m.force_elements.joint_springs[k].dof;
      if (given_force(dof)) fd.input[dof] += fd.joint_force[static_cast<Eigen::Index>(k)];
    }
  }
  const Status status = rigid(rows == SpringInputRows::none ? u : fd.input.data(), fd.body_wrench.data());
  if (rows == SpringInputRows::all) return status;  // forward dynamics returns no generalized force
  for (std::size_t k = 0; k < m.force_elements.joint_springs.size(); ++k) {
    const int dof = m.force_elements.joint_springs[k].dof;
    if (given_force(dof))
      d.tau[dof] = u[dof];
    else
      d.tau[dof] -= fd.joint_force[static_cast<Eigen::Index>(k)];
  }
  return status;
}

}  // namespace detail

template <class S>
void evaluate_force_elements(const ModelTpl<S>& m, DataTpl<S>& d, const S* q, const S* v, const S* f_ext) {
  ForceElementDataTpl<S>& fd = d.force_elements;
  const ForceElementsTpl<S>& fe = m.force_elements;
  for (std::size_t k = 0; k < fe.joint_springs.size(); ++k) {
    const JointSpringTpl<S>& s = fe.joint_springs[k];
    S Q = -s.stiffness * (q[s.coordinate] - s.rest);
    if (v) Q -= s.damping * v[s.dof];
    fd.joint_force[static_cast<Eigen::Index>(k)] = Q;
  }
  if (f_ext)
    fd.body_wrench = Eigen::Map<const VecX<S>>(f_ext, 6 * m.nbodies());
  else
    fd.body_wrench.setZero();
  if (fe.point_springs.empty()) return;
  detail::point_spring_geometry(m, d, q, v);
  for (std::size_t k = 0; k < fe.point_springs.size(); ++k) {
    const PointSpringTpl<S>& s = fe.point_springs[k];
    const Eigen::Index ks = static_cast<Eigen::Index>(k);
    const S L = fd.length[ks];
    const S T = detail::point_spring_tension(s, L, fd.length_rate[ks]);
    fd.tension[ks] = T;
    if (!(L > S(0))) continue;  // coincident points: no line of action
    Vec3<S> a, b, unused;
    detail::spring_end_in_world(d, s.body_a, s.point_a, false, a, unused);
    detail::spring_end_in_world(d, s.body_b, s.point_b, false, b, unused);
    const Vec3<S> pull_on_a = (T / L) * (b - a);  // A towards B by T, B towards A by T
    detail::add_point_force(d, fd.body_wrench.data(), s.body_a, s.point_a, pull_on_a);
    detail::add_point_force(d, fd.body_wrench.data(), s.body_b, s.point_b, Vec3<S>(-pull_on_a));
  }
}

namespace detail {

// Calls share(k, value) with each force element's potential at q (v null) or
// the power its damper dissipates at (q, v), k counting the joint springs
// first, then the point springs.
template <class S, class Share>
void visit_force_element_shares(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& q, const S* v,
                                Share&& share) {
  int k = 0;
  for (const JointSpringTpl<S>& s : m.force_elements.joint_springs) {
    const S stretch = q[s.coordinate] - s.rest;
    share(k++, v ? s.damping * v[s.dof] * v[s.dof] : S(0.5) * s.stiffness * stretch * stretch);
  }
  if (m.force_elements.point_springs.empty()) return;
  point_spring_geometry(m, d, q.data(), v);
  for (std::size_t p = 0; p < m.force_elements.point_springs.size(); ++p) {
    const auto& spring = m.force_elements.point_springs[p];
    const Eigen::Index e = static_cast<Eigen::Index>(p);
    const S rate = v ? d.force_elements.length_rate[e] : S(0);
    share(k++, v ? spring.damping * rate * rate : point_spring_potential(spring, d.force_elements.length[e]));
  }
}

template <class S>
S sum_of_force_element_shares(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& q, const S* v) {
  S total(0);
  visit_force_element_shares(m, d, q, v, [&](int, S value) { total += value; });
  return total;
}

}  // namespace detail

template <class S>
S force_element_potential(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& q) {
  return detail::sum_of_force_element_shares<S>(m, d, q, nullptr);
}

template <class S>
S force_element_dissipation(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& q, const ConstVecRef<S>& v) {
  return detail::sum_of_force_element_shares<S>(m, d, q, v.data());
}

template <class S>
int force_element_at_fault(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& q, const S* v) {
  int fault = -1;
  S largest(-1);
  detail::visit_force_element_shares<S>(m, d, q, v, [&](int k, S value) {
    if (fault >= 0 && !std::isfinite(static_cast<double>(largest))) return;  // the first non-finite one stays
    const S size = std::isfinite(static_cast<double>(value)) ? std::abs(value) : std::numeric_limits<S>::infinity();
    if (size > largest) {
      largest = size;
      fault = k;
    }
  });
  return fault;
}

}  // namespace soadyn
