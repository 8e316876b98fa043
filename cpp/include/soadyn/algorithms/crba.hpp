// Joint-space mass matrix by the composite-rigid-body algorithm.
#pragma once
#include "soadyn/algorithms/steps.hpp"

namespace soadyn {

// data.mass_matrix = M(q), both triangles filled. Returns non_finite_result
// naming the first DOF (column) with a non-finite entry.
template <class S>
Status mass_matrix(const ModelTpl<S>& model, DataTpl<S>& data, const ConstVecRef<S>& q);

}  // namespace soadyn
