#include "soadyn/sweeps/joint_angles.hpp"
#include "soadyn/core/packet.hpp"
#include "soadyn/core/processor_features.hpp"

#include <algorithm>
#include <cmath>
#if defined(__x86_64__) && defined(__GNUC__)
#define SOADYN_HAVE_AVX2_KERNEL 1  // the polynomial kernel below
#endif
#if defined(SOADYN_HAVE_AVX2_KERNEL) || defined(SOADYN_HAVE_LIBMVEC)
#include <immintrin.h>
#endif
#ifdef SOADYN_HAVE_LIBMVEC
// glibc's libmvec, under the x86-64 vector function ABI's names: sine and
// cosine of two doubles (SSE2) and of four (AVX2).
extern "C" __m128d _ZGVbN2v_sin(__m128d);
extern "C" __m128d _ZGVbN2v_cos(__m128d);
extern "C" __m256d _ZGVdN4v_sin(__m256d);
extern "C" __m256d _ZGVdN4v_cos(__m256d);
#endif

namespace soadyn {

namespace {

using detail::SineCosineKernel;
using Sources = JointAngleSources<double>;

// Slot k's angle, or 0 past the last slot (a vector's spare lanes).
double angle_or_zero(const Sources& sources, Eigen::Index k) { return k < sources.n ? sources[k] : 0.0; }

#ifdef SOADYN_HAVE_AVX2_KERNEL
// Slots k .. k + 3 in one AVX register, read straight from the coordinates.
__attribute__((target("avx2,fma"))) inline __m256d four_angles(const Sources& sources, Eigen::Index k) {
  return _mm256_set_pd(angle_or_zero(sources, k + 3), angle_or_zero(sources, k + 2), angle_or_zero(sources, k + 1),
                       sources[k]);
}
#endif

void sine_cosine_std(const Sources& sources, double* angle, double* sine, double* cosine) {
  for (Eigen::Index k = 0; k < sources.n; ++k) {
    angle[k] = sources[k];
    sine[k] = std::sin(angle[k]);
    cosine[k] = std::cos(angle[k]);
  }
}

#ifdef SOADYN_HAVE_LIBMVEC
void sine_cosine_sse2(const Sources& sources, double* angle, double* sine, double* cosine) {
  for (Eigen::Index k = 0; k < sources.n; k += 2) {
    const __m128d x = _mm_set_pd(angle_or_zero(sources, k + 1), sources[k]);
    _mm_storeu_pd(angle + k, x);
    _mm_storeu_pd(sine + k, _ZGVbN2v_sin(x));
    _mm_storeu_pd(cosine + k, _ZGVbN2v_cos(x));
  }
}

__attribute__((target("avx2,fma"))) void sine_cosine_libmvec_avx2(const Sources& sources, double* angle,
                                                                  double* sine, double* cosine) {
  for (Eigen::Index k = 0; k < sources.n; k += 4) {
    const __m256d x = four_angles(sources, k);
    _mm256_storeu_pd(angle + k, x);
    _mm256_storeu_pd(sine + k, _ZGVdN4v_sin(x));
    _mm256_storeu_pd(cosine + k, _ZGVdN4v_cos(x));
  }
}
#endif

#ifdef SOADYN_HAVE_AVX2_KERNEL
// Beyond this magnitude the AVX2 kernel's reduction is not exact (and its
// quadrant no longer fits 32 bits): such angles go to std::sin and std::cos.
constexpr double kPolynomialReach = 1e9;

// Bit b of each 64-bit lane, moved to the sign bit (the rest zero).
__attribute__((target("avx2,fma"))) inline __m256d bit_as_sign(__m256i bits, int b) {
  return _mm256_castsi256_pd(_mm256_slli_epi64(_mm256_srli_epi64(bits, b), 63));
}

// Sine and cosine of four angles in one pass, in registers (no call):
// x = k pi/2 + r with k the nearest integer to 2x/pi, and r = x - k pi/2
// from pi/2 split into three doubles (Cody and Waite's reduction; with FMA
// the first step is exact for |k| < 2^31, so |r| <= pi/4 is accurate to an
// ulp); then the Taylor polynomials of sin r (to r^17) and cos r (to r^16),
// whose truncation errors on |r| <= pi/4 are below 1e-18; then sin x and
// cos x from the quadrant k mod 4. Within an ulp of std::sin and std::cos;
// NaN for non-finite angles.
__attribute__((target("avx2,fma"))) inline void sine_cosine_of_four(__m256d x, __m256d& sine, __m256d& cosine) {
  const __m256d k = _mm256_round_pd(_mm256_mul_pd(x, _mm256_set1_pd(0.6366197723675814)),
                                    _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC);
  __m256d r = _mm256_fnmadd_pd(k, _mm256_set1_pd(1.5707963267948966), x);
  r = _mm256_fnmadd_pd(k, _mm256_set1_pd(6.123233995736766e-17), r);
  r = _mm256_fnmadd_pd(k, _mm256_set1_pd(-1.4973849048591698e-33), r);
  const __m256d r2 = _mm256_mul_pd(r, r);
  // sin r = r + r^3 (-1/3! + r^2 (1/5! - ...)), by Horner in r^2.
  static constexpr double sine_terms[] = {2.8114572543455206e-15, -7.647163731819816e-13, 1.6059043836821613e-10,
                                          -2.505210838544172e-08, 2.7557319223985893e-06, -0.0001984126984126984,
                                          0.008333333333333333, -0.16666666666666666};
  // cos r = 1 - r^2/2 + r^4 (1/4! - r^2 (1/6! - ...)).
  static constexpr double cosine_terms[] = {4.779477332387385e-14, -1.1470745597729725e-11, 2.08767569878681e-09,
                                            -2.755731922398589e-07, 2.48015873015873e-05, -0.001388888888888889,
                                            0.041666666666666664};
  __m256d ps = _mm256_set1_pd(sine_terms[0]), pc = _mm256_set1_pd(cosine_terms[0]);
  for (int t = 1; t < 8; ++t) ps = _mm256_fmadd_pd(ps, r2, _mm256_set1_pd(sine_terms[t]));
  for (int t = 1; t < 7; ++t) pc = _mm256_fmadd_pd(pc, r2, _mm256_set1_pd(cosine_terms[t]));
  const __m256d sine_r = _mm256_fmadd_pd(_mm256_mul_pd(ps, r2), r, r);
  // 1 - r^2/2 rounded to w, and its rounding error (1 - w) - r^2/2 added back with the rest.
  const __m256d one = _mm256_set1_pd(1.0), half_r2 = _mm256_mul_pd(_mm256_set1_pd(0.5), r2);
  const __m256d w = _mm256_sub_pd(one, half_r2);
  const __m256d w_error = _mm256_sub_pd(_mm256_sub_pd(one, w), half_r2);
  const __m256d cosine_r = _mm256_add_pd(w, _mm256_fmadd_pd(_mm256_mul_pd(r2, r2), pc, w_error));
  // Quadrant q: sin x = (s, c, -s, -c)[q], cos x = (c, -s, -c, s)[q]: bit 0 of q
  // swaps the two, bit 1 of q negates the sine, bit 1 of q + 1 the cosine.
  const __m256i q = _mm256_cvtepi32_epi64(_mm256_cvtpd_epi32(k));
  const __m256d swap = bit_as_sign(q, 0);
  sine = _mm256_xor_pd(_mm256_blendv_pd(sine_r, cosine_r, swap), bit_as_sign(q, 1));
  cosine = _mm256_xor_pd(_mm256_blendv_pd(cosine_r, sine_r, swap),
                         bit_as_sign(_mm256_add_epi64(q, _mm256_set1_epi64x(1)), 1));
}

__attribute__((target("avx2,fma"))) void sine_cosine_polynomial_avx2(const Sources& sources, double* angle,
                                                                     double* sine, double* cosine) {
  const __m256d reach = _mm256_set1_pd(kPolynomialReach);
  const __m256d magnitude_mask = _mm256_castsi256_pd(_mm256_set1_epi64x(0x7fffffffffffffff));
  for (Eigen::Index k = 0; k < sources.n; k += 4) {
    const __m256d x = four_angles(sources, k);
    _mm256_storeu_pd(angle + k, x);
    // A finite angle beyond the reach: the whole vector from the C library
    // (NaN and infinities stay here, and come out NaN).
    const __m256d magnitude = _mm256_and_pd(x, magnitude_mask);
    const __m256d far = _mm256_and_pd(_mm256_cmp_pd(magnitude, reach, _CMP_GT_OQ),
                                      _mm256_cmp_pd(magnitude, _mm256_set1_pd(INFINITY), _CMP_LT_OQ));
    if (_mm256_movemask_pd(far) != 0) {
      for (int lane = 0; lane < 4; ++lane) {
        sine[k + lane] = std::sin(angle[k + lane]);
        cosine[k + lane] = std::cos(angle[k + lane]);
      }
      continue;
    }
    __m256d s, c;
    sine_cosine_of_four(x, s, c);
    _mm256_storeu_pd(sine + k, s);
    _mm256_storeu_pd(cosine + k, c);
  }
}

#endif

constexpr SineCosineKernel std_kernel{"std", sine_cosine_std};
#ifdef SOADYN_HAVE_LIBMVEC
constexpr SineCosineKernel libmvec_sse2_kernel{"libmvec SSE2", sine_cosine_sse2};
constexpr SineCosineKernel libmvec_avx2_kernel{"libmvec AVX2", sine_cosine_libmvec_avx2};
#endif
#ifdef SOADYN_HAVE_AVX2_KERNEL
constexpr SineCosineKernel polynomial_avx2_kernel{"polynomial AVX2", sine_cosine_polynomial_avx2};
#endif

// Every kernel this processor can run (AVX2 ones unless the baseline kernels
// were requested: processor_features.hpp), the fastest first: the polynomial
// kernel (no library call), libmvec, then the C library.
std::vector<SineCosineKernel> runnable_kernels() {
  std::vector<SineCosineKernel> kernels;
#ifdef SOADYN_HAVE_AVX2_KERNEL
  if (avx2_fma_kernels_enabled()) kernels.push_back(polynomial_avx2_kernel);
#endif
#ifdef SOADYN_HAVE_LIBMVEC
  if (avx2_fma_kernels_enabled()) kernels.push_back(libmvec_avx2_kernel);
  kernels.push_back(libmvec_sse2_kernel);
#endif
  kernels.push_back(std_kernel);
  return kernels;
}

SineCosineKernel choose_kernel() {
#ifdef SOADYN_HAVE_AVX2_KERNEL
  if (avx2_fma_kernels_enabled()) return polynomial_avx2_kernel;
#endif
#ifdef SOADYN_HAVE_LIBMVEC
  return libmvec_sse2_kernel;
#else
  return std_kernel;
#endif
}

using SineCosineFunction = void(const Sources&, double*, double*, double*);

SineCosineFunction* chosen_function() { return choose_kernel().run; }

using ChosenSineCosine = FirstCallChoice<SineCosineFunction, chosen_function>;

// The kernel this process runs.
SineCosineKernel running_kernel() {
  constexpr SineCosineKernel compiled[] = {
#ifdef SOADYN_HAVE_AVX2_KERNEL
      polynomial_avx2_kernel,
#endif
#ifdef SOADYN_HAVE_LIBMVEC
      libmvec_avx2_kernel, libmvec_sse2_kernel,
#endif
      std_kernel};
  return kernel_running(compiled, ChosenSineCosine::chosen());
}

}  // namespace

std::vector<SineCosineKernel> detail::available_sine_cosine_kernels() {
  std::vector<SineCosineKernel> kernels{running_kernel()};
  for (const SineCosineKernel& kernel : runnable_kernels())
    if (kernel.run != kernels.front().run) kernels.push_back(kernel);
  return kernels;
}

void tabulate_joint_angles(const ModelTpl<double>& m, SweepData<double>& sweep, const double* q) {
  ChosenSineCosine::run(joint_angle_sources(m, q), sweep.tree_joint_angle.data(), sweep.tree_joint_sine.data(),
                        sweep.tree_joint_cosine.data());
}

template <>
void tabulate_joint_angles<Packet4d>(const ModelTpl<Packet4d>& m, SweepData<Packet4d>& sweep, const Packet4d* q) {
  // The lanes of the packets, as doubles: lane l of slot k is entry 4 k + l.
  constexpr int lanes = Packet4d::lanes, chunk = 16;
  static_assert(sizeof(Packet4d) == lanes * sizeof(double), "a packet is its lanes");
  const double* coordinates = reinterpret_cast<const double*>(q);
  double* angle = reinterpret_cast<double*>(sweep.tree_joint_angle.data());
  double* sine = reinterpret_cast<double*>(sweep.tree_joint_sine.data());
  double* cosine = reinterpret_cast<double*>(sweep.tree_joint_cosine.data());
  const auto n = static_cast<Eigen::Index>(m.angle_coordinates.size());
  int lane_coordinate[chunk * lanes];
  double lane_sign[chunk * lanes];
  for (Eigen::Index first = 0; first < n; first += chunk) {
    const Eigen::Index slots = std::min<Eigen::Index>(chunk, n - first);
    for (Eigen::Index k = 0; k < slots; ++k)
      for (int l = 0; l < lanes; ++l) {
        lane_coordinate[k * lanes + l] = lanes * m.angle_coordinates[static_cast<std::size_t>(first + k)] + l;
        lane_sign[k * lanes + l] = m.angle_signs[static_cast<std::size_t>(first + k)][l];
      }
    const Eigen::Index at = first * lanes;
    ChosenSineCosine::run(Sources{coordinates, lane_coordinate, lane_sign, slots * lanes}, angle + at, sine + at,
                          cosine + at);
  }
}

const char* joint_angle_kernel() { return running_kernel().name; }

}  // namespace soadyn
