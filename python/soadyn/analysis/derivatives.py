"""Derivatives of the dynamics with respect to q, v and the inputs.

Rigid trees use the analytic recursive algorithm in C++
(cpp/include/soadyn/analysis/dynamics_derivatives.hpp): the derivative of
the Newton-Euler sweeps, O(N d) for tree depth d, and the hybrid problem's
partitioned solve with the tree-sparse factor of the mass matrix. Models with
closed loops are differentiated by forward-mode automatic differentiation of
constrained_dynamics' own sweeps (exact to rounding, one evaluation per
column), and so are models with point springs (whose line-of-action
stiffness the analytic sweeps do not carry) and models with flexible bodies
(whose modal coordinates' columns come out of the same dual-number sweeps).

Derivatives with respect to q are taken in the tangent space: column k is
d/de of the output at soadyn.integrate(q, e * e_k), so every derivative with
respect to q has nv columns (a spherical or free joint's columns are
body-frame rotations and translations, as its velocities are), the convention
of Pinocchio's derivatives.
"""
from __future__ import annotations

import numpy as np

from .. import _soadyn

__all__ = ["inverse_dynamics_derivatives", "dynamics_derivatives"]


def _has_point_springs(model) -> bool:
    return any(e["kind"] == "point_spring" for e in _soadyn.force_elements(model))


def by_dual_numbers(model) -> bool:
    """Whether the model needs the dual-number sweeps: loops, point springs or flexible bodies."""
    return bool(model.nloops) or any(model.n_modes) or _has_point_springs(model)


def inverse_dynamics_derivatives(model, q, v, qdd, f_ext=None):
    """(dtau_dq, dtau_dv, dtau_dqdd) of tau = inverse_dynamics(model, q, v, qdd, f_ext), each (nv, nv).

    dtau_dqdd is the mass matrix M(q). f_ext: (nbodies, 6) body-frame wrenches, which
    turn with their bodies when q changes. On a loop model these are the spanning
    tree's (the loop forces are not part of inverse_dynamics).

    Raises TypeError or ValueError naming an argument of the wrong type or shape or a non-finite entry, and
    DynamicsError naming the body or DOF when the dynamics fail, as the state calls do
    (soadyn.forward_dynamics).
    """
    if any(model.n_modes):
        # Modal DOFs are always regular, so differentiate forward dynamics at tau = ID(q, v, qdd):
        # FD(q, v, ID(q, v, qdd)) = qdd gives dID/dx = -M dFD/dx (x = q, v) and dID/dqdd = M.
        regular = model.copy()
        regular.set_prescribed(np.zeros(model.nv, dtype=bool))
        tau = _soadyn.inverse_dynamics(model, q, v, qdd, f_ext)
        dq, dv, _, *_ = _soadyn._dual_dynamics_derivatives(regular, q, v, tau, f_ext)
        M = _soadyn.mass_matrix(model, q)
        return -M @ dq, -M @ dv, M
    if _has_point_springs(model):  # by the dual-number sweeps: every DOF prescribed, u = qdd
        at_rest = model.copy()
        at_rest.set_prescribed(np.ones(model.nv, dtype=bool))
        d = _soadyn._dual_dynamics_derivatives(at_rest, q, v, qdd, f_ext, True)
        return d[3], d[4], d[5]
    return _soadyn._tree_inverse_dynamics_derivatives(model, q, v, qdd, f_ext)


def dynamics_derivatives(model, q, v, u, f_ext=None):
    """(dqdd_dq, dqdd_dv, dqdd_du, dtau_dq, dtau_dv, dtau_du) of the hybrid dynamics, each (nv, nv).

    The outputs (qdd, tau) and the input u are those of hybrid_dynamics under the
    model's prescribed flags: u is the torque of a regular DOF and the acceleration
    of a prescribed one, so dqdd_du has the identity on prescribed rows and dtau_du
    on regular rows. With every DOF regular, dqdd_dq and dqdd_dv are the derivatives
    of forward dynamics and dqdd_du = M^-1.

    Loop models: the derivatives of constrained_dynamics (the same outputs and inputs), by
    forward-mode automatic differentiation of its sweeps (one dual-number evaluation per column,
    exact to rounding; soadyn/analysis/parameter_sensitivity.hpp).

    Raises TypeError or ValueError naming an argument of the wrong type or shape or a non-finite entry, and
    DynamicsError naming the body or DOF when the dynamics fail, as the state calls do
    (soadyn.forward_dynamics).
    """
    if by_dual_numbers(model):
        return _soadyn._dual_dynamics_derivatives(model, q, v, u, f_ext)
    return _soadyn._tree_dynamics_derivatives(model, q, v, u, f_ext)
