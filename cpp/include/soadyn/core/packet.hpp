// Packet4d: four doubles that travel together through the dynamics, one
// state per lane, so that one pass of a sweep computes four states (the
// batched calls' packet path, algorithms/packet_dynamics.hpp). Every
// arithmetic operation acts lane by lane with the rounding of the double
// operation it stands for (+, -, *, / and sqrt are IEEE operations in each
// lane; the transcendental functions call the double ones per lane), so a
// lane computes exactly what the double algorithm computes on its state as
// long as every branch the algorithm takes on a value goes the same way in
// all four lanes.
//
// Comparisons therefore answer for all lanes at once, and record when the
// lanes disagree: lanes_diverged() is then true on this thread until
// clear_lane_divergence(). The caller replays such a packet state by state
// with the double algorithm, so that each lane's result and status are
// exactly those of the single call.
//
// The type is in namespace soadyn, so the algorithms' unqualified calls
// (sin, sqrt, abs, ...) find its functions by argument-dependent lookup.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <limits>
#include <new>
#include <type_traits>

#include <Eigen/Core>

namespace soadyn {

struct Packet4d {
  static constexpr int lanes = 4;
  // Aligned as a double, so loads and stores are unaligned ones: Eigen's
  // own temporaries hold packets on 16 bytes where the baseline allocates
  // them. A packet that straddles two cache lines costs two accesses, so
  // Eigen's arrays of packets (the allocation functions below) and the
  // library's vectors (aligned_vector, spatial/types.hpp) start on a cache
  // line, where no packet straddles one (docs/performance.md, packets of
  // states).
  typedef double Lanes __attribute__((vector_size(32), aligned(8)));
  typedef long long Mask __attribute__((vector_size(32), aligned(8)));

  Lanes v;

  // Uninitialised, as a double is; value-initialisation (Packet4d(), S{}) gives zeros.
  Packet4d() = default;
  Packet4d(double x) : v{x, x, x, x} {}  // NOLINT: implicit, as a double constant converts to the scalar
  Packet4d(int x) : Packet4d(static_cast<double>(x)) {}  // NOLINT
  Packet4d(long x) : Packet4d(static_cast<double>(x)) {}  // NOLINT: sizes and indices (Eigen::Index)
  explicit Packet4d(const Lanes& x) : v(x) {}
  // User-provided copies make the type non-trivial for calls: the C++ ABI
  // then passes and returns it through memory whether or not the unit is
  // compiled for AVX (a bare 32-byte vector would travel in a YMM register
  // only where AVX is on). Code compiled for the baseline and code compiled
  // for AVX2 can thus call each other's packet functions.
  Packet4d(const Packet4d& o) : v(o.v) {}
  Packet4d& operator=(const Packet4d& o) {
    v = o.v;
    return *this;
  }

  double operator[](int lane) const { return v[lane]; }
  double& operator[](int lane) { return reinterpret_cast<double*>(&v)[lane]; }

  // The sum of the lanes: non-finite when any lane is (scalar_value, the
  // algorithms' finiteness checks).
  double value() const { return (v[0] + v[1]) + (v[2] + v[3]); }

