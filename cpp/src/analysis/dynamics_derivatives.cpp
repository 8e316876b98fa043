#include "soadyn/analysis/dynamics_derivatives.hxx"

namespace soadyn {
#define SOADYN_INSTANTIATE(S)                                                                                      \
  template struct DynamicsDerivativesTpl<S>;                                                                       \
  template Status inverse_dynamics_derivatives<S>(const ModelTpl<S>&, DataTpl<S>&, DynamicsDerivativesTpl<S>&,     \
                                                  const ConstVecRef<S>&, const ConstVecRef<S>&,                    \
                                                  const ConstVecRef<S>&, const S*);                                \
  template Status dynamics_derivatives<S>(const ModelTpl<S>&, DataTpl<S>&, DynamicsDerivativesTpl<S>&,             \
                                          const ConstVecRef<S>&, const ConstVecRef<S>&, const ConstVecRef<S>&,     \
                                          const S*);
SOADYN_INSTANTIATE(double)
#if SOADYN_FLOAT
SOADYN_INSTANTIATE(float)
#endif
}  // namespace soadyn
