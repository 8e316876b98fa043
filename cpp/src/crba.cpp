#include "soadyn/algorithms/crba.hxx"

namespace soadyn {
template Status mass_matrix<double>(const ModelTpl<double>&, DataTpl<double>&, const ConstVecRef<double>&);
template Status mass_matrix<float>(const ModelTpl<float>&, DataTpl<float>&, const ConstVecRef<float>&);
}  // namespace soadyn
