// Translation joint: three-DOF Cartesian translation, q = v = (x, y, z) in
// the joint frame (Pinocchio's JointModelTranslation). The body keeps the
// joint frame's orientation, so S = [0; I] is constant and there is no bias.
#pragma once
#include "soadyn/joints/joint_base.hpp"

namespace soadyn {

template <class S>
struct TranslationJoint {
  static constexpr const char* name = "translation";
  static constexpr const char* description =
      "Cartesian translation along the joint frame's x, y, z: q = v = (x, y, z). DOFs ':x', ':y', ':z'.";
  using Parameters = std::tuple<>;
  static constexpr std::array<const char*, 0> parameter_names{};
  using Space = VectorSpace<S, 3>;
  static constexpr int nq = Space::nq, nv = Space::nv;
  static constexpr bool translates = true;
  static constexpr std::array<const char*, 3> coordinate_suffixes{"x", "y", "z"}, velocity_suffixes{"x", "y", "z"};

  void calc(const S* q, const S*, Transform<S>& pose, Mat6N<S>&, Vec6<S>&) const {
    pose.rotation.setIdentity();
    pose.translation << q[0], q[1], q[2];
  }
  void fill_subspace(Mat6N<S>& s) const {
    s.setZero();
    s.template bottomRows<3>().setIdentity();
  }
  void random(CoordinateSampler& draw, S* q) const {
    for (int k = 0; k < 3; ++k) q[k] = S(draw.offset());
  }
  void check(const std::string&) {}
};

}  // namespace soadyn
