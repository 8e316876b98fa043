"""Small oscillations about a configuration at rest: stiffness, natural frequencies, modes.

Linearised about (q, v = 0, qdd = 0), the regular DOFs obey
    M e'' + D e' + K e = 0,
M the mass matrix at q, K = d tau/dq the stiffness (the derivative of the
generalized bias h(q, 0): gravity, elastic and spring forces, along each DOF's
tangent direction) and D = d tau/dv at rest (dampers and modal damping; the
velocity products vanish at rest), all from inverse_dynamics_derivatives at
(q, 0, 0). Prescribed DOFs are held where they are (their accelerations are
given, zero here), so only the regular DOFs oscillate. Models with flexible
bodies or point springs take K, D and M from the dual-number sweeps
(soadyn.inverse_dynamics_derivatives), exact to rounding as for rigid models.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import _soadyn
from .derivatives import by_dual_numbers, inverse_dynamics_derivatives

__all__ = ["Modes", "modes", "natural_frequencies", "stiffness_matrix"]

def _at_rest_derivatives(model, q):
    """(K, D, M) at (q, v = 0, qdd = 0)."""
    zero = np.zeros(model.nv)
    return inverse_dynamics_derivatives(model, q, zero, zero)


def stiffness_matrix(model, q) -> np.ndarray:
    """K = d h(q, 0) / dq (nv x nv) in the tangent space of soadyn.integrate, exact
    (inverse_dynamics_derivatives at rest).

    Raises TypeError or ValueError naming an argument of the wrong type or shape or a non-finite entry, and
    DynamicsError naming the body or DOF when the dynamics fail, as the state calls do
    (soadyn.forward_dynamics).
    """
    return _at_rest_derivatives(model, q)[0]


def natural_frequencies(model, q) -> np.ndarray:
    """Natural frequencies (rad/s, ascending) of the model linearised about q at rest.

    One entry per regular DOF (prescribed DOFs are held). An entry is
    sqrt(lambda) for each eigenvalue lambda of M^-1 K; a DOF without
    stiffness (a free joint, a free hinge without gravity) gives 0, and a
    negative entry -sqrt(-lambda) marks an unstable direction (for example
    a pendulum linearised upside down). If q is not an equilibrium, the
    result describes the linearised restoring forces about q all the same.
    Damping is left out (see `modes` for damped modes).

    Raises TypeError or ValueError naming an argument of the wrong type or shape or a non-finite entry, and
    DynamicsError naming the body or DOF when the dynamics fail, as the state calls do
    (soadyn.forward_dynamics).
    """
    regular = ~np.asarray(model.prescribed, dtype=bool)
    K, _, M = _at_rest_derivatives(model, q)
    M, K = M[np.ix_(regular, regular)], K[np.ix_(regular, regular)]
    lam = np.linalg.eigvals(np.linalg.solve(M, K)).real
    scale = max(np.abs(lam).max(initial=0.0), 1.0)
    lam[np.abs(lam) < 1e-9 * scale] = 0.0  # rigid-body directions: zero to rounding
    return np.sort(np.sign(lam) * np.sqrt(np.abs(lam)))


@dataclass
class Modes:
    """Modes of the regular DOFs about a configuration at rest, by increasing |frequency|.

    Each mode is a root pair of s^2 + 2 zeta w s + w^2 of the linearised system
    M e'' + D e' + K e = 0:
    - angular_frequencies: w (rad/s), the undamped natural frequency; negative
      (-sqrt(-w^2)) for an unstable mode, 0 for a rigid-body mode;
    - frequencies_hz: w / (2 pi);
    - damping_ratios: zeta (nan for a rigid-body mode);
    - eigenvalues: (n, 2) complex roots of each mode;
    - shapes: (n, len(dof_names)) real mode shapes (the eigenvector's position part,
      turned so its largest entry is real and scaled to 1);
    - dof_names: the regular DOFs the shapes' columns stand for.
    """
    angular_frequencies: np.ndarray
    frequencies_hz: np.ndarray
    damping_ratios: np.ndarray
    eigenvalues: np.ndarray
    shapes: np.ndarray
    dof_names: list

    def table(self, dofs_per_mode: int = 3) -> str:
        """One line per mode: frequency, damping ratio and the DOFs that move most."""
        lines = ["mode  frequency (Hz)  damping ratio  largest DOFs"]
        for k, (f, z, shape) in enumerate(zip(self.frequencies_hz, self.damping_ratios, self.shapes)):
            top = np.argsort(-np.abs(shape))[:dofs_per_mode]
            dofs = ", ".join(f"{self.dof_names[j]} {shape[j]:+.3f}" for j in top)
            lines.append(f"{k + 1:4d}  {f:14.6g}  {z:13.4g}  {dofs}")
        return "\n".join(lines)


def modes(model, q) -> Modes:
    """Frequencies (Hz and rad/s), damping ratios and DOF-labelled mode shapes of the
    model linearised about q at rest (see Modes; C++: soadyn/analysis/modes.hpp).
    Prescribed DOFs are held. Models with flexible bodies or point springs: from the dual-number
    derivatives (soadyn.inverse_dynamics_derivatives) through the same eigen-analysis.

    Raises TypeError or ValueError naming an argument of the wrong type or shape or a non-finite entry, and
    DynamicsError naming the body or DOF when the dynamics fail, as the state calls do
    (soadyn.forward_dynamics).
    """
    if by_dual_numbers(model) and not model.nloops:
        K, D, M = _at_rest_derivatives(model, q)
        dofs, w, zeta, roots, shapes = _soadyn._modes_of(model, M, K, D)
    else:
        dofs, w, zeta, roots, shapes = _soadyn._modes(model, q)
    names = [model.dof_names[k] for k in dofs]
    return Modes(w, w / (2 * np.pi), zeta, roots, shapes, names)
