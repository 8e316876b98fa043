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

// A spatial inertia as its ten parameters about a frame's origin: the
// rotational inertia about the origin (six entries), the first moment m c
// and the mass.
template <class S>
struct InertiaParameters {
  S xx, yy, zz, xy, xz, yz;
  Vec3<S> mc;
  S mass;
  // The inertia of two bodies together, both about the same origin: ten
  // additions where the 6x6 form takes 36 (composite inertias, crba.hxx).
  InertiaParameters& operator+=(const InertiaParameters& o) {
    xx += o.xx, yy += o.yy, zz += o.zz, xy += o.xy, xz += o.xz, yz += o.yz;
    mc += o.mc;
    mass += o.mass;
    return *this;
  }
};

// The parameters of a body whose frame has `pose` in a frame F, in F's
// coordinates and about F's origin: the centre of mass and the rotational
// inertia carried to F (c' = R c + t, R Ic R').
template <class S>
SOADYN_ALWAYS_INLINE InertiaParameters<S> inertia_parameters_in_frame(const Transform<S>& pose, const S& mass,
                                                                     const Vec3<S>& com, const Mat3<S>& inertia_com) {
  const Mat3<S>& R = pose.rotation;
  const Mat3<S> half = R * inertia_com;  // R Ic R' is symmetric: its six entries are rows of R Ic dotted with rows of R
  const Vec3<S> c = pose.apply_point(com);
  const Vec3<S> mc = mass * c;
  const S shift = mc.dot(c);  // -m [c]x[c]x = m (|c|^2 1 - c c')
  return {half.row(0).dot(R.row(0)) + shift - mc.x() * c.x(),
          half.row(1).dot(R.row(1)) + shift - mc.y() * c.y(),
          half.row(2).dot(R.row(2)) + shift - mc.z() * c.z(),
          half.row(1).dot(R.row(0)) - mc.x() * c.y(),
          half.row(2).dot(R.row(0)) - mc.x() * c.z(),
          half.row(2).dot(R.row(1)) - mc.y() * c.z(),
          mc,
          mass};
}

// The spatial inertia of those parameters, [I_o, [mc]x; -[mc]x, m 1], written
// in place and entry by entry: the sweeps fill their Data without a 6x6
// copy, and no symmetric temporary is stored and read back.
template <class S>
SOADYN_ALWAYS_INLINE void assign_spatial_inertia(const InertiaParameters<S>& p, Mat6<S>& I) {
  const Vec3<S>& mc = p.mc;
  const S zero(0);
  I.col(0) << p.xx, p.xy, p.xz, zero, -mc.z(), mc.y();
  I.col(1) << p.xy, p.yy, p.yz, mc.z(), zero, -mc.x();
  I.col(2) << p.xz, p.yz, p.zz, -mc.y(), mc.x(), zero;
  I.col(3) << zero, mc.z(), -mc.y(), p.mass, zero, zero;
  I.col(4) << -mc.z(), zero, mc.x(), zero, p.mass, zero;
  I.col(5) << mc.y(), -mc.x(), zero, zero, zero, p.mass;
}

// The momentum I V of those parameters, [I_o w + mc x v; m v - mc x w], from
// the parameters rather than from I: I's entries, just stored one by one,
// would be read back as 2-vectors (a store-forwarding stall).
template <class S, class Motion>
SOADYN_ALWAYS_INLINE Vec6<S> momentum(const InertiaParameters<S>& p, const Motion& V) {
  const Vec3<S>& mc = p.mc;
  Vec6<S> h;
  h[0] = p.xx * V[0] + p.xy * V[1] + p.xz * V[2] + mc[1] * V[5] - mc[2] * V[4];
  h[1] = p.xy * V[0] + p.yy * V[1] + p.yz * V[2] + mc[2] * V[3] - mc[0] * V[5];
  h[2] = p.xz * V[0] + p.yz * V[1] + p.zz * V[2] + mc[0] * V[4] - mc[1] * V[3];
  h[3] = p.mass * V[3] - mc[1] * V[2] + mc[2] * V[1];
  h[4] = p.mass * V[4] - mc[2] * V[0] + mc[0] * V[2];
  h[5] = p.mass * V[5] - mc[0] * V[1] + mc[1] * V[0];
  return h;
}

// The spatial inertia of a body whose frame has `pose` in a frame F, in F's
// coordinates and about F's origin, written into I.
template <class S>
SOADYN_ALWAYS_INLINE void spatial_inertia_in_frame(const Transform<S>& pose, const S& mass, const Vec3<S>& com,
                                                   const Mat3<S>& inertia_com, Mat6<S>& I) {
  assign_spatial_inertia(inertia_parameters_in_frame(pose, mass, com, inertia_com), I);
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
