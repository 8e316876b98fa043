// Built-in scenes, shared by C++ programs and the Python package.
//
// cassini: the application example of the prescribed-motion paper (Jain &
// Rodriguez): a free-flying spacecraft bus with a turntable driven at 3 rpm,
// a two-axis scan platform, a probe relay antenna, a two-axis main-engine
// gimbal, four reaction wheels and two fuel-slosh pendulums, in free fall.
// Masses and sizes are round figures of the Cassini orbiter's published
// class (about 2.5 t dry bus, an 11 m magnetometer boom, a 4 m high-gain
// antenna, the 320 kg Huygens probe): plausible, not flight data.
// Prescribed DOFs: turntable, gimbal_pitch, gimbal_yaw. Two flexible booms
// clamped to the bus (flex/flexible_body.hpp): the magnetometer boom
// (first bending mode 0.50 Hz) and a radio and plasma wave antenna
// (0.30 Hz), each with two bending modes per plane and 0.5 % damping.
//
// pendulum_chain: n identical links swinging about parallel x axes.
#pragma once
#include "soadyn/model.hpp"
#include "soadyn/sim/simulator.hpp"

namespace soadyn {

constexpr double kTurntableRate = 3.0 * 2.0 * 3.14159265358979323846 / 60.0;  // 3 rpm in rad/s

template <class S>
ModelTpl<S> cassini_model();

// Drives the scene's simulator as in the paper: the turntable at 3 rpm and
// the two-axis engine gimbal under direct velocity control (slow sinusoidal
// rate commands of 0.5 deg/s amplitude, period 20 s).
template <class S>
void drive_cassini(SimulatorTpl<S>& sim);

template <class S>
ModelTpl<S> pendulum_chain_model(int links, S length = S(0.5), S mass = S(1));

extern template ModelTpl<double> cassini_model<double>();
extern template ModelTpl<float> cassini_model<float>();
extern template void drive_cassini<double>(SimulatorTpl<double>&);
extern template void drive_cassini<float>(SimulatorTpl<float>&);
extern template ModelTpl<double> pendulum_chain_model<double>(int, double, double);
extern template ModelTpl<float> pendulum_chain_model<float>(int, float, float);

}  // namespace soadyn
