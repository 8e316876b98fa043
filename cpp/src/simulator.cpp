#include "soadyn/sim/simulator.hxx"

namespace soadyn {
template class SimulatorTpl<double>;
template class SimulatorTpl<float>;
}  // namespace soadyn
