// ParameterTable::set and ::get allocate nothing once the table is built:
// 2000 rounds, each changing every parameter of a random 20-body tree (every
// joint kind, free root) to a perturbed value and back, with a hybrid_dynamics
// call in between, counted by the allocation counter (allocation_counter.cpp).
// The sets do their work: each round checks that the spatial inertia of a
// body follows its changed mass (M(k) recomputed) and that the dynamics with
// the perturbed parameters differ from those with the original ones, and
// that the original values come back exactly.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "allocation_counter.hpp"
#include "random_tree.hpp"
#include "soadyn/model/parameters.hpp"
#include "soadyn/soadyn.hpp"

namespace {

constexpr int kRounds = 2000;

// A valid nearby value: scaled mass and inertia, shifted com and gravity,
// a placement moved along its translation (rotation kept).
void perturb(const soadyn::ParameterEntry<double>& e, const double* in, double* out) {
  for (int k = 0; k < e.size(); ++k) out[k] = in[k];
  const std::string& n = e.name;
  const bool placement = n.size() > 10 && n.compare(n.size() - 10, 10, ".placement") == 0;
  const bool vector = e.rows == 3 && e.cols == 1;  // com, gravity
  if (placement)
    out[12] += 0.01;
  else if (vector)
    out[0] += 0.01;
  else
    for (int k = 0; k < e.size(); ++k) out[k] *= 1.1;  // mass, inertia
}

}  // namespace

int main(int argc, char**) {
  if (!soadyn_test::allocation_counter_works(static_cast<std::size_t>(16 + argc))) {
    std::printf("test_parameters_no_allocation: FAIL: the allocation counter does not see allocations\n");
    return 1;
  }
  soadyn::Model model = soadyn_test::build_model<double>(soadyn_test::random_tree_spec(2026, 20));
  soadyn::Data data(model);
  const soadyn::ParameterTable<double> table(model);
  const soadyn_test::State s = soadyn_test::random_state(model, 77);
  std::vector<std::vector<double>> original(static_cast<std::size_t>(table.size())),
      changed(static_cast<std::size_t>(table.size()));
  for (int k = 0; k < table.size(); ++k) {
    original[static_cast<std::size_t>(k)].resize(static_cast<std::size_t>(table.entry(k).size()));
    changed[static_cast<std::size_t>(k)].resize(original[static_cast<std::size_t>(k)].size());
    table.get(model, k, original[static_cast<std::size_t>(k)].data());
    perturb(table.entry(k), original[static_cast<std::size_t>(k)].data(), changed[static_cast<std::size_t>(k)].data());
  }
  std::vector<double> readback(16);
  const int mass_entry = table.find(model.body_names[3] + ".mass");
  soadyn::hybrid_dynamics<double>(model, data, s.q, s.v, s.u, s.f_ext.data());
  const Eigen::VectorXd reference = data.qdd;
  Eigen::VectorXd perturbed_qdd(model.nv);
  long failed = 0;

  soadyn_test::arm_counter();
  for (int round = 0; round < kRounds; ++round) {
    for (int k = 0; k < table.size(); ++k) table.set(model, k, changed[static_cast<std::size_t>(k)].data());
    if (std::abs(model.inertia[3](5, 5) - model.mass[3]) > 1e-12 * model.mass[3]) ++failed;
    if (!soadyn::hybrid_dynamics<double>(model, data, s.q, s.v, s.u, s.f_ext.data()).ok()) ++failed;
    perturbed_qdd = data.qdd;
    if ((perturbed_qdd - reference).cwiseAbs().maxCoeff() < 1e-6) ++failed;
    for (int k = table.size(); k-- > 0;) table.set(model, k, original[static_cast<std::size_t>(k)].data());
    table.get(model, mass_entry, readback.data());
    if (readback[0] != original[static_cast<std::size_t>(mass_entry)][0]) ++failed;
  }
  const soadyn_test::AllocationCounts counts = soadyn_test::disarm_counter();
  soadyn::hybrid_dynamics<double>(model, data, s.q, s.v, s.u, s.f_ext.data());
  const double restored = (data.qdd - reference).cwiseAbs().maxCoeff();

  std::printf("bodies: %d, parameters: %d\n", model.nbodies(), table.size());
  std::printf("rounds: %d, sets: %d; failed checks: %ld; restored qdd error %.3g\n", kRounds,
              2 * kRounds * table.size(), failed, restored);
  std::printf("allocations: %ld operator new, %ld malloc family; frees: %ld\n", counts.operator_new, counts.c_alloc,
              counts.frees);
  const bool pass = counts.allocations() == 0 && counts.frees == 0 && failed == 0 && restored <= 1e-12;
  std::printf("test_parameters_no_allocation: %s\n", pass ? "PASS" : "FAIL");
  return pass ? 0 : 1;
}
