"""Design sensitivities of a static equilibrium ("Joint Coordinate Method, Part 1", Sects. 6-7).

At an equilibrium (q*, nu*) the residual R(q, nu; p) = [G_f(q; p) - C_f(q)' nu; Psi(q)] vanishes
(statics.py: G the static force, inverse dynamics at rest; f the free DOFs; C the loop Jacobian,
Psi the closure). Differentiating R(q*(p), nu*(p); p) = 0 gives the direct method
    J [dq_f/dp; dnu/dp] = -[dG_f/dp; 0],   J = [[K_ff, -C_f'], [C_f, 0]],
K = dG/dq - d(C' nu)/dq (inverse_dynamics_derivatives and loop_force_stiffness, analytic), dG/dp
by forward-mode automatic differentiation of inverse dynamics at rest (parameter_sensitivity on
the spanning tree with every DOF prescribed). J is singular when the loop equations are redundant
(a planar four-bar's 3-D cut joint); the minimum-norm solution is taken (nu itself is the
minimum-norm one), so dq/dp is exact and dnu/dp is the derivative of the minimum-norm multipliers
within the equations' range. The adjoint method gives the gradient of a scalar objective
phi(q, nu) with one solve, J' lambda = [dphi/dq_f; dphi/dnu], dphi/dp = -lambda' [dG_f/dp; 0]:
one solve whatever the number of parameters. Holding forces H = G_h - C_h' nu of held DOFs h:
dH/dp = dG_h/dp + K_hf dq_f/dp - C_h' dnu/dp.

Parameters whose change moves the loops' closure (a body's placement on a loop model) are refused:
the closure's own dependence on them is not differentiated here.
"""
from __future__ import annotations

import numpy as np

from . import _soadyn
from .derivatives import inverse_dynamics_derivatives

__all__ = ["equilibrium_sensitivities", "objective_gradient"]


def static_force_sensitivity(model, q, params) -> dict:
    """{name: dG/dp} with G = inverse_dynamics(q, 0, 0), shape (nv, *parameter directions)."""
    at_rest = model.copy()
    at_rest.set_prescribed(np.ones(model.nv, dtype=bool))
    zero = np.zeros(model.nv)
    out = _soadyn._parameter_sensitivity(at_rest, q, zero, zero, list(params), True)
    return {name: value[1] for name, value in out.items()}


def _refuse_closure_parameters(model, params):
    if model.nloops == 0:
        return
    for name in params:
        if name.endswith(".placement"):
            raise ValueError(f"parameter '{name}': a placement moves the loops' closure, whose dependence on it "
                             "is not differentiated (equilibrium sensitivities take masses, centres of mass, "
                             "inertias, springs and gravity)")


def _newton_matrix(model, equilibrium):
    """(J, K, C, free): the equilibrium's Jacobian and its parts at (q*, nu*)."""
    free = np.ones(model.nv, dtype=bool)
    free[list(equilibrium.held)] = False
    zero = np.zeros(model.nv)
    K = inverse_dynamics_derivatives(model, equilibrium.q, zero, zero)[0]
    if model.nloops:
        K = K - _soadyn.loop_force_stiffness(model, equilibrium.q, equilibrium.multipliers)
        C = _soadyn.loop_jacobian(model, equilibrium.q)
    else:
        C = np.zeros((0, model.nv))
    nf, ne = int(free.sum()), C.shape[0]
    J = np.zeros((nf + ne, nf + ne))
    J[:nf, :nf] = K[np.ix_(free, free)]
    J[:nf, nf:] = -C[:, free].T
    J[nf:, :nf] = C[:, free]
    return J, K, C, free


def _gradient(x, n, name) -> np.ndarray:
    x = np.asarray(x, dtype=float)
    if x.shape != (n,):
        raise ValueError(f"{name} must have shape ({n},), got {x.shape}")
    if not np.isfinite(x).all():
        raise ValueError(f"{name} entry {int(np.flatnonzero(~np.isfinite(x))[0])} is not finite")
    return x


def _flat(x, nv):
    """(nv, *dirs) -> (nv, ndirs) and the direction shape."""
    return x.reshape(nv, -1), x.shape[1:]


def equilibrium_sensitivities(model, equilibrium, params) -> dict:
    """{name: {"q": dq*/dp (nv tangent, *dirs; zero on held DOFs), "multipliers": dnu/dp,
    "holding_forces": {held DOF name: dH/dp}}} by the direct method (module docstring)."""
    params = [params] if isinstance(params, str) else list(params)
    _refuse_closure_parameters(model, params)
    J, K, C, free = _newton_matrix(model, equilibrium)
    J_pinv = np.linalg.pinv(J)
    nv, nf = model.nv, int(free.sum())
    out = {}
    for name, dG in static_force_sensitivity(model, equilibrium.q, params).items():
        dG, shape = _flat(dG, nv)
        rhs = np.zeros((J.shape[0], dG.shape[1]))
        rhs[:nf] = dG[free]
        x = -J_pinv @ rhs
        dq = np.zeros((nv, dG.shape[1]))
        dq[free] = x[:nf]
        dnu = x[nf:]
        held = np.flatnonzero(~free)
        dH = dG[held] + K[np.ix_(held, np.flatnonzero(free))] @ x[:nf] - C[:, held].T @ dnu
        out[name] = {"q": dq.reshape((nv,) + shape), "multipliers": dnu.reshape((len(dnu),) + shape),
                     "holding_forces": {model.dof_names[k]: dH[j].reshape(shape) for j, k in enumerate(held)}}
    return out


def objective_gradient(model, equilibrium, params, dphi_dq, dphi_dnu=None) -> dict:
    """{name: dphi/dp (*dirs)} of a scalar objective phi(q*, nu*) at the equilibrium, by the adjoint
    method (one solve for every parameter). dphi_dq: (nv,) gradient with respect to q in the tangent
    space (held DOFs' entries are ignored: they do not move); dphi_dnu: (nloop_equations,) or None."""
    params = [params] if isinstance(params, str) else list(params)
    _refuse_closure_parameters(model, params)
    dphi_dq = _gradient(dphi_dq, model.nv, "dphi_dq")
    dphi_dnu = None if dphi_dnu is None else _gradient(dphi_dnu, model.nloop_equations, "dphi_dnu")
    J, _, C, free = _newton_matrix(model, equilibrium)
    nv, nf = model.nv, int(free.sum())
    g = np.zeros(J.shape[0])
    g[:nf] = dphi_dq[free]
    if dphi_dnu is not None:
        g[nf:] = dphi_dnu
    adjoint = np.linalg.pinv(J.T) @ g
    out = {}
    for name, dG in static_force_sensitivity(model, equilibrium.q, params).items():
        dG, shape = _flat(dG, nv)
        out[name] = (-(adjoint[:nf] @ dG[free])).reshape(shape)
    return out
