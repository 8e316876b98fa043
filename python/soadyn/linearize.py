"""Exact linearizations of the dynamics: continuous (A, B) and the discrete map of an integrator.

State x = (e, v): e (nv) perturbs q in the tangent space of soadyn.integrate
(q = integrate(q_bar, e)), v the velocities; input u as hybrid_dynamics (torque
of regular DOFs, acceleration of prescribed DOFs).

Continuous: dx/dt = f(x, u) ~ f(x_bar, u_bar) + A dx + B du with
    A = [[-1/2 ad_v, I], [dqdd/dq, dqdd/dv]],  B = [[0], [dqdd/du]].
The kinematic block: q = q_bar exp(e) moves with body velocity v = J_r(e) de/dt,
so de/dt = J_r(e)^-1 v = v + 1/2 [e, v] + O(e^2), whose e-derivative is
-1/2 ad_v (manifold_jacobians.lie_bracket_matrix): zero for vector-space joints
and at rest.

Discrete (dt given): the exact Jacobian of one step of the Simulator's
integrator ("euler": semi-implicit Euler; "rk4"), inputs held over the step,
from state (e, v) at q_bar to state (e', v') at the step's end q_bar' (e'
again in the tangent space of integrate): the chain rule through the
integrator's stages, each with the analytic dynamics derivatives at the stage
point and the chart's Jacobians (manifold_jacobians). "dopri5" adapts its
sub-steps, so its step has no fixed discrete map: refused.
"""
from __future__ import annotations

import numpy as np

from . import manifold_jacobians as mj
from .derivatives import dynamics_derivatives
from ._soadyn import hybrid_dynamics

__all__ = ["linearize"]

# Butcher tableaux of the Simulator's explicit integrators (cpp/include/soadyn/sim/simulator.hxx).
_RK4_A = np.array([[0, 0, 0, 0], [0.5, 0, 0, 0], [0, 0.5, 0, 0], [0, 0, 1, 0]])
_RK4_B = np.array([1 / 6, 1 / 3, 1 / 3, 1 / 6])


def linearize(model, q, v, u, dt=None, integrator: str = "rk4", f_ext=None):
    """(A, B): continuous (2nv x 2nv, 2nv x nv) at (q, v, u), or with dt the discrete map
    of `integrator` ("rk4" or "euler", the Simulator's). See the module docstring."""
    q, v, u = (np.asarray(x, dtype=float) for x in (q, v, u))
    if dt is None:
        return _continuous(model, q, v, u, f_ext)
    dt = float(dt)
    if not np.isfinite(dt) or dt <= 0:
        raise ValueError(f"dt must be finite and positive, got {dt}")
    if integrator == "rk4":
        return _runge_kutta(model, q, v, u, dt, _RK4_A, _RK4_B, f_ext)
    if integrator in ("euler", "semi-implicit-euler"):
        return _semi_implicit_euler(model, q, v, u, dt, f_ext)
    if integrator == "dopri5":
        raise ValueError("integrator 'dopri5' adapts its sub-steps: its step has no fixed discrete map to "
                         "linearize (choose 'rk4' or 'euler', or dt=None for the continuous system)")
    raise ValueError(f"unknown integrator '{integrator}' (choose 'rk4' or 'euler')")


def _continuous(model, q, v, u, f_ext):
    nv = model.nv
    dqdd_dq, dqdd_dv, dqdd_du = dynamics_derivatives(model, q, v, u, f_ext)[:3]
    A = np.zeros((2 * nv, 2 * nv))
    A[:nv, :nv] = -0.5 * mj.lie_bracket_matrix(model, v)
    A[:nv, nv:] = np.eye(nv)
    A[nv:, :nv], A[nv:, nv:] = dqdd_dq, dqdd_dv
    B = np.zeros((2 * nv, nv))
    B[nv:] = dqdd_du
    return A, B


class _Stage:
    """Values and Jacobians (columns: e at the step's base, v, u) of one stage point."""

    def __init__(self, model, q0, xi, v, u, f_ext, d_xi, d_v):
        nv = model.nv
        q = mj.retract(model, q0, xi)
        self.acceleration = hybrid_dynamics(model, q, v, u, f_ext)[0]
        dqdd_dq, dqdd_dv, dqdd_du = dynamics_derivatives(model, q, v, u, f_ext)[:3]
        base = np.hstack([np.eye(nv), np.zeros((nv, 2 * nv))])
        input_ = np.hstack([np.zeros((nv, 2 * nv)), np.eye(nv)])
        d_tangent = mj.base_transport(model, q0, xi) @ base + mj.chart_transport(model, q0, xi) @ d_xi
        self.d_acceleration = dqdd_dq @ d_tangent + dqdd_dv @ d_v + dqdd_du @ input_
        self.rate = mj.chart_rate(model, q0, xi, v)
        r_base, r_xi, r_v = mj.rate_derivatives(model, q0, xi, v)
        self.d_rate = r_base @ base + r_xi @ d_xi + r_v @ d_v


def _end_of_step(model, q0, xi, d_xi, d_v1):
    """(A, B) from the chart value xi at the step's end and the Jacobians of xi and v'."""
    nv = model.nv
    base = np.hstack([np.eye(nv), np.zeros((nv, 2 * nv))])
    d_e1 = mj.base_transport(model, q0, xi) @ base + mj.chart_transport(model, q0, xi) @ d_xi
    J = np.vstack([d_e1, d_v1])
    return J[:, :2 * nv], J[:, 2 * nv:]


def _runge_kutta(model, q0, v0, u, dt, a, b, f_ext):
    nv = model.nv
    d_v0 = np.hstack([np.zeros((nv, nv)), np.eye(nv), np.zeros((nv, nv))])
    stages = []
    for k in range(len(b)):
        xi = np.zeros(nv)
        v = v0.copy()
        d_xi = np.zeros((nv, 3 * nv))
        d_v = d_v0.copy()
        for j in range(k):
            if a[k, j]:
                xi += dt * a[k, j] * stages[j].rate
                v += dt * a[k, j] * stages[j].acceleration
                d_xi += dt * a[k, j] * stages[j].d_rate
                d_v += dt * a[k, j] * stages[j].d_acceleration
        stages.append(_Stage(model, q0, xi, v, u, f_ext, d_xi, d_v))
    xi_end = dt * sum(bk * s.rate for bk, s in zip(b, stages))
    d_xi_end = dt * sum(bk * s.d_rate for bk, s in zip(b, stages))
    d_v1 = d_v0 + dt * sum(bk * s.d_acceleration for bk, s in zip(b, stages))
    return _end_of_step(model, q0, xi_end, d_xi_end, d_v1)


def _semi_implicit_euler(model, q0, v0, u, dt, f_ext):
    """v' = v + dt qdd(q, v, u); q' = retract(q, dt rate(q, 0, v'))."""
    nv = model.nv
    zero = np.zeros(nv)
    d_v0 = np.hstack([np.zeros((nv, nv)), np.eye(nv), np.zeros((nv, nv))])
    stage = _Stage(model, q0, zero, v0, u, f_ext, np.zeros((nv, 3 * nv)), d_v0)
    v1 = v0 + dt * stage.acceleration
    d_v1 = d_v0 + dt * stage.d_acceleration
    r_base, _, r_v = mj.rate_derivatives(model, q0, zero, v1)
    base = np.hstack([np.eye(nv), np.zeros((nv, 2 * nv))])
    xi = dt * mj.chart_rate(model, q0, zero, v1)
    d_xi = dt * (r_base @ base + r_v @ d_v1)
    return _end_of_step(model, q0, xi, d_xi, d_v1)
