// Frames and Jacobians (algorithms/frames.hpp) never touch the heap once the
// caller has sized the outputs and the centre-of-mass workspace.
//
// The workload, on a random 20-body tree with every joint type and a welded
// tool frame: 2000 rounds over 16 states, each calling frame_pose,
// frame_velocity, frame_acceleration (spatial and classical),
// frame_jacobian and frame_jacobian_time_variation in the three references
// on a body and on the welded frame, and center_of_mass_jacobian. Zero
// allocations and frees, finite results, and the identity J v = frame
// velocity checked outside the armed section, are required.
#include <cstdio>
#include <set>
#include "allocation_counter.hpp"
#include "random_tree.hpp"
#include "soadyn/algorithms/frames.hpp"

using namespace soadyn_test;

namespace {

constexpr int kRounds = 2000;
constexpr int kStates = 16;
constexpr soadyn::Reference kReferences[] = {soadyn::Reference::world, soadyn::Reference::local,
                                             soadyn::Reference::local_world_aligned};

struct Outputs {
  explicit Outputs(const soadyn::Model& m) : J(6, m.nv), dJ(6, m.nv), com_J(3, m.nv), workspace(m) {}
  Eigen::Matrix<double, 6, Eigen::Dynamic> J, dJ;
  Eigen::Matrix<double, 3, Eigen::Dynamic> com_J;
  soadyn::SubtreeMassWorkspace<double> workspace;
  double sum = 0;  // every result summed: finite, and kept by the compiler
  long calls = 0;
};

// The armed section: nothing here may allocate, print or throw.
void run_workload(const soadyn::Model& m, soadyn::Data& d, const std::vector<State>& states,
                  const soadyn::FrameLocation<double> (&frames)[2], Outputs& out) {
  for (int round = 0; round < kRounds; ++round) {
    const State& s = states[static_cast<std::size_t>(round % kStates)];
    const soadyn::FrameLocation<double>& f = frames[round % 2];
    const soadyn::Reference r = kReferences[round % 3];
    out.sum += soadyn::frame_pose<double>(m, d, s.q, f).translation.sum();
    out.sum += soadyn::frame_velocity<double>(m, d, s.q, s.v, f, r).sum();
    out.sum += soadyn::frame_acceleration<double>(m, d, s.q, s.v, s.u, f, r, round % 2 == 0).sum();
    soadyn::frame_jacobian<double>(m, d, s.q, f, r, out.J);
    soadyn::frame_jacobian_time_variation<double>(m, d, s.q, s.v, f, r, out.dJ);
    out.sum += out.J.sum() + out.dJ.sum();
    if (soadyn::center_of_mass_jacobian<double>(m, d, s.q, out.workspace, out.com_J)) out.sum += out.com_J.sum();
    out.calls += 6;
  }
}

}  // namespace

int main(int argc, char**) {
  if (!allocation_counter_works(static_cast<std::size_t>(16 + argc))) {
    std::printf("test_frames_no_allocation: FAIL: the allocation counter does not see allocations\n");
    return 1;
  }
  soadyn::Model m = build_model<double>(random_tree_spec(2024, 20));
  soadyn::Transform<double> tool;
  tool.translation << 0.1, -0.05, 0.2;
  m.add_body("tool", m.body_names.back(), soadyn::FixedJoint<double>{}, tool, 0.0, soadyn::Vec3<double>::Zero(),
             soadyn::Mat3<double>::Zero());
  std::set<std::size_t> types;
  for (const soadyn::JointModel<double>& joint : m.joints) types.insert(joint.index());
  if (types.size() != all_joint_kinds().size()) {
    std::printf("test_frames_no_allocation: FAIL: the random tree lacks a joint type\n");
    return 1;
  }
  soadyn::Data d(m);
  std::vector<State> states;
  for (int k = 0; k < kStates; ++k) states.push_back(random_state(m, 300 + k));
  const soadyn::FrameLocation<double> frames[2] = {soadyn::locate_frame(m, m.nbodies() / 2),
                                                  soadyn::locate_frame(m, std::string("tool"))};
  Outputs out(m);
  std::printf("tree: %d bodies, nv = %d, welded frame on body %d\n", m.nbodies(), m.nv, frames[1].body);

  arm_counter();
  run_workload(m, d, states, frames, out);
  const AllocationCounts counts = disarm_counter();

  // J v is the frame velocity (outside the armed section).
  double worst = 0;
  for (const State& s : states)
    for (const auto& f : frames)
      for (const soadyn::Reference r : kReferences) {
        soadyn::frame_jacobian<double>(m, d, s.q, f, r, out.J);
        const soadyn::Vec6<double> V = soadyn::frame_velocity<double>(m, d, s.q, s.v, f, r);
        worst = std::max(worst, (out.J * s.v - V).cwiseAbs().maxCoeff() / std::max(1.0, V.cwiseAbs().maxCoeff()));
      }
  const bool finite = std::isfinite(out.sum);
  std::printf("calls: %ld frame calls; finite results: %s; J v against frame_velocity: %.3e\n", out.calls,
              finite ? "yes" : "no", worst);
  std::printf("allocations: %ld operator new, %ld malloc family; frees: %ld\n", counts.operator_new, counts.c_alloc,
              counts.frees);
  const bool pass = counts.allocations() == 0 && counts.frees == 0 && finite && worst < 1e-12;
  std::printf("test_frames_no_allocation: %s\n", pass ? "PASS" : "FAIL");
  return pass ? 0 : 1;
}
