// Fixed joint: welds the body to its parent. Model::add_body merges a rigid
// body so welded into its parent; only a clamped flexible body reaches the
// dynamics sweeps with it (no hinge DOF, modal DOFs only).
#pragma once
#include "soadyn/joints/joint_base.hpp"

namespace soadyn {

template <class S>
struct FixedJoint {
  static constexpr const char* name = "fixed";
  static constexpr const char* description = "Weld: the body is merged into its parent and becomes a named frame.";
  using Parameters = std::tuple<>;
  static constexpr std::array<const char*, 0> parameter_names{};
  using Space = VectorSpace<S, 0>;
  static constexpr int nq = Space::nq, nv = Space::nv;
  static constexpr bool translates = false;
  static constexpr std::array<const char*, 0> coordinate_suffixes{}, velocity_suffixes{};

  void calc(const S*, const S*, Transform<S>& pose, Mat6N<S>&, Vec6<S>&) const { pose = Transform<S>(); }
  void fill_subspace(Mat6N<S>&) const {}
  void random(CoordinateSampler&, S*) const {}
  void check(const std::string&) {}

  // Fast path: the body's pose is its placement (sweeps/body_updates.hpp).
  JointFastPath fast_path(S& sign) const {
    sign = S(1);
    return JointFastPath::fixed;
  }
};

}  // namespace soadyn