  Packet4d& operator+=(const Packet4d& o) { v += o.v; return *this; }
  Packet4d& operator-=(const Packet4d& o) { v -= o.v; return *this; }
  Packet4d& operator*=(const Packet4d& o) { v *= o.v; return *this; }
  Packet4d& operator/=(const Packet4d& o) { v /= o.v; return *this; }
};

namespace packet_detail {
// Set by a comparison whose lanes disagree (thread-local; see above).
inline thread_local bool diverged = false;

// The common answer of a lane mask; a split one is recorded, and lane 0's
// answer is returned (the caller replays the packet).
inline bool common(const Packet4d::Mask& m) {
  const bool first = m[0] != 0;
  if ((m[1] != 0) != first || (m[2] != 0) != first || (m[3] != 0) != first) diverged = true;
  return first;
}
}  // namespace packet_detail

inline bool lanes_diverged() { return packet_detail::diverged; }
inline void clear_lane_divergence() { packet_detail::diverged = false; }

inline Packet4d operator+(const Packet4d& a, const Packet4d& b) { return Packet4d(a.v + b.v); }
inline Packet4d operator-(const Packet4d& a, const Packet4d& b) { return Packet4d(a.v - b.v); }
inline Packet4d operator*(const Packet4d& a, const Packet4d& b) { return Packet4d(a.v * b.v); }
inline Packet4d operator/(const Packet4d& a, const Packet4d& b) { return Packet4d(a.v / b.v); }
inline Packet4d operator-(const Packet4d& a) { return Packet4d(-a.v); }
inline Packet4d operator+(const Packet4d& a) { return a; }

inline bool operator<(const Packet4d& a, const Packet4d& b) { return packet_detail::common(a.v < b.v); }
inline bool operator>(const Packet4d& a, const Packet4d& b) { return packet_detail::common(a.v > b.v); }
inline bool operator<=(const Packet4d& a, const Packet4d& b) { return packet_detail::common(a.v <= b.v); }
inline bool operator>=(const Packet4d& a, const Packet4d& b) { return packet_detail::common(a.v >= b.v); }
inline bool operator==(const Packet4d& a, const Packet4d& b) { return packet_detail::common(a.v == b.v); }
inline bool operator!=(const Packet4d& a, const Packet4d& b) { return packet_detail::common(a.v != b.v); }

// Lane-by-lane functions: one double call per lane.
template <class F>
inline Packet4d per_lane(const Packet4d& a, F&& f) {
  Packet4d r;
  for (int k = 0; k < Packet4d::lanes; ++k) r[k] = f(a[k]);
  return r;
}
template <class F>
inline Packet4d per_lane(const Packet4d& a, const Packet4d& b, F&& f) {
  Packet4d r;
  for (int k = 0; k < Packet4d::lanes; ++k) r[k] = f(a[k], b[k]);
  return r;
}

inline Packet4d abs(const Packet4d& a) {  // clears the sign bits, as fabs does
  constexpr long long magnitude = ~(1LL << 63);
  return Packet4d((Packet4d::Lanes)((Packet4d::Mask)a.v & Packet4d::Mask{magnitude, magnitude, magnitude, magnitude}));
}
// The square root of each lane: IEEE's correctly rounded one, as std::sqrt
// gives, in one instruction for the four lanes (two with SSE2 alone).
inline Packet4d sqrt(const Packet4d& a) {
#if defined(__AVX__)
  return Packet4d(__builtin_ia32_sqrtpd256(a.v));
#elif defined(__SSE2__)
  typedef double Half __attribute__((vector_size(16)));
  const Half lo = {a.v[0], a.v[1]}, hi = {a.v[2], a.v[3]};
  const Half root_lo = __builtin_ia32_sqrtpd(lo), root_hi = __builtin_ia32_sqrtpd(hi);
  return Packet4d(Packet4d::Lanes{root_lo[0], root_lo[1], root_hi[0], root_hi[1]});
#else
  return per_lane(a, [](double x) { return std::sqrt(x); });
#endif
}
inline Packet4d sin(const Packet4d& a) { return per_lane(a, [](double x) { return std::sin(x); }); }
inline Packet4d cos(const Packet4d& a) { return per_lane(a, [](double x) { return std::cos(x); }); }
inline Packet4d tan(const Packet4d& a) { return per_lane(a, [](double x) { return std::tan(x); }); }
inline Packet4d exp(const Packet4d& a) { return per_lane(a, [](double x) { return std::exp(x); }); }
inline Packet4d log(const Packet4d& a) { return per_lane(a, [](double x) { return std::log(x); }); }
inline Packet4d acos(const Packet4d& a) { return per_lane(a, [](double x) { return std::acos(x); }); }
inline Packet4d asin(const Packet4d& a) { return per_lane(a, [](double x) { return std::asin(x); }); }
inline Packet4d atan(const Packet4d& a) { return per_lane(a, [](double x) { return std::atan(x); }); }
inline Packet4d atan2(const Packet4d& a, const Packet4d& b) {
  return per_lane(a, b, [](double y, double x) { return std::atan2(y, x); });
}
inline Packet4d pow(const Packet4d& a, const Packet4d& b) {
  return per_lane(a, b, [](double x, double y) { return std::pow(x, y); });
}
// std::max and std::min lane by lane, selected without a branch: std::max(x, y)
// is x < y ? y : x, std::min(x, y) is y < x ? y : x (x when unordered).
inline Packet4d max(const Packet4d& a, const Packet4d& b) { return Packet4d(a.v < b.v ? b.v : a.v); }
inline Packet4d min(const Packet4d& a, const Packet4d& b) { return Packet4d(b.v < a.v ? b.v : a.v); }
// For spatial/lie.hpp's series near zero (series_near_zero): how many lanes
// of x lie below `threshold`, and lane by lane `below` where x < threshold,
// `otherwise` elsewhere (NaN lanes: `otherwise`, as the double branch).
inline int lanes_below(const Packet4d& x, const Packet4d& threshold) {
  const Packet4d::Mask m = x.v < threshold.v;
  return (m[0] != 0) + (m[1] != 0) + (m[2] != 0) + (m[3] != 0);
}
inline Packet4d blend_below(const Packet4d& x, const Packet4d& threshold, const Packet4d& below,
                            const Packet4d& otherwise) {
  return Packet4d(x.v < threshold.v ? below.v : otherwise.v);
}
// Whether every entry of a vector of packets is zero in every lane; a split
// answer is recorded (spatial/types.hpp's exactly_zero).
template <class Derived>
bool lanes_all_zero(const Eigen::MatrixBase<Derived>& x) {
  Packet4d::Mask zero = {-1, -1, -1, -1};
  for (Eigen::Index k = 0; k < x.size(); ++k) zero &= x.derived().coeff(k).v == Packet4d::Lanes{};
  return packet_detail::common(zero);
}
inline bool isfinite(const Packet4d& a) { return std::isfinite(a.value()); }  // all lanes finite
inline bool isnan(const Packet4d& a) { return std::isnan(a.value()); }        // some lane NaN
inline bool isinf(const Packet4d& a) { return !isfinite(a) && !isnan(a); }

}  // namespace soadyn

