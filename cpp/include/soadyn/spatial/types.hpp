// Fixed-size Eigen types and the spatial cross products.
// Spatial vectors are [angular; linear] (Jain & Rodriguez 1993; Featherstone 2008).
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstddef>
#include <new>
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

// Inlines every call in a function's body that can be (the CRBA's sweep:
// its joint updates then return no unused bias through memory, and keep the
// pose they just formed in registers for the inertia that reads it).
#if defined(__GNUC__)
#define SOADYN_FLATTEN __attribute__((flatten))
#else
#define SOADYN_FLATTEN
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

struct Packet4d;  // core/packet.hpp

// Whether S is a packet of states (core/packet.hpp).
template <class S>
inline constexpr bool is_packet_scalar_v = std::is_same_v<S, Packet4d>;

// Whether every entry of x is exactly zero (-0 included). A packet vector's
// answer is one comparison for the whole vector (core/packet.hpp), so its
// lanes split only when their answers differ, not when single entries do.
template <class Derived>
bool exactly_zero(const Eigen::MatrixBase<Derived>& x) {
  using S = typename Derived::Scalar;
  if constexpr (is_packet_scalar_v<S>)
    return lanes_all_zero(x);
  else
    return (x.array() == S(0)).all();
}

// Whether S holds real numbers, one per state: a floating-point type, or a
// packet of doubles (core/packet.hpp) whose lanes each take the double
// algorithm's every step. The speed paths and the model's precomputed
// shapes (placement axes, diagonal inertias, constant tree inertias) are
// for such scalars; automatic-differentiation scalars take the general
// paths, so that derivatives flow through every product.
template <class S>
inline constexpr bool is_real_scalar_v = std::is_floating_point_v<S> || std::is_same_v<S, Packet4d>;

// The value of a scalar as a double: the number itself, or the value part of
// an automatic-differentiation scalar (one with .value()).
template <class S>
double scalar_value(const S& x) {
  if constexpr (std::is_arithmetic_v<S>)
    return static_cast<double>(x);
  else
    return scalar_value(x.value());
}

// Whether T holds packets of states (core/packet.hpp): a packet, an Eigen
// matrix of them, or a class template of the library on them (Transform<S>,
// FlexibleBodyData<S>, ...).
template <class T>
struct holds_packets : std::false_type {};
template <class S, int Rows, int Cols, int Options, int MaxRows, int MaxCols>
struct holds_packets<Eigen::Matrix<S, Rows, Cols, Options, MaxRows, MaxCols>> : std::is_same<S, Packet4d> {};
template <template <class...> class Tpl, class... Args>
struct holds_packets<Tpl<Args...>> : std::disjunction<std::is_same<Args, Packet4d>..., holds_packets<Args>...> {};
template <class T>
inline constexpr bool holds_packets_v = std::is_same_v<T, Packet4d> || holds_packets<T>::value;

// The allocator of vectors of packets: their storage starts on a cache line
// (64 bytes), so no 32-byte packet in them straddles two lines (malloc's
// 16 bytes let one access in four do so).
template <class T>
struct CacheLineAllocator {
  using value_type = T;
  static constexpr std::align_val_t alignment{alignof(T) > 64 ? alignof(T) : 64};
  CacheLineAllocator() noexcept = default;
  template <class U>
  CacheLineAllocator(const CacheLineAllocator<U>&) noexcept {}  // NOLINT: rebinding, as std::allocator's
  T* allocate(std::size_t n) { return static_cast<T*>(::operator new(n * sizeof(T), alignment)); }
  void deallocate(T* p, std::size_t) noexcept { ::operator delete(p, alignment); }
  template <class U>
  bool operator==(const CacheLineAllocator<U>&) const noexcept { return true; }
  template <class U>
  bool operator!=(const CacheLineAllocator<U>&) const noexcept { return false; }
};

// The library's vectors of Eigen objects: cache lines for packets, Eigen's
// allocator (malloc's 16 bytes) for everything else, as before packets.
template <class T>
using aligned_vector =
    std::vector<T, std::conditional_t<holds_packets_v<T>, CacheLineAllocator<T>, Eigen::aligned_allocator<T>>>;

template <class S>
Mat3<S> skew(const Vec3<S>& w) {
  Mat3<S> m;
  m << S(0), -w.z(), w.y(), w.z(), S(0), -w.x(), -w.y(), w.x(), S(0);
  return m;
}

