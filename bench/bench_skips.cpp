// What each skip of the sweeps saves. Each row times the same problem two
// ways, with the skip and without it, batch by batch in turn (batch_timing.hpp),
// checks that both give the same accelerations and forces, and reports the
// median times and their ratio. "Without" runs what the library would run
// if it did not know better: every joint through the general joint code,
// body frames instead of tree frames, the flexible-body code on a rigid
// model, articulated inertias for every body, joint wrenches computed.
// Output: a markdown table on stdout; exit status 1 if a pair disagrees.
//
// Usage: bench_skips [batches]   (default 2000 batches per variant)
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>
#include "batch_timing.hpp"
#include "random_tree.hpp"  // tests/cpp: the models shared with the tests
#include "soadyn/algorithms/hybrid.hxx"
#include "soadyn_scenes/scenes.hpp"

namespace {

using namespace soadyn_bench;
using soadyn::Model;
using Flags = soadyn::detail::ModePolicy;

// A model, its states and one Data per variant (a variant may leave Data in
// another frame).
struct Scene {
  std::string name;
  Model model;
  std::vector<soadyn_test::State> states;
  Scene(std::string name_, Model m) : name(std::move(name_)), model(std::move(m)) {
    for (int k = 0; k < kStates; ++k) states.push_back(soadyn_test::random_state(model, 500 + k));
  }
  const soadyn_test::State& state(int k) const { return states[static_cast<std::size_t>(k)]; }
};

// One way of solving a scene's problem: `solve(model, data, state)`.
using Solver = std::function<void(const Model&, soadyn::Data&, const soadyn_test::State&)>;

struct Variant {
  Model model;
  std::unique_ptr<soadyn::Data> data;
  Solver solve;
  Variant(Model m, Solver s) : model(std::move(m)), data(std::make_unique<soadyn::Data>(model)), solve(std::move(s)) {}
};

struct Row {
  std::string skip, scene;
  std::shared_ptr<Scene> source;
  std::unique_ptr<Variant> with, without;
  std::vector<Timed> timed;
  bool check_results = true;
};

void hybrid(const Model& m, soadyn::Data& d, const soadyn_test::State& s) {
  soadyn::hybrid_dynamics<double>(m, d, s.q, s.v, s.u);
}
void hybrid_with_wrenches(const Model& m, soadyn::Data& d, const soadyn_test::State& s) {
  soadyn::hybrid_dynamics<double>(m, d, s.q, s.v, s.u, nullptr, soadyn::DynamicsOutputs{true});
}
void body_frame_sweeps(const Model& m, soadyn::Data& d, const soadyn_test::State& s) {
  soadyn::detail::body_frame_sweeps<Flags::model_flags, double>(m, d, s.q.data(), s.v.data(), s.u.data(), nullptr,
                                                               soadyn::detail::world_acceleration(m), false);
}
template <bool Flex>
void tree_frame_sweeps(const Model& m, soadyn::Data& d, const soadyn_test::State& s) {
  soadyn::detail::tree_frame_sweeps<Flags::model_flags, Flex, double>(m, d, s.q.data(), s.v.data(), s.u.data(), nullptr,
                                                              soadyn::detail::world_acceleration(m), false);
}
const Eigen::VectorXd& zeros() {
  static const Eigen::VectorXd zero = Eigen::VectorXd::Zero(256);  // no allocation in the timed calls
  return zero;
}
// At rest: hybrid_dynamics sees v = 0 and skips the velocity terms...
void hybrid_at_rest(const Model& m, soadyn::Data& d, const soadyn_test::State& s) {
  soadyn::hybrid_dynamics<double>(m, d, s.q, zeros().head(m.nv), s.u);
}
// ...which the sweeps given the zero vector itself compute.
void sweeps_at_rest_with_velocity_terms(const Model& m, soadyn::Data& d, const soadyn_test::State& s) {
  soadyn::detail::tree_frame_sweeps<Flags::model_flags, false, double>(m, d, s.q.data(), zeros().data(), s.u.data(),
                                                                       nullptr, soadyn::detail::world_acceleration(m), false);
}

Model general_joints(Model m) {  // every joint through the general joint code
  for (auto& kernel : m.joint_fast_path) kernel = soadyn::JointFastPath::general;
  m.refresh_derived_caches();  // the constant inertias and leaf terms assume the kernels' frames
  return m;
}
Model every_body_articulated(Model m) {  // no Newton-Euler regions
  for (auto& modes : m.modes) modes.needs_articulated_inertia = true;
  return m;
}
Model without_gravity(Model m) {
  m.gravity.setZero();
  return m;
}
Model with_mask(Model m, const std::vector<int>& prescribed_dofs) {
  for (int dof : prescribed_dofs) m.set_prescribed(dof, true);
  return m;
}
Model with_random_mask(Model m, std::uint64_t seed) {
  soadyn_test::Random rng(seed);
  soadyn_test::apply_mask(m, soadyn_test::random_mask(m.nv, rng, 0.5));
  return m;
}

std::vector<Row> rows() {
  auto arm = std::make_shared<Scene>("7-DOF arm", soadyn_test::build_model<double>(soadyn_test::seven_dof_arm_spec()));
  auto tree = std::make_shared<Scene>("random tree, 30 bodies, free root",
                                      soadyn_test::build_model<double>(soadyn_test::random_tree_spec(30, 30)));
  auto cassini = std::make_shared<Scene>("cassini (2 flexible booms)", soadyn::cassini_model<double>());
  std::vector<Row> out;
  auto add = [&out](std::string skip, const std::shared_ptr<Scene>& scene, Variant with, Variant without,
                    bool check_results = true) {
    Row r{std::move(skip), scene->name, scene, std::make_unique<Variant>(std::move(with)),
          std::make_unique<Variant>(std::move(without)), {}, check_results};
    out.push_back(std::move(r));
  };
  const Model& a = arm->model;
  const Model& t = tree->model;
  add("joint kernels: axis-aligned revolute (vs general joint code)", arm, {a, hybrid}, {general_joints(a), hybrid});
  add("joint kernels and the free root's closed form", tree, {t, hybrid}, {general_joints(t), hybrid});
  add("tree frames (vs body frames: 6x6 congruence per body)", arm, {a, hybrid}, {a, body_frame_sweeps});
  add("tree frames (vs body frames: 6x6 congruence per body)", tree, {t, hybrid}, {t, body_frame_sweeps});
  add("rigid scene: no flexible-body code (compile time)", tree, {t, tree_frame_sweeps<false>},
      {t, tree_frame_sweeps<true>});
  const Model all_prescribed = with_mask(a, {0, 1, 2, 3, 4, 5, 6});
  add("every DOF prescribed: RNEA (vs articulated inertias)", arm, {all_prescribed, hybrid},
      {every_body_articulated(all_prescribed), tree_frame_sweeps<false>});
  const Model root_side = with_mask(a, {0, 1, 2});
  add("prescribed root-side joints 1-3: Newton-Euler region", arm, {root_side, hybrid},
      {every_body_articulated(root_side), tree_frame_sweeps<false>});
  const Model half = with_random_mask(t, 7);
  add("random 50 % mask: Newton-Euler regions", tree, {half, hybrid}, {every_body_articulated(half), hybrid});
  add("joint wrenches only on request", tree, {half, hybrid}, {half, hybrid_with_wrenches});
  add("flexible appendages: tree frames, M_ee^-1 precomputed (vs body frames)", cassini, {cassini->model, hybrid},
      {cassini->model, body_frame_sweeps});
  add("rigid model at rest: no velocity terms", arm, {a, hybrid_at_rest}, {a, sweeps_at_rest_with_velocity_terms});
  add("rigid model at rest: no velocity terms", tree, {t, hybrid_at_rest}, {t, sweeps_at_rest_with_velocity_terms});
  // Not a skip: what a gravity-free special case could save.
  add("(no skip) gravity off vs on: gravity is the base acceleration", arm, {without_gravity(a), hybrid}, {a, hybrid},
      false);
  return out;
}

bool agrees(const Eigen::VectorXd& x, const Eigen::VectorXd& reference) {
  return (x - reference).cwiseAbs().maxCoeff() <= 1e-8 * std::max(1.0, reference.cwiseAbs().maxCoeff());
}

// Both variants solve the same problem: same accelerations and generalized forces.
bool same_results(Row& r) {
  const soadyn_test::State& s = r.source->state(0);
  r.with->solve(r.with->model, *r.with->data, s);
  r.without->solve(r.without->model, *r.without->data, s);
  return agrees(r.without->data->qdd, r.with->data->qdd) && agrees(r.without->data->tau, r.with->data->tau);
}

Timed timed(const std::string& label, Variant& v, const Scene& scene) {
  return Timed(label, [&v, &scene](int k) { v.solve(v.model, *v.data, scene.state(k)); });
}

}  // namespace

