"""Rigid-body inertia for the URDF loader: merging welded links, and the
smallest repair that makes an inertia physical.

A physical rigid body has a rotational inertia about its centre of mass whose
principal moments (l1, l2, l3) obey the triangle inequalities
l_i <= l_j + l_k (which imply l_i >= 0), and no inertia without mass. The set
of such moments is a convex polyhedral cone; the repair is the Euclidean
projection of the moments onto it, keeping the principal axes: the smallest
change (in the Frobenius norm of the inertia matrix, among changes that keep
the axes) that makes the body physical. When only l3 > l1 + l2 is violated,
by d, it moves every moment by d / 3 (l1 and l2 up, l3 down). MuJoCo's
compiler option balanceinertia instead replaces all three diagonal moments
by their mean; the projection changes less.
"""
from __future__ import annotations

from itertools import combinations

import numpy as np

__all__ = ["merge_parts", "physical_moments", "repaired_inertia", "minimal_inertial"]

# Row k is the triangle constraint l_j + l_k - l_i >= 0 written as a_k . l >= 0.
_TRIANGLE = np.array([[-1.0, 1.0, 1.0], [1.0, -1.0, 1.0], [1.0, 1.0, -1.0]])

# A link the repair gives mass to gets this fraction of the robot's mean link mass and moment.
MINIMAL_FRACTION = 1e-6


def merge_parts(parts) -> tuple[float, np.ndarray, np.ndarray]:
    """(mass, com, inertia about the com) of rigidly joined parts, each given as
    (mass, com, inertia about its com) in one common frame (parallel-axis theorem)."""
    mass = sum(m for m, _, _ in parts)
    if mass == 0:
        return 0.0, np.zeros(3), sum((I for _, _, I in parts), np.zeros((3, 3)))
    com = sum(m * c for m, c, _ in parts) / mass
    inertia = np.zeros((3, 3))
    for m, c, I in parts:
        d = c - com
        inertia += I + m * (d @ d * np.eye(3) - np.outer(d, d))
    return mass, com, 0.5 * (inertia + inertia.T)


def physical_moments(moments: np.ndarray) -> np.ndarray:
    """The Euclidean projection of three principal moments onto the triangle-inequality cone.

    The projection lies on the face where some set S of constraints is
    active; it is the projection of `moments` onto the subspace a_k . l = 0
    (k in S). Every candidate that is feasible lies in the cone, and the true
    projection is among them, so the nearest feasible candidate is it.
    """
    x = np.asarray(moments, dtype=float)
    scale = max(float(np.max(np.abs(x))), np.finfo(float).tiny)
    best, best_distance = np.zeros(3), float(np.linalg.norm(x))  # all three active: the origin
    for size in (0, 1, 2):
        for active in combinations(range(3), size):
            A = _TRIANGLE[list(active)]
            candidate = x - A.T @ np.linalg.solve(A @ A.T, A @ x) if size else x
            if np.all(_TRIANGLE @ candidate >= -1e-12 * scale):
                distance = float(np.linalg.norm(candidate - x))
                if distance < best_distance:
                    best, best_distance = candidate, distance
    return best


def repaired_inertia(inertia: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(repaired inertia, moments before, moments after): the principal moments
    projected onto the physical cone, the principal axes kept."""
    moments, axes = np.linalg.eigh(0.5 * (inertia + inertia.T))
    fixed = physical_moments(moments)
    repaired = axes @ np.diag(fixed) @ axes.T
    return 0.5 * (repaired + repaired.T), moments, fixed


def minimal_inertial(links) -> tuple[float, float]:
    """(mass, principal moment) given by the repair to a moving link that has
    none: MINIMAL_FRACTION of the robot's mean positive link mass and of its
    mean positive principal moment (trace / 3); 1e-6 kg and 1e-10 kg m^2
    (1e-6 kg at 1 cm) for a robot that has none."""
    masses = [link.inertial.mass for link in links if link.inertial is not None and link.inertial.mass > 0]
    moments = [np.trace(link.inertial.inertia) / 3 for link in links
               if link.inertial is not None and np.trace(link.inertial.inertia) > 0]
    mass = MINIMAL_FRACTION * float(np.mean(masses)) if masses else 1e-6
    moment = MINIMAL_FRACTION * float(np.mean(moments)) if moments else mass * 1e-4
    return mass, moment
