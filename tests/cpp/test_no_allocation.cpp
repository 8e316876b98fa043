// The run-time algorithms never touch the heap.
//
// allocation_counter.cpp replaces every allocation function of the process
// and counts calls while armed; its self-check first proves that the counter
// sees each family, so the test cannot pass vacuously.
//
// The workload, on a random 20-body tree with every joint type and on the same
// tree with flexible bodies added (hinged, clamped, on a node, rigid child on
// a node), on it with armatures, and on the rigid tree with flexible
// appendages (nothing on their nodes: the tree-frame appendage step, compiled
// for 4 modes and generic for 8): 10^5 hybrid_dynamics calls each preceded by a random flag change
// of a few hinge DOFs, with and without external wrenches and hinge-force
// outputs, interleaved with the other run-time algorithms and the energies
// (mechanical_energy equal bit for bit to kinetic_energy and potential_energy).
// Zero allocations, zero frees and every Status ok are required.
#include <cstdio>
#include <set>
#include "allocation_counter.hpp"
#include "random_tree.hpp"

using namespace soadyn_test;

namespace {

// ---------------------------------------------------------------------------
// Workload
// ---------------------------------------------------------------------------

constexpr int kHybridCalls = 100000;
constexpr int kOtherAlgorithmsEvery = 10;   // forward/inverse dynamics, M, h, integrate
constexpr int kSetAllFlagsEvery = 997;      // also exercise set_all_prescribed
constexpr int kStates = 16;

struct Tally {
  long hybrid_calls = 0, other_calls = 0, flag_changes = 0, failed_statuses = 0;
  soadyn::Status first_failure;
  int first_failure_call = -1;
  long energy_mismatches = 0;  // mechanical_energy against kinetic_energy and potential_energy

  void check(const soadyn::Status& s, int call) {
    if (s.ok()) return;
    if (failed_statuses++ == 0) first_failure = s, first_failure_call = call;
  }
};

// Flips a few hinge DOFs to a random mode (the model is shared by every state).
void change_random_flags(soadyn::Model& model, std::mt19937_64& rng, Tally& tally) {
  std::uniform_int_distribution<int> how_many(1, 3), dof(0, model.nv - 1), flag(0, 1);
  for (int k = how_many(rng); k > 0; --k, ++tally.flag_changes) {
    const int d = dof(rng);
    if (!model.is_modal(d)) model.set_prescribed(d, flag(rng) != 0);
  }
}

void run_other_algorithms(const soadyn::Model& model, soadyn::Data& data, const soadyn_test::State& s,
                          Eigen::VectorXd& q_next, int call, Tally& tally) {
  tally.check(soadyn::forward_dynamics(model, data, s.q, s.v, s.u, s.f_ext.data()), call);
  soadyn::inverse_dynamics(model, data, s.q, s.v, s.u, s.f_ext.data());
  soadyn::mass_matrix(model, data, s.q);
  soadyn::bias_forces(model, data, s.q, s.v);
  soadyn::integrate(model, s.q, s.v, 1e-3, q_next);
  tally.check(soadyn::hybrid_impulse(model, data, s.q, s.u), call);  // lock impacts use it
  const double kinetic = soadyn::kinetic_energy(model, data, s.q, s.v), potential = soadyn::potential_energy(model, data, s.q);
  double kinetic_together = 0, potential_together = 0;  // from one sweep: the same values, bit for bit
  soadyn::mechanical_energy(model, data, s.q, s.v, kinetic_together, potential_together);
  if (kinetic_together != kinetic || potential_together != potential) ++tally.energy_mismatches;
  volatile double sink = kinetic + potential + soadyn::momentum(model, data, s.q, s.v).sum();
  (void)sink;
  tally.other_calls += 10;
}

// The armed section: nothing here may allocate, print or throw.
Tally run_workload(soadyn::Model& model, soadyn::Data& data, const std::vector<soadyn_test::State>& states,
                   Eigen::VectorXd& q_next) {
  Tally tally;
  std::mt19937_64 rng(7);
  for (int call = 0; call < kHybridCalls; ++call) {
    if (call % kSetAllFlagsEvery == 0) model.set_all_prescribed((call / kSetAllFlagsEvery) % 2 == 0);
    change_random_flags(model, rng, tally);
    const soadyn_test::State& s = states[static_cast<std::size_t>(call % kStates)];
    const double* f_ext = call % 2 ? s.f_ext.data() : nullptr;
    const soadyn::DynamicsOutputs outputs{call % 3 == 0};
    tally.check(soadyn::hybrid_dynamics(model, data, s.q, s.v, s.u, f_ext, outputs), call);
    ++tally.hybrid_calls;
    if (call % kOtherAlgorithmsEvery == 0) run_other_algorithms(model, data, s, q_next, call, tally);
  }
  return tally;
}

// The workload must reach every joint type's code: the tree holds every
// movable joint type (fixed joints are merged away and never reach the model).
bool has_every_joint_type(const soadyn::Model& model) {
  std::set<std::size_t> types;
  for (const soadyn::JointModel<double>& joint : model.joints) types.insert(joint.index());
  return types.size() == soadyn_test::all_joint_kinds().size();
}

// Runs the workload on `model` with counting armed; true when it passes.
bool run_counted(const char* label, soadyn::Model model) {
  soadyn::Data data(model);
  std::vector<soadyn_test::State> states;
  for (int k = 0; k < kStates; ++k) states.push_back(soadyn_test::random_state(model, 100 + k));
  Eigen::VectorXd q_next(model.nq);
  std::printf("%s: %d bodies (%zu flexible), nq = %d, nv = %d\n", label, model.nbodies(), model.flexible_bodies.size(),
              model.nq, model.nv);

  arm_counter();
  const Tally tally = run_workload(model, data, states, q_next);
  const AllocationCounts counts = disarm_counter();

  std::printf("calls: %ld hybrid_dynamics, %ld other, %ld flag changes; failed statuses: %ld; energies from one sweep "
              "unequal to the separate calls: %ld\n", tally.hybrid_calls, tally.other_calls, tally.flag_changes,
              tally.failed_statuses, tally.energy_mismatches);
  std::printf("allocations: %ld operator new, %ld malloc family; frees: %ld\n", counts.operator_new, counts.c_alloc,
              counts.frees);
  if (tally.failed_statuses > 0)
    std::printf("first failure: call %d, status code %d, dof %d\n", tally.first_failure_call,
                static_cast<int>(tally.first_failure.code), tally.first_failure.index);
  return counts.allocations() == 0 && counts.frees == 0 && tally.failed_statuses == 0 && tally.energy_mismatches == 0;
}

}  // namespace

