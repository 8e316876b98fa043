// What the processor running this process offers beyond the baseline x86-64
// the library is compiled for. Kernels compiled for more (the joint angles'
// sines and cosines, the composite-rigid-body algorithm) are chosen by it on
// their first call, and run the same on every later one.
#pragma once

namespace soadyn {

// Whether the processor runs AVX2 and FMA instructions (false off x86-64).
bool processor_has_avx2_fma();

}  // namespace soadyn