// Writes [a; b] into the 6-vector `out` as three 2-vector stores. A 6-vector
// that the sweeps read back as 2-vectors right after it is written (a hinge
// subspace, read by the velocity update) is stored so: a 2-vector load cannot
// forward from two scalar stores, and waits about a dozen cycles instead.
template <class S, class Out>
SOADYN_ALWAYS_INLINE void store_as_pairs(const Vec3<S>& a, const Vec3<S>& b, Out&& out) {
  using Pair = Eigen::Matrix<S, 2, 1>;
  out.template segment<2>(0) = Pair(a[0], a[1]);
  out.template segment<2>(2) = Pair(a[2], b[0]);
  out.template segment<2>(4) = Pair(b[1], b[2]);
}

// x itself, held in a register the optimiser cannot see into (x86 float
// and double; other scalars pass through). Reading a 6-vector that was
// just stored through such values keeps GCC from merging neighbouring
// reads into one 2-vector load across two stores (a load straddling two
// stores cannot take its data from the store buffer and waits, as in the
// velocity update's cross product).
template <class S>
SOADYN_ALWAYS_INLINE S in_register(S x) {
#if defined(__GNUC__) && (defined(__x86_64__) || defined(__i386__)) && defined(__SSE2__)
  if constexpr (std::is_same_v<S, double> || std::is_same_v<S, float>) asm("" : "+x"(x));
#endif
  return x;
}

// The first N entries of a vector, read one by one (in_register).
template <class S, int N>
struct ScalarsInRegister {
  S e[N];
  template <class Vector>
  SOADYN_ALWAYS_INLINE explicit ScalarsInRegister(const Vector& x) {
    for (int k = 0; k < N; ++k) e[k] = in_register(S(x[k]));
  }
  SOADYN_ALWAYS_INLINE const S& operator[](int k) const { return e[k]; }
};

// Motion cross product v x m (Featherstone's crm): [w x mw; w x mv + vl x mw],
// stored into r as three 2-vectors (r must not alias v or m). The sweeps use
// this form: a product assembled from two 3-vector cross products was stored
// as scalars and read back as 2-vectors across the halves, which stalls
// store forwarding; the
// operands are read entry by entry for the same reason (in_register).
template <class S>
SOADYN_ALWAYS_INLINE void motion_cross_into(const Vec6<S>& V, const Vec6<S>& M, Vec6<S>& r) {
  const ScalarsInRegister<S, 6> v(V), m(M);
  store_as_pairs(Vec3<S>(v[1] * m[2] - v[2] * m[1], v[2] * m[0] - v[0] * m[2], v[0] * m[1] - v[1] * m[0]),
                 Vec3<S>((v[1] * m[5] - v[2] * m[4]) + (v[4] * m[2] - v[5] * m[1]),
                         (v[2] * m[3] - v[0] * m[5]) + (v[5] * m[0] - v[3] * m[2]),
                         (v[0] * m[4] - v[1] * m[3]) + (v[3] * m[1] - v[4] * m[0])),
                 r);
}

// Force cross product v x* f (Featherstone's crf): [w x n + vl x f; w x f],
// element by element: entry k goes to sink(k, value).
template <class S, class Sink>
SOADYN_ALWAYS_INLINE void force_cross_each(const Vec6<S>& v, const Vec6<S>& f, Sink&& sink) {
  sink(0, (v[1] * f[2] - v[2] * f[1]) + (v[4] * f[5] - v[5] * f[4]));
  sink(1, (v[2] * f[0] - v[0] * f[2]) + (v[5] * f[3] - v[3] * f[5]));
  sink(2, (v[0] * f[1] - v[1] * f[0]) + (v[3] * f[4] - v[4] * f[3]));
  sink(3, v[1] * f[5] - v[2] * f[4]);
  sink(4, v[2] * f[3] - v[0] * f[5]);
  sink(5, v[0] * f[4] - v[1] * f[3]);
}

// The same into r (r must not alias v or f), as motion_cross_into.
template <class S>
SOADYN_ALWAYS_INLINE void force_cross_into(const Vec6<S>& v, const Vec6<S>& f, Vec6<S>& r) {
  force_cross_each(v, f, [&r](int k, const S& x) { r[k] = x; });
}

template <class S>
SOADYN_ALWAYS_INLINE Vec6<S> motion_cross(const Vec6<S>& v, const Vec6<S>& m) {
  Vec6<S> r;
  motion_cross_into(v, m, r);
  return r;
}

template <class S>
SOADYN_ALWAYS_INLINE Vec6<S> force_cross(const Vec6<S>& v, const Vec6<S>& f) {
  Vec6<S> r;
  force_cross_into(v, f, r);
  return r;
}

}  // namespace soadyn
