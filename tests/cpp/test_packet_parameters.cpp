// Four runs with their own parameter values in one Simulator of packets
// (PacketModel::of_lanes, run_packet_simulation), against a Simulator on
// each run's model alone.
//
// - A random tree of 20 bodies (every joint type, a free root) with a joint
//   spring and a point spring; the four models differ in a mass, a centre
//   of mass, an inertia, a placement's translation, gravity and the springs'
//   constants, set through the ParameterTable as a rollout sets them. The
//   packet model holds each model's values in its lane, and 200 RK4 steps of
//   the four runs side by side, from four random states with their own
//   torques, equal each run's own Simulator, bit for bit. The runs stand as
//   one packet throughout:
//   gravity's x entry is zero in lane 0 only (one answer for the whole
//   vector, exactly_zero), and the charts of the spherical and free joints
//   cross their series thresholds in some lanes only (spatial/lie.hpp).
//   Likewise with two DOFs driven by motion sources shared by the runs (with
//   RK4, and with DOPRI5: each lane takes its own sub-steps), and
//   with a lock and a release of a DOF at each run's own times, due in the
//   same steps in the four (the lock an impact: the impulse form on
//   packets). Times due in different steps split the packet, and a time
//   that is not finite in one lane is refused (the rollout then steps the
//   runs one by one, and the run alone reports it).
// - Four models whose values give them different derived properties (a
//   placement's rotation the identity in three lanes and a turn in the
//   fourth; an inertia diagonal in three lanes only) or different flags (a
//   DOF prescribed in one) get no packet model.
#include <cmath>
#include <cstdio>
#include <utility>
#include <vector>

#include <soadyn/algorithms/configuration.hpp>
#include <soadyn/algorithms/packet_dynamics.hpp>
#include <soadyn/model/parameters.hpp>
#include <soadyn/sim/packet_simulation.hpp>
#include <soadyn/sim/simulator.hpp>

#include "random_tree.hpp"

