// Joint-space mass matrix by the composite-rigid-body algorithm.
#pragma once
#include "soadyn/algorithms/steps.hpp"

namespace soadyn {

// data.mass_matrix = M(q), both triangles filled.
template <class S>
void mass_matrix(const ModelTpl<S>& model, DataTpl<S>& data, const ConstVecRef<S>& q);

}  // namespace soadyn
