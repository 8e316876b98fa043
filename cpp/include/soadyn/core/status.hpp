// Status codes returned by the run-time algorithms, which never throw.
#pragma once

namespace soadyn {

enum class StatusCode {
  ok = 0,
  singular_articulated_inertia,  // D = S' P S of a regular hinge is not positive definite
  non_finite_result,             // an output came out NaN or infinite
  invalid_dof,                   // a DOF index out of range (index: the DOF)
  step_size_underflow,           // the adaptive integrator could not meet its tolerance
  non_finite_source,             // a motion source returned a non-finite value (index: its DOF)
  substep_limit,                 // the adaptive integrator used up its sub-steps in one step
  loop_not_closed,               // loop-closure projection did not converge (index: the loop, not a DOF)
  inconsistent_loop_equations,   // closure accelerations cannot be met (index: the loop); data holds the
                                 // least-squares answer (constrained_dynamics.hpp)
  loop_assembly_stalled,         // assembly makes no progress: the residual stopped decreasing (index: the loop)
  interrupted,                   // stopped by an Interrupt (interrupt.hpp) between iterations
  diverging,                     // the divergence guard stopped the step before the state lost its finiteness
                                 // (sim/divergence_guard.hpp; index: the DOF)
};

inline const char* status_message(StatusCode code) {
  switch (code) {
    case StatusCode::ok: return "ok";
    case StatusCode::singular_articulated_inertia: return "singular articulated inertia";
    case StatusCode::non_finite_result: return "non-finite result";
    case StatusCode::invalid_dof: return "invalid DOF";
    case StatusCode::step_size_underflow: return "step size underflow";
    case StatusCode::non_finite_source: return "motion source returned a non-finite value";
    case StatusCode::substep_limit: return "sub-step limit reached";
    case StatusCode::loop_not_closed: return "loop closure not reached";
    case StatusCode::inconsistent_loop_equations: return "loop-closure equations cannot be met";
    case StatusCode::loop_assembly_stalled: return "loop assembly stalled";
    case StatusCode::interrupted: return "interrupted";
    case StatusCode::diverging: return "diverging";
  }
  return "unknown";
}

struct Status {
  StatusCode code = StatusCode::ok;
  int index = -1;  // the DOF at fault (velocity index), the loop for inconsistent_loop_equations, or -1
  bool ok() const { return code == StatusCode::ok; }
};

namespace detail {

// What a tree-frame sweep returns (sweeps/tree_frame_sweeps.hxx, the CRBA,
// the tree-frame loop solves): its Status, or, with `beyond_reach`, that body
// `status.index` lies beyond its tree-frame reach (model/tree_frame_reach.hxx).
// No output has then changed, and the caller redoes the call in body frames;
// public algorithms never return it.
struct TreeFrameStatus {
  Status status;
  bool beyond_reach = false;
  TreeFrameStatus() = default;
  TreeFrameStatus(Status s) : status(s) {}  // NOLINT: a sweep's Status converts implicitly
  TreeFrameStatus(StatusCode code, int index) : status{code, index} {}
  static TreeFrameStatus beyond(int body) {
    TreeFrameStatus t{Status{StatusCode::ok, body}};
    t.beyond_reach = true;
    return t;
  }
  bool ok() const { return !beyond_reach && status.ok(); }
};

}  // namespace detail

}  // namespace soadyn