namespace {

constexpr int kLanes = soadyn::PacketSimulation::lanes;
constexpr int kSteps = 200;
using Models = std::array<soadyn::Model, kLanes>;

soadyn::Model tree_with_springs() {
  soadyn::Model m = soadyn_test::build_model<double>(soadyn_test::random_tree_spec(77, 20));
  int dof = -1;  // the first one-coordinate joint's DOF
  for (int b = m.nbodies() - 1; b >= 0; --b)
    if (m.nq_body[static_cast<std::size_t>(b)] == 1 && m.nv_body[static_cast<std::size_t>(b)] == 1)
      dof = m.v_index[static_cast<std::size_t>(b)];
  m.add_joint_spring("spring_a", dof, 3.0, 0.2, 0.1);
  const double rest = 0.25;
  m.add_point_spring("spring_b", m.body_names[2], m.body_names[9], Eigen::Vector3d(0.05, 0.0, 0.0),
                     Eigen::Vector3d(0.0, 0.02, 0.0), 40.0, 0.5, &rest);
  return m;
}

void set(const soadyn::ParameterTable<double>& table, soadyn::Model& m, const std::string& name,
         const std::vector<double>& values) {
  table.set(m, name, values.data());
}

// A placement as the table takes it: 4 x 4 column-major, a turn of `angle` about z.
std::vector<double> placement(double angle, const Eigen::Vector3d& p) {
  Eigen::Matrix4d H = Eigen::Matrix4d::Identity();
  H.topLeftCorner<3, 3>() = Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  H.topRightCorner<3, 1>() = p;
  return std::vector<double>(H.data(), H.data() + 16);
}

// Four copies of `base`, copy l with values that depend on l.
Models lane_models(const soadyn::Model& base) {
  const soadyn::ParameterTable<double> table(base);
  Models m{base, base, base, base};
  for (int l = 0; l < kLanes; ++l) {
    const double s = 1.0 + 0.1 * l;
    soadyn::Model& x = m[static_cast<std::size_t>(l)];
    set(table, x, "b3.mass", {base.mass[3] * s});
    set(table, x, "b5.com", {0.01 * l, -0.02, 0.03 * s});
    set(table, x, "b7.inertia", {0.02 * s, 0.001, 0.0, 0.001, 0.03, 0.002, 0.0, 0.002, 0.025});
    const soadyn::Transform<double>& X = base.placement[4];
    Eigen::Matrix4d H = Eigen::Matrix4d::Identity();
    H.topLeftCorner<3, 3>() = X.rotation;
    H.topRightCorner<3, 1>() = X.translation * s;
    set(table, x, "b4.placement", std::vector<double>(H.data(), H.data() + 16));
    set(table, x, "gravity", {0.1 * l, 0.0, -9.81 * s});
    set(table, x, "spring_a.stiffness", {3.0 * s});
    set(table, x, "spring_b.damping", {0.5 * s});
  }
  return m;
}

std::array<const soadyn::Model*, kLanes> pointers(const Models& m) { return {&m[0], &m[1], &m[2], &m[3]}; }

// Lanes of the packet model that hold another value than their model's
// (masses, centres of mass, inertias, placements, gravity, spring constants).
long lanes_differing(const soadyn::PacketModel& packets, const Models& m) {
  const soadyn::ModelTpl<soadyn::Packet4d>& p = packets.get();
  long differ = 0;
  for (int l = 0; l < kLanes; ++l) {
    const soadyn::Model& x = m[static_cast<std::size_t>(l)];
    for (int i = 0; i < x.nbodies(); ++i) {
      const std::size_t b = static_cast<std::size_t>(i);
      differ += p.mass[b][l] != x.mass[b];
      for (int k = 0; k < 3; ++k) {
        differ += p.com[b][k][l] != x.com[b][k];
        differ += p.placement[b].translation[k][l] != x.placement[b].translation[k];
        for (int c = 0; c < 3; ++c) {
          differ += p.inertia_com[b](k, c)[l] != x.inertia_com[b](k, c);
          differ += p.placement[b].rotation(k, c)[l] != x.placement[b].rotation(k, c);
        }
      }
      for (int k = 0; k < 36; ++k) differ += p.inertia[b](k)[l] != x.inertia[b](k);
    }
    for (int k = 0; k < 3; ++k) differ += p.gravity[k][l] != x.gravity[k];
    differ += p.force_elements.joint_springs[0].stiffness[l] != x.force_elements.joint_springs[0].stiffness;
    differ += p.force_elements.point_springs[0].damping[l] != x.force_elements.point_springs[0].damping;
  }
  return differ;
}

using Sources = std::vector<std::pair<int, soadyn::MotionSource<double>>>;

// Events of the same kinds and DOFs in the four runs, lane l at times[l].
struct Events {
  std::vector<std::pair<soadyn::EventKind, int>> kinds;
  std::array<std::vector<double>, kLanes> times;
};

// Runs of the four models side by side, with `sources` and `events`, against
// each alone: recorded entries that differ; -1 if the packet simulation did
// not stand.
long runs_differing(const Models& m, const soadyn::PacketModel& packets, const Sources& sources,
                    const Events& events = {}, soadyn::Integrator integrator = soadyn::Integrator::rk4,
                    long* uneven_steps = nullptr) {
  const soadyn::Model& base = m[0];
  const int nq = base.nq, nv = base.nv;
  soadyn_test::Random rng(11);
  std::vector<std::vector<double>> x0(kLanes), q(kLanes), v(kLanes), u(kLanes);
  soadyn::PacketSimulation s;
  s.model = &base;
  s.packets = &packets;
  s.dt = 1e-3;
  s.integrator = integrator;
  s.steps = kSteps;
  s.sources = &sources;
  s.events = events.kinds.empty() ? nullptr : &events.kinds;
  s.control_stride = nv;
  for (int l = 0; l < kLanes; ++l) {
    const std::size_t k = static_cast<std::size_t>(l);
    Eigen::VectorXd q0(nq);
    soadyn::random_configuration<double>(base, 100 + k, q0);
    x0[k].assign(q0.data(), q0.data() + nq);
    for (int j = 0; j < nv; ++j) x0[k].push_back(rng.uniform(-1, 1));
    for (int j = 0; j < kSteps * nv; ++j) u[k].push_back(rng.uniform(-0.5, 0.5));
    q[k].resize(static_cast<std::size_t>((kSteps + 1) * nq));
    v[k].resize(static_cast<std::size_t>((kSteps + 1) * nv));
    s.initial_states[l] = x0[k].data();
    s.controls[l] = u[k].data();
    s.event_times[l] = events.times[k].data();
    s.q[l] = q[k].data();
    s.v[l] = v[k].data();
  }
  if (!soadyn::run_packet_simulation(s)) return -1;
  long differ = 0;
  std::vector<std::vector<int>> substeps(kLanes);  // each run's sub-steps per step alone
  for (int l = 0; l < kLanes; ++l) {
    const std::size_t k = static_cast<std::size_t>(l);
    soadyn::Simulator alone(m[k], s.dt, integrator);
    for (const auto& [dof, source] : sources) alone.prescribe(dof, source);
    alone.set_state(Eigen::Map<const Eigen::VectorXd>(x0[k].data(), nq),
                    Eigen::Map<const Eigen::VectorXd>(x0[k].data() + nq, nv));
    for (std::size_t e = 0; e < events.kinds.size(); ++e)
      alone.schedule(events.times[k][e], events.kinds[e].first, events.kinds[e].second);
    for (int step = 1; step <= kSteps; ++step) {
      for (int j = 0; j < nv; ++j)  // the regular DOFs' torques (a sourced DOF is prescribed)
        if (!alone.model().is_prescribed(j)) alone.set_input(j, u[k][static_cast<std::size_t>((step - 1) * nv + j)]);
      if (!alone.step().ok()) return -1;
      substeps[k].push_back(alone.last_substeps());
      for (int j = 0; j < nq; ++j) differ += alone.q()[j] != q[k][static_cast<std::size_t>(step * nq + j)];
      for (int j = 0; j < nv; ++j) differ += alone.v()[j] != v[k][static_cast<std::size_t>(step * nv + j)];
    }
  }
  if (uneven_steps) {  // steps in which the runs alone took different numbers of sub-steps
    *uneven_steps = 0;
    for (std::size_t step = 0; step < substeps[0].size(); ++step)
      for (std::size_t l = 1; l < substeps.size(); ++l)
        if (substeps[l][step] != substeps[0][step]) {
          ++*uneven_steps;
          break;
        }
  }
  return differ;
}

// Two one-coordinate DOFs driven by a cycloidal move and a spline.
Sources two_sources(const soadyn::Model& m) {
  std::vector<int> dofs;
  for (int b = 0; b < m.nbodies(); ++b)
    if (m.nq_body[static_cast<std::size_t>(b)] == 1 && m.nv_body[static_cast<std::size_t>(b)] == 1)
      dofs.push_back(m.v_index[static_cast<std::size_t>(b)]);
  return {{dofs.at(0), soadyn::Cycloidal<double>{0.02, 0.1, 0.0, 0.4}},
          {dofs.at(2), soadyn::CubicSpline<double>({0.0, 0.05, 0.12, 0.2}, {0.1, -0.2, 0.3, 0.0})}};
}

// A lock of the third one-coordinate DOF at about 50 ms and its release at
// about 120 ms, lane l's times `spread` x l later than lane 0's.
Events lock_and_release(const soadyn::Model& m, double spread) {
  int dof = -1, found = 0;
  for (int b = 0; b < m.nbodies() && found < 3; ++b)
    if (m.nq_body[static_cast<std::size_t>(b)] == 1 && m.nv_body[static_cast<std::size_t>(b)] == 1) {
      dof = m.v_index[static_cast<std::size_t>(b)];
      ++found;
    }
  Events e;
  e.kinds = {{soadyn::EventKind::lock, dof}, {soadyn::EventKind::release, dof}};
  for (int l = 0; l < kLanes; ++l) e.times[static_cast<std::size_t>(l)] = {0.0501 + spread * l, 0.1201 + spread * l};
  return e;
}

// How many of the three sets of models that cannot share packets get none.
int refused_sets(const soadyn::Model& base) {
  const soadyn::ParameterTable<double> table(base);
  int refused = 0;
  Models turned{base, base, base, base};  // b4's rotation: the identity, but a turn in lane 2
  for (int l = 0; l < kLanes; ++l)
    set(table, turned[static_cast<std::size_t>(l)], "b4.placement", placement(l == 2 ? 0.3 : 0.0, {0.1, 0.0, 0.2}));
  refused += soadyn::PacketModel::of_lanes(pointers(turned)) == nullptr;
  Models diagonal{base, base, base, base};  // b6's inertia diagonal but in lane 3
  for (int l = 0; l < kLanes; ++l)
    set(table, diagonal[static_cast<std::size_t>(l)], "b6.inertia",
        {0.02, 0.0, 0.0, 0.0, 0.03, l == 3 ? 0.001 : 0.0, 0.0, l == 3 ? 0.001 : 0.0, 0.025});
  refused += soadyn::PacketModel::of_lanes(pointers(diagonal)) == nullptr;
  Models flags{base, base, base, base};  // DOF 4 prescribed in lane 1
  flags[1].set_prescribed(4, true);
  refused += soadyn::PacketModel::of_lanes(pointers(flags)) == nullptr;
  return refused;
}

}  // namespace

