// Modes of small oscillations about a configuration at rest.
//
// Linearised about (q, v = 0, qdd = 0), the regular DOFs obey
//   M e'' + D e' + K e = 0,
// K = dtau/dq (gravity and elastic forces' stiffness), D = dtau/dv at rest,
// M the mass matrix: inverse_dynamics_derivatives at (q, 0, 0)
// (dynamics_derivatives.hpp). Prescribed DOFs are held. Each mode is a root
// pair of s^2 + 2 zeta w s + w^2: complex conjugate roots, or two real roots
// (paired by increasing magnitude: rigid-body zeros together, the +- roots of
// an unstable direction together). w is signed: negative (-sqrt(-w^2)) for an
// unstable mode, 0 for a rigid-body mode (zeta then NaN). Shapes are the
// position part of the first root's eigenvector, turned so its largest entry
// is real and scaled to 1, real part kept.
//
// Analysis only: the eigen-decomposition allocates.
#pragma once
#include <complex>
#include <vector>

#include "soadyn/analysis/dynamics_derivatives.hpp"

namespace soadyn {

struct Modes {
  std::vector<int> dofs;              // the regular DOFs, the shapes' columns
  Eigen::VectorXd angular_frequency;  // w (rad/s), by increasing |w|
  Eigen::VectorXd damping_ratio;      // zeta
  Eigen::MatrixXcd roots;             // (n, 2): each mode's root pair
  Eigen::MatrixXd shapes;             // (n, dofs.size()), one mode per row
};

// Throws std::invalid_argument for a flexible body (DynamicsDerivatives) and
// DynamicsError-style failures as a Status in `status`.
Modes modes(const Model& model, Data& data, DynamicsDerivatives& derivatives, const ConstVecRef<double>& q,
            Status& status);

// The same from the full (nv x nv) mass matrix M, stiffness K = dtau/dq and
// damping D = dtau/dv at rest, keeping the DOFs `dofs` (the regular ones):
// for models whose derivatives come from elsewhere (flexible bodies and
// point springs, by the dual-number sweeps of parameter_sensitivity.hpp).
Modes modes_of(const Eigen::MatrixXd& mass_matrix, const Eigen::MatrixXd& stiffness, const Eigen::MatrixXd& damping,
               const std::vector<int>& dofs);

}  // namespace soadyn
