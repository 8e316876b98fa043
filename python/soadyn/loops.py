"""Assembly and projection of closed loops (C++: soadyn/constraints/loop_assembly.hpp).

``assemble`` solves the closure equations Psi(q) = 0 by Gauss-Newton with
minimum-norm steps of the DOFs not held; ``project_velocity`` makes C(q) v = 0
the same way in one linear step; ``independent_coordinates`` partitions the
DOFs by the largest pivots of C ("Joint Coordinate Method, Part 1",
Eqs. 1.16-1.20). Corrections are minimum-norm in the Euclidean norm of the
tangent coordinates (radians and metres alike) of the DOFs allowed to move.
"""
from __future__ import annotations

import numpy as np

from ._soadyn import _assemble, _project_velocity


def _free(model, hold) -> list[bool]:
    free = [True] * model.nv
    if hold is not None:
        for k in model._dof_indices(hold):
            free[k] = False
    return free


def assemble(model, q, hold=None, tolerance: float = 1e-12, max_iterations: int = 50) -> np.ndarray:
    """A configuration near q that closes every loop: each |Psi_i| <= tolerance.

    hold: DOF or joint names (or indices) that keep their values; every other
    DOF may move. Raises DynamicsError naming the loop that cannot close (the
    mechanism cannot reach closure from q with the DOFs allowed to move).
    Returns a fresh array; a model without loops returns q unchanged.
    """
    return _assemble(model, q, _free(model, hold), tolerance, max_iterations)


def project_velocity(model, q, v, hold=None) -> np.ndarray:
    """The velocity nearest v, changing only the DOFs not held, with C(q) v = 0.

    When the held DOFs' velocities make closure impossible the result is the
    least-squares one (check soadyn.loop_residual(m, q, v)). Returns a fresh array.

    q (nq,) and v (nv,) as in the state calls; hold names unknown DOFs in a ValueError. Raises TypeError or
    ValueError naming an argument of the wrong type or shape or a non-finite entry, and DynamicsError naming the
    body or DOF when the dynamics fail, as the state calls do (soadyn.forward_dynamics).
    """
    return _project_velocity(model, q, v, _free(model, hold))
