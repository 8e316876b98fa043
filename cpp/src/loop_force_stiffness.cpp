#include "soadyn/algorithms/loop_force_stiffness.hxx"

namespace soadyn {
#define SOADYN_INSTANTIATE(S)                                                                                      \
  template Status loop_force_stiffness<S>(const ModelTpl<S>&, DataTpl<S>&, const ConstVecRef<S>&, const ConstVecRef<S>&, \
                                          Eigen::Ref<MatX<S>>);
SOADYN_INSTANTIATE(double)
SOADYN_INSTANTIATE(float)
}  // namespace soadyn
