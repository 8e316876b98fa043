#include "soadyn/algorithms/crba.hxx"

#include "soadyn/core/processor_features.hpp"

namespace soadyn {

// The kernels themselves have external linkage, so that profilers and
// bench/bench_instructions.py find them by name in the stripped module.
namespace detail {

TreeFrameStatus baseline_mass_matrix(const ModelTpl<double>& m, DataTpl<double>& d, const ConstVecRef<double>& q) {
  return composite_rigid_body(m, d, q);
}

#if defined(__x86_64__) && defined(__GNUC__)
#define SOADYN_HAVE_AVX2_FMA_CRBA 1
// The same algorithm with every call inlined and compiled for AVX2 and FMA:
// the 3- and 6-vector products become fused multiply-adds in 3-operand
// instructions (docs/performance.md has the measurements). Each fused
// product is rounded once instead of twice, so M differs from the
// baseline's in its last bits.
__attribute__((target("avx2,fma"), flatten)) TreeFrameStatus avx2_fma_mass_matrix(const ModelTpl<double>& m, DataTpl<double>& d,
                                                                         const ConstVecRef<double>& q) {
  return composite_rigid_body(m, d, q);
}
#endif

}  // namespace detail

namespace {

using detail::MassMatrixKernel;

#ifdef SOADYN_HAVE_AVX2_FMA_CRBA
constexpr MassMatrixKernel avx2_fma_kernel{"AVX2 FMA", detail::avx2_fma_mass_matrix};
#endif
constexpr MassMatrixKernel baseline_kernel{"baseline", detail::baseline_mass_matrix};

MassMatrixKernel choose_kernel() {
#ifdef SOADYN_HAVE_AVX2_FMA_CRBA
  if (avx2_fma_kernels_enabled()) return avx2_fma_kernel;
#endif
  return baseline_kernel;
}

using MassMatrixFunction = detail::TreeFrameStatus(const ModelTpl<double>&, DataTpl<double>&, const ConstVecRef<double>&);

MassMatrixFunction* chosen_function() { return choose_kernel().run; }

using ChosenMassMatrix = FirstCallChoice<MassMatrixFunction, chosen_function>;

// The kernel this process runs.
MassMatrixKernel running_kernel() {
  constexpr MassMatrixKernel compiled[] = {
#ifdef SOADYN_HAVE_AVX2_FMA_CRBA
      avx2_fma_kernel,
#endif
      baseline_kernel};
  return kernel_running(compiled, ChosenMassMatrix::chosen());
}

}  // namespace

template <>
detail::TreeFrameStatus detail::rigid_mass_matrix<double>(const ModelTpl<double>& m, DataTpl<double>& d, const ConstVecRef<double>& q) {
  return ChosenMassMatrix::run(m, d, q);
}

std::vector<MassMatrixKernel> detail::available_mass_matrix_kernels() {
  std::vector<MassMatrixKernel> kernels{running_kernel()};
  if (kernels.front().run != baseline_kernel.run) kernels.push_back(baseline_kernel);
  return kernels;
}

const char* mass_matrix_kernel() { return running_kernel().name; }

template Status mass_matrix<double>(const ModelTpl<double>&, DataTpl<double>&, const ConstVecRef<double>&);
#if SOADYN_FLOAT
template Status mass_matrix<float>(const ModelTpl<float>&, DataTpl<float>&, const ConstVecRef<float>&);
#endif
}  // namespace soadyn
