"""First-order maps between the joint manifolds' tangent spaces, for linearize.

A configuration's tangent space is that of soadyn.integrate: a perturbation e of
q is q (+) e, body-frame rotations and translations for spherical, free and planar
joints. The integrators step in charts (cpp/include/soadyn/sim/chart.hpp): around
a base q0, q = retract(q0, xi), with xi a parent-frame rotation vector
(spherical, and the free joint's rotation: q0 exp(xi)), a parent-frame translation
(free joint), or the coordinates themselves (planar and vector-space joints); and
dxi/dt = rate(q0, xi, v). Each function returns the block-diagonal nv x nv matrix
of one derivative, joint by joint (identity or zero blocks for vector-space
joints and modal coordinates).
"""
from __future__ import annotations

import numpy as np

__all__ = ["lie_bracket_matrix", "coordinate_of_dof", "retract", "base_transport", "chart_transport", "chart_rate", "rate_derivatives"]

_SMALL = 1e-6  # |xi|^2 below which the series of the so(3) functions are used (as lie.hpp)


def skew(w) -> np.ndarray:
    return np.array([[0.0, -w[2], w[1]], [w[2], 0.0, -w[0]], [-w[1], w[0], 0.0]])


def quaternion_matrix(quat) -> np.ndarray:
    x, y, z, w = quat
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def _quaternion_product(a, b) -> np.ndarray:
    av, aw, bv, bw = a[:3], a[3], b[:3], b[3]
    return np.concatenate([aw * bv + bw * av + np.cross(av, bv), [aw * bw - av @ bv]])


def _quaternion_exp(xi) -> np.ndarray:
    t = np.linalg.norm(xi)
    s = 0.5 - t * t / 48 if t * t < _SMALL else np.sin(t / 2) / t
    return np.concatenate([s * xi, [np.cos(t / 2)]])


def so3_exp(xi) -> np.ndarray:
    return quaternion_matrix(_quaternion_exp(xi))


def _so3_coefficients(xi):
    t2 = xi @ xi
    if t2 < _SMALL:
        return 0.5 - t2 / 24, 1 / 6 - t2 / 120
    t = np.sqrt(t2)
    return (1 - np.cos(t)) / t2, (t - np.sin(t)) / (t2 * t)


def so3_right_jacobian(xi) -> np.ndarray:
    """J_r(xi): q0 exp(xi + d) = q0 exp(xi) exp(J_r(xi) d) to first order."""
    a, b = _so3_coefficients(xi)
    k = skew(xi)
    return np.eye(3) - a * k + b * k @ k


def _inverse_coefficient(xi):
    """c(t) of J_r^-1 = I + K/2 + c K^2 and c'(t)/t, t = |xi|."""
    t2 = xi @ xi
    if t2 < _SMALL:
        return 1 / 12 + t2 / 720, 1 / 360
    t = np.sqrt(t2)
    half_cot = 1 / np.tan(t / 2)
    c = 1 / t2 - half_cot / (2 * t)
    dc = -2 / (t2 * t) + 0.25 / (t * np.sin(t / 2) ** 2) + half_cot / (2 * t2)
    return c, dc / t


def so3_right_jacobian_inverse(xi) -> np.ndarray:
    c, _ = _inverse_coefficient(xi)
    k = skew(xi)
    return np.eye(3) + k / 2 + c * k @ k


def so3_right_jacobian_inverse_derivative(xi, w) -> np.ndarray:
    """d/dxi of J_r^-1(xi) w (3 x 3)."""
    c, dc_over_t = _inverse_coefficient(xi)
    k = skew(xi)
    kkw = k @ k @ w  # xi x (xi x w) = xi (xi . w) - w |xi|^2
    return (-skew(w) / 2 + np.outer(kkw, xi) * dc_over_t
            + c * ((xi @ w) * np.eye(3) + np.outer(xi, w) - 2 * np.outer(w, xi)))


def _planar_rotation(theta) -> tuple[np.ndarray, np.ndarray]:
    c, s = np.cos(theta), np.sin(theta)
    return np.array([[c, -s], [s, c]]), np.array([[-s, -c], [c, -s]])


def _joints(model):
    """(kind, q index, v index) of every spherical, free and planar joint."""
    return [(kind, model.q_index[i], model.v_index[i]) for i, kind in enumerate(model.joint_types)
            if kind in ("spherical", "free", "planar")]


def lie_bracket_matrix(model, v) -> np.ndarray:
    """ad_v (nv x nv): ad_v e = [v, e], the Lie bracket of the joints' groups in the
    tangent space of soadyn.integrate: so(3) (spherical), se(3) with v = (w, u) (free),
    se(2) with v = (vx, vy, w) (planar); zero for vector-space joints."""
    ad = np.zeros((model.nv, model.nv))
    for kind, _, o in _joints(model):
        if kind == "planar":
            vx, vy, w = v[o:o + 3]
            ad[o:o + 3, o:o + 3] = [[0.0, -w, vy], [w, 0.0, -vx], [0.0, 0.0, 0.0]]
            continue
        r = slice(o, o + 3)
        ad[r, r] = skew(v[r])
        if kind == "free":
            t = slice(o + 3, o + 6)
            ad[t, t] = skew(v[r])
            ad[t, r] = skew(v[t])
    return ad


