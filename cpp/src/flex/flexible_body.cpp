// Flexible bodies, modal integrals and cantilever beams for double (and
// float with SOADYN_FLOAT).
#include "soadyn/flex/cantilever_beam.hxx"
#include "soadyn/flex/flexible_body.hxx"
#include "soadyn/flex/modal_integrals.hxx"

namespace soadyn {
#define SOADYN_INSTANTIATE(S)                                                                                       \
  template struct ModalIntegrals<S>;                                                                                \
  template void ModalIntegrals<S>::second_moment_rates<Eigen::Dynamic>(const Eigen::Ref<const VecX<S>>&, MatX<S>&) \
      const;                                                                                                        \
  template void ModalIntegrals<S>::inertial_bias<Eigen::Dynamic>(const Eigen::Ref<const VecX<S>>&, const Vec6<S>&,  \
                                                                 const Vec6<S>&, const MatX<S>&,                    \
                                                                 Eigen::Ref<VecX<S>>) const;                        \
  template MatX<S> modal_mass_matrix<S>(const FlexibleNodes<S>&, int);                                              \
  template struct FlexibleBodyDescription<S>;                                                                       \
  template class FlexibleBodyTpl<S>;                                                                                \
  template S clamped_free_root<S>(int);                                                                             \
  template class ClampedFreeMode<S>;                                                                                \
  template FlexibleBodyTpl<S> cantilever_beam<S>(const S&, const S&, const S&, int, int);
SOADYN_INSTANTIATE(double)
#if SOADYN_FLOAT
SOADYN_INSTANTIATE(float)
#endif
}  // namespace soadyn
