#include "soadyn/analysis/static_equilibrium.hxx"

namespace soadyn {
#define SOADYN_INSTANTIATE(S)                                                                                 \
  template struct StaticEquilibriumTpl<S>;                                                                  \
  template void static_equilibrium<S>(const ModelTpl<S>&, DataTpl<S>&, StaticEquilibriumTpl<S>&,            \
                                      const ConstVecRef<S>&, const std::vector<bool>&, S, int,           \
                                      const Interrupt*);
SOADYN_INSTANTIATE(double)
#if SOADYN_FLOAT
SOADYN_INSTANTIATE(float)
#endif
}  // namespace soadyn
