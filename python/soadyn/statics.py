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
fixed nu from loop_force_stiffness (C++,
soadyn/algorithms/loop_force_stiffness.hpp). Increments are tangent vectors
applied with soadyn.integrate (q-derivatives in the tangent space).

Decisions:
- nu starts from the least-squares estimate C_f C_f' nu = C_f G_f (the
  paper's C C' nu = -C B' g in this sign convention), after the loops are
  closed from q0 by soadyn.assemble with the held DOFs fixed.
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
- Flexible bodies are refused (the analytic stiffness covers rigid models).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from . import _soadyn
from ._soadyn import DynamicsError, constrained_dynamics, integrate, inverse_dynamics, loop_jacobian, loop_residual
from .derivatives import inverse_dynamics_derivatives
from .loops import assemble

__all__ = ["StaticEquilibrium", "static_equilibrium", "loop_force_stiffness"]

loop_force_stiffness = _soadyn.loop_force_stiffness

_SINGULAR = 1e-9  # reduced-stiffness eigenvalues below this times the largest (or 1) count as zero
_MIN_STEP = 1.0 / 1024  # smallest line-search fraction


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


class _Problem:
    """The equilibrium equations of one model with a set of held DOFs."""

    def __init__(self, model, free: np.ndarray):
        self.model = model
        self.free = free
        self.nv = model.nv
        self.m = model.nloop_equations
        self.zero = np.zeros(model.nv)

    def forces(self, q):
        return inverse_dynamics(self.model, q, self.zero, self.zero)

    def residual(self, q, nu):
        """[G_f - C_f' nu; Psi]."""
        G = self.forces(q)
        if self.m == 0:
            return G[self.free]
        C = loop_jacobian(self.model, q)
        return np.concatenate([(G - C.T @ nu)[self.free], loop_residual(self.model, q)])

    def stiffness(self, q, nu):
        """d(G - C' nu)/dq (nv x nv) and C (m x nv), both at q."""
        K = inverse_dynamics_derivatives(self.model, q, self.zero, self.zero)[0]
        if self.m == 0:
            return K, np.zeros((0, self.nv))
        return K - loop_force_stiffness(self.model, q, nu), loop_jacobian(self.model, q)

    def newton_matrix(self, q, nu):
        K, C = self.stiffness(q, nu)
        f = self.free
        nf = int(f.sum())
        J = np.zeros((nf + self.m, nf + self.m))
        J[:nf, :nf] = K[np.ix_(f, f)]
        J[:nf, nf:] = -C[:, f].T
        J[nf:, :nf] = C[:, f]
        return J

    def step(self, q, nu, dx, fraction):
        nf = int(self.free.sum())
        dv = np.zeros(self.nv)
        dv[self.free] = fraction * dx[:nf]
        return integrate(self.model, q, dv, 1.0), nu + fraction * dx[nf:]

    def reduced_stiffness(self, q, nu):
        """(N' H_ff N symmetrised, N) with N an orthonormal basis of null(C_f)."""
        K, C = self.stiffness(q, nu)
        f = self.free
        H = K[np.ix_(f, f)]
        N = np.eye(H.shape[0])
        if self.m and H.shape[0]:
            _, s, Vt = np.linalg.svd(C[:, f])
            rank = int(np.sum(s > 1e-10 * max(1.0, s[0]))) if s.size else 0
            N = Vt[rank:].T
        R = N.T @ H @ N
        return 0.5 * (R + R.T), N


def _free_mask(model, hold) -> np.ndarray:
    free = np.ones(model.nv, dtype=bool)
    if hold is None:
        return free
    held = model._dof_indices(hold)
    model._require_regular_modal_dofs(held)
    free[held] = False
    return free


def _check_arguments(model, q0, tol, max_iterations) -> np.ndarray:
    if not (isinstance(tol, (int, float)) and math.isfinite(tol) and tol > 0):
        raise ValueError(f"static_equilibrium: tol must be positive and finite, got {tol!r}")
    if isinstance(max_iterations, bool) or not isinstance(max_iterations, (int, np.integer)) or max_iterations < 1:
        raise ValueError(f"static_equilibrium: max_iterations must be an integer >= 1, got {max_iterations!r}")
    q = np.array(q0, dtype=float)
    if q.shape != (model.nq,):
        raise ValueError(f"static_equilibrium: q0 has shape {q.shape}, expected ({model.nq},)")
    bad = np.flatnonzero(~np.isfinite(q))
    if bad.size:
        raise ValueError(f"static_equilibrium: q0 entry {bad[0]} ('{model.coordinate_names[bad[0]]}') is not finite")
    return q


def _equation_name(model, problem: _Problem, row: int) -> str:
    free_names = [n for n, f in zip(model.dof_names, problem.free) if f]
    if row < len(free_names):
        return f"DOF '{free_names[row]}'"
    name = _soadyn._loop_equation_names(model)[row - len(free_names)]
    return f"loop '{name[:name.rindex('[')]}' (equation {name[name.rindex('['):]})"


