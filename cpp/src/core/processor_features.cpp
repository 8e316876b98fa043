#include "soadyn/core/processor_features.hpp"

#include <cstdlib>
#include <cstring>

namespace soadyn {

bool processor_has_avx2_fma() {
#if defined(__x86_64__) && defined(__GNUC__)
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
#else
  return false;
#endif
}

bool baseline_kernels_requested() {
  const char* value = std::getenv("SOADYN_BASELINE_KERNELS");
  return value != nullptr && value[0] != '\0' && std::strcmp(value, "0") != 0;
}

bool avx2_fma_kernels_enabled() { return processor_has_avx2_fma() && !baseline_kernels_requested(); }

}  // namespace soadyn