int main(int argc, char** argv) {
  const int batches = argc > 1 ? std::max(10, std::atoi(argv[1])) : 2000;
  constexpr int kRounds = 10;
  std::vector<Row> table = rows();
  bool all_agree = true;
  for (Row& r : table) {
    if (r.check_results && !same_results(r)) {
      std::fprintf(stderr, "%s, %s: the two variants disagree\n", r.skip.c_str(), r.scene.c_str());
      all_agree = false;
    }
    r.timed = {timed("with", *r.with, *r.source), timed("without", *r.without, *r.source)};
    for (Timed& t : r.timed) calibrate(t);
  }
  const int per_round = (batches + kRounds - 1) / kRounds;
  for (int round = 0; round < kRounds; ++round)
    for (Row& r : table)
      for (int b = 0; b < per_round; ++b)
        for (Timed& t : r.timed) time_one_batch(t);

  std::printf("Built with %s and Eigen %d.%d.%d; %zu timed batches of ~%.0f us per variant in %d rounds; "
              "medians per call in microseconds.\n\n",
              compiler(), EIGEN_WORLD_VERSION, EIGEN_MAJOR_VERSION, EIGEN_MINOR_VERSION,
              table.front().timed.front().per_call.size(), kBatchSeconds * 1e6, kRounds);
  std::printf("| skip | model | with (us) | without (us) | speed-up (without / with) |\n|---|---|---:|---:|---:|\n");
  for (const Row& r : table) {
    const std::vector<double> us = median_microseconds(r.timed);
    std::printf("| %s | %s | %.2f | %.2f | **%.2f** |\n", r.skip.c_str(), r.scene.c_str(), us[0], us[1], us[1] / us[0]);
  }
  return all_agree ? 0 : 1;
}
