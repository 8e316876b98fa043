// Fixed-size Eigen types and the spatial cross products.
// Spatial vectors are [angular; linear] (Jain & Rodriguez 1993; Featherstone 2008).
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <type_traits>
#include <vector>

// Forces inlining of the small per-body kernels the sweeps call many times
// per body: at -O3 GCC otherwise leaves some as calls that pass 6-vectors
// through memory.
#if defined(__GNUC__)
#define SOADYN_ALWAYS_INLINE inline __attribute__((always_inline))
#else
#define SOADYN_ALWAYS_INLINE inline
#endif

namespace soadyn {

template <class S> using Vec3 = Eigen::Matrix<S, 3, 1>;
template <class S> using Mat3 = Eigen::Matrix<S, 3, 3>;
template <class S> using Mat4 = Eigen::Matrix<S, 4, 4>;
template <class S> using Vec6 = Eigen::Matrix<S, 6, 1>;
template <class S> using Mat6 = Eigen::Matrix<S, 6, 6>;
template <class S> using VecX = Eigen::Matrix<S, Eigen::Dynamic, 1>;
template <class S> using MatX = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;
// At most six columns: a hinge's motion subspace (H*(k), Jain & Rodriguez 1993) and its
// articulated-inertia products. The storage is inline, never on the heap.
template <class S> using Mat6N = Eigen::Matrix<S, 6, Eigen::Dynamic, 0, 6, 6>;
template <class S> using MatN = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic, 0, 6, 6>;
template <class S> using VecN = Eigen::Matrix<S, Eigen::Dynamic, 1, 0, 6, 1>;

// The value of a scalar as a double: the number itself, or the value part of
// an automatic-differentiation scalar (one with .value()).
template <class S>
double scalar_value(const S& x) {
  if constexpr (std::is_arithmetic_v<S>)
    return static_cast<double>(x);
  else
    return scalar_value(x.value());
}

template <class T> using aligned_vector = std::vector<T, Eigen::aligned_allocator<T>>;

template <class S>
Mat3<S> skew(const Vec3<S>& w) {
  Mat3<S> m;
  m << S(0), -w.z(), w.y(), w.z(), S(0), -w.x(), -w.y(), w.x(), S(0);
  return m;
}

// Motion cross product v x m (Featherstone's crm): [w x mw; w x mv + vl x mw].
template <class S>
SOADYN_ALWAYS_INLINE Vec6<S> motion_cross(const Vec6<S>& v, const Vec6<S>& m) {
  const Vec3<S> w = v.template head<3>(), vl = v.template tail<3>();
  const Vec3<S> mw = m.template head<3>(), mv = m.template tail<3>();
  Vec6<S> r;
  r << w.cross(mw), w.cross(mv) + vl.cross(mw);
  return r;
}

// Force cross product v x* f (Featherstone's crf): [w x n + vl x f; w x f].
template <class S>
SOADYN_ALWAYS_INLINE Vec6<S> force_cross(const Vec6<S>& v, const Vec6<S>& f) {
  const Vec3<S> w = v.template head<3>(), vl = v.template tail<3>();
  const Vec3<S> n = f.template head<3>(), fl = f.template tail<3>();
  Vec6<S> r;
  r << w.cross(n) + vl.cross(fl), w.cross(fl);
  return r;
}

}  // namespace soadyn
