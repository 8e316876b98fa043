// ModelTpl::add_loop and its checks (model/loop.hpp). Included by model.hxx.
#pragma once
#include <cmath>
#include "soadyn/model/model.hpp"
#include "soadyn/spatial/scaled_norm.hpp"
#include "soadyn/core/validation.hpp"

namespace soadyn {

namespace detail {
[[noreturn]] inline void loop_fail(const std::string& loop, const std::string& what) {
  throw LoopError("loop '" + loop + "': " + what);
}

// A placement must be finite with an orthonormal, proper rotation (within the
// model's validation tolerance).
template <class S>
void check_loop_placement(const std::string& loop, const Transform<S>& X, const char* which) {
  if (!X.rotation.allFinite() || !X.translation.allFinite())
    loop_fail(loop, std::string(which) + " is not finite");
  const S tol = S(100) * validation_tolerance<S>();
  if ((X.rotation.transpose() * X.rotation - Mat3<S>::Identity()).cwiseAbs().maxCoeff() > tol ||
      std::abs(X.rotation.determinant() - S(1)) > tol)
    loop_fail(loop, std::string(which) + " rotation is not a rotation matrix (orthonormal, determinant 1)");
}

// World pose of rigid `body` (-1: the world) at coordinates q, chaining each
// joint's placement and motion to the root (loops are never on or under a
// flexible body, so the chain is rigid).
template <class S>
Transform<S> rigid_body_pose_at(const ModelTpl<S>& m, int body, const S* q) {
  Transform<S> pose;
  for (int j = body; j >= 0; j = m.parent[static_cast<std::size_t>(j)]) {
    const std::size_t js = static_cast<std::size_t>(j);
    Transform<S> joint_pose;
    Mat6N<S> subspace;
    Vec6<S> bias;
    joint_init_subspace(m.joints[js], subspace);
    joint_calc(m.joints[js], q + m.q_index[js], static_cast<const S*>(nullptr), joint_pose, subspace, bias);
    pose = m.placement[js] * joint_pose * pose;
  }
  return pose;
}

// The current length of a "distance" loop: |p_A - p_B| at `q`, or at the
// neutral configuration when q is null.
template <class S>
S loop_length_at(const ModelTpl<S>& m, const LoopTpl<S>& loop, const S* q) {
  VecX<S> neutral;
  if (!q) {
    neutral = VecX<S>::Zero(m.nq);
    for (std::size_t i = 0; i < static_cast<std::size_t>(m.nbodies()); ++i)
      joint_neutral(m.joints[i], neutral.data() + m.q_index[i]);
    q = neutral.data();
  }
  const Vec3<S> a = rigid_body_pose_at(m, loop.body_a, q).apply_point(loop.placement_a.translation);
  const Vec3<S> b = rigid_body_pose_at(m, loop.body_b, q).apply_point(loop.placement_b.translation);
  return scaled_norm<S>(a - b, nullptr);
}
}  // namespace detail

template <class S>
int ModelTpl<S>::loop_index(const std::string& name) const {
  for (std::size_t k = 0; k < loops.size(); ++k)
    if (loops[k].name == name) return static_cast<int>(k);
  return -1;
}

template <class S>
int ModelTpl<S>::resolve_loop_frame(const std::string& loop, const std::string& frame, const Transform<S>& placement,
                                    const char* which, Transform<S>& in_body) const {
  if (frame.empty() || frame == "world") {
    in_body = placement;
    return -1;
  }
  int body = body_index(frame);
  Transform<S> frame_in_body = Transform<S>::Identity();
  if (body < 0) {
    const int f = frame_index(frame);
    if (f < 0) detail::loop_fail(loop, std::string(which) + " '" + frame + "' is neither a body nor a frame");
    const Frame<S>& fr = frames[static_cast<std::size_t>(f)];
    if (fr.node >= 0)
      detail::loop_fail(loop, std::string(which) + " '" + frame + "' is a node of flexible body '" +
                        body_names[static_cast<std::size_t>(fr.body)] + "'; loops on flexible bodies are not supported");
    body = fr.body;
    frame_in_body = fr.placement;
    if (body < 0) {
      in_body = frame_in_body * placement;
      return -1;
    }
  }
  for (int j = body; j >= 0; j = parent[static_cast<std::size_t>(j)])
    if (is_flexible(j))
      detail::loop_fail(loop, std::string(which) + " '" + frame + "' is on flexible body '" +
                        body_names[static_cast<std::size_t>(j)] + "' or carried by it; loops on flexible bodies "
                        "are not supported");
  in_body = frame_in_body * placement;
  return body;
}

template <class S>
int ModelTpl<S>::add_loop(const std::string& name, const std::string& frame_a, const std::string& frame_b,
                          LoopKind kind, const Transform<S>& placement_a, const Transform<S>& placement_b,
                          S length, const S* configuration) {
  if (name.empty()) throw LoopError("loop name must not be empty");
  if (loop_index(name) >= 0) detail::loop_fail(name, "duplicate loop name");
  detail::check_loop_placement(name, placement_a, "placement_a");
  detail::check_loop_placement(name, placement_b, "placement_b");
  LoopTpl<S> loop;
  loop.name = name;
  loop.kind = kind;
  loop.body_a = resolve_loop_frame(name, frame_a, placement_a, "frame_a", loop.placement_a);
  loop.body_b = resolve_loop_frame(name, frame_b, placement_b, "frame_b", loop.placement_b);
  if (loop.body_a < 0)
    detail::loop_fail(name, "frame_a '" + frame_a + "' is on the world; frame_a must be on a body");
  if (loop.body_a == loop.body_b)
    detail::loop_fail(name, "frame_a '" + frame_a + "' and frame_b '" + frame_b + "' are on the same body '" +
                      body_names[static_cast<std::size_t>(loop.body_a)] + "'");
  if (kind == LoopKind::distance) {
    if (!(std::isfinite(static_cast<double>(length)) && length >= S(0)))
      detail::loop_fail(name, "a distance loop needs a finite, positive length");
    if (configuration)
      for (int k = 0; k < nq; ++k)
        if (!std::isfinite(static_cast<double>(configuration[k])))
          detail::loop_fail(name, "coordinate '" + coordinate_names[static_cast<std::size_t>(k)] +
                            "' of the configuration that gives the length is not finite");
    if (length == S(0)) length = detail::loop_length_at(*this, loop, configuration);
    if (!std::isfinite(static_cast<double>(length)))
      detail::loop_fail(name, std::string("the distance between frame_a and frame_b at the ") +
                        (configuration ? "given" : "neutral") +
                        " configuration is not finite (too large for floating point): give the rod's length=");
    if (!(length > S(100) * Eigen::NumTraits<S>::epsilon()))
      detail::loop_fail(name, std::string("frame_a and frame_b coincide at the ") +
                        (configuration ? "given" : "neutral") + " configuration: give the rod's length=");
    loop.length = length;
  }
  loop.first_row = nloop_equations;
  nloop_equations += loop.rows();
  loops.push_back(loop);
  ++version;
  return static_cast<int>(loops.size()) - 1;
}

}  // namespace soadyn
