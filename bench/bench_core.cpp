// Core benchmark: the hybrid algorithm against the dedicated algorithms it
// generalises, on a few representative models.
//
// Per model (rigid trees, and a chain of flexible beams beside its rigid
// 10-body counterpart): forward dynamics (the dedicated ABA), hybrid dynamics with every
// DOF regular (the same problem), inverse dynamics (RNEA), hybrid dynamics
// with every DOF prescribed (the same problem), hybrid dynamics with a random
// 50% mask, and the mass matrix (CRBA). The machine may be noisy, so each
// algorithm is timed in many short batches, the algorithms interleaved batch
// by batch and the models visited in rounds (drifts hit all of them alike),
// and the median per-call time is reported. Output: a markdown table on stdout.
//
// Usage: bench_core [repetitions]   (default 3000 batches per algorithm)
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <memory>
#include <string>
#include <vector>
#include "batch_timing.hpp"
#include "random_tree.hpp"  // tests/cpp: the models shared with the tests

namespace {

using namespace soadyn_bench;
using soadyn_test::JointKind;
using soadyn_test::TreeSpec;

constexpr int kRounds = 10;  // passes over all models

// ---------------------------------------------------------------------------
// Models
// ---------------------------------------------------------------------------


// A chain of `n` flexible beams (0.5 m, 2 bending modes per plane: 4 modal
// DOFs each) on revolute joints alternating about z and y, each hinged at the
// previous beam's tip node: the flexible counterpart of the 10-body chain.
soadyn::Model flexible_chain(int n) {
  const soadyn::FlexibleBody beam = soadyn::cantilever_beam<double>(0.5, 20.0, 1.0, 2, 12);
  soadyn::Model m;
  std::string parent = "world";
  for (int i = 0; i < n; ++i) {
    const std::string name = "beam_" + std::to_string(i + 1);
    const Eigen::Vector3d axis = i % 2 == 0 ? Eigen::Vector3d::UnitZ() : Eigen::Vector3d::UnitY();
    m.add_flexible_body(name, parent, soadyn::RevoluteJoint<double>{axis}, soadyn::Transform<double>(), beam);
    parent = name + ":tip";
  }
  return m;
}

struct Case {
  std::string name;
  std::function<soadyn::Model()> build;
};

Case tree_case(const std::string& name, const TreeSpec& spec) {
  return {name, [spec] { return soadyn_test::build_model<double>(spec); }};
}

std::vector<Case> benchmark_cases() {
  return {
      tree_case("7-DOF revolute arm", soadyn_test::seven_dof_arm_spec()),
      tree_case("revolute chain, 10 bodies", soadyn_test::chain_spec(std::vector<JointKind>(10, JointKind::revolute), 10)),
      tree_case("revolute chain, 100 bodies",
                soadyn_test::chain_spec(std::vector<JointKind>(100, JointKind::revolute), 100)),
      tree_case("random tree, 30 bodies, free root", soadyn_test::random_tree_spec(30, 30)),
      {"flexible chain, 10 beams x 4 modes", [] { return flexible_chain(10); }},
  };
}

// ---------------------------------------------------------------------------
// One model
// ---------------------------------------------------------------------------

// The model with three flag settings (flags live in the model), one Data
// shared by every algorithm and a pool of input states.
struct Workbench {
  soadyn::Model regular, prescribed, mixed;
  soadyn::Data data;
  std::vector<soadyn_test::State> states;

  explicit Workbench(const soadyn::Model& model) : regular(model), prescribed(regular), mixed(regular), data(regular) {
    prescribed.set_all_prescribed(true);
    soadyn_test::Random rng(99);
    soadyn_test::apply_mask(mixed, soadyn_test::random_mask(mixed.nv, rng, 0.5));
    for (int k = 0; k < kStates; ++k) states.push_back(soadyn_test::random_state(regular, 1000 + k));
  }

  // The six algorithms of the table, in column order. `u` is the torque of
  // the regular DOFs and the acceleration of the prescribed ones, so ABA and
  // hybrid-all-regular solve the same problem, as do RNEA and
  // hybrid-all-prescribed.
  std::vector<Timed> algorithms() {
    auto hybrid = [this](const soadyn::Model& m) {
      return [this, &m](int k) { soadyn::hybrid_dynamics<double>(m, data, state(k).q, state(k).v, state(k).u); };
    };
    auto aba = [this](int k) { soadyn::forward_dynamics<double>(regular, data, state(k).q, state(k).v, state(k).u); };
    auto rnea = [this](int k) { soadyn::inverse_dynamics<double>(regular, data, state(k).q, state(k).v, state(k).u); };
    auto crba = [this](int k) { soadyn::mass_matrix<double>(regular, data, state(k).q); };
    return {{"ABA", aba},
            {"hybrid all-regular", hybrid(regular)},
            {"RNEA", rnea},
            {"hybrid all-prescribed", hybrid(prescribed)},
            {"hybrid 50% mixed", hybrid(mixed)},
            {"CRBA", crba}};
  }

