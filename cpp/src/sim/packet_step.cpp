// The Simulator's step on packets (sim/packet_simulation.hpp), compiled for
// AVX2 without fused multiply-adds as the packet kernels are
// (CMakeLists.txt), so each lane rounds as the Simulator on doubles does.
// Only the step (and the setup's members that reach the dynamics) is here:
// the Simulator is built, fed and read in packet_simulation.cpp, compiled
// for the baseline, so that this object holds no copy of the model or text
// of a message (tests/cpp/check_packet_objects.py).
#include "soadyn/algorithms/configuration.hxx"
#include "soadyn/algorithms/energy.hxx"
#include "soadyn/constraints/constrained_dynamics.hxx"
#include "soadyn/constraints/constrained_impulse.hxx"
#include "soadyn/constraints/loop_assembly.hxx"
#include "soadyn/constraints/loop_closure.hxx"
#include "soadyn/core/packet.hpp"
#include "soadyn/model/model.hxx"
#include "soadyn/sim/chart.hpp"
#include "soadyn/sim/simulator.hxx"

namespace soadyn {
template Status SimulatorTpl<Packet4d>::step();
// For packet_simulation.cpp's setup (set_state, prescribe), which must not
// instantiate them for the baseline.
template Status SimulatorTpl<Packet4d>::switch_mode(int, Drive, int, bool);
template void SimulatorTpl<Packet4d>::restart_divergence_guard();
template bool detail::fires_after<Packet4d>(const Event<Packet4d>&, const Event<Packet4d>&);
// For packet_dynamics.cpp (the packet model's cast and refresh).
template void ModelTpl<Packet4d>::refresh_leaf_presums();
}  // namespace soadyn
