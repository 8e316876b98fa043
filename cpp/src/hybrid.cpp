#include "soadyn/algorithms/hybrid.hxx"

namespace soadyn {
#define SOADYN_INSTANTIATE(S)                                                                                 \
  template Status hybrid_dynamics<S>(const ModelTpl<S>&, DataTpl<S>&, const ConstVecRef<S>&, const ConstVecRef<S>&, \
                                     const ConstVecRef<S>&, const S*, HybridOutputs);
SOADYN_INSTANTIATE(double)
SOADYN_INSTANTIATE(float)
}  // namespace soadyn