  const soadyn_test::State& state(int k) const { return states[static_cast<std::size_t>(k)]; }
};

bool agrees(const Eigen::VectorXd& x, const Eigen::VectorXd& reference) {
  return (x - reference).cwiseAbs().maxCoeff() <= 1e-8 * std::max(1.0, reference.cwiseAbs().maxCoeff());
}

// The hybrid runs must be right, or the comparison is void: all-regular
// reproduces ABA, and RNEA fed the all-prescribed run's accelerations
// reproduces its generalized forces (with flexible bodies the modal DOFs stay
// regular, so all-prescribed is not RNEA's problem there).
bool hybrid_matches_dedicated(Workbench& w) {
  const soadyn_test::State& s = w.state(0);
  soadyn::forward_dynamics<double>(w.regular, w.data, s.q, s.v, s.u);
  const Eigen::VectorXd aba_qdd = w.data.qdd;
  soadyn::hybrid_dynamics<double>(w.regular, w.data, s.q, s.v, s.u);
  const bool regular_ok = agrees(w.data.qdd, aba_qdd);
  soadyn::hybrid_dynamics<double>(w.prescribed, w.data, s.q, s.v, s.u);
  const Eigen::VectorXd qdd = w.data.qdd, tau = w.data.tau;
  soadyn::inverse_dynamics<double>(w.regular, w.data, s.q, s.v, qdd);
  return regular_ok && agrees(w.data.tau, tau);
}

// ---------------------------------------------------------------------------
// Report
// ---------------------------------------------------------------------------

void print_table_header(const std::vector<Timed>& algorithms) {
  std::printf("| model | nv |");
  for (const Timed& t : algorithms) std::printf(" %s (us) |", t.label.c_str());
  std::printf(" hybrid all-regular / ABA | hybrid all-prescribed / RNEA | mixed / all-regular |\n|---|---:|");
  for (std::size_t k = 0; k < algorithms.size() + 3; ++k) std::printf("---:|");
  std::printf("\n");
}

// Column order as in Workbench::algorithms.
void print_table_row(const std::string& model, int nv, const std::vector<double>& us) {
  enum { aba, hybrid_regular, rnea, hybrid_prescribed, hybrid_mixed, crba };
  std::printf("| %s | %d |", model.c_str(), nv);
  for (double t : us) std::printf(" %.2f |", t);
  std::printf(" %.2f | %.2f | %.2f |\n", us[hybrid_regular] / us[aba], us[hybrid_prescribed] / us[rnea],
              us[hybrid_mixed] / us[hybrid_regular]);
}

// A benchmark case ready to time. Workbench is held by pointer: the
// algorithms' closures point into it.
struct Prepared {
  std::string name;
  std::unique_ptr<Workbench> bench;
  std::vector<Timed> algorithms;
};

std::vector<Prepared> prepare_cases(bool& all_match) {
  std::vector<Prepared> prepared;
  for (const Case& c : benchmark_cases()) {
    auto bench = std::make_unique<Workbench>(c.build());
    if (!hybrid_matches_dedicated(*bench)) {
      std::fprintf(stderr, "%s: hybrid results differ from ABA/RNEA\n", c.name.c_str());
      all_match = false;
    }
    std::vector<Timed> algorithms = bench->algorithms();
    for (Timed& t : algorithms) calibrate(t);
    prepared.push_back({c.name, std::move(bench), std::move(algorithms)});
  }
  return prepared;
}

// Rounds over the models, interleaved batches within a model: each model's
// samples span the whole run and each algorithm's the same moments as its
// comparison partners, so slow phases of the machine hit them all alike.
void time_all(std::vector<Prepared>& cases, int repetitions) {
  const int per_round = (repetitions + kRounds - 1) / kRounds;
  for (int round = 0; round < kRounds; ++round)
    for (Prepared& c : cases)
      for (int rep = 0; rep < per_round; ++rep)
        for (Timed& t : c.algorithms) time_one_batch(t);
}

}  // namespace

int main(int argc, char** argv) {
  const int repetitions = argc > 1 ? std::max(kRounds, std::atoi(argv[1])) : 3000;
  bool all_match = true;
  std::vector<Prepared> cases = prepare_cases(all_match);
  time_all(cases, repetitions);

  std::printf("Built with %s and Eigen %d.%d.%d; %zu timed batches of ~%.0f us per algorithm in %d rounds; "
              "medians per call in microseconds.\n\n",
              compiler(), EIGEN_WORLD_VERSION, EIGEN_MAJOR_VERSION, EIGEN_MINOR_VERSION,
              cases.front().algorithms.front().per_call.size(), kBatchSeconds * 1e6, kRounds);
  print_table_header(cases.front().algorithms);
  for (const Prepared& c : cases)
    print_table_row(c.name, c.bench->regular.nv, median_microseconds(c.algorithms));
  return all_match ? 0 : 1;
}
