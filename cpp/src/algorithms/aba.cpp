#include "soadyn/algorithms/aba.hxx"

namespace soadyn {
#define SOADYN_INSTANTIATE(S)                                                                                  \
  template Status forward_dynamics<S>(const ModelTpl<S>&, DataTpl<S>&, const ConstVecRef<S>&, const ConstVecRef<S>&, \
                                      const ConstVecRef<S>&, const S*);
SOADYN_INSTANTIATE(double)
#if SOADYN_FLOAT
SOADYN_INSTANTIATE(float)
#endif
}  // namespace soadyn
