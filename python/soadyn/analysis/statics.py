"""Static equilibrium by Newton's method with the analytic stiffness.

With v = 0 and qdd = 0 the equations of motion leave the static force
G(q) = inverse_dynamics(q, 0, 0) (gravity and every force element that enters
inverse dynamics). A configuration is in equilibrium when the generalized
force on every DOF not held vanishes ("Joint Coordinate Method, Part 1",
Eq. 1.33 for trees) or, with closed loops, when it is carried by the cut-joint
reactions and the loops are closed (Eq. 1.34, multipliers nu):

    G_f(q) - C_f(q)' nu = 0,    Psi(q) = 0,

f the free DOFs (not held), C the loop Jacobian and nu the multipliers of
constrained_dynamics (M qdd + h = tau + C' nu). Newton's matrix is analytic:
dG/dq from inverse_dynamics_derivatives at v = 0, qdd = 0, and d(C' nu)/dq at
fixed nu from loop_force_stiffness. Increments are tangent vectors applied
with soadyn.integrate (q-derivatives in the tangent space). The Newton solve
is C++ (soadyn/analysis/static_equilibrium.hpp, loop_force_stiffness.hpp);
this module turns `hold` into the mask of free DOFs and adds the wrenches.

Decisions:
- nu starts from the least-squares estimate C_f C_f' nu = C_f G_f (the
  paper's C C' nu = -C B' g in this sign convention), after the loops are
  closed from q0 (soadyn.assemble's algorithm) with the held DOFs fixed.
- Each Newton step is the minimum-norm least-squares solution of the Newton
  system (redundant loop equations, as a planar four-bar's revolute cut joint
  has, leave nu non-unique; the minimum-norm nu is reported), followed by a
  backtracking line search on the residual norm.
- An equilibrium that is not isolated (a floating base without springs, a DOF
  no force depends on) is refused: DynamicsError naming the DOFs without
  stiffness; hold them. Not converging within max_iterations is a
  DynamicsError naming the DOF or loop equation with the largest residual.
- Stability: stiffness_eigenvalues are the eigenvalues (ascending) of the
  symmetric part of the reduced stiffness N' (dG/dq - d(C' nu)/dq)_ff N, with N
  an orthonormal basis of the free motions that keep the loops closed
  (null(C_f); N = I for trees), in tangent units (N m/rad, N/m). It is the
  Hessian of the potential energy on the constraint manifold: stable iff
  every eigenvalue is > 0 (a hanging pendulum: m g l; upside down: -m g l).
- Only `hold` fixes DOFs: the model's prescribed flags play no part.
- Models with flexible bodies or point springs take the stiffness from the
  dual-number sweeps (soadyn/analysis/static_stiffness.hpp).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import _soadyn
from .._soadyn import constrained_dynamics
from .equilibrium_sensitivity import equilibrium_sensitivities, objective_gradient

__all__ = ["StaticEquilibrium", "static_equilibrium", "loop_force_stiffness", "equilibrium_sensitivities",
           "objective_gradient"]

loop_force_stiffness = _soadyn.loop_force_stiffness


@dataclass
class StaticEquilibrium:
    """Result of static_equilibrium (see the module docstring for the conventions)."""
    q: np.ndarray                    # equilibrium configuration (nq)
    loop_wrenches: np.ndarray        # (nloops, 6) as constrained_dynamics returns them
    joint_wrenches: np.ndarray       # (nbodies, 6) as soadyn.joint_wrenches returns them
    holding_forces: dict             # held DOF name -> generalized force the holder applies
    multipliers: np.ndarray          # nu (nloop_equations): G - C' nu = holding forces
    iterations: int                  # Newton iterations taken
    converged: bool                  # always True on return (failures raise)
    residual_norm: float             # max |G_f - C_f' nu|, |Psi| at q
    stiffness_eigenvalues: np.ndarray  # ascending eigenvalues of the reduced stiffness
    stable: bool                     # every stiffness eigenvalue > 0
    held: list                       # indices of the held DOFs
    sensitivities: dict | None = None  # with static_equilibrium(..., sensitivities=params): equilibrium_sensitivities


def _free_mask(model, hold) -> np.ndarray:
    free = np.ones(model.nv, dtype=bool)
    if hold is None:
        return free
    held = model._dof_indices(hold)
    model._require_regular_modal_dofs(held)
    free[held] = False
    return free


def static_equilibrium(model, q0, hold=None, tol: float = 1e-12, max_iterations: int = 100,
                       sensitivities=None) -> StaticEquilibrium:
    """The static equilibrium nearest q0 (Newton's method, analytic stiffness; see the module docstring).

    hold: DOF or joint names (or indices) kept at their q0 values; their holding forces
    (the generalized forces the holder applies, G - C' nu) are reported by DOF name.
    tol: convergence when every entry of [G_f - C_f' nu; Psi] is at most
    tol * (1 + largest static force at q0). Raises ValueError for bad arguments and
    DynamicsError when Newton does not converge within max_iterations or the
    equilibrium is not isolated (naming the DOFs without stiffness).
    sensitivities: parameter names (model.parameter_names); the result's .sensitivities is then
    {name: {"q": dq*/dp, "multipliers": dnu/dp, "holding_forces": {...}}} by the direct method
    (equilibrium_sensitivity.py; soadyn.objective_gradient gives a scalar objective's by the adjoint).
    """
    free = _free_mask(model, hold)
    q, nu, force, eigenvalues, iterations, residual_norm, stable = _soadyn._static_equilibrium(
        model, q0, [bool(f) for f in free], tol, max_iterations)
    # Wrenches: the constrained dynamics at rest with the held DOFs prescribed (qdd = 0), the free ones unforced.
    at_rest = model.copy()
    at_rest.set_prescribed(~free, True)
    zero = np.zeros(model.nv)
    _, _, loop_wrenches, joint_wrenches = constrained_dynamics(at_rest, q, zero, zero, joint_wrenches=True)
    result = StaticEquilibrium(
        q=q, loop_wrenches=loop_wrenches, joint_wrenches=joint_wrenches,
        holding_forces={model.dof_names[k]: float(force[k]) for k in np.flatnonzero(~free)}, multipliers=nu,
        iterations=iterations, converged=True, residual_norm=residual_norm,
        stiffness_eigenvalues=eigenvalues, stable=stable, held=[int(k) for k in np.flatnonzero(~free)])
    if sensitivities is not None:
        result.sensitivities = equilibrium_sensitivities(model, result, sensitivities)
    return result
