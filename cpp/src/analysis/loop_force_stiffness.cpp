#include "soadyn/analysis/loop_force_stiffness.hxx"

namespace soadyn {
#define SOADYN_INSTANTIATE(S)                                                                                      \
  template Status loop_force_stiffness<S>(const ModelTpl<S>&, DataTpl<S>&, const ConstVecRef<S>&, const ConstVecRef<S>&, \
                                          Eigen::Ref<MatX<S>>);
SOADYN_INSTANTIATE(double)
#if SOADYN_FLOAT
SOADYN_INSTANTIATE(float)
#endif
}  // namespace soadyn