int main(int argc, char**) {
  // The probe size depends on run-time input so it cannot be folded away.
  if (!allocation_counter_works(static_cast<std::size_t>(16 + argc))) {
    std::printf("test_no_allocation: FAIL: the allocation counter does not see allocations\n");
    return 1;
  }
  const soadyn::Model rigid = soadyn_test::build_model<double>(soadyn_test::random_tree_spec(2024, 20));
  if (!has_every_joint_type(rigid)) {
    std::printf("test_no_allocation: FAIL: the random tree lacks a joint type\n");
    return 1;
  }
  soadyn::Model flexible = rigid;
  soadyn_test::add_flexible_bodies(flexible);
  soadyn::Model with_armature = flexible;  // rotor inertias on every other hinge DOF
  for (int d = 0; d < with_armature.nv; d += 2)
    if (!with_armature.is_modal(d)) with_armature.set_armature(d, 0.25 + 0.01 * d);
  soadyn::Model appendages = rigid;  // a boom of 8 modes welded to the root, one of 4 on a hinge
  const soadyn::Transform<double> offset = soadyn::Transform<double>::Identity();
  appendages.add_flexible_body("boom_8", appendages.body_names[0], soadyn::FixedJoint<double>{}, offset,
                               soadyn::cantilever_beam<double>(0.5, 2.0, 1.0, 4, 16));
  appendages.add_flexible_body("boom_4", appendages.body_names[2], soadyn::RevoluteJoint<double>{Eigen::Vector3d::UnitX()},
                               offset, soadyn::cantilever_beam<double>(0.5, 2.0, 1.0, 2, 12));
  const bool pass = run_counted("rigid tree", rigid) && run_counted("tree with flexible bodies", flexible) &&
                    run_counted("flexible tree with armature", with_armature) &&
                    run_counted("tree with appendages", appendages);
  std::printf("test_no_allocation: %s: %d hybrid_dynamics calls per model\n", pass ? "PASS" : "FAIL", kHybridCalls);
  return pass ? 0 : 1;
}
