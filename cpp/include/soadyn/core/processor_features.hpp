// What the processor running this process offers beyond the baseline x86-64
// the library is compiled for. Kernels compiled for more (the joint angles'
// sines and cosines, the composite-rigid-body algorithm, the flexible
// appendages' step) are chosen by it on their first call, and run the same
// on every later one (FirstCallChoice).
#pragma once
#include <atomic>
#include <cstddef>

namespace soadyn {

// Whether the processor runs AVX2 and FMA instructions (false off x86-64).
bool processor_has_avx2_fma();

// Whether the environment variable SOADYN_BASELINE_KERNELS is set (to
// anything but "" or "0"): every kernel is then chosen as on a processor
// without AVX2 and FMA ("libmvec SSE2" or "std" for the joint angles,
// "baseline" for the mass matrix and the appendages' step), so that processes on different x86-64
// processors give bit-identical results, and the tests' lists of kernels
// (detail::available_sine_cosine_kernels, available_mass_matrix_kernels,
// available_appendage_kernels) hold those only. Read when a kernel is
// chosen, on its first call: set it before the process's first dynamics
// call.
bool baseline_kernels_requested();

// Whether kernels compiled for AVX2 and FMA are chosen: the processor has
// them and the baseline ones were not requested.
bool avx2_fma_kernels_enabled();

// A kernel of signature `Signature` chosen on its first call: run() calls the
// function `Choose` returns, asked once per process. The pointer is
// constant-initialised to the choosing call, so run() is valid from any
// static initialiser, and lock free: one relaxed atomic load per call. Two
// threads making the first calls at once both ask `Choose`, and both get
// the same answer. chosen() names the kernel run() calls (choosing it now
// if no call has), so a kernel's reported name is the one that runs even if
// the environment changes after the first call.
template <class Signature, Signature* (*Choose)()>
class FirstCallChoice;

template <class R, class... Args, R (*(*Choose)())(Args...)>
class FirstCallChoice<R(Args...), Choose> {
 public:
  static R run(Args... args) { return chosen_.load(std::memory_order_relaxed)(args...); }

  static R (*chosen())(Args...) {
    R (*kernel)(Args...) = chosen_.load(std::memory_order_relaxed);
    if (kernel != &choose_and_run) return kernel;
    kernel = Choose();
    chosen_.store(kernel, std::memory_order_relaxed);
    return kernel;
  }

 private:
  static R choose_and_run(Args... args) { return chosen()(args...); }
  static inline std::atomic<R (*)(Args...)> chosen_{&choose_and_run};
};

// The entry of `kernels` (each with a `run` function pointer, compiled in
// this build) whose function is `run`; the last entry, the baseline, if none.
template <class Kernel, std::size_t N, class Function>
const Kernel& kernel_running(const Kernel (&kernels)[N], Function* run) {
  for (const Kernel& kernel : kernels)
    if (kernel.run == run) return kernel;
  return kernels[N - 1];
}

}  // namespace soadyn
