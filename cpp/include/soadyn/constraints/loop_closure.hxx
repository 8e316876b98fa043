#pragma once
#include <Eigen/Geometry>
#include <cmath>
#include "soadyn/algorithms/kinematics.hpp"
#include "soadyn/constraints/loop_closure.hpp"
#include "soadyn/spatial/scaled_norm.hpp"

namespace soadyn {

namespace detail {

// Motion of a point fixed on a body (or on the world, body -1), world axes:
// angular velocity, the point's velocity, and the angular and the classical
// point acceleration of the body accelerations in `data`.
template <class S>
struct PointMotion {
  Vec3<S> omega = Vec3<S>::Zero(), velocity = Vec3<S>::Zero();
  Vec3<S> angular_acceleration = Vec3<S>::Zero(), acceleration = Vec3<S>::Zero();
};

// The motion of the point at `arm` from the reference point of a spatial
// velocity V and acceleration alpha (world axes; alpha with the -gravity
// base acceleration, null: not wanted): v = v_ref + omega x arm and the
// classical acceleration alpha_lin + alpha_ang x arm + omega x v + g.
template <class S>
PointMotion<S> point_motion_at(const Vec6<S>& V, const Vec6<S>* alpha, const Vec3<S>& arm, const Vec3<S>& gravity) {
  PointMotion<S> pm;
  pm.omega = V.template head<3>();
  pm.velocity = V.template tail<3>() + pm.omega.cross(arm);
  if (alpha) {
    pm.angular_acceleration = alpha->template head<3>();
    pm.acceleration = alpha->template tail<3>() + pm.angular_acceleration.cross(arm) + pm.omega.cross(pm.velocity) + gravity;
  }
  return pm;
}

// Where the loop equations read the kinematics. Body frames: pose_in_world,
// body_subspace, body_velocity and body_acceleration, as forward kinematics
// and inverse dynamics leave them (the accelerations of qdd = 0 for kappa).
struct BodyFrameLoopKinematics {
  // `r`: the point in the body frame.
  template <class S>
  static PointMotion<S> point_motion(const ModelTpl<S>& m, const DataTpl<S>& d, int body, const Vec3<S>& r,
                                     bool with_acceleration) {
    if (body < 0) return PointMotion<S>();
    const std::size_t b = static_cast<std::size_t>(body);
    const Transform<S>& X = d.pose_in_world[b];
    const auto to_world = [&](const Vec6<S>& x) {
      Vec6<S> w;
      w << X.rotation * x.template head<3>(), X.rotation * x.template tail<3>();
      return w;
    };
    const Vec6<S> alpha = with_acceleration ? to_world(d.body_acceleration[b]) : Vec6<S>::Zero();
    return point_motion_at<S>(to_world(d.body_velocity[b]), with_acceleration ? &alpha : nullptr, X.rotation * r,
                              m.gravity);
  }

  // Body j's hinge columns H*(j) carried to the world, about world point p.
  template <class S>
  static void point_columns(const ModelTpl<S>&, const DataTpl<S>& d, std::size_t j, const Vec3<S>& p,
                            Eigen::Index c, Vec3<S>& angular, Vec3<S>& linear) {
    const Transform<S>& X = d.pose_in_world[j];
    const Mat6N<S>& H = d.sweep.body_subspace[j];
    angular = X.rotation * H.col(c).template head<3>();
    linear = X.rotation * H.col(c).template tail<3>() + angular.cross(p - X.translation);
  }
};

// Tree frames, as the tree-frame sweeps leave them (tree_frame_updates.hpp:
// world axes, about the origin of the body's tree), with
// loops.tree_origin[b] the world position of that origin and pose_in_world
// filled (set_world_poses_from_tree_frames). The accelerations are those of
// the sweeps' qdd: kappa then comes out as kappa - C qdd.
struct TreeFrameLoopKinematics {
  template <class S>
  static PointMotion<S> point_motion(const ModelTpl<S>& m, const DataTpl<S>& d, int body, const Vec3<S>& r,
                                     bool with_acceleration) {
    if (body < 0) return PointMotion<S>();
    const std::size_t b = static_cast<std::size_t>(body);
    const Transform<S>& X = d.sweep.tree_pose[b];  // the arm runs from the tree origin to the point
    return point_motion_at<S>(d.sweep.tree_velocity[b], with_acceleration ? &d.sweep.tree_acceleration[b] : nullptr,
                              X.rotation * r + X.translation, m.gravity);
  }

