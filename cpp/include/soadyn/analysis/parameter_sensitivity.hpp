// Design sensitivity of the dynamics: derivatives of hybrid_dynamics (trees)
// or constrained_dynamics (models with closed loops) with respect to a named
// model parameter (parameters.hpp), the direct method of "Joint Coordinate
// Method, Part 1" (Sects. 6-7, Eqs. 1.37 and 1.39) evaluated by forward-mode
// automatic differentiation: the model is cast to a dual-number scalar
// (Eigen's AutoDiffScalar with one derivative) and the scalar-templated core
// runs once per parameter direction. Results are exact to rounding (no step
// size). Flexible bodies included (ModelTpl::cast converts them).
//
// Directions of a parameter (the trailing axis of each derivative):
//   mass       1
//   com, gravity  3: the coordinates
//   inertia    3 x 3 (column-major): entry (a, b) is the derivative along the
//              symmetric change (E_ab + E_ba) / 2, so for any symmetric dI
//              the first-order change is sum_ab d/dI[a, b] dI[a, b]
//   placement  6: (dtheta, dp), the placement (R, p) moved to
//              (R exp([dtheta]x), p + dp): dtheta in the joint frame,
//              dp in the parent body's frame
// Outputs per direction: dqdd (nv), dtau (nv) and, with loops, the loop
// wrenches' derivative (6 per loop, data.loops.wrench's layout).
#pragma once
#include <memory>
#include "soadyn/sweeps/body_updates.hpp"
#include "soadyn/model/model.hpp"
#include "soadyn/model/parameters.hpp"
#include "soadyn/core/status.hpp"

namespace soadyn {

// How many directions parameter entry `e` has (see above).
int parameter_directions(const ParameterEntry<double>& e);

class ParameterSensitivity {
 public:
  // Casts `model` (allocates).
  explicit ParameterSensitivity(const Model& model);
  ~ParameterSensitivity();
  ParameterSensitivity(const ParameterSensitivity&) = delete;
  ParameterSensitivity& operator=(const ParameterSensitivity&) = delete;

  // Derivatives of the dynamics at (q, v, u) (u as hybrid_dynamics) of the
  // model `model` (the one given to the constructor, possibly with changed
  // parameters and flags) with respect to entry `k` of `table`: column j of
  // dqdd (nv x directions), dtau (nv x directions) and dwrench
  // (6 nloops x directions) is direction j. Returns the status of the
  // dynamics (hybrid_dynamics / constrained_dynamics).
  // With `spanning_tree`, a loop model's spanning tree is differentiated
  // (hybrid_dynamics, loops ignored, dwrench left zero): with every DOF
  // prescribed and v = u = 0, dtau is then the static force's derivative
  // dG/dp, G = inverse dynamics at rest (static_equilibrium's sensitivities).
  Status compute(const Model& model, const ParameterTable<double>& table, int k, const ConstVecRef<double>& q,
                 const ConstVecRef<double>& v, const ConstVecRef<double>& u, Eigen::Ref<MatX<double>> dqdd,
                 Eigen::Ref<MatX<double>> dtau, Eigen::Ref<MatX<double>> dwrench, bool spanning_tree = false);

 // The derivatives of the dynamics with respect to the state and the inputs
  // by the same dual-number sweeps (one direction per column): dqdd_dq ...
  // dtau_du as DynamicsDerivativesTpl defines them (q-derivatives in the
  // tangent space of integrate), of constrained_dynamics for a loop model and
  // of hybrid_dynamics otherwise (and with `spanning_tree`). `f_ext`: nbodies
  // x 6 body-frame wrenches or null. Each output nv x nv. Returns the
  // dynamics' status. Point springs included (they enter the sweeps).
  Status state_derivatives(const Model& model, const ConstVecRef<double>& q, const ConstVecRef<double>& v,
                           const ConstVecRef<double>& u, const double* f_ext, Eigen::Ref<MatX<double>> dqdd_dq,
                           Eigen::Ref<MatX<double>> dqdd_dv, Eigen::Ref<MatX<double>> dqdd_du,
                           Eigen::Ref<MatX<double>> dtau_dq, Eigen::Ref<MatX<double>> dtau_dv,
                           Eigen::Ref<MatX<double>> dtau_du, bool spanning_tree = false);

 private:
  void load(const Model& model);  // the current parameters and flags of `model`, as constants
  struct Dual;
  std::unique_ptr<Dual> dual_;
};

}  // namespace soadyn
