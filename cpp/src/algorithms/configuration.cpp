#include "soadyn/algorithms/configuration.hxx"

namespace soadyn {
#define SOADYN_INSTANTIATE(S)                                                                                  \
  template void neutral_configuration<S>(const ModelTpl<S>&, VecRef<S>);                              \
  template void random_configuration<S>(const ModelTpl<S>&, std::uint64_t, VecRef<S>);                \
  template void integrate<S>(const ModelTpl<S>&, const ConstVecRef<S>&, const ConstVecRef<S>&, S,               \
                             VecRef<S>);                                                              \
  template int first_non_unit_quaternion<S>(const ModelTpl<S>&, const ConstVecRef<S>&, S, S*);              \
  template bool unit_quaternion<S>(const S*, S, S*);                                                         \
  template std::vector<int> quaternion_coordinates<S>(const ModelTpl<S>&);
SOADYN_INSTANTIATE(double)
#if SOADYN_FLOAT
SOADYN_INSTANTIATE(float)
#endif
}  // namespace soadyn
