// Rigid-body spatial inertia about the body frame origin (M(k), Jain & Rodriguez 1993).
#pragma once
#include "soadyn/spatial/transform.hpp"

namespace soadyn {

// Spatial inertia about the body origin for a body of `mass` whose centre of
// mass is `com` (body frame) and whose rotational inertia about the centre of
// mass is `inertia_com` (body frame), written into I:
//   [ Ic - m [c]x[c]x   m [c]x ]
//   [ -m [c]x           m 1    ]
template <class S>
SOADYN_ALWAYS_INLINE void assign_spatial_inertia(const S& mass, const Vec3<S>& com, const Mat3<S>& inertia_com,
                                                 Mat6<S>& I) {
  const Mat3<S> cx = skew(com);
  const Vec3<S> mc = mass * com;
  // -m [c]x[c]x = m (|c|^2 1 - c c')
  I.template topLeftCorner<3, 3>() = inertia_com - mc * com.transpose();
  I.template topLeftCorner<3, 3>().diagonal().array() += mc.dot(com);
  I.template topRightCorner<3, 3>() = mass * cx;
  I.template bottomLeftCorner<3, 3>() = -mass * cx;
  I.template bottomRightCorner<3, 3>() = mass * Mat3<S>::Identity();
}

template <class S>
Mat6<S> spatial_inertia(const S& mass, const Vec3<S>& com, const Mat3<S>& inertia_com) {
  Mat6<S> I;
  assign_spatial_inertia(mass, com, inertia_com, I);
  return I;
}

// The spatial inertia of a body whose frame has `pose` in a frame F, in F's
// coordinates and about F's origin, written into I: the centre of mass and
// the rotational inertia are carried to F (c' = R c + t, R Ic R'), then
// assembled as above. Written in place and entry by entry: the sweeps fill
// their Data without a 6x6 copy, and no symmetric temporary is stored and
// read back.
template <class S>
SOADYN_ALWAYS_INLINE void spatial_inertia_in_frame(const Transform<S>& pose, const S& mass, const Vec3<S>& com,
                                                   const Mat3<S>& inertia_com, Mat6<S>& I) {
  const Mat3<S>& R = pose.rotation;
  const Mat3<S> half = R * inertia_com;  // R Ic R' is symmetric: its six entries are rows of R Ic dotted with rows of R
  const Vec3<S> c = pose.apply_point(com);
  const Vec3<S> mc = mass * c;
  const S shift = mc.dot(c);  // -m [c]x[c]x = m (|c|^2 1 - c c')
  const S xx = half.row(0).dot(R.row(0)) + shift - mc.x() * c.x();
  const S yy = half.row(1).dot(R.row(1)) + shift - mc.y() * c.y();
  const S zz = half.row(2).dot(R.row(2)) + shift - mc.z() * c.z();
  const S xy = half.row(1).dot(R.row(0)) - mc.x() * c.y();
  const S xz = half.row(2).dot(R.row(0)) - mc.x() * c.z();
  const S yz = half.row(2).dot(R.row(1)) - mc.y() * c.z();
  const S zero(0);
  I.col(0) << xx, xy, xz, zero, -mc.z(), mc.y();
  I.col(1) << xy, yy, yz, mc.z(), zero, -mc.x();
  I.col(2) << xz, yz, zz, -mc.y(), mc.x(), zero;
  I.col(3) << zero, mc.z(), -mc.y(), mass, zero, zero;
  I.col(4) << -mc.z(), zero, mc.x(), zero, mass, zero;
  I.col(5) << mc.y(), -mc.x(), zero, zero, zero, mass;
}

// Mass, centre of mass and rotational inertia about it, read back from a
// spatial inertia about the origin (used when fixed bodies are merged).
template <class S>
void decompose_spatial_inertia(const Mat6<S>& I, S& mass, Vec3<S>& com, Mat3<S>& inertia_com) {
  mass = I(5, 5);
  const Mat3<S> mcx = I.template topRightCorner<3, 3>();
  const Vec3<S> mc(mcx(2, 1), mcx(0, 2), mcx(1, 0));
  com = mass > S(0) ? Vec3<S>(mc / mass) : Vec3<S>::Zero();
  const Mat3<S> cx = skew(com);
  inertia_com = I.template topLeftCorner<3, 3>() + mass * cx * cx;
}

}  // namespace soadyn
