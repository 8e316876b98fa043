#include "soadyn/algorithms/energy.hxx"

namespace soadyn {
#define SOADYN_INSTANTIATE(S)                                                                                     \
  template S kinetic_energy<S>(const ModelTpl<S>&, DataTpl<S>&, const ConstVecRef<S>&, const ConstVecRef<S>&);     \
  template S potential_energy<S>(const ModelTpl<S>&, DataTpl<S>&, const ConstVecRef<S>&);                          \
  template void mechanical_energy<S>(const ModelTpl<S>&, DataTpl<S>&, const ConstVecRef<S>&, const ConstVecRef<S>&, \
                                     S&, S&);                                                                      \
  template Vec6<S> momentum<S>(const ModelTpl<S>&, DataTpl<S>&, const ConstVecRef<S>&, const ConstVecRef<S>&);     \
  template Vec3<S> center_of_mass<S>(const ModelTpl<S>&, DataTpl<S>&, const ConstVecRef<S>&, S*);                 \
  template S force_element_potential<S>(const ModelTpl<S>&, DataTpl<S>&, const ConstVecRef<S>&);                   \
  template S force_element_dissipation<S>(const ModelTpl<S>&, DataTpl<S>&, const ConstVecRef<S>&,                  \
                                          const ConstVecRef<S>&);                                                  \
  template int force_element_at_fault<S>(const ModelTpl<S>&, DataTpl<S>&, const ConstVecRef<S>&, const S*);      \
  template void evaluate_force_elements<S>(const ModelTpl<S>&, DataTpl<S>&, const S*, const S*, const S*);
SOADYN_INSTANTIATE(double)
#if SOADYN_FLOAT
SOADYN_INSTANTIATE(float)
#endif
}  // namespace soadyn
