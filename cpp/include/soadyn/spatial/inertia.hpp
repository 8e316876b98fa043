// Rigid-body spatial inertia about the body frame origin (M(k), Jain & Rodriguez 1993).
#pragma once
#include <type_traits>

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
  // xx yy zz xy xz yz (I_o), m c, m: one vector, so that a sum is five
  // 2-vector additions whose stores later 2-vector loads can forward from.
  Eigen::Matrix<S, 10, 1> values;

  const S& xx() const { return values[0]; }
  const S& yy() const { return values[1]; }
  const S& zz() const { return values[2]; }
  const S& xy() const { return values[3]; }
  const S& xz() const { return values[4]; }
  const S& yz() const { return values[5]; }
  auto mc() const { return values.template segment<3>(6); }
  const S& mass() const { return values[9]; }
  // The inertia of two bodies together, both about the same origin: ten
  // additions where the 6x6 form takes 36 (composite inertias, crba.hxx).
  InertiaParameters& operator+=(const InertiaParameters& o) {
    values += o.values;
    return *this;
  }
};

// The parameters of a body whose frame has `pose` in a frame F, in F's
// coordinates and about F's origin, written into p: the centre of mass and
// the rotational inertia carried to F (c' = R c + t, R Ic R'). Written in
// place: a copy of p would read its scalar stores back as 2-vectors.
namespace detail {
// Whether a 3x3 matrix's off-diagonal entries are all exactly zero.
template <class S>
bool is_diagonal(const Mat3<S>& A) {
  return A(0, 1) == S(0) && A(0, 2) == S(0) && A(1, 2) == S(0) && A(1, 0) == S(0) && A(2, 0) == S(0) &&
         A(2, 1) == S(0);
}
}  // namespace detail

// `diagonal`: inertia_com is exactly diagonal (the model's
// diagonal_inertia_com, formed once; the overload below tests it per call).
template <class S>
SOADYN_ALWAYS_INLINE void inertia_parameters_in_frame(const Transform<S>& pose, const S& mass, const Vec3<S>& com,
                                                      const Mat3<S>& inertia_com, bool diagonal,
                                                      InertiaParameters<S>& p) {
  const Mat3<S>& R = pose.rotation;
  // R Ic R' is symmetric: its six entries are rows of R Ic dotted with rows
  // of R. A diagonal Ic (exactly, as many URDFs give it) scales R's columns:
  // 9 multiplications instead of 27, and the same numbers (the products
  // skipped are exact zeros).
  Mat3<S> half;
  if (diagonal)
    half = R * inertia_com.diagonal().asDiagonal();
  else
    half.noalias() = R * inertia_com;
  const Vec3<S> c = pose.apply_point(com);
  const Vec3<S> mc = mass * c;
  const S shift = mc.dot(c);  // -m [c]x[c]x = m (|c|^2 1 - c c')
  p.values << half.row(0).dot(R.row(0)) + shift - mc.x() * c.x(), half.row(1).dot(R.row(1)) + shift - mc.y() * c.y(),
      half.row(2).dot(R.row(2)) + shift - mc.z() * c.z(), half.row(1).dot(R.row(0)) - mc.x() * c.y(),
      half.row(2).dot(R.row(0)) - mc.x() * c.z(), half.row(2).dot(R.row(1)) - mc.y() * c.z(), mc, mass;
}

// The same with the diagonal test made here (floating-point scalars only: an
// automatic-differentiation scalar keeps the derivatives by every entry).
template <class S>
SOADYN_ALWAYS_INLINE void inertia_parameters_in_frame(const Transform<S>& pose, const S& mass, const Vec3<S>& com,
                                                      const Mat3<S>& inertia_com, InertiaParameters<S>& p) {
  bool diagonal = false;
  if constexpr (is_real_scalar_v<S>) diagonal = detail::is_diagonal(inertia_com);
  inertia_parameters_in_frame(pose, mass, com, inertia_com, diagonal, p);
}

// The spatial inertia of those parameters, [I_o, [mc]x; -[mc]x, m 1], written
// in place and entry by entry: the sweeps fill their Data without a 6x6
// copy, and no symmetric temporary is stored and read back.
template <class S>
SOADYN_ALWAYS_INLINE void assign_spatial_inertia(const InertiaParameters<S>& p, Mat6<S>& I) {
  const Vec3<S> mc = p.mc();
  const S zero(0), m = p.mass();
  I.col(0) << p.xx(), p.xy(), p.xz(), zero, -mc.z(), mc.y();
  I.col(1) << p.xy(), p.yy(), p.yz(), mc.z(), zero, -mc.x();
  I.col(2) << p.xz(), p.yz(), p.zz(), -mc.y(), mc.x(), zero;
  I.col(3) << zero, mc.z(), -mc.y(), m, zero, zero;
  I.col(4) << -mc.z(), zero, mc.x(), zero, m, zero;
  I.col(5) << mc.y(), -mc.x(), zero, zero, zero, m;
}

// The momentum I V of those parameters, [I_o w + mc x v; m v - mc x w], from
// the parameters rather than from I: I's entries, just stored one by one,
// would be read back as 2-vectors (a store-forwarding stall).
template <class S, class Motion>
SOADYN_ALWAYS_INLINE Vec6<S> momentum(const InertiaParameters<S>& p, const Motion& motion) {
  // Both operands are often just stored: read entry by entry (in_register).
  const ScalarsInRegister<S, 6> V(motion);
  const ScalarsInRegister<S, 10> a(p.values);  // xx yy zz xy xz yz mcx mcy mcz m
  const Vec3<S> angular(a[0] * V[0] + a[3] * V[1] + a[4] * V[2] + a[7] * V[5] - a[8] * V[4],
                        a[3] * V[0] + a[1] * V[1] + a[5] * V[2] + a[8] * V[3] - a[6] * V[5],
                        a[4] * V[0] + a[5] * V[1] + a[2] * V[2] + a[6] * V[4] - a[7] * V[3]);
  const Vec3<S> linear(a[9] * V[3] - a[7] * V[2] + a[8] * V[1], a[9] * V[4] - a[8] * V[0] + a[6] * V[2],
                       a[9] * V[5] - a[6] * V[1] + a[7] * V[0]);
  Vec6<S> h;
  store_as_pairs(angular, linear, h);  // F is read as 2-vectors at once (crba.hxx)
  return h;
}

// The spatial inertia of a body whose frame has `pose` in a frame F, in F's
// coordinates and about F's origin, written into I.
template <class S>
SOADYN_ALWAYS_INLINE void spatial_inertia_in_frame(const Transform<S>& pose, const S& mass, const Vec3<S>& com,
                                                   const Mat3<S>& inertia_com, Mat6<S>& I) {
  InertiaParameters<S> p;
  inertia_parameters_in_frame(pose, mass, com, inertia_com, p);
  assign_spatial_inertia(p, I);
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
