#include "soadyn/algorithms/rnea.hxx"

namespace soadyn {
#define SOADYN_INSTANTIATE(S)                                                                                  \
  template Status inverse_dynamics<S>(const ModelTpl<S>&, DataTpl<S>&, const ConstVecRef<S>&, const ConstVecRef<S>&, \
                                      const ConstVecRef<S>&, const S*);                                          \
  template Status bias_forces<S>(const ModelTpl<S>&, DataTpl<S>&, const ConstVecRef<S>&, const ConstVecRef<S>&);
SOADYN_INSTANTIATE(double)
#if SOADYN_FLOAT
SOADYN_INSTANTIATE(float)
#endif
}  // namespace soadyn
