"""The closed-form static equilibrium of a planar four-bar in a vertical plane (gravity in the
plane) with a torsion spring on the crank (stiffness K, rest angle 0): its potential written from the
loop's geometry (circle intersection) without soadyn, the equilibrium found by scipy's brentq and its
sensitivities by the implicit function theorem on that potential."""
import numpy as np
from scipy.optimize import brentq

A, B, C, D = 0.4, 1.0, 0.8, 0.9   # crank, coupler, rocker lengths; ground pivot distance
MASSES = {"crank": 1.2, "coupler": 2.0, "rocker": 1.5}
G, K = 9.81, 5.0


def pin(theta):
    """Coupler-rocker pin Q for crank angle theta (the upper intersection of the two circles)."""
    P = A * np.array([np.cos(theta), np.sin(theta)])
    O2 = np.array([D, 0.0])
    d = np.linalg.norm(O2 - P)
    along = (B ** 2 - C ** 2 + d ** 2) / (2 * d)
    h = np.sqrt(B ** 2 - along ** 2)
    u = (O2 - P) / d
    return P, P + along * u + h * np.array([-u[1], u[0]])


def potential(theta, k=K, masses=MASSES):
    P, Q = pin(theta)
    heights = {"crank": P[1] / 2, "coupler": (P[1] + Q[1]) / 2, "rocker": Q[1] / 2}
    return 0.5 * k * theta ** 2 + G * sum(masses[b] * heights[b] for b in masses)


def derivative(f, x, h=1e-5):
    return (f(x + h) - f(x - h)) / (2 * h)


def reference_equilibrium(k=K, masses=MASSES, bracket=(-1.5, -0.8)):
    return brentq(lambda t: derivative(lambda s: potential(s, k, masses), t), *bracket, xtol=1e-14)


def reference_sensitivities(theta):
    """dtheta*/dp = -(d/dp V'(theta*)) / V''(theta*) for p = k and each link's mass."""
    second = derivative(lambda t: derivative(potential, t, 1e-4), theta, 1e-4)
    out = {"crank_spring.stiffness": -theta / second}
    for body in MASSES:
        def height_rate(t, body=body):
            unit = {b: (1.0 if b == body else 0.0) for b in MASSES}
            return derivative(lambda s: potential(s, 0.0, unit), t) / G
        out[f"{body}.mass"] = -G * height_rate(theta) / second
    return out
