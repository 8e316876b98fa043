// The Simulator for double and float, and the joint charts it integrates on
// (sim/chart.hpp), compiled for both scalars here.
#include "soadyn/sim/chart.hpp"
#include "soadyn/sim/simulator.hxx"

namespace soadyn {
template class SimulatorTpl<double>;
#if SOADYN_FLOAT
template class SimulatorTpl<float>;
#endif

#define SOADYN_INSTANTIATE_CHARTS(S)                                                   \
  template void chart_retract<S>(const JointModel<S>&, const S*, const S*, S*);        \
  template void chart_rate<S>(const JointModel<S>&, const S*, const S*, const S*, S*);
SOADYN_INSTANTIATE_CHARTS(double)
#if SOADYN_FLOAT
SOADYN_INSTANTIATE_CHARTS(float)
#endif
}  // namespace soadyn
