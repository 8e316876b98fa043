// Built-in scenes (see scenes.hpp for the sources of the parameters).
#include "soadyn_scenes/scenes.hpp"

#include "soadyn/flex/cantilever_beam.hpp"

#include <cmath>
#include <initializer_list>
#include <stdexcept>
#include <string>

namespace soadyn {

namespace {

// Principal inertia of a thin rod of `length` along `axis`, about its centre.
template <class S>
Mat3<S> rod(S mass, S length, int axis) {
  Mat3<S> I = Mat3<S>::Identity() * (mass * length * length / S(12));
  I(axis, axis) = S(1e-3) * mass;
  return I;
}

// A uniform slender rod of `length` along its body x axis, hinged at its end:
// centre of mass at length/2 and principal moments m l^2/12 (none about the axis).
template <class S>
struct SlenderRod {
  S mass, length;
  Vec3<S> com() const { return Vec3<S>(length / S(2), S(0), S(0)); }
  Mat3<S> inertia() const {
    const S across = mass * length * length / S(12);
    return Vec3<S>(S(0), across, across).asDiagonal();
  }
};

template <class S>
int add_rod(ModelTpl<S>& m, const std::string& name, const std::string& parent, const JointModel<S>& joint,
            const Transform<S>& placement, const SlenderRod<S>& rod) {
  return m.add_body(name, parent, joint, placement, rod.mass, rod.com(), rod.inertia());
}

// The cut of a planar scene: the physical pin ("revolute") or its point form.
void require_planar_cut(LoopKind closure, const char* scene) {
  if (closure != LoopKind::revolute && closure != LoopKind::point)
    throw std::invalid_argument(std::string(scene) + ": the loop must be 'revolute' or 'point', got '" +
                                loop_kind_name(closure) + "'");
}

// The start of the planar linkages: gravity -9.81 m/s^2 along y, a "crank"
// hinged to the world at the origin and a rod `rod_name` hinged to its tip,
// both about z.
template <class S>
ModelTpl<S> crank_and_rod(LoopKind closure, const char* scene, const SlenderRod<S>& crank, const std::string& rod_name,
                          const SlenderRod<S>& rod) {
  require_planar_cut(closure, scene);
  ModelTpl<S> m;
  m.gravity = Vec3<S>(S(0), S(-9.81), S(0));
  const RevoluteJoint<S> hinge{Vec3<S>::UnitZ()};
  add_rod<S>(m, "crank", "", hinge, Transform<S>(), crank);
  Transform<S> tip;
  tip.translation.x() = crank.length;
  add_rod<S>(m, rod_name, "crank", hinge, tip, rod);
  return m;
}

// Solid cylinder of `radius` and `height` along `axis`, about its centre.
template <class S>
Mat3<S> cylinder(S mass, S radius, S height, int axis = 2) {
  Mat3<S> I = Mat3<S>::Identity() * (mass * (S(3) * radius * radius + height * height) / S(12));
  I(axis, axis) = mass * radius * radius / S(2);
  return I;
}

template <class S>
Transform<S> at(S x, S y, S z) {
  Transform<S> X;
  X.translation << x, y, z;
  return X;
}

// A rotation whose z column is the unit `axis`.
template <class S>
Mat3<S> frame_with_z(const Vec3<S>& axis) {
  const Vec3<S> z = axis.normalized();
  const Vec3<S> helper = std::abs(z.x()) < S(0.9) ? Vec3<S>::UnitX() : Vec3<S>::UnitY();
  const Vec3<S> x = helper.cross(z).normalized();
  Mat3<S> R;
  R << x, z.cross(x), z;
  return R;
}

template <class S>
Vec3<S> vec(S x, S y, S z) {
  return Vec3<S>(x, y, z);
}

// A uniform boom (cantilever_beam: two bending modes per plane, 40 lumped
// segments) with modal damping ratio `zeta`: C_kk = 2 zeta sqrt(K_kk M_kk)
// (the beam's modes are mass- and stiffness-orthogonal to within the lumping).
template <class S>
FlexibleBodyTpl<S> boom(S length, S bending_stiffness, S mass_per_length, S zeta) {
  using std::sqrt;
  FlexibleBodyDescription<S> d = cantilever_beam<S>(length, bending_stiffness, mass_per_length, 2, 40).description();
  const FlexibleBodyTpl<S> undamped(d);
  d.damping.setZero();
  for (int k = 0; k < undamped.n_modes(); ++k)
    d.damping(k, k) = S(2) * zeta * sqrt(undamped.stiffness()(k, k) * undamped.modal_mass()(k, k));
  return FlexibleBodyTpl<S>(d);
}

// Placement at (x, y, z) whose x axis (a boom's axis) points along `axis`.
template <class S>
Transform<S> boom_mount(S x, S y, S z, const Vec3<S>& axis) {
  Transform<S> X = at<S>(x, y, z);
  const Mat3<S> R = frame_with_z(axis);  // z column = axis
  X.rotation << R.col(2), R.col(0), R.col(1);
  return X;
}

}  // namespace

template <class S>
ModelTpl<S> cassini_model() {
  using R = RevoluteJoint<S>;
  ModelTpl<S> m;
  m.gravity.setZero();  // in orbit: free fall
  const Vec3<S> zero = Vec3<S>::Zero();
  m.add_body("bus", -1, FreeJoint<S>{}, Transform<S>(), S(2500), vec<S>(0, 0, 1.5), cylinder<S>(2500, 1, 4));
  m.add_body("high_gain_antenna", "bus", FixedJoint<S>{}, at<S>(0, 0, 4), S(105),
             zero, Vec3<S>(105, 105, 210).asDiagonal());
  m.add_body("huygens_probe", "bus", FixedJoint<S>{}, at<S>(1.3, 0, 1), S(320), zero, cylinder<S>(320, 1.35, 0.6, 0));
  // Flexible booms clamped to the bus: the 11 m, 30 kg magnetometer boom
  // (first bending mode 0.50 Hz) and a 10 m, 4 kg radio and plasma wave
  // antenna (0.30 Hz), both with 0.5 % modal damping.
  m.add_flexible_body("magnetometer_boom", "bus", FixedJoint<S>{}, boom_mount<S>(0, 1, 3.5, Vec3<S>::UnitY()),
                      boom<S>(11, 3.2e4, S(30) / S(11), S(0.005)));
  m.add_flexible_body("plasma_wave_antenna", "bus", FixedJoint<S>{}, boom_mount<S>(-1, 0.5, 3.8, -Vec3<S>::UnitX()),
                      boom<S>(10, 1150, 0.4, S(0.005)));
  m.add_body("turntable", "bus", R{Vec3<S>::UnitZ()}, at<S>(0, -1.2, 0.5), S(80), vec<S>(0, 0, 0.2),
             cylinder<S>(80, 0.6, 0.3));
  m.add_body("scan_az", "bus", R{Vec3<S>::UnitZ()}, at<S>(-1.2, 0, 2.5), S(40), vec<S>(0, 0, 0.3),
             cylinder<S>(40, 0.3, 0.6));
  m.add_body("scan_el", "scan_az", R{Vec3<S>::UnitX()}, at<S>(0, 0, 0.6), S(60), vec<S>(0, 0.2, 0.1),
             Vec3<S>(3, 2, 2.5).asDiagonal());
  m.add_body("probe_relay_antenna", "bus", R{Vec3<S>::UnitY()}, at<S>(0.8, 0.8, 3), S(5), vec<S>(0, 0, 0.25),
             cylinder<S>(5, 0.25, 0.05));
  m.add_body("gimbal_pitch", "bus", R{Vec3<S>::UnitX()}, at<S>(0, 0, -0.5), S(4), zero,
             Mat3<S>(Mat3<S>::Identity() * S(0.05)));
  m.add_body("engine", "gimbal_pitch", R{Vec3<S>::UnitY()}, Transform<S>(), S(15), vec<S>(0, 0, -0.5),
             cylinder<S>(15, 0.3, 1), "gimbal_yaw");
  const Vec3<S> wheel_axes[4] = {Vec3<S>::UnitX(), Vec3<S>::UnitY(), Vec3<S>::UnitZ(), Vec3<S>::Ones()};
  for (int k = 0; k < 4; ++k) {
    Transform<S> X = at<S>(S(0.5) * (S(k) - S(1.5)), -0.5, 1);
    X.rotation = frame_with_z(wheel_axes[k]);
    m.add_body("wheel_" + std::to_string(k + 1), "bus", R{Vec3<S>::UnitZ()}, X, S(12), zero,
               cylinder<S>(12, 0.17, 0.08));
  }
  const char* slosh[2] = {"oxidizer_slosh", "fuel_slosh"};
  const S height[2] = {S(2.2), S(0.9)};
  for (int k = 0; k < 2; ++k)
    m.add_body(slosh[k], "bus", UniversalJoint<S>{Vec3<S>::UnitX(), Vec3<S>::UnitY()}, at<S>(0, 0, height[k]), S(400),
               vec<S>(0, 0, -0.35), Mat3<S>::Identity());
  for (const char* dof : {"turntable", "gimbal_pitch", "gimbal_yaw"}) m.set_prescribed(m.dof_index(dof), true);
  return m;
}

template <class S>
void drive_cassini(SimulatorTpl<S>& sim) {
  ConstantAcceleration<S> rate;
  rate.v0 = S(kTurntableRate);
  sim.prescribe(sim.model().dof_index("turntable"), rate);
  // Gimbal under direct velocity control: rate commands w(t) = A sin(2 pi t / T + phase),
  // A = 0.5 deg/s, T = 20 s, yaw a quarter period behind pitch.
  const char* axes[2] = {"gimbal_pitch", "gimbal_yaw"};
  for (int k = 0; k < 2; ++k) {
    const S amplitude = S(0.5 * 3.14159265358979323846 / 180.0), omega = S(2 * 3.14159265358979323846 / 20.0);
    const S phase = S(k) * S(3.14159265358979323846 / 2);
    const S start = amplitude / omega * std::cos(phase);  // the position's constant term, once
    CallbackSource<S> command;
    command.fn = [amplitude, omega, phase, start](S t) {
      using std::cos;
      using std::sin;
      const S angle = omega * t + phase;
      const S cosine = cos(angle), sine = sin(angle);
      return MotionSample<S>{start - amplitude / omega * cosine, amplitude * sine, amplitude * omega * cosine};
    };
    sim.prescribe(sim.model().dof_index(axes[k]), command);
  }
}

template <class S>
ModelTpl<S> pendulum_chain_model(int links, S length, S mass) {
  if (links < 1) throw std::invalid_argument("pendulum_chain needs at least one link, got " + std::to_string(links));
  ModelTpl<S> m;
  for (int i = 0; i < links; ++i)
    m.add_body("link_" + std::to_string(i + 1), i - 1, RevoluteJoint<S>{Vec3<S>::UnitX()},
               at<S>(0, 0, i ? -length : S(0)), mass, vec<S>(0, 0, -length / S(2)), rod<S>(mass, length, 2));
  return m;
}

template <class S>
ModelTpl<S> four_bar_model(LoopKind closure) {
  using D = FourBarData;
  ModelTpl<S> m = crank_and_rod<S>(closure, "four_bar", {S(D::crank_mass), S(D::crank_length)}, "coupler",
                                   {S(D::coupler_mass), S(D::coupler_length)});
  add_rod<S>(m, "rocker", "", RevoluteJoint<S>{Vec3<S>::UnitZ()}, at<S>(D::ground_length, 0, 0),
             {S(D::rocker_mass), S(D::rocker_length)});
  m.add_loop("coupler_rocker", "coupler", "rocker", closure, at<S>(D::coupler_length, 0, 0),
             at<S>(D::rocker_length, 0, 0));
  return m;
}

template <class S>
ModelTpl<S> slider_crank_model(LoopKind closure) {
  using D = SliderCrankData;
  ModelTpl<S> m = crank_and_rod<S>(closure, "slider_crank", {S(D::crank_mass), S(D::crank_length)},
                                   "connecting_rod", {S(D::rod_mass), S(D::rod_length)});
  const S cube = S(D::slider_mass * D::slider_size * D::slider_size / 6.0);
  m.add_body("slider", "", PrismaticJoint<S>{Vec3<S>::UnitX()}, at<S>(0, D::offset, 0), S(D::slider_mass),
             Vec3<S>::Zero(), Mat3<S>(Mat3<S>::Identity() * cube));
  m.add_loop("wrist_pin", "connecting_rod", "slider", closure, at<S>(D::rod_length, 0, 0), Transform<S>());
  return m;
}

template <class S>
ModelTpl<S> delta_robot_model() {
  using D = DeltaRobotData;
  using std::cos;
  using std::sin;
  ModelTpl<S> m;
  const SlenderRod<S> arm{S(D::arm_mass), S(D::arm_length)}, rod{S(D::rod_mass), S(D::rod_length)};
  const UniversalJoint<S> elbow{Vec3<S>::UnitY(), Vec3<S>::UnitZ()};
  std::string rods[6];
  Vec3<S> balls[6];  // each rod's ball joint on the plate, in the plate frame
  for (int k = 0; k < 3; ++k) {
    const S azimuth = S(2 * 3.14159265358979323846 / 3) * S(k);
    const Vec3<S> radial(cos(azimuth), sin(azimuth), S(0)), tangent(-sin(azimuth), cos(azimuth), S(0));
    // Hinge frame: x radial, y the tangent (the hinge axis), z up.
    Transform<S> hinge;
    hinge.rotation << radial, tangent, Vec3<S>::UnitZ();
    hinge.translation = S(D::base_radius) * radial;
    const std::string arm_name = "arm_" + std::to_string(k + 1);
    add_rod<S>(m, arm_name, "", RevoluteJoint<S>{Vec3<S>::UnitY()}, hinge, arm);
    for (int side = 0; side < 2; ++side) {
      const S across = (side ? S(-0.5) : S(0.5)) * S(D::rod_spacing);
      const int r = 2 * k + side;
      rods[r] = "rod_" + std::to_string(k + 1) + (side ? "b" : "a");
      add_rod<S>(m, rods[r], arm_name, elbow, at<S>(D::arm_length, across, 0), rod);
      balls[r] = S(D::plate_radius) * radial + across * tangent;
    }
  }
  const S disc = S(D::plate_mass * D::plate_radius * D::plate_radius / 4.0);
  m.add_body("plate", "", FreeJoint<S>{}, Transform<S>(), S(D::plate_mass), Vec3<S>::Zero(),
             Vec3<S>(disc, disc, S(2) * disc).asDiagonal());
  for (int r = 0; r < 6; ++r) {
    Transform<S> on_plate;
    on_plate.translation = balls[r];
    m.add_loop("ball_" + rods[r].substr(4), rods[r], "plate", LoopKind::point, at<S>(D::rod_length, 0, 0), on_plate);
  }
  return m;
}

// ---------------------------------------------------------------------------
// Closed-form states of the loop scenes
// ---------------------------------------------------------------------------

namespace {

template <class S>
void require_finite(const char* what, std::initializer_list<S> values) {
  for (S x : values)
    if (!std::isfinite(static_cast<double>(x)))
      throw std::invalid_argument(std::string(what) + ": arguments must be finite");
}

template <class S>
Eigen::Matrix<S, 2, 1> unit(S angle) {
  return {std::cos(angle), std::sin(angle)};
}

// d/d(angle) of unit(angle).
template <class S>
Eigen::Matrix<S, 2, 1> normal(S angle) {
  return {-std::sin(angle), std::cos(angle)};
}

template <class S>
S angle_of(const Eigen::Matrix<S, 2, 1>& x) {
  return std::atan2(x.y(), x.x());
}

// `angle` wrapped to (-pi, pi].
template <class S>
S wrapped(S angle) {
  return std::atan2(std::sin(angle), std::cos(angle));
}

template <class S>
SceneState<S> planar_state(S crank, S second_absolute, S third, S crank_rate, S second_rate, S third_rate) {
  SceneState<S> state{VecX<S>(3), VecX<S>(3)};
  state.q << crank, wrapped(second_absolute - crank), third;
  state.v << crank_rate, second_rate - crank_rate, third_rate;
  return state;
}

}  // namespace

template <class S>
SceneState<S> four_bar_state(S crank_angle, S crank_rate) {
  using D = FourBarData;
  using V2 = Eigen::Matrix<S, 2, 1>;
  require_finite("four_bar_state", {crank_angle, crank_rate});
  const S a = S(D::crank_length), b = S(D::coupler_length), c = S(D::rocker_length);
  // The pin Q is where the circles of radius b about the crank's tip P and c about O2 meet.
  const V2 tip = a * unit(crank_angle), pivot(S(D::ground_length), S(0));
  const V2 diagonal = pivot - tip;
  const S length = diagonal.norm();
  const S along = (b * b - c * c + length * length) / (S(2) * length), height_sq = b * b - along * along;
  if (!(height_sq >= S(0)))
    throw std::invalid_argument("four_bar_state: the linkage does not close at crank angle " +
                                std::to_string(crank_angle));
  const V2 direction = diagonal / length;
  const V2 pin = tip + along * direction + std::sqrt(height_sq) * V2(-direction.y(), direction.x());
  const S coupler = angle_of<S>(pin - tip), rocker = angle_of<S>(pin - pivot);
  // Time derivative of the closure a e(t1) + b e(phi2) - c e(t3) = O2 (Saha, Shah & Nandihal 2013,
  // Eqs. 51-52): b phi2' n(phi2) - c t3' n(t3) = -a t1' n(t1), solved for (phi2', t3').
  Eigen::Matrix<S, 2, 2> J;
  J << b * normal(coupler), -c * normal(rocker);
  const V2 rates = J.partialPivLu().solve(-a * crank_rate * normal(crank_angle));
  return planar_state(crank_angle, coupler, rocker, crank_rate, rates.x(), rates.y());
}

template <class S>
SceneState<S> slider_crank_state(S crank_angle, S crank_rate) {
  using D = SliderCrankData;
  require_finite("slider_crank_state", {crank_angle, crank_rate});
  const S r = S(D::crank_length), l = S(D::rod_length);
  // The rod's absolute angle phi: sin phi = (offset - P_y) / l, the slider at x = P_x + l cos phi.
  const S rise = (S(D::offset) - r * std::sin(crank_angle)) / l;
  if (!(std::abs(rise) < S(1)))
    throw std::invalid_argument("slider_crank_state: the linkage does not close at crank angle " +
                                std::to_string(crank_angle));
  const S rod = std::asin(rise), x = r * std::cos(crank_angle) + l * std::cos(rod);
  // Differentiated: phi' = -r w cos(t) / (l cos phi), x' = -r w sin(t) - l phi' sin(phi).
  const S rod_rate = -r * crank_rate * std::cos(crank_angle) / (l * std::cos(rod));
  const S x_rate = -r * crank_rate * std::sin(crank_angle) - l * rod_rate * std::sin(rod);
  return planar_state(crank_angle, rod, x, crank_rate, rod_rate, x_rate);
}

namespace {

// One Delta arm (k = 0, 1, 2) placed for the plate at `position` moving at `velocity`.
template <class S>
struct DeltaArm {
  S angle, rate;        // the arm's hinge
  S swing, swing_rate;  // the rods' universal joints: about the arm's hinge axis,
  S lean, lean_rate;    // then about the rod frame's z
};

// In the hinge frame (radial u, tangent w, up z) the elbow is E = B + L_a (cos t, 0, -sin t) and the
// parallelogram's mid-line r = P - E (P: the arm's mid-ball on the plate) has |r| = L_f:
// a cos t - c sin t = K with (a, c) the u and z parts of P - B and K = (|P - B|^2 + L_a^2 - L_f^2) / (2 L_a),
// so t = beta - acos(K / rho), rho = hypot(a, c), beta = atan2(-c, a) (the elbow-out branch). Each rod
// points along n = r / L_f; in the arm's frame n = (cos al cos be, sin be, -sin al cos be) for the
// universal joint Rot(y, al) Rot(z, be).
template <class S>
DeltaArm<S> delta_arm(int k, const Vec3<S>& position, const Vec3<S>& velocity) {
  using D = DeltaRobotData;
  using std::cos;
  using std::sin;
  const S azimuth = S(2 * 3.14159265358979323846 / 3) * S(k), La = S(D::arm_length), Lf = S(D::rod_length);
  Mat3<S> hinge;  // columns u, w, z
  hinge << cos(azimuth), -sin(azimuth), S(0), sin(azimuth), cos(azimuth), S(0), S(0), S(0), S(1);
  const Vec3<S> d = hinge.transpose() * position + Vec3<S>(S(D::plate_radius) - S(D::base_radius), S(0), S(0));
  const S rho = std::hypot(d.x(), d.z());
  const S K = (d.squaredNorm() + La * La - Lf * Lf) / (S(2) * La);
  if (!(std::abs(K) < rho))
    throw std::invalid_argument("delta_robot_state: the plate position is out of reach of arm_" +
                                std::to_string(k + 1));
  DeltaArm<S> arm;
  arm.angle = std::atan2(-d.z(), d.x()) - std::acos(K / rho);
  const S c = cos(arm.angle), s = sin(arm.angle);
  const Vec3<S> elbow_per_rate = La * Vec3<S>(-s, S(0), -c);  // dE/dt per unit arm rate
  const Vec3<S> r = d - La * Vec3<S>(c, S(0), -s), p_dot = hinge.transpose() * velocity;
  arm.rate = r.dot(p_dot) / r.dot(elbow_per_rate);
  const Vec3<S> r_dot = p_dot - arm.rate * elbow_per_rate;
  // The rod's direction in the arm's frame (rotated by Ry(angle)) and its rate of change.
  Mat3<S> Ry;
  Ry << c, S(0), s, S(0), S(1), S(0), -s, S(0), c;
  const Vec3<S> n = Ry.transpose() * r / Lf;
  const Vec3<S> n_dot = Ry.transpose() * r_dot / Lf - arm.rate * Vec3<S>::UnitY().cross(n);
  arm.swing = std::atan2(-n.z(), n.x());
  arm.lean = std::asin(n.y());
  arm.swing_rate = (n.z() * n_dot.x() - n.x() * n_dot.z()) / (n.x() * n.x() + n.z() * n.z());
  arm.lean_rate = n_dot.y() / cos(arm.lean);
  return arm;
}

}  // namespace

template <class S>
SceneState<S> delta_robot_state(const Vec3<S>& position, const Vec3<S>& velocity) {
  require_finite("delta_robot_state",
                 {position.x(), position.y(), position.z(), velocity.x(), velocity.y(), velocity.z()});
  // Layout of delta_robot_model: per arm k, the arm's angle then its two rods' (swing, lean): 5 coordinates
  // at 5 k; then the plate's free joint (position, quaternion x y z w; v: angular, linear), at 15.
  SceneState<S> state{VecX<S>::Zero(22), VecX<S>::Zero(21)};
  for (int k = 0; k < 3; ++k) {
    const DeltaArm<S> arm = delta_arm(k, position, velocity);
    state.q(5 * k) = arm.angle;
    state.v(5 * k) = arm.rate;
    for (int rod = 0; rod < 2; ++rod) {
      state.q.template segment<2>(5 * k + 1 + 2 * rod) << arm.swing, arm.lean;
      state.v.template segment<2>(5 * k + 1 + 2 * rod) << arm.swing_rate, arm.lean_rate;
    }
  }
  state.q.template segment<3>(15) = position;
  state.q(21) = S(1);  // level: the identity quaternion
  state.v.template segment<3>(18) = velocity;
  return state;
}

#define SOADYN_INSTANTIATE_SCENES(S)                                                   \
  template ModelTpl<S> cassini_model<S>();                                              \
  template void drive_cassini<S>(SimulatorTpl<S>&);                                     \
  template ModelTpl<S> pendulum_chain_model<S>(int, S, S);                              \
  template ModelTpl<S> four_bar_model<S>(LoopKind);                                     \
  template ModelTpl<S> slider_crank_model<S>(LoopKind);                                 \
  template ModelTpl<S> delta_robot_model<S>();                                          \
  template SceneState<S> four_bar_state<S>(S, S);                                       \
  template SceneState<S> slider_crank_state<S>(S, S);                                   \
  template SceneState<S> delta_robot_state<S>(const Vec3<S>&, const Vec3<S>&);
SOADYN_INSTANTIATE_SCENES(double)
#if SOADYN_FLOAT
SOADYN_INSTANTIATE_SCENES(float)
#endif

}  // namespace soadyn
