#pragma once
#include <stdexcept>
#include "soadyn/algorithms/frames.hpp"
#include "soadyn/algorithms/kinematics.hxx"

namespace soadyn {

namespace detail {

// Throws naming the frame when `body` or one of its ancestors is flexible.
template <class S>
void refuse_flexible_carrier(const ModelTpl<S>& m, int body, const std::string& frame) {
  for (int j = body; j >= 0; j = m.parent[static_cast<std::size_t>(j)])
    if (m.is_flexible(j))
      throw std::invalid_argument("frame '" + frame + "' is carried by flexible body '" +
                                  m.body_names[static_cast<std::size_t>(j)] +
                                  "': frames and Jacobians on flexible bodies are not supported");
}

// The rate dS/dt (body frame) of body i's motion subspace at (q, v). Every
// joint type but the universal one has a constant body-frame subspace (the
// Lie-group joints, planar, spherical and free, take body-frame twists as
// velocities); the universal joint's first column R2(q1)' a1 turns with q1:
// d/dt (R2' a1) = qd1 (R2' a1) x a2 (joints/universal.hpp; its bias is this
// column times qd0).
template <class S>
void subspace_rate(const ModelTpl<S>& m, const DataTpl<S>& d, std::size_t i, const S* v, Mat6N<S>& rate) {
  rate.setZero(6, m.nv_body[i]);
  if (const auto* u = std::get_if<UniversalJoint<S>>(&m.joints[i])) {
    const Vec3<S> a1_body = d.sweep.body_subspace[i].col(0).template head<3>();
    rate.col(0).template head<3>() = v[m.v_index[i] + 1] * a1_body.cross(u->axis2);
  }
}

// A motion vector given in world axes about the world origin, expressed in
// `r` for the frame at pose `X` in the world.
template <class S>
Vec6<S> motion_in_reference(const Vec6<S>& world, const Transform<S>& X, Reference r) {
  switch (r) {
    case Reference::local: return X.motion_to_child(world);
    case Reference::local_world_aligned: {
      Vec6<S> out = world;
      out.template tail<3>() += world.template head<3>().cross(X.translation);
      return out;
    }
    case Reference::world: break;
  }
  return world;
}

// Forward kinematics of `body` and its ancestors only, root first (the
// outward sweep of Jain & Rodriguez 1993, Eq. 1, along one path): their
// pose_in_parent, pose_in_world, motion subspace and, with v, velocity and
// Coriolis term. The path is walked without storage: the ancestor at each
// depth is found from `body` again (O(depth^2) parent lookups, integers only).
// Frames on flexible bodies being refused, the path is rigid.
template <class S>
void path_kinematics(const ModelTpl<S>& m, DataTpl<S>& d, int body, const S* q, const S* v) {
  int depth = 0;
  for (int j = body; j >= 0; j = m.parent[static_cast<std::size_t>(j)]) ++depth;
  for (int level = depth - 1; level >= 0; --level) {
    int j = body;
    for (int k = 0; k < level; ++k) j = m.parent[static_cast<std::size_t>(j)];
    const std::size_t b = static_cast<std::size_t>(j);
    detail::joint_update(m, d, b, q, v);
    const int p = m.parent[b];
    d.pose_in_world[b] = p >= 0 ? d.pose_in_world[static_cast<std::size_t>(p)] * d.pose_in_parent[b] : d.pose_in_parent[b];
    if (v) detail::velocity_update(m, d, b, v);
  }
}

template <class S>
Transform<S> frame_pose_in_world(const DataTpl<S>& d, const FrameLocation<S>& f) {
  return f.body >= 0 ? d.pose_in_world[static_cast<std::size_t>(f.body)] * f.placement : f.placement;
}

// The frame's spatial velocity in world axes about the world origin (after forward kinematics with v).
template <class S>
Vec6<S> frame_world_velocity(const DataTpl<S>& d, const FrameLocation<S>& f) {
  if (f.body < 0) return Vec6<S>::Zero();
  const std::size_t b = static_cast<std::size_t>(f.body);
  return d.pose_in_world[b].motion_to_parent(d.body_velocity[b]);
}

}  // namespace detail

template <class S>
FrameLocation<S> locate_frame(const ModelTpl<S>& m, const std::string& name) {
  FrameLocation<S> f;
  const int body = m.body_index(name);
  if (body >= 0) {
    f.body = body;
  } else {
    const int k = m.frame_index(name);
    if (k < 0 && name == "world") return f;  // the world frame itself (as a parent name in add_body)
    if (k < 0) throw std::invalid_argument("unknown frame '" + name + "' (neither a body nor a frame of the model)");
    const Frame<S>& frame = m.frames[static_cast<std::size_t>(k)];
    f.body = frame.body;
    f.placement = frame.placement;
  }
  detail::refuse_flexible_carrier(m, f.body, name);
  return f;
}

template <class S>
FrameLocation<S> locate_frame(const ModelTpl<S>& m, int body) {
  if (body < 0 || body >= m.nbodies())
    throw std::invalid_argument("frame index " + std::to_string(body) + " is not a body index (the model has " +
                                std::to_string(m.nbodies()) + " bodies)");
  return locate_frame(m, m.body_names[static_cast<std::size_t>(body)]);
}

template <class S>
Transform<S> frame_pose(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& q, const FrameLocation<S>& f) {
  detail::path_kinematics(m, d, f.body, q.data(), static_cast<const S*>(nullptr));
  return detail::frame_pose_in_world(d, f);
}

template <class S>
Vec6<S> frame_velocity(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& q, const ConstVecRef<S>& v,
                       const FrameLocation<S>& f, Reference r) {
  detail::path_kinematics(m, d, f.body, q.data(), v.data());
  return detail::motion_in_reference(detail::frame_world_velocity(d, f), detail::frame_pose_in_world(d, f), r);
}

// World-axes acceleration as the sum over the frame's ancestors j of
// X(0, j) (S(j) qdd(j) + a(j)): the outward recursion alpha(k) =
// phi*(k+1, k) alpha(k+1) + H*(k) qdd(k) + a(k) of Jain & Rodriguez 1993,
// Eq. 1 (without the base acceleration), carried to world axes term by term.
template <class S>
Vec6<S> frame_acceleration(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& q, const ConstVecRef<S>& v,
                           const ConstVecRef<S>& qdd, const FrameLocation<S>& f, Reference r, bool classical) {
  detail::path_kinematics(m, d, f.body, q.data(), v.data());
  Vec6<S> world = Vec6<S>::Zero();
  for (int j = f.body; j >= 0; j = m.parent[static_cast<std::size_t>(j)]) {
    const std::size_t b = static_cast<std::size_t>(j);
    const Vec6<S> relative = detail::subspace_times(d.sweep.body_subspace[b], qdd.data() + m.v_index[b]) + d.sweep.body_coriolis[b];
    world += d.pose_in_world[b].motion_to_parent(relative);
  }
  const Transform<S> X = detail::frame_pose_in_world(d, f);
  Vec6<S> a = detail::motion_in_reference(world, X, r);
  if (classical) {
    const Vec6<S> V = detail::motion_in_reference(detail::frame_world_velocity(d, f), X, r);
    a.template tail<3>() += V.template head<3>().cross(V.template tail<3>());
  }
  return a;
}

// Column k of body j's DOFs: X(0, j) S(j) e_k, world axes about the world
// origin. A unit rate of that DOF moves body j by the twist S(j) e_k (the
// H*(k) qd(k) term of V(k), Jain & Rodriguez 1993, Eq. 1), and the frame,
// carried rigidly by j's descendants, with the same world twist.
template <class S>
void frame_jacobian(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& q, const FrameLocation<S>& f,
                    Reference r, Mat6XRef<S> J) {
  detail::path_kinematics(m, d, f.body, q.data(), static_cast<const S*>(nullptr));
  J.setZero();
  const Transform<S> X = detail::frame_pose_in_world(d, f);
  for (int j = f.body; j >= 0; j = m.parent[static_cast<std::size_t>(j)]) {
    const std::size_t b = static_cast<std::size_t>(j);
    const Mat6N<S>& s = d.sweep.body_subspace[b];
    for (Eigen::Index k = 0; k < s.cols(); ++k)
      J.col(m.v_index[b] + k) =
          detail::motion_in_reference(d.pose_in_world[b].motion_to_parent(Vec6<S>(s.col(k))), X, r);
  }
}

// d/dt (X(0, j) S(j)) = V(j) x (X(0, j) S(j)) + X(0, j) dS(j)/dt (world
// axes, V(j) the body's world-axes velocity), formed in body j's frame and
// carried to world axes. Then, with J_w the world column and V_f the frame's
// velocity: local = X_f^-1 dJ_w - V_f(local) x (X_f^-1 J_w), since
// d/dt X_f^-1 = -V_f(local) x X_f^-1; local_world_aligned shifts dJ_w to the
// frame origin p and subtracts pdot x (angular rows of J_w), since its
// linear rows are J_w's shifted by the moving p.
template <class S>
void frame_jacobian_time_variation(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& q,
                                   const ConstVecRef<S>& v, const FrameLocation<S>& f, Reference r,
                                   Mat6XRef<S> dJ) {
  detail::path_kinematics(m, d, f.body, q.data(), v.data());
  dJ.setZero();
  const Transform<S> X = detail::frame_pose_in_world(d, f);
  const Vec6<S> V_world = detail::frame_world_velocity(d, f);
  const Vec6<S> V_frame = detail::motion_in_reference(V_world, X, r);
  Mat6N<S> rate;
  for (int j = f.body; j >= 0; j = m.parent[static_cast<std::size_t>(j)]) {
    const std::size_t b = static_cast<std::size_t>(j);
    const Mat6N<S>& s = d.sweep.body_subspace[b];
    detail::subspace_rate(m, d, b, v.data(), rate);
    for (Eigen::Index k = 0; k < s.cols(); ++k) {
      const Vec6<S> column = s.col(k);
      const Vec6<S> column_rate = motion_cross(d.body_velocity[b], column) + Vec6<S>(rate.col(k));
      const Vec6<S> world = d.pose_in_world[b].motion_to_parent(column);
      const Vec6<S> world_rate = d.pose_in_world[b].motion_to_parent(column_rate);
      Vec6<S> out = detail::motion_in_reference(world_rate, X, r);
      if (r == Reference::local)
        out -= motion_cross(V_frame, Vec6<S>(X.motion_to_child(world)));
      else if (r == Reference::local_world_aligned)
        out.template tail<3>() -= V_frame.template tail<3>().cross(world.template head<3>());
      dJ.col(m.v_index[b] + k) = out;
    }
  }
}

// Column k of body j's DOFs, with c = X(0, j) S(j) e_k (world axes about the
// world origin): sum over j's subtree of m_i (c_lin + c_ang x com_i) / M =
// (m_sub c_lin + c_ang x h_sub) / M, m_sub and h_sub the subtree's mass and
// first moment, summed in one inward sweep.
template <class S>
bool center_of_mass_jacobian(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& q,
                             SubtreeMassWorkspace<S>& w, Mat3XRef<S> J) {
  J.setZero();
  if (m.has_flexible_bodies()) return false;
  forward_kinematics<S>(m, d, q.data(), nullptr);
  S total(0);
  for (int i = m.nbodies() - 1; i >= 0; --i) {
    const std::size_t b = static_cast<std::size_t>(i);
    w.mass[b] = m.mass[b];
    w.first_moment[b] = m.mass[b] * d.pose_in_world[b].apply_point(m.com[b]);
  }
  for (int i = m.nbodies() - 1; i >= 0; --i) {
    const std::size_t b = static_cast<std::size_t>(i);
    const int p = m.parent[b];
    if (p >= 0) {
      w.mass[static_cast<std::size_t>(p)] += w.mass[b];
      w.first_moment[static_cast<std::size_t>(p)] += w.first_moment[b];
    } else {
      total += w.mass[b];
    }
  }
  if (!(total > S(0))) return false;
  for (std::size_t b = 0; b < static_cast<std::size_t>(m.nbodies()); ++b) {
    const Mat6N<S>& s = d.sweep.body_subspace[b];
    for (Eigen::Index k = 0; k < s.cols(); ++k) {
      const Vec6<S> c = d.pose_in_world[b].motion_to_parent(Vec6<S>(s.col(k)));
      J.col(m.v_index[b] + k) =
          (w.mass[b] * c.template tail<3>() + c.template head<3>().cross(w.first_moment[b])) / total;
    }
  }
  return true;
}

}  // namespace soadyn
