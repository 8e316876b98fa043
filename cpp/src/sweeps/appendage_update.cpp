// The flexible-appendage update for double and float (appendage_update.hpp), for
// each mode count up to max_fixed_appendage_modes and for any count; for
// double, in two kernels, one chosen on the first call.
#include "soadyn/sweeps/appendage_update.hpp"

#include "soadyn/flex/modal_integrals.hxx"
#include "soadyn/core/processor_features.hpp"

namespace soadyn {

namespace detail {

// The update for N modes, out of line: one function per mode count, as
// appendage_terms's own compiled code (the kernels have external linkage, so
// that profilers find them by name in the stripped module).
template <int N, class S>
[[gnu::noinline]] void appendage_terms_for(const ModelTpl<S>& m, DataTpl<S>& d, std::size_t i,
                                           const ModalIntegrals<S>& mi, const S* q, const S* v, const S* u,
                                           const Vec6<S>* external, const Vec6<S>& V, Mat6<S>& P, Vec6<S>& z) {
  appendage_terms<N>(m, d, i, mi, q, v, u, external, V, P, z);
}

#if defined(__x86_64__) && defined(__GNUC__)
#define SOADYN_HAVE_AVX2_FMA_APPENDAGE 1
// The same with every call inlined and compiled for AVX2 and FMA: the
// products over four modes fill a register, and the 3- and 6-vector updates
// fuse (docs/performance.md has the measurements). Fused products round
// once instead of twice, so the results differ from the baseline's in their
// last bits.
template <int N>
[[gnu::noinline]] __attribute__((target("avx2,fma"), flatten)) void avx2_fma_appendage_terms(
    const ModelTpl<double>& m, DataTpl<double>& d, std::size_t i, const ModalIntegrals<double>& mi, const double* q,
    const double* v, const double* u, const Vec6<double>* external, const Vec6<double>& V, Mat6<double>& P,
    Vec6<double>& z) {
  appendage_terms<N>(m, d, i, mi, q, v, u, external, V, P, z);
}
#endif

// Each kernel calls its update for the appendage's mode count.
template <class S>
void baseline_appendage_update(const ModelTpl<S>& m, DataTpl<S>& d, std::size_t i, const ModalIntegrals<S>& mi,
                             const S* q, const S* v, const S* u, const Vec6<S>* external, const Vec6<S>& V,
                             Mat6<S>& P, Vec6<S>& z) {
  with_mode_count<1, max_fixed_appendage_modes>(mi.n_modes, [&](auto count) {
    appendage_terms_for<decltype(count)::value>(m, d, i, mi, q, v, u, external, V, P, z);
  });
}

#ifdef SOADYN_HAVE_AVX2_FMA_APPENDAGE
void avx2_fma_appendage_update(const ModelTpl<double>& m, DataTpl<double>& d, std::size_t i,
                             const ModalIntegrals<double>& mi, const double* q, const double* v, const double* u,
                             const Vec6<double>* external, const Vec6<double>& V, Mat6<double>& P, Vec6<double>& z) {
  with_mode_count<1, max_fixed_appendage_modes>(mi.n_modes, [&](auto count) {
    avx2_fma_appendage_terms<decltype(count)::value>(m, d, i, mi, q, v, u, external, V, P, z);
  });
}
#endif

}  // namespace detail

namespace {

using detail::AppendageKernel;

#ifdef SOADYN_HAVE_AVX2_FMA_APPENDAGE
constexpr AppendageKernel avx2_fma_kernel{"AVX2 FMA", detail::avx2_fma_appendage_update};
#endif
constexpr AppendageKernel baseline_kernel{"baseline", detail::baseline_appendage_update<double>};

AppendageKernel choose_kernel() {
#ifdef SOADYN_HAVE_AVX2_FMA_APPENDAGE
  if (avx2_fma_kernels_enabled()) return avx2_fma_kernel;
#endif
  return baseline_kernel;
}

AppendageUpdateFunction<double>* chosen_function() { return choose_kernel().run; }

using ChosenAppendageUpdate = FirstCallChoice<AppendageUpdateFunction<double>, chosen_function>;

// The kernel this process runs.
AppendageKernel running_kernel() {
  constexpr AppendageKernel compiled[] = {
#ifdef SOADYN_HAVE_AVX2_FMA_APPENDAGE
      avx2_fma_kernel,
#endif
      baseline_kernel};
  return kernel_running(compiled, ChosenAppendageUpdate::chosen());
}

}  // namespace

void detail::compiled_appendage_update(const ModelTpl<double>& m, DataTpl<double>& d, std::size_t i,
                                     const ModalIntegrals<double>& mi, const double* q, const double* v,
                                     const double* u, const Vec6<double>* external, const Vec6<double>& V,
                                     Mat6<double>& P, Vec6<double>& z) {
  ChosenAppendageUpdate::run(m, d, i, mi, q, v, u, external, V, P, z);
}

#if SOADYN_FLOAT
void detail::compiled_appendage_update(const ModelTpl<float>& m, DataTpl<float>& d, std::size_t i,
                                     const ModalIntegrals<float>& mi, const float* q, const float* v, const float* u,
                                     const Vec6<float>* external, const Vec6<float>& V, Mat6<float>& P,
                                     Vec6<float>& z) {
  detail::baseline_appendage_update(m, d, i, mi, q, v, u, external, V, P, z);
}
#endif

std::vector<AppendageKernel> detail::available_appendage_kernels() {
  std::vector<AppendageKernel> kernels{running_kernel()};
  if (kernels.front().run != baseline_kernel.run) kernels.push_back(baseline_kernel);
  return kernels;
}

const char* appendage_kernel() { return running_kernel().name; }

}  // namespace soadyn
