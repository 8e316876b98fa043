// The rule "modal DOFs are always regular", checked in one place. A flexible
// body's modal coordinates are driven by the elastic forces, never by a
// prescribed acceleration, a lock or a motion source: the hybrid sweeps
// eliminate them inside the body's articulated inertia (a flexible body
// always needs one). Model::set_prescribed, the simulator's lock, release,
// prescribe and schedule, and the Python binding all refuse a modal DOF
// through require_regular_modal_dof, with the one message below.
#pragma once
#include <cstddef>
#include <stdexcept>
#include <string>

namespace soadyn {

// Throws std::invalid_argument naming the DOF and its flexible body when
// velocity index `dof` of `model` (a ModelTpl) is a modal coordinate. `dof`
// must be in range. Not for the real-time path (it throws): there, lock and
// release return Status invalid_dof for a modal DOF.
template <class Model>
void require_regular_modal_dof(const Model& model, int dof) {
  if (!model.is_modal(dof)) return;
  const std::size_t d = static_cast<std::size_t>(dof);
  throw std::invalid_argument("DOF '" + model.dof_names[d] + "' is a modal coordinate of flexible body '" +
                              model.body_names[static_cast<std::size_t>(model.dof_body[d])] +
                              "': modal DOFs are always regular");
}

}  // namespace soadyn