def _without_stiffness(model, problem: _Problem, q, nu) -> list[str]:
    """Names of the free DOFs that move along the zero modes of the reduced stiffness."""
    R, N = problem.reduced_stiffness(q, nu)
    if R.size == 0:
        return []
    values, vectors = np.linalg.eigh(R)
    scale = max(1.0, float(np.max(np.abs(values))))
    zero_modes = N @ vectors[:, np.abs(values) <= _SINGULAR * scale]
    if zero_modes.size == 0:
        return []
    free_names = [n for n, f in zip(model.dof_names, problem.free) if f]
    weight = np.max(np.abs(zero_modes), axis=1)
    return [free_names[i] for i in np.flatnonzero(weight > 1e-6)]


def _initial_multipliers(problem: _Problem, q) -> np.ndarray:
    """Least-squares nu of C_f C_f' nu = C_f G_f (Eq. 1.34's start, our sign)."""
    if problem.m == 0:
        return np.zeros(0)
    Cf = loop_jacobian(problem.model, q)[:, problem.free]
    return np.linalg.lstsq(Cf.T, problem.forces(q)[problem.free], rcond=None)[0]


def static_equilibrium(model, q0, hold=None, tol: float = 1e-12, max_iterations: int = 100) -> StaticEquilibrium:
    """The static equilibrium nearest q0 (Newton's method, analytic stiffness; see the module docstring).

    hold: DOF or joint names (or indices) kept at their q0 values; their holding forces
    (the generalized forces the holder applies, G - C' nu) are reported by DOF name.
    tol: convergence when every entry of [G_f - C_f' nu; Psi] is at most
    tol * (1 + largest static force at q0). Raises ValueError for bad arguments and
    DynamicsError when Newton does not converge within max_iterations or the
    equilibrium is not isolated (naming the DOFs without stiffness).
    """
    q = _check_arguments(model, q0, tol, max_iterations)
    free = _free_mask(model, hold)
    flexible = [name for name, n in zip(model.body_names, model.n_modes) if n > 0]
    if flexible:
        raise ValueError(f"static_equilibrium: body '{flexible[0]}' is flexible; the analytic stiffness covers "
                         "rigid models only")
    problem = _Problem(model, free)
    if problem.m:
        q = assemble(model, q, hold=[k for k in range(model.nv) if not free[k]], tolerance=tol)
    nu = _initial_multipliers(problem, q)
    threshold = tol * (1.0 + float(np.max(np.abs(problem.forces(q)), initial=0.0)))
    r = problem.residual(q, nu)
    iterations = 0
    while float(np.max(np.abs(r), initial=0.0)) > threshold:
        if iterations == max_iterations:
            worst = int(np.argmax(np.abs(r)))
            raise DynamicsError(f"static_equilibrium did not converge in {max_iterations} iterations: "
                                f"{_equation_name(model, problem, worst)} has residual {r[worst]:.3e}")
        dx = np.linalg.lstsq(problem.newton_matrix(q, nu), -r, rcond=None)[0]
        norm = np.linalg.norm(r)
        fraction = 1.0
        while True:  # backtracking on the residual norm
            q_try, nu_try = problem.step(q, nu, dx, fraction)
            r_try = problem.residual(q_try, nu_try)
            if np.linalg.norm(r_try) < norm or fraction <= _MIN_STEP:
                break
            fraction *= 0.5
        if not np.linalg.norm(r_try) < norm:
            missing = _without_stiffness(model, problem, q, nu)
            worst = int(np.argmax(np.abs(r)))
            detail = f"; no stiffness along {missing} (hold them)" if missing else ""
            raise DynamicsError(f"static_equilibrium: Newton step cannot reduce the residual of "
                                f"{_equation_name(model, problem, worst)} ({r[worst]:.3e}){detail}")
        q, nu, r = q_try, nu_try, r_try
        iterations += 1
    missing = _without_stiffness(model, problem, q, nu)
    if missing:
        raise DynamicsError(f"static_equilibrium: the equilibrium is not isolated: no stiffness along {missing} "
                            "(hold them, or add springs)")
    return _result(model, problem, q, nu, r, iterations)


def _result(model, problem: _Problem, q, nu, r, iterations) -> StaticEquilibrium:
    G = problem.forces(q)
    holding = G - loop_jacobian(model, q).T @ nu if problem.m else G
    held = np.flatnonzero(~problem.free)
    # Wrenches: the constrained dynamics at rest with the held DOFs prescribed (qdd = 0) and the free ones unforced.
    at_rest = model.copy()
    at_rest.set_prescribed(~problem.free, True)
    _, _, loop_wrenches, joint_wrenches = constrained_dynamics(at_rest, q, problem.zero, problem.zero,
                                                               joint_wrenches=True)
    R, _ = problem.reduced_stiffness(q, nu)
    eigenvalues = np.linalg.eigvalsh(R) if R.size else np.zeros(0)
    return StaticEquilibrium(
        q=q, loop_wrenches=loop_wrenches, joint_wrenches=joint_wrenches,
        holding_forces={model.dof_names[k]: float(holding[k]) for k in held}, multipliers=nu,
        iterations=iterations, converged=True, residual_norm=float(np.max(np.abs(r), initial=0.0)),
        stiffness_eigenvalues=eigenvalues, stable=bool(eigenvalues.size == 0 or eigenvalues[0] > 0))