_JOINT_SIZES = {"revolute": (1, 1), "prismatic": (1, 1), "helical": (1, 1), "universal": (2, 2),
                "cylindrical": (2, 2), "planar": (3, 3), "spherical": (4, 3), "free": (7, 6), "translation": (3, 3),
                "fixed": (0, 0)}


def coordinate_of_dof(model) -> np.ndarray:
    """The coordinate of each DOF whose coordinate adds its chart value (every DOF but
    those of spherical and free joints, -1): planar x, y, theta, modal coordinates."""
    out = np.full(model.nv, -1)
    for i, kind in enumerate(model.joint_types):
        nq, nv = _JOINT_SIZES[kind]
        qi, vi = model.q_index[i], model.v_index[i]
        if kind not in ("spherical", "free"):
            out[vi:vi + nv] = np.arange(qi, qi + nv)
        modes = model.n_modes[i]
        out[vi + nv:vi + nv + modes] = np.arange(qi + nq, qi + nq + modes)
    return out


def retract(model, q0, xi) -> np.ndarray:
    """The integrators' chart: q = retract(q0, xi)."""
    q0 = np.asarray(q0, dtype=float)
    q = q0.copy()
    coordinate = coordinate_of_dof(model)
    additive = coordinate >= 0
    q[coordinate[additive]] += np.asarray(xi)[additive]
    for kind, qi, o in _joints(model):
        if kind == "planar":
            continue
        rot_q = qi + (3 if kind == "free" else 0)
        q[rot_q:rot_q + 4] = _quaternion_product(q0[rot_q:rot_q + 4], _quaternion_exp(xi[o:o + 3]))
        if kind == "free":
            q[qi:qi + 3] = q0[qi:qi + 3] + xi[o + 3:o + 6]
    return q


def base_transport(model, q0, xi) -> np.ndarray:
    """d(tangent at retract(q0, xi)) / d(tangent at q0), xi fixed."""
    T = np.eye(model.nv)
    for kind, qi, o in _joints(model):
        if kind == "planar":
            R0, _ = _planar_rotation(q0[qi + 2])
            R1, _ = _planar_rotation(q0[qi + 2] + xi[o + 2])
            T[o:o + 2, o:o + 2] = R1.T @ R0
            continue
        r = slice(o, o + 3)
        E = so3_exp(xi[r])
        T[r, r] = E.T
        if kind == "free":
            t = slice(o + 3, o + 6)
            T[t, t] = E.T  # R1' R0 = exp(xi)'
    return T


def chart_transport(model, q0, xi) -> np.ndarray:
    """d(tangent at retract(q0, xi)) / d xi."""
    T = np.eye(model.nv)
    for kind, qi, o in _joints(model):
        if kind == "planar":
            R1, _ = _planar_rotation(q0[qi + 2] + xi[o + 2])
            T[o:o + 2, o:o + 2] = R1.T
            continue
        r = slice(o, o + 3)
        T[r, r] = so3_right_jacobian(xi[r])
        if kind == "free":
            t = slice(o + 3, o + 6)
            T[t, t] = (quaternion_matrix(q0[qi + 3:qi + 7]) @ so3_exp(xi[r])).T
    return T


def chart_rate(model, q0, xi, v) -> np.ndarray:
    """dxi/dt at q = retract(q0, xi) for velocity v (cpp/include/soadyn/sim/chart.hpp)."""
    rate = np.array(v, dtype=float)
    for kind, qi, o in _joints(model):
        if kind == "planar":
            R1, _ = _planar_rotation(q0[qi + 2] + xi[o + 2])
            rate[o:o + 2] = R1 @ v[o:o + 2]
            continue
        r = slice(o, o + 3)
        rate[r] = so3_right_jacobian_inverse(xi[r]) @ v[r]
        if kind == "free":
            t = slice(o + 3, o + 6)
            rate[t] = quaternion_matrix(q0[qi + 3:qi + 7]) @ so3_exp(xi[r]) @ v[t]
    return rate


def rate_derivatives(model, q0, xi, v) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(d rate/d tangent at q0, d rate/d xi, d rate/d v) of chart_rate."""
    nv = model.nv
    d_base, d_xi, d_v = np.zeros((nv, nv)), np.zeros((nv, nv)), np.eye(nv)
    for kind, qi, o in _joints(model):
        if kind == "planar":
            R1, dR1 = _planar_rotation(q0[qi + 2] + xi[o + 2])
            d_v[o:o + 2, o:o + 2] = R1
            d_xi[o:o + 2, o + 2] = dR1 @ v[o:o + 2]
            d_base[o:o + 2, o + 2] = dR1 @ v[o:o + 2]
            continue
        r = slice(o, o + 3)
        d_v[r, r] = so3_right_jacobian_inverse(xi[r])
        d_xi[r, r] = so3_right_jacobian_inverse_derivative(xi[r], v[r])
        if kind == "free":
            t = slice(o + 3, o + 6)
            E = so3_exp(xi[r])
            R1 = quaternion_matrix(q0[qi + 3:qi + 7]) @ E
            u_cross = skew(v[t])
            d_v[t, t] = R1
            d_xi[t, r] = -R1 @ u_cross @ so3_right_jacobian(xi[r])
            d_base[t, r] = -R1 @ u_cross @ E.T
    return d_base, d_xi, d_v
