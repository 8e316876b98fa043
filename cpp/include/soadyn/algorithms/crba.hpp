// Joint-space mass matrix by the composite-rigid-body algorithm.
#pragma once
#include <algorithm>
#include <vector>

#include "soadyn/sweeps/body_updates.hpp"

namespace soadyn {

// data.mass_matrix = M(q), both triangles filled. Returns non_finite_result
// naming the first DOF (column) with a non-finite entry.
template <class S>
Status mass_matrix(const ModelTpl<S>& model, DataTpl<S>& data, const ConstVecRef<S>& q);

// The double-precision kernel of rigid models' mass matrix on this processor:
// "AVX2 FMA" (the same algorithm compiled for AVX2 with fused multiply-adds,
// where the processor has them) or "baseline" (x86-64's SSE2, or any other
// target). Like the joint angles' kernel, it is chosen on the first call, or
// by this question if no call came first: results agree bit for bit only
// between processes that use the same one.
const char* mass_matrix_kernel();

// M's rows one after another into `rows` (nv * nv values), as the batched
// calls return it. Both triangles of M are written with one value, so M is
// exactly symmetric and its column-major storage is its row-major one: one
// contiguous copy, where a transposing one took 40 % of talos's batched
// mass matrix (docs/performance.md).
inline void copy_mass_matrix_rows(const MatX<double>& M, double* rows) { std::copy_n(M.data(), M.size(), rows); }

namespace detail {
// A kernel: the composite-rigid-body algorithm of rigid models in tree frames
// (crba.hxx), for double.
struct MassMatrixKernel {
  const char* name;
  TreeFrameStatus (*run)(const ModelTpl<double>& model, DataTpl<double>& data, const ConstVecRef<double>& q);
};
// Every kernel of this build that this processor can run, the chosen one
// first (the tests compare them all).
std::vector<MassMatrixKernel> available_mass_matrix_kernels();
}  // namespace detail

}  // namespace soadyn
