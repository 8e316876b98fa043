#include "soadyn/flex/cantilever_beam.hxx"
#include "soadyn/flex/flexible_body.hxx"
#include "soadyn/flex/modal_integrals.hxx"

namespace soadyn {
template struct ModalIntegrals<double>;
template struct ModalIntegrals<float>;
template void ModalIntegrals<double>::second_moment_rates<Eigen::Dynamic>(const Eigen::Ref<const VecX<double>>&,
                                                                           MatX<double>&) const;
template void ModalIntegrals<float>::second_moment_rates<Eigen::Dynamic>(const Eigen::Ref<const VecX<float>>&,
                                                                         MatX<float>&) const;
template void ModalIntegrals<double>::inertial_bias<Eigen::Dynamic>(const Eigen::Ref<const VecX<double>>&,
                                                                     const Vec6<double>&, const Vec6<double>&,
                                                                     const MatX<double>&, Eigen::Ref<VecX<double>>) const;
template void ModalIntegrals<float>::inertial_bias<Eigen::Dynamic>(const Eigen::Ref<const VecX<float>>&,
                                                                    const Vec6<float>&, const Vec6<float>&,
                                                                    const MatX<float>&, Eigen::Ref<VecX<float>>) const;
template MatX<double> modal_mass_matrix<double>(const FlexibleNodes<double>&, int);
template MatX<float> modal_mass_matrix<float>(const FlexibleNodes<float>&, int);
template struct FlexibleBodyDescription<double>;
template struct FlexibleBodyDescription<float>;
template class FlexibleBodyTpl<double>;
template class FlexibleBodyTpl<float>;
template double clamped_free_root<double>(int);
template float clamped_free_root<float>(int);
template class ClampedFreeMode<double>;
template class ClampedFreeMode<float>;
template FlexibleBodyTpl<double> cantilever_beam<double>(const double&, const double&, const double&, int, int);
template FlexibleBodyTpl<float> cantilever_beam<float>(const float&, const float&, const float&, int, int);
}  // namespace soadyn
