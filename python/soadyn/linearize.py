"""Small oscillations about a configuration at rest: natural frequencies.

Linearised about (q, v = 0), the regular DOFs obey M dq'' + K dq = 0 with
M the mass matrix at q and K the stiffness, the derivative of the
generalized bias h(q, 0) (gravity and elastic forces) along each DOF's
tangent direction. Prescribed DOFs are held where they are (their
accelerations are given, zero here), so only the regular DOFs oscillate.
"""
from __future__ import annotations

import numpy as np

from ._soadyn import bias_forces, integrate, mass_matrix

__all__ = ["natural_frequencies", "stiffness_matrix"]

_STEP = 1e-6  # central-difference step in each DOF's tangent direction


def stiffness_matrix(model, q) -> np.ndarray:
    """d h(q, 0) / dq (nv x nv), by central differences on the joint manifolds.

    Elastic forces are linear in the modal coordinates, so their part is exact
    to rounding; the gravity part has a truncation error of order 1e-12.
    """
    q = np.asarray(q, dtype=float)
    zero = np.zeros(model.nv)
    K = np.empty((model.nv, model.nv))
    for k in range(model.nv):
        step = np.zeros(model.nv)
        step[k] = _STEP
        h_plus = bias_forces(model, integrate(model, q, step, 1.0), zero)
        h_minus = bias_forces(model, integrate(model, q, -step, 1.0), zero)
        K[:, k] = (h_plus - h_minus) / (2 * _STEP)
    return K


def natural_frequencies(model, q) -> np.ndarray:
    """Natural frequencies (rad/s, ascending) of the model linearised about q at rest.

    One entry per regular DOF (prescribed DOFs are held). An entry is
    sqrt(lambda) for each eigenvalue lambda of M^-1 K; a DOF without
    stiffness (a free joint, a free hinge without gravity) gives 0, and a
    negative entry -sqrt(-lambda) marks an unstable direction (for example
    a pendulum linearised upside down). If q is not an equilibrium, the
    result describes the linearised restoring forces about q all the same.
    """
    q = np.asarray(q, dtype=float)
    regular = ~np.asarray(model.prescribed, dtype=bool)
    M = mass_matrix(model, q)[np.ix_(regular, regular)]
    K = stiffness_matrix(model, q)[np.ix_(regular, regular)]
    lam = np.linalg.eigvals(np.linalg.solve(M, K)).real
    scale = max(np.abs(lam).max(initial=0.0), 1.0)
    lam[np.abs(lam) < 1e-9 * scale] = 0.0  # rigid-body directions: zero to rounding
    return np.sort(np.sign(lam) * np.sqrt(np.abs(lam)))
