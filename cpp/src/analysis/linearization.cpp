#include "soadyn/analysis/linearization.hxx"

namespace soadyn {
template struct LinearizationTpl<double>;
template Status linearize<double>(const Model&, Data&, LinearizationTpl<double>&, const ConstVecRef<double>&,
                                  const ConstVecRef<double>&, const ConstVecRef<double>&, const double*);
template Status linearize_step<double>(const Model&, Data&, LinearizationTpl<double>&, const ConstVecRef<double>&,
                                       const ConstVecRef<double>&, const ConstVecRef<double>&, double, Integrator,
                                       const double*);
}  // namespace soadyn
