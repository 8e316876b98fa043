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
//
// Closed-loop scenes (each a tree closed by cut joints, model/loop.hpp):
//
// four_bar: the planar crank-rocker of Saha, Shah & Nandihal, "Evolution of
// the DeNOC-based dynamic modelling for multibody systems", Mechanical
// Sciences 4, 2013 (Sect. 5, Fig. 16): crank 0.038 m (1.5 kg), coupler
// 0.1152 m (5 kg), output link (rocker) 0.1152 m (3 kg), ground 0.0895 m,
// uniform slender rods, gravity -9.81 m/s^2 along y in the x-y plane. Tree:
// "crank" hinged to the world at O1 = (0, 0, 0), "coupler" hinged to the
// crank's tip, "rocker" hinged to the world at O2 = (0.0895, 0, 0); all
// joints about z, each rod along its body x axis, so q = (crank angle from
// the ground line, coupler angle relative to the crank, rocker angle from the
// ground line). The loop "coupler_rocker" joins the coupler's tip to the
// rocker's tip: a "revolute" cut (the physical pin: 5 equations of rank 2)
// by default, or a "point" cut (3 equations of rank 2); both give the same
// motion and forces.
//
// slider_crank: an offset slider-crank in the x-y plane, gravity -9.81 m/s^2
// along y: "crank" 0.05 m (1 kg) hinged to the world at the origin,
// "connecting_rod" 0.2 m (1.5 kg) hinged to the crank's tip (uniform slender
// rods), and the "slider" (a 0.8 kg piston, a 0.05 m cube) on a prismatic
// joint along x whose line is y = 0.02 m (the offset); q = (crank angle,
// rod angle relative to the crank, slider position). The loop "wrist_pin"
// joins the rod's tip to the slider's origin ("revolute" by default, or
// "point").
//
// delta_robot: a Delta parallel robot (Clavel's architecture), base at
// z = 0 and gravity -9.81 m/s^2 along z. Three upper arms ("arm_1..3",
// 0.3 m, 0.4 kg slender rods) hinged at radius 0.2 m, at azimuths 0, 120
// and 240 degrees, about the horizontal tangent (DOF "arm_k": 0 horizontal,
// positive downwards). Each arm carries a parallelogram of two forearm rods
// ("rod_ka", "rod_kb", 0.7 m, 0.1 kg slender rods, 0.1 m apart along the
// arm's hinge axis) on universal joints (first axis parallel to the arm's
// hinge, then the rod frame's z; rods along their x axis). The travelling
// plate ("plate", 0.5 kg, a 0.05 m radius disc) is a free body; six "point"
// loops ("ball_ka", "ball_kb") join each rod's far end to the plate at
// radius 0.05 m, +-0.05 m along the arm's tangent: 21 DOFs, 18 loop
// equations, 3 degrees of freedom (the plate translates).
#pragma once
#include "soadyn/model/loop.hpp"
#include "soadyn/model/model.hpp"
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

// Dimensions (m) and masses (kg) of the closed-loop scenes.
struct FourBarData {
  static constexpr double crank_length = 0.038, coupler_length = 0.1152, rocker_length = 0.1152,
                          ground_length = 0.0895;
  static constexpr double crank_mass = 1.5, coupler_mass = 5.0, rocker_mass = 3.0;
};
struct SliderCrankData {
  static constexpr double crank_length = 0.05, rod_length = 0.2, offset = 0.02, slider_size = 0.05;
  static constexpr double crank_mass = 1.0, rod_mass = 1.5, slider_mass = 0.8;
};
struct DeltaRobotData {
  static constexpr double base_radius = 0.2, plate_radius = 0.05, arm_length = 0.3, rod_length = 0.7,
                          rod_spacing = 0.1;
  static constexpr double arm_mass = 0.4, rod_mass = 0.1, plate_mass = 0.5;
};

// The paper's four-bar, closed by a "revolute" or a "point" cut (any other
// kind: std::invalid_argument).
template <class S>
ModelTpl<S> four_bar_model(LoopKind closure = LoopKind::revolute);

// The offset slider-crank, closed by a "revolute" or a "point" cut.
template <class S>
ModelTpl<S> slider_crank_model(LoopKind closure = LoopKind::revolute);

template <class S>
ModelTpl<S> delta_robot_model();

// A closed state of a loop scene: q (nq) and v (nv) in the scene's layout.
template <class S>
struct SceneState {
  VecX<S> q, v;
};

// Closed-form position and velocity analysis (std::invalid_argument for a
// non-finite argument or a state the linkage cannot reach):
// four_bar_state: the four-bar at `crank_angle` (rad from the ground line)
// turning at `crank_rate`, in the assembly with the coupler-rocker pin above
// the ground line (on the left of the crank's tip -> O2);
// slider_crank_state: the slider on the far side of the crank's tip;
// delta_robot_state: the plate level with its centre at `position` (base
// frame), translating at `velocity`, each arm on its elbow-out branch.
template <class S>
SceneState<S> four_bar_state(S crank_angle, S crank_rate = S(0));
template <class S>
SceneState<S> slider_crank_state(S crank_angle, S crank_rate = S(0));
template <class S>
SceneState<S> delta_robot_state(const Vec3<S>& position, const Vec3<S>& velocity = Vec3<S>::Zero());

extern template ModelTpl<double> cassini_model<double>();
extern template ModelTpl<float> cassini_model<float>();
extern template void drive_cassini<double>(SimulatorTpl<double>&);
extern template void drive_cassini<float>(SimulatorTpl<float>&);
extern template ModelTpl<double> pendulum_chain_model<double>(int, double, double);
extern template ModelTpl<float> pendulum_chain_model<float>(int, float, float);
extern template ModelTpl<double> four_bar_model<double>(LoopKind);
extern template ModelTpl<float> four_bar_model<float>(LoopKind);
extern template ModelTpl<double> slider_crank_model<double>(LoopKind);
extern template ModelTpl<float> slider_crank_model<float>(LoopKind);
extern template ModelTpl<double> delta_robot_model<double>();
extern template ModelTpl<float> delta_robot_model<float>();
extern template SceneState<double> four_bar_state<double>(double, double);
extern template SceneState<float> four_bar_state<float>(float, float);
extern template SceneState<double> slider_crank_state<double>(double, double);
extern template SceneState<float> slider_crank_state<float>(float, float);
extern template SceneState<double> delta_robot_state<double>(const Vec3<double>&, const Vec3<double>&);
extern template SceneState<float> delta_robot_state<float>(const Vec3<float>&, const Vec3<float>&);

}  // namespace soadyn
