// Status codes returned by the run-time algorithms, which never throw.
#pragma once

namespace soadyn {

enum class StatusCode {
  ok = 0,
  singular_articulated_inertia,  // D = S' P S of a regular hinge is not positive definite
  non_finite_result,             // an output came out NaN or infinite
};

struct Status {
  StatusCode code = StatusCode::ok;
  int index = -1;  // the DOF at fault (velocity index), or -1
  bool ok() const { return code == StatusCode::ok; }
};

}  // namespace soadyn
