#include "soadyn/algorithms/rnea.hxx"

namespace soadyn {
namespace detail {
SOADYN_NEWTON_EULER_SWEEPS(false, double)
SOADYN_NEWTON_EULER_SWEEPS(true, double)
#if SOADYN_FLOAT
SOADYN_NEWTON_EULER_SWEEPS(false, float)
SOADYN_NEWTON_EULER_SWEEPS(true, float)
#endif
}  // namespace detail

#define SOADYN_INSTANTIATE(S)                                                                                  \
  template Status inverse_dynamics<S>(const ModelTpl<S>&, DataTpl<S>&, const ConstVecRef<S>&, const ConstVecRef<S>&, \
                                      const ConstVecRef<S>&, const S*);                                          \
  template Status bias_forces<S>(const ModelTpl<S>&, DataTpl<S>&, const ConstVecRef<S>&, const ConstVecRef<S>&);
SOADYN_INSTANTIATE(double)
#if SOADYN_FLOAT
SOADYN_INSTANTIATE(float)
#endif
}  // namespace soadyn
