#include "soadyn/algorithms/rnea.hxx"

namespace soadyn {
#define SOADYN_INSTANTIATE(S)                                                                                  \
  template void inverse_dynamics<S>(const ModelTpl<S>&, DataTpl<S>&, const ConstVecRef<S>&, const ConstVecRef<S>&, \
                                    const ConstVecRef<S>&, const S*);                                          \
  template void bias_forces<S>(const ModelTpl<S>&, DataTpl<S>&, const ConstVecRef<S>&, const ConstVecRef<S>&);
SOADYN_INSTANTIATE(double)
SOADYN_INSTANTIATE(float)
}  // namespace soadyn
