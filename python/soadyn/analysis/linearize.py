"""Exact linearizations of the dynamics (C++: soadyn/analysis/linearization.hpp, which documents the math)."""
from __future__ import annotations

from .. import _soadyn

__all__ = ["linearize"]


def linearize(model, q, v, u, dt=None, integrator: str = "rk4", f_ext=None):
    """(A, B) of the dynamics at (q, v, u): continuous, or with dt the exact Jacobian of one Simulator step.

    State x = (e, v), e the tangent-space perturbation of q (q = integrate(q_bar, e)), input u as
    hybrid_dynamics (torque of regular DOFs, acceleration of prescribed ones).
    - dt=None: dx/dt ~ f + A dx + B du, A = [[-1/2 ad_v, I], [dqdd_dq, dqdd_dv]] (2nv x 2nv),
      B = [[0], [dqdd_du]] (2nv x nv); ad_v is the joints' Lie bracket, zero for vector-space
      joints and at rest.
    - dt > 0: (e', v') after one step of `integrator` ("rk4" or "euler", as soadyn.Simulator
      steps, inputs held over the step), e' in the tangent space at the step's end. "dopri5"
      adapts its sub-steps and has no fixed step map: refused with a ValueError.

    Raises TypeError or ValueError naming an argument of the wrong type or shape or a non-finite entry, and
    DynamicsError naming the body or DOF when the dynamics fail, as the state calls do
    (soadyn.forward_dynamics).
    """
    return _soadyn._linearize(model, q, v, u, dt, integrator, f_ext)
