#include "soadyn/algorithms/equation_terms.hxx"

namespace soadyn {
#define SOADYN_INSTANTIATE(S)                                                                                   \
  template struct EquationTermsWorkspace<S>;                                                                   \
  template Status gravity_forces<S>(const ModelTpl<S>&, DataTpl<S>&, const ConstVecRef<S>&);                   \
  template Status external_forces_to_generalized<S>(const ModelTpl<S>&, DataTpl<S>&, const ConstVecRef<S>&,    \
                                                    const S*);                                                 \
  template Status coriolis_matrix<S>(const ModelTpl<S>&, DataTpl<S>&, EquationTermsWorkspace<S>&,              \
                                     const ConstVecRef<S>&, const ConstVecRef<S>&, Eigen::Ref<MatX<S>>);       \
  template Status mass_matrix_derivative<S>(const ModelTpl<S>&, DataTpl<S>&, EquationTermsWorkspace<S>&,       \
                                            const ConstVecRef<S>&, const ConstVecRef<S>&, Eigen::Ref<MatX<S>>, \
                                            Eigen::Ref<MatX<S>>);                                              \
  template Status christoffel_symbols<S>(const ModelTpl<S>&, DataTpl<S>&, EquationTermsWorkspace<S>&,          \
                                         const ConstVecRef<S>&, Eigen::Ref<MatX<S>>);
SOADYN_INSTANTIATE(double)
#if SOADYN_FLOAT
SOADYN_INSTANTIATE(float)
#endif
}  // namespace soadyn
