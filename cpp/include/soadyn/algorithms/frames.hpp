// Frames and their Jacobians: the pose, velocity and acceleration of a frame
// rigidly attached to a body (or a welded link), the frame Jacobian J
// (6 x nv, rows [angular; linear]) in three references, its time derivative
// dJ/dt, and the Jacobian of the centre of mass (3 x nv).
//
// References (the meanings Pinocchio gives them):
//   world                spatial quantity in world axes, about the world origin;
//   local                frame axes, about the frame origin (a body's V(k) of
//                        Jain & Rodriguez 1993, Eq. 1, for the body frame itself);
//   local_world_aligned  world axes, about the frame origin.
// J v is the frame's velocity in the reference. dJ/dt is the exact time
// derivative of J along v, so J qdd + dJ/dt v = d(J v)/dt: the frame's
// spatial acceleration for world and local; for local_world_aligned, whose
// origin moves with the frame, its linear rows are the classical acceleration
// of the frame origin (frame_acceleration with classical = true).
//
// On a loop model these are the quantities of its spanning tree (every DOF
// counted; v and qdd are meant to satisfy the closure). Frames carried by a
// flexible body (the body itself, its nodes, or any body downstream of it) are
// refused by locate_frame, and center_of_mass_jacobian refuses flexible
// models: their Jacobians would need the modal columns and their rates.
//
// The frame functions compute the kinematics of the frame's body and its
// ancestors only (their pose_in_parent, pose_in_world, subspace and, given v,
// body_velocity and Coriolis term in `data`; other bodies' entries are left as
// they were); center_of_mass_jacobian runs forward kinematics of the whole
// tree. None allocates (the caller sizes J: 6 x nv, or 3 x nv) or throws;
// frame lookup (locate_frame) is the only step that may throw.
#pragma once
#include <string>
#include "soadyn/algorithms/kinematics.hpp"

namespace soadyn {

// How a frame quantity is expressed (see the top of this file).
enum class Reference { world, local, local_world_aligned };

// A frame: a body (-1: the world) and the frame's pose in the body frame.
template <class S>
struct FrameLocation {
  int body = -1;
  Transform<S> placement;
};

// The frame called `name`: a body (its own frame), a frame of Model::frames
// (a welded link, a named frame) or, when nothing else has that name,
// "world" (the world frame: fixed, zero Jacobian). Throws std::invalid_argument
// naming it when it is unknown or carried by a flexible body.
template <class S>
FrameLocation<S> locate_frame(const ModelTpl<S>& model, const std::string& name);
// Body `body`'s own frame (0 <= body < nbodies); throws std::invalid_argument
// naming the index when it is out of range, or the body when it is carried by
// a flexible body.
template <class S>
FrameLocation<S> locate_frame(const ModelTpl<S>& model, int body);

template <class S> using Mat6XRef = typename detail::type_identity<Eigen::Ref<Eigen::Matrix<S, 6, Eigen::Dynamic>>>::type;
template <class S> using Mat3XRef = typename detail::type_identity<Eigen::Ref<Eigen::Matrix<S, 3, Eigen::Dynamic>>>::type;

// Pose of the frame in the world at q.
template <class S>
Transform<S> frame_pose(const ModelTpl<S>& model, DataTpl<S>& data, const ConstVecRef<S>& q,
                        const FrameLocation<S>& frame);

// Spatial velocity [angular; linear] of the frame at (q, v) in `reference`.
template <class S>
Vec6<S> frame_velocity(const ModelTpl<S>& model, DataTpl<S>& data, const ConstVecRef<S>& q, const ConstVecRef<S>& v,
                       const FrameLocation<S>& frame, Reference reference);

// Spatial acceleration of the frame at (q, v, qdd) in `reference`, with the
// velocity-product terms and without gravity. `classical`: the linear rows
// become the classical acceleration w x v + (spatial linear acceleration),
// w and v the frame's velocity in the same reference (in local and
// local_world_aligned, the acceleration of the frame origin).
template <class S>
Vec6<S> frame_acceleration(const ModelTpl<S>& model, DataTpl<S>& data, const ConstVecRef<S>& q,
                           const ConstVecRef<S>& v, const ConstVecRef<S>& qdd, const FrameLocation<S>& frame,
                           Reference reference, bool classical);

// J (6 x nv) of the frame at q in `reference`; columns of DOFs that do not
// move the frame are zero.
template <class S>
void frame_jacobian(const ModelTpl<S>& model, DataTpl<S>& data, const ConstVecRef<S>& q,
                    const FrameLocation<S>& frame, Reference reference, Mat6XRef<S> jacobian);

// dJ/dt (6 x nv) of the frame's J in `reference` along (q, v).
template <class S>
void frame_jacobian_time_variation(const ModelTpl<S>& model, DataTpl<S>& data, const ConstVecRef<S>& q,
                                   const ConstVecRef<S>& v, const FrameLocation<S>& frame, Reference reference,
                                   Mat6XRef<S> jacobian_rate);

// Per-body subtree sums of center_of_mass_jacobian, sized once from a model.
template <class S>
struct SubtreeMassWorkspace {
  explicit SubtreeMassWorkspace(const ModelTpl<S>& model)
      : mass(static_cast<std::size_t>(model.nbodies())), first_moment(static_cast<std::size_t>(model.nbodies())) {}
  std::vector<S> mass;                  // mass of body i and its descendants
  aligned_vector<Vec3<S>> first_moment;  // their sum of mass * centre of mass, world frame
};

// d(centre of mass)/dt = J v, J (3 x nv) in the world frame at q. Returns
// false (J zero) when the model has no mass or flexible bodies (refused, see
// the top of this file).
template <class S>
bool center_of_mass_jacobian(const ModelTpl<S>& model, DataTpl<S>& data, const ConstVecRef<S>& q,
                             SubtreeMassWorkspace<S>& workspace, Mat3XRef<S> jacobian);

}  // namespace soadyn
