#include "soadyn/algorithms/static_equilibrium.hxx"

namespace soadyn {
template struct StaticEquilibriumTpl<double>;
template void static_equilibrium<double>(const ModelTpl<double>&, DataTpl<double>&, StaticEquilibriumTpl<double>&,
                                         const ConstVecRef<double>&, const std::vector<bool>&, double, int);
}  // namespace soadyn
