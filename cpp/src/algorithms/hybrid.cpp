#include "soadyn/algorithms/hybrid.hxx"

namespace soadyn {
#define SOADYN_INSTANTIATE(S)                                                                                 \
  template Status hybrid_dynamics<S>(const ModelTpl<S>&, DataTpl<S>&, const ConstVecRef<S>&, const ConstVecRef<S>&, \
                                     const ConstVecRef<S>&, const S*, DynamicsOutputs);                          \
  template Status hybrid_impulse<S>(const ModelTpl<S>&, DataTpl<S>&, const ConstVecRef<S>&, const ConstVecRef<S>&);
SOADYN_INSTANTIATE(double)
#if SOADYN_FLOAT
SOADYN_INSTANTIATE(float)
#endif
}  // namespace soadyn
