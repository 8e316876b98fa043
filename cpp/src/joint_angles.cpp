#include "soadyn/algorithms/joint_angles.hpp"
#include <atomic>
#include <cmath>
#ifdef SOADYN_HAVE_LIBMVEC
#include <immintrin.h>
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

__attribute__((target("avx2,fma"))) void sine_cosine_avx2(const Sources& sources, double* angle, double* sine,
                                                          double* cosine) {
  for (Eigen::Index k = 0; k < sources.n; k += 4) {
    const __m256d x = _mm256_set_pd(angle_or_zero(sources, k + 3), angle_or_zero(sources, k + 2),
                                    angle_or_zero(sources, k + 1), sources[k]);
    _mm256_storeu_pd(angle + k, x);
    _mm256_storeu_pd(sine + k, _ZGVdN4v_sin(x));
    _mm256_storeu_pd(cosine + k, _ZGVdN4v_cos(x));
  }
}

bool processor_has_avx2() {
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
}
#endif

constexpr SineCosineKernel std_kernel{"std", sine_cosine_std};
#ifdef SOADYN_HAVE_LIBMVEC
constexpr SineCosineKernel sse2_kernel{"libmvec SSE2", sine_cosine_sse2};
constexpr SineCosineKernel avx2_kernel{"libmvec AVX2", sine_cosine_avx2};
#endif

SineCosineKernel choose_kernel() {
#ifdef SOADYN_HAVE_LIBMVEC
  return processor_has_avx2() ? avx2_kernel : sse2_kernel;
#else
  return std_kernel;
#endif
}

void choose_and_run(const Sources& sources, double* angle, double* sine, double* cosine);

// Constant-initialised to choose_and_run, which stores the choice on the first
// call: valid from any static initialiser, and lock free (a relaxed atomic
// load per call).
std::atomic<void (*)(const Sources&, double*, double*, double*)> chosen_kernel{choose_and_run};

void choose_and_run(const Sources& sources, double* angle, double* sine, double* cosine) {
  const SineCosineKernel kernel = choose_kernel();
  chosen_kernel.store(kernel.run, std::memory_order_relaxed);
  kernel.run(sources, angle, sine, cosine);
}

}  // namespace

std::vector<SineCosineKernel> detail::available_sine_cosine_kernels() {
  std::vector<SineCosineKernel> kernels{choose_kernel()};
#ifdef SOADYN_HAVE_LIBMVEC
  if (processor_has_avx2()) kernels.push_back(sse2_kernel);
  kernels.push_back(std_kernel);
#endif
  return kernels;
}

void tabulate_joint_angles(const ModelTpl<double>& m, SweepData<double>& sweep, const double* q) {
  const auto kernel = chosen_kernel.load(std::memory_order_relaxed);
  kernel(joint_angle_sources(m, q), sweep.tree_joint_angle.data(), sweep.tree_joint_sine.data(),
         sweep.tree_joint_cosine.data());
}

const char* joint_angle_kernel() { return choose_kernel().name; }

}  // namespace soadyn
