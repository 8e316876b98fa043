#include "soadyn/algorithms/kinematics.hxx"
#include "soadyn/data.hxx"

namespace soadyn {
template struct DataTpl<double>;
template struct DataTpl<float>;
#define SOADYN_INSTANTIATE(S)                                                              \
  template void forward_kinematics<S>(const ModelTpl<S>&, DataTpl<S>&, const S*, const S*); \
  template void update_world_poses<S>(const ModelTpl<S>&, DataTpl<S>&);
SOADYN_INSTANTIATE(double)
SOADYN_INSTANTIATE(float)
}  // namespace soadyn