  template <class S>
  static void point_columns(const ModelTpl<S>&, const DataTpl<S>& d, std::size_t j, const Vec3<S>& p,
                            Eigen::Index c, Vec3<S>& angular, Vec3<S>& linear) {
    const Mat6N<S>& H = d.sweep.tree_subspace[j];
    angular = H.col(c).template head<3>();
    linear = H.col(c).template tail<3>() + angular.cross(p - d.loops.tree_origin[j]);
  }
};

// J += sign * [angular; linear velocity of the body's point at world
// position p] as a map of v: the body's world Jacobian, one column per
// hinge DOF on its root path (H*(j) of Jain & Rodriguez 1993 carried to the world).
template <class Kinematics, class S>
void add_point_jacobian(const ModelTpl<S>& m, const DataTpl<S>& d, int body, const Vec3<S>& p, S sign,
                        Mat6X<S>& J) {
  for (int j = body; j >= 0; j = m.parent[static_cast<std::size_t>(j)]) {
    const std::size_t js = static_cast<std::size_t>(j);
    for (Eigen::Index c = 0; c < m.nv_body[js]; ++c) {
      Vec3<S> w, lin;
      Kinematics::point_columns(m, d, js, p, c, w, lin);
      J.col(m.v_index[js] + c).template head<3>() += sign * w;
      J.col(m.v_index[js] + c).template tail<3>() += sign * lin;
    }
  }
}

template <class S>
Transform<S> loop_frame_in_world(const DataTpl<S>& d, int body, const Transform<S>& placement) {
  return body < 0 ? placement : d.pose_in_world[static_cast<std::size_t>(body)] * placement;
}

template <class S>
Vec3<S> rotation_vector(const Mat3<S>& R) {
  const Eigen::AngleAxis<S> aa(R);
  return aa.angle() * aa.axis();
}

// Whether a loop's directions W turn with a frame: a revolute loop's with
// frame A, a prismatic loop's with frame B (the other kinds' W are fixed or,
// for a distance loop, follow the two origins).
template <class S>
bool directions_turn(const LoopTpl<S>& loop) {
  return loop.kind == LoopKind::revolute || loop.kind == LoopKind::prismatic;
}

// The directions of a revolute or prismatic loop: the identity in rows
// [fixed, fixed + 3) of W's first three columns, and in rows [turning,
// turning + 3) of columns 3 and 4 the x and y axes of the frame (rotation R,
// angular velocity omega) they turn with; their rates omega x axis.
template <class S>
void turning_directions(int fixed, int turning, const Mat3<S>& R, const Vec3<S>& omega, Mat6<S>& W, Mat6<S>* W_rate) {
  W.template block<3, 3>(fixed, 0).setIdentity();
  W.template block<3, 2>(turning, 3) = R.template leftCols<2>();
  if (!W_rate) return;
  W_rate->template block<3, 1>(turning, 3) = omega.cross(R.col(0));
  W_rate->template block<3, 1>(turning, 4) = omega.cross(R.col(1));
}

// The constraint directions W (6 x k, first k columns) of a loop, in `W`,
// and their rate Wdot, in `W_rate` (null: not wanted), from the loop frames'
// origins a and b, the linear relative velocity v_A - v_B(P), the frames'
// angular velocities and, for a turning loop (directions_turn), the
// rotation of frame A (revolute) or B (prismatic) in `R` (model/loop.hpp).
template <class S>
void loop_directions(const LoopTpl<S>& loop, const Vec3<S>& a, const Vec3<S>& b, const Mat3<S>& R,
                     const Vec3<S>& relative_velocity, const Vec3<S>& omega_a, const Vec3<S>& omega_b, Mat6<S>& W,
                     Mat6<S>* W_rate) {
  W.setZero();
  if (W_rate) W_rate->setZero();
  switch (loop.kind) {
    case LoopKind::point:
      W.template block<3, 3>(3, 0).setIdentity();
      break;
    case LoopKind::revolute:  // points together; turning only about A's z
      turning_directions(3, 0, R, omega_a, W, W_rate);
      break;
    case LoopKind::prismatic:  // rotations equal; sliding only along B's z
      turning_directions(0, 3, R, omega_b, W, W_rate);
      break;
    case LoopKind::weld:
      W.setIdentity();
      break;
    case LoopKind::distance: {
      Vec3<S> n;
      const S length = scaled_norm<S>(a - b, &n);
      W.template block<3, 1>(3, 0) = n;
      if (W_rate) {
        W_rate->template block<3, 1>(3, 0) = (relative_velocity - n * n.dot(relative_velocity)) / length;
      }
      break;
    }
  }
}

// The loop's position residual Psi (model/loop.hpp), first rows() entries.
template <class S>
Vec6<S> closure_residual(const LoopTpl<S>& loop, const Transform<S>& A, const Transform<S>& B) {
  Vec6<S> residual = Vec6<S>::Zero();
  const Vec3<S> d = A.translation - B.translation;
  switch (loop.kind) {
    case LoopKind::point:
      residual.template head<3>() = d;
      break;
    case LoopKind::revolute: {
      const Vec3<S> tilt = B.rotation.col(2).cross(A.rotation.col(2));
      residual << d, A.rotation.col(0).dot(tilt), A.rotation.col(1).dot(tilt), S(0);
      break;
    }
    case LoopKind::prismatic:
      residual << rotation_vector<S>(A.rotation * B.rotation.transpose()), B.rotation.col(0).dot(d),
          B.rotation.col(1).dot(d), S(0);
      break;
    case LoopKind::weld:
      residual << rotation_vector<S>(A.rotation * B.rotation.transpose()), d;
      break;
    case LoopKind::distance:
      residual[0] = scaled_norm<S>(d, nullptr) - loop.length;
      break;
  }
  return residual;
}

// Adds sign * W' [angular; linear velocity of the body's point at world
// position p] to `rows` (k x nv: a loop's rows of C), as a map of v: one
// column per hinge DOF on the body's root path (add_point_jacobian with the
// loop's directions applied column by column; a point loop's W' picks the
// linear part, a weld's is the identity).
template <class Kinematics, class S, class Rows>
void add_loop_jacobian_rows(const ModelTpl<S>& m, const DataTpl<S>& d, const LoopTpl<S>& loop, int body,
                            const Vec3<S>& p, S sign, const Mat6<S>& W, Rows& rows) {
  const Eigen::Index k = rows.rows();
  for (int j = body; j >= 0; j = m.parent[static_cast<std::size_t>(j)]) {
    const std::size_t js = static_cast<std::size_t>(j);
    for (Eigen::Index c = 0; c < m.nv_body[js]; ++c) {
      Vec3<S> w, lin;
      Kinematics::point_columns(m, d, js, p, c, w, lin);
      auto column = rows.col(m.v_index[js] + c);
      switch (loop.kind) {
        case LoopKind::point:
          column.template head<3>() += sign * lin;
          break;
        case LoopKind::weld:
          column.template head<3>() += sign * w;
          column.template tail<3>() += sign * lin;
          break;
        default:
          for (Eigen::Index r = 0; r < k; ++r)
            column[r] += sign * (W.col(r).template head<3>().dot(w) + W.col(r).template tail<3>().dot(lin));
      }
    }
  }
}

// Column r of a 6 x 6 map dotted with the motion [angular; linear].
template <class S>
S column_dot(const Mat6<S>& W, int r, const Vec3<S>& angular, const Vec3<S>& linear) {
  return W.col(r).template head<3>().dot(angular) + W.col(r).template tail<3>().dot(linear);
}

template <class Kinematics, class S>
void loop_equations_from(const ModelTpl<S>& m, DataTpl<S>& d, LoopTerms terms) {
  LoopData<S>& ld = d.loops;
  const bool with_kappa = terms == LoopTerms::acceleration;
  const auto origin = [&](int body, const Transform<S>& placement) {
    return body < 0 ? placement.translation : d.pose_in_world[static_cast<std::size_t>(body)].apply_point(placement.translation);
  };
  for (std::size_t l = 0; l < m.loops.size(); ++l) {
    const LoopTpl<S>& loop = m.loops[l];
    const bool prismatic = loop.kind == LoopKind::prismatic;
    // The frames' origins, and their rotations where the terms read them.
    const Vec3<S> a = origin(loop.body_a, loop.placement_a), b = origin(loop.body_b, loop.placement_b);
    Mat3<S> R;  // of the frame W turns with
    if (directions_turn(loop))
      R = loop_frame_in_world(d, prismatic ? loop.body_b : loop.body_a, prismatic ? loop.placement_b : loop.placement_a).rotation;
    // P: the point of body B whose velocity enters (A's origin for a prismatic loop, B's otherwise).
    const Vec3<S> P = prismatic ? a : b;
    const Vec3<S> P_in_b = !prismatic ? loop.placement_b.translation
                           : loop.body_b < 0 ? P
                                             : d.pose_in_world[static_cast<std::size_t>(loop.body_b)].inverse().apply_point(P);
    ld.point_a[l] = a;
    ld.point_p[l] = P;
    const PointMotion<S> motion_a = Kinematics::point_motion(m, d, loop.body_a, loop.placement_a.translation, with_kappa);
    const PointMotion<S> motion_b = Kinematics::point_motion(m, d, loop.body_b, P_in_b, with_kappa);
    // The relative motion's angular and linear parts, kept apart (a 6-vector
    // written by halves and read whole stalls the loads).
    const Vec3<S> relative_omega = motion_a.omega - motion_b.omega;
    const Vec3<S> relative_velocity = motion_a.velocity - motion_b.velocity;
    Mat6<S>& W = ld.directions[l];
    Mat6<S> W_rate;
    loop_directions(loop, a, b, R, relative_velocity, motion_a.omega, motion_b.omega, W, with_kappa ? &W_rate : nullptr);
    const int k = loop.rows();
    auto rows = ld.jacobian.middleRows(loop.first_row, k);
    rows.setZero();
    add_loop_jacobian_rows<Kinematics>(m, d, loop, loop.body_a, a, S(1), W, rows);
    add_loop_jacobian_rows<Kinematics>(m, d, loop, loop.body_b, P, S(-1), W, rows);
    if (!with_kappa) {
      const Transform<S> A = loop_frame_in_world(d, loop.body_a, loop.placement_a);
      const Transform<S> B = loop_frame_in_world(d, loop.body_b, loop.placement_b);
      ld.residual.segment(loop.first_row, k) = closure_residual(loop, A, B).head(k);
      for (int r = 0; r < k; ++r)
        ld.velocity_residual[loop.first_row + r] = column_dot(W, r, relative_omega, relative_velocity);
      continue;
    }
    // kappa = -d/dt (W' relative velocity) at qdd = 0. A prismatic loop
    // follows B's point under A's moving origin: its rate adds omega_B x (v_A - v_B(P)).
    const Vec3<S> angular_acceleration = motion_a.angular_acceleration - motion_b.angular_acceleration;
    Vec3<S> acceleration = motion_a.acceleration - motion_b.acceleration;
    if (prismatic) acceleration -= motion_b.omega.cross(relative_velocity);
    for (int r = 0; r < k; ++r)
      ld.kappa[loop.first_row + r] = -(column_dot(W, r, angular_acceleration, acceleration) +
                                       column_dot(W_rate, r, relative_omega, relative_velocity));
  }
}

template <class S>
void loop_equations(const ModelTpl<S>& m, DataTpl<S>& d, LoopTerms terms) {
  loop_equations_from<BodyFrameLoopKinematics>(m, d, terms);
}

}  // namespace detail

template <class S>
void loop_residual(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& q, const S* v) {
  forward_kinematics(m, d, q.data(), v);
  if (!v)
    for (auto& V : d.body_velocity) V.setZero();
  detail::loop_equations(m, d, detail::LoopTerms::closure);
}

template <class S>
int loop_rank(const ModelTpl<S>& m, DataTpl<S>& d, const ConstVecRef<S>& q) {
  loop_residual(m, d, q, static_cast<const S*>(nullptr));
  if (m.nloop_equations == 0) return 0;
  d.loops.rank_qr.setThreshold(loop_rank_threshold<S>());
  d.loops.rank_qr.compute(d.loops.jacobian);
  return static_cast<int>(d.loops.rank_qr.rank());
}

}  // namespace soadyn
