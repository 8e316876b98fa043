"""The crank-rocker four-bar of Saha, Shah & Nandihal 2013 (Fig. 16) in closed form: the soadyn
model (a planar loop cut at the coupler-rocker pin), its assembly (elbow up), the closure Jacobian
(Eq. 52b) and the velocity product of the closure's second derivative."""
from __future__ import annotations

import numpy as np

import soadyn

# The crank-rocker of Saha, Shah & Nandihal 2013 (Fig. 16): link lengths (m) and masses (kg).
CRANK, COUPLER, ROCKER, GROUND = 0.038, 0.1152, 0.1152, 0.0895
MASSES = (1.5, 5.0, 3.0)


def rod(length, mass):
    """Uniform slender rod along its body x axis: centre of mass and principal moments about it."""
    return dict(mass=mass, com=(length / 2, 0.0, 0.0), inertia=(0.0, mass * length**2 / 12, mass * length**2 / 12))


def four_bar(kind="revolute"):
    m = soadyn.Model()
    m.gravity = (0.0, -9.81, 0.0)
    z = soadyn.Joint.revolute((0.0, 0.0, 1.0))
    m.add_body("crank", None, z, **rod(CRANK, MASSES[0]))
    m.add_body("coupler", "crank", z, placement=(CRANK, 0.0, 0.0), **rod(COUPLER, MASSES[1]))
    m.add_body("rocker", None, z, placement=(GROUND, 0.0, 0.0), **rod(ROCKER, MASSES[2]))
    m.add_loop("pin", "coupler", "rocker", kind, placement_a=(None, (COUPLER, 0, 0)),
               placement_b=(None, (ROCKER, 0, 0)))
    return m


def e(x):
    return np.array([np.cos(x), np.sin(x)])


def e_perp(x):
    return np.array([-np.sin(x), np.cos(x)])


def assembled(theta1):
    """Joint angles (crank, coupler relative to crank, rocker) closing the four-bar, elbow up."""
    P, G = CRANK * e(theta1), np.array([GROUND, 0.0])
    d = np.linalg.norm(G - P)
    # Q on the circles |Q - P| = COUPLER, |Q - G| = ROCKER.
    along = (COUPLER**2 - ROCKER**2 + d * d) / (2 * d)
    u = (G - P) / d
    Q = P + along * u + np.sqrt(COUPLER**2 - along**2) * np.array([-u[1], u[0]])
    phi2 = np.arctan2(*(Q - P)[::-1])
    theta3 = np.arctan2(*(Q - G)[::-1])
    return np.array([theta1, phi2 - theta1, theta3])


def closure_jacobian(theta):
    """d/dtheta of the in-plane closure f = crank tip + coupler - (ground + rocker) (Eq. 52b)."""
    t1, t2, t3 = theta
    phi2 = t1 + t2
    return np.column_stack([CRANK * e_perp(t1) + COUPLER * e_perp(phi2), COUPLER * e_perp(phi2), -ROCKER * e_perp(t3)])


def closure_velocity_product(theta, thetad):
    """The part of f'' without accelerations: -a t1'^2 e(t1) - b phi2'^2 e(phi2) + c t3'^2 e(t3)."""
    t1, t2, t3 = theta
    return (-CRANK * thetad[0]**2 * e(t1) - COUPLER * (thetad[0] + thetad[1])**2 * e(t1 + t2)
            + ROCKER * thetad[2]**2 * e(t3))


def four_bar_state(theta1, rate):
    """Joint angles closing the four-bar at crank angle theta1, and joint rates with crank rate `rate`
    that keep it closed."""
    theta = assembled(theta1)
    J = closure_jacobian(theta)
    thetad = np.r_[rate, -np.linalg.solve(J[:, 1:], J[:, 0] * rate)]
    return theta, thetad
