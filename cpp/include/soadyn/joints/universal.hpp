// Universal joint: rotation q0 about axis1, then q1 about axis2 (axis2 given
// in the frame rotated by q0). The subspace depends on q1, hence a nonzero
// bias.
#pragma once
#include "soadyn/joints/revolute.hpp"

namespace soadyn {

template <class S>
struct UniversalJoint {
  static constexpr const char* name = "universal";
  static constexpr const char* description =
      "Rotation about axis1, then about axis2 of the rotated frame. DOFs '<name>:1', '<name>:2'.";
  using Parameters = std::tuple<Vec3<S>, Vec3<S>>;
  static constexpr std::array<const char*, 2> parameter_names{"axis1", "axis2"};
  using Space = VectorSpace<S, 2>;
  static constexpr int nq = Space::nq, nv = Space::nv;
  static constexpr bool translates = false;
  static constexpr std::array<const char*, 2> coordinate_suffixes{"1", "2"}, velocity_suffixes{"1", "2"};

  Vec3<S> axis1, axis2;

  void calc(const S* q, const S* v, Transform<S>& pose, Mat6N<S>& subspace, Vec6<S>& bias) const {
    const Mat3<S> r2 = axis_angle_rotation(axis2, q[1]);
    pose.rotation = axis_angle_rotation(axis1, q[0]) * r2;
    pose.translation.setZero();
    const Vec3<S> a1_body = r2.transpose() * axis1;
    subspace.col(0) << a1_body, Vec3<S>::Zero();
    subspace.col(1) << axis2, Vec3<S>::Zero();
    // d/dt (R2' a1) = -v1 [a2]x R2' a1, times v0.
    if (v)
      bias << (v[0] * v[1]) * a1_body.cross(axis2), Vec3<S>::Zero();
    else
      bias.setZero();
  }
  void fill_subspace(Mat6N<S>&) const {}  // configuration dependent, set in calc
  void random(CoordinateSampler& draw, S* q) const {
    q[0] = S(draw.angle());
    q[1] = S(draw.angle());
  }
  void check(const std::string& joint_name) {
    axis1 = checked_joint_axis(axis1, joint_name, "axis1");
    axis2 = checked_joint_axis(axis2, joint_name, "axis2");
    if (axis1.cross(axis2).norm() < detail::validation_tolerance<S>())
      throw std::invalid_argument("joint '" + joint_name + "': universal joint axes are parallel");
  }

  JointFastPath fast_path(S& sign) const {
    sign = S(1);
    return JointFastPath::universal;
  }
  // Tree-frame fast path (sweeps/tree_frame_updates.hpp): rotation R1 about
  // a1, then R2 about a2. In the tree frame the axes are w1 = R_base a1 and
  // w2 = R_base R1 a2 = R a2, both through the body origin t, so
  // H* = [w1 w2; t x w1  t x w2]. The body-frame velocity product
  // (qd1 qd2) (R2' a1) x a2 is, carried by R, (qd1 qd2) w1 x w2 (R2 a2 = a2,
  // R1 a1 = a1): returns that bias [c; t x c] (zero when v is null).
  Vec6<S> tree_update(const Transform<S>& base, const S* q, const S* v, bool root, Transform<S>& pose,
                    Mat6N<S>& s) const {
    S sign1, sign2;
    const int k1 = coordinate_axis(axis1, sign1), k2 = coordinate_axis(axis2, sign2);
    if (k1 >= 0 && k2 >= 0) {  // both axes along coordinate axes: two column rotations
      Transform<S> first;
      rotate_about_coordinate_axis(k1, base, S(sign1 * q[0]), first);
      rotate_about_coordinate_axis(k2, first, S(sign2 * q[1]), pose);
    } else {
      pose.rotation.noalias() = base.rotation * (axis_angle_rotation(axis1, q[0]) * axis_angle_rotation(axis2, q[1]));
    }
    return tree_subspace_and_bias(base, v, root, pose, s);
  }
  // The same for axes along coordinate axes, with the cosines and sines of
  // the two angles (sign times coordinate) from the sweep's table
  // (sweeps/joint_angles.hpp; ModelTpl::angle_slot).
  Vec6<S> aligned_tree_update(const Transform<S>& base, const S* cosine, const S* sine, const S* v, bool root,
                            Transform<S>& pose, Mat6N<S>& s) const {
    S sign1, sign2;
    const int k1 = coordinate_axis(axis1, sign1), k2 = coordinate_axis(axis2, sign2);
    Transform<S> first;
    rotate_about_coordinate_axis(k1, base, cosine[0], sine[0], first);
    rotate_about_coordinate_axis(k2, first, cosine[1], sine[1], pose);
    return tree_subspace_and_bias(base, v, root, pose, s);
  }

 private:
  // The tree-frame translation, subspace and bias once pose.rotation is set.
  Vec6<S> tree_subspace_and_bias(const Transform<S>& base, const S* v, bool root, Transform<S>& pose,
                                 Mat6N<S>& s) const {
    pose.translation = root ? Vec3<S>::Zero() : base.translation;
    const Vec3<S> w1 = base.rotation * axis1, w2 = pose.rotation * axis2;
    store_as_pairs(w1, Vec3<S>(pose.translation.cross(w1)), s.col(0));
    store_as_pairs(w2, Vec3<S>(pose.translation.cross(w2)), s.col(1));
    if (!v) return Vec6<S>::Zero();
    const Vec3<S> c = (v[0] * v[1]) * w1.cross(w2);
    Vec6<S> bias;
    bias << c, pose.translation.cross(c);
    return bias;
  }
};

}  // namespace soadyn