int main() {
  if (!soadyn::PacketDynamics::available()) {
    std::printf("test_packet_parameters: this processor runs no packets (AVX2 and FMA): FAIL\n");
    return 1;
  }
  const soadyn::Model base = tree_with_springs();
  const Models models = lane_models(base);
  const std::unique_ptr<soadyn::PacketModel> packets = soadyn::PacketModel::of_lanes(pointers(models));
  const long values = packets ? lanes_differing(*packets, models) : -1;
  std::printf("packet model of four parameter sets: %s, lane values differing from their model's: %ld\n",
              packets ? "built" : "refused", values);
  const long runs = packets ? runs_differing(models, *packets, {}) : -1;
  std::printf("four runs side by side, %d RK4 steps: entries differing from each run alone: %ld\n", kSteps, runs);
  const long sourced = packets ? runs_differing(models, *packets, two_sources(base)) : -1;
  std::printf("the same with two DOFs driven by sources (cycloidal, spline): entries differing: %ld\n", sourced);
  long uneven = 0;
  const long adaptive =
      packets ? runs_differing(models, *packets, two_sources(base), {}, soadyn::Integrator::dopri5, &uneven) : -1;
  std::printf("the same with DOPRI5, each lane its own sub-steps: entries differing: %ld; steps whose runs alone "
              "take different numbers of sub-steps: %ld\n", adaptive, uneven);
  const long locked = packets ? runs_differing(models, *packets, {}, lock_and_release(base, 2e-4)) : -1;
  std::printf("the same with a lock and a release at each run's times, due in the same steps: entries differing: %ld\n",
              locked);
  const long apart = packets ? runs_differing(models, *packets, {}, lock_and_release(base, 1.5e-3)) : 0;
  std::printf("events due in different steps: %s\n", apart < 0 ? "the packet splits" : "the packet stood (wrong)");
  Events unscheduled = lock_and_release(base, 2e-4);  // lane 2's lock at a time that is not finite
  unscheduled.times[2][0] = std::nan("");
  const long refused_event = packets ? runs_differing(models, *packets, {}, unscheduled) : 0;
  std::printf("an event time that is not finite in one lane: %s\n",
              refused_event < 0 ? "the packet is refused" : "the packet stood (wrong)");
  const int refused = refused_sets(base);
  std::printf("models that cannot share packets (a placement's axes, an inertia's symmetry, a flag): refused %d of 3\n",
              refused);
  const bool pass = values == 0 && runs == 0 && sourced == 0 && adaptive == 0 && uneven > 0 && locked == 0 &&
                    apart < 0 && refused_event < 0 && refused == 3;
  std::printf("test_packet_parameters: %s\n", pass ? "PASS" : "FAIL");
  return pass ? 0 : 1;
}