namespace std {
template <>
class numeric_limits<soadyn::Packet4d> : public numeric_limits<double> {};
}  // namespace std

namespace soadyn {
// Eigen's vector of two Packet4d scalars. Declaring packets of this size, as
// SSE2's two doubles are, makes Eigen evaluate every expression on packets
// in the order it evaluates the same expression on doubles: its sums of
// products (matrix-vector products, dot products) add their terms in the
// same order, so each lane rounds as the double call does.
struct Packet4dPair {
  Packet4d lo, hi;
};
}  // namespace soadyn

namespace Eigen {
namespace internal {

template <>
struct packet_traits<soadyn::Packet4d> : default_packet_traits {
  typedef soadyn::Packet4dPair type;
  typedef soadyn::Packet4dPair half;
  // As packet_traits<double> with SSE2 (arch/SSE/PacketMath.h), for the
  // operations the algorithms use.
  enum {
    Vectorizable = 1,
    AlignedOnScalar = 1,
    size = 2,
    HasHalfPacket = 0,
    HasShift = 0,
    HasSetLinear = 0,
    HasDiv = 1,
    HasSqrt = 1
  };
};

template <>
struct unpacket_traits<soadyn::Packet4dPair> {
  typedef soadyn::Packet4d type;
  typedef soadyn::Packet4dPair half;
  enum { size = 2, alignment = Aligned16, vectorizable = true, masked_load_available = false,
         masked_store_available = false };
};

// (Eigen::internal has its own Packet4d: AVX's four doubles.)
using LanePacket = soadyn::Packet4d;
using LanePair = soadyn::Packet4dPair;

template <>
inline LanePair pset1<LanePair>(const LanePacket& a) { return {a, a}; }
template <>
inline LanePair pload<LanePair>(const LanePacket* from) { return {from[0], from[1]}; }
template <>
inline LanePair ploadu<LanePair>(const LanePacket* from) { return {from[0], from[1]}; }
template <>
inline LanePair ploaddup<LanePair>(const LanePacket* from) { return {from[0], from[0]}; }
template <>
inline void pstore<LanePacket>(LanePacket* to, const LanePair& a) { to[0] = a.lo; to[1] = a.hi; }
template <>
inline void pstoreu<LanePacket>(LanePacket* to, const LanePair& a) { to[0] = a.lo; to[1] = a.hi; }
template <>
inline LanePair pgather<LanePacket, LanePair>(const LanePacket* from, Index stride) { return {from[0], from[stride]}; }
template <>
inline void pscatter<LanePacket, LanePair>(LanePacket* to, const LanePair& a, Index stride) {
  to[0] = a.lo;
  to[stride] = a.hi;
}
template <>
inline LanePair padd<LanePair>(const LanePair& a, const LanePair& b) { return {a.lo + b.lo, a.hi + b.hi}; }
template <>
inline LanePair psub<LanePair>(const LanePair& a, const LanePair& b) { return {a.lo - b.lo, a.hi - b.hi}; }
template <>
inline LanePair pmul<LanePair>(const LanePair& a, const LanePair& b) { return {a.lo * b.lo, a.hi * b.hi}; }
template <>
inline LanePair pdiv<LanePair>(const LanePair& a, const LanePair& b) { return {a.lo / b.lo, a.hi / b.hi}; }
template <>
inline LanePair pnegate<LanePair>(const LanePair& a) { return {-a.lo, -a.hi}; }
template <>
inline LanePair pconj<LanePair>(const LanePair& a) { return a; }
// SSE2 has no fused multiply-add: a product, rounded, then a sum.
template <>
inline LanePair pmadd<LanePair>(const LanePair& a, const LanePair& b, const LanePair& c) {
  return padd(pmul(a, b), c);
}
template <>
inline LanePair pabs<LanePair>(const LanePair& a) { return {abs(a.lo), abs(a.hi)}; }
template <>
inline LanePair pmin<LanePair>(const LanePair& a, const LanePair& b) {
  return {min(a.lo, b.lo), min(a.hi, b.hi)};
}
template <>
inline LanePair pmax<LanePair>(const LanePair& a, const LanePair& b) {
  return {max(a.lo, b.lo), max(a.hi, b.hi)};
}
template <>
inline LanePair psqrt<LanePair>(const LanePair& a) { return {sqrt(a.lo), sqrt(a.hi)}; }
template <>
inline LanePair preverse<LanePair>(const LanePair& a) { return {a.hi, a.lo}; }
template <>
inline LanePacket pfirst<LanePair>(const LanePair& a) { return a.lo; }
// The horizontal sum as SSE2's: lane 0 plus lane 1.
template <>
inline LanePacket predux<LanePair>(const LanePair& a) { return a.lo + a.hi; }
template <>
inline LanePacket predux_mul<LanePair>(const LanePair& a) { return a.lo * a.hi; }
template <>
inline LanePacket predux_min<LanePair>(const LanePair& a) { return min(a.lo, a.hi); }
template <>
inline LanePacket predux_max<LanePair>(const LanePair& a) { return max(a.lo, a.hi); }
inline void ptranspose(PacketBlock<LanePair, 2>& block) {
  const LanePair a = block.packet[0], b = block.packet[1];
  block.packet[0] = {a.lo, b.lo};
  block.packet[1] = {a.hi, b.hi};
}

}  // namespace internal

// Eigen's dynamic arrays of packets: their storage on a cache line (its
// own allocation is aligned for doubles only), elements left uninitialised
// as a double array's are (RequireInitialization below).
namespace internal {
constexpr std::align_val_t packet_array_alignment{64};

template <>
inline soadyn::Packet4d* conditional_aligned_new_auto<soadyn::Packet4d, true>(std::size_t size) {
  if (size == 0) return nullptr;
  check_size_for_overflow<soadyn::Packet4d>(size);
  return static_cast<soadyn::Packet4d*>(::operator new(sizeof(soadyn::Packet4d) * size, packet_array_alignment));
}
template <>
inline soadyn::Packet4d* conditional_aligned_new_auto<soadyn::Packet4d, false>(std::size_t size) {
  return conditional_aligned_new_auto<soadyn::Packet4d, true>(size);
}
template <>
inline void conditional_aligned_delete_auto<soadyn::Packet4d, true>(soadyn::Packet4d* ptr, std::size_t) {
  if (ptr) ::operator delete(ptr, packet_array_alignment);
}
template <>
inline void conditional_aligned_delete_auto<soadyn::Packet4d, false>(soadyn::Packet4d* ptr, std::size_t size) {
  conditional_aligned_delete_auto<soadyn::Packet4d, true>(ptr, size);
}
template <>
inline soadyn::Packet4d* conditional_aligned_realloc_new_auto<soadyn::Packet4d, true>(soadyn::Packet4d* ptr,
                                                                                     std::size_t new_size,
                                                                                     std::size_t old_size) {
  soadyn::Packet4d* out = conditional_aligned_new_auto<soadyn::Packet4d, true>(new_size);
  if (ptr && out) std::memcpy(static_cast<void*>(out), ptr, sizeof(soadyn::Packet4d) * std::min(new_size, old_size));
  conditional_aligned_delete_auto<soadyn::Packet4d, true>(ptr, old_size);
  return out;
}
template <>
inline soadyn::Packet4d* conditional_aligned_realloc_new_auto<soadyn::Packet4d, false>(soadyn::Packet4d* ptr,
                                                                                      std::size_t new_size,
                                                                                      std::size_t old_size) {
  return conditional_aligned_realloc_new_auto<soadyn::Packet4d, true>(ptr, new_size, old_size);
}
}  // namespace internal

template <>
struct NumTraits<soadyn::Packet4d> : GenericNumTraits<soadyn::Packet4d> {
  typedef soadyn::Packet4d Real;
  typedef soadyn::Packet4d NonInteger;
  typedef soadyn::Packet4d Nested;
  typedef soadyn::Packet4d Literal;
  enum { IsComplex = 0, IsInteger = 0, IsSigned = 1, RequireInitialization = 0, ReadCost = 1, AddCost = 1, MulCost = 1 };
  static soadyn::Packet4d epsilon() { return std::numeric_limits<double>::epsilon(); }
  static soadyn::Packet4d dummy_precision() { return 1e-12; }
  static soadyn::Packet4d highest() { return std::numeric_limits<double>::max(); }
  static soadyn::Packet4d lowest() { return std::numeric_limits<double>::lowest(); }
  static int digits10() { return std::numeric_limits<double>::digits10; }
};
}  // namespace Eigen
