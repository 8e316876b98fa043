#include "soadyn/algorithms/kinematics.hxx"
#include "soadyn/model/data.hxx"

namespace soadyn {
template struct DataTpl<double>;
#if SOADYN_FLOAT
template struct DataTpl<float>;
#endif
#define SOADYN_INSTANTIATE(S)                                                              \
  template void forward_kinematics<S>(const ModelTpl<S>&, DataTpl<S>&, const S*, const S*); \
  template void update_world_poses<S>(const ModelTpl<S>&, DataTpl<S>&);
SOADYN_INSTANTIATE(double)
#if SOADYN_FLOAT
SOADYN_INSTANTIATE(float)
#endif
}  // namespace soadyn
