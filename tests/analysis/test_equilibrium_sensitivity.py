"""Design sensitivities of a static equilibrium (soadyn.static_equilibrium(..., sensitivities=...),
soadyn.objective_gradient) against an independent closed-form reference: a planar four-bar in a
vertical plane (gravity in the plane) with a torsion spring on the crank (5 N m/rad, rest angle 0),
whose potential is written in support/equilibria.py from the loop's geometry (circle intersection)
without soadyn, its equilibrium found by scipy's brentq and its sensitivities by the implicit function
theorem on that potential. Also trees (a pendulum with a torsion spring: k theta = m g l sin theta) and the adjoint
gradient against the direct method.
"""
from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import brentq

import soadyn
from support.equilibria import A, B, C, D, G, K, MASSES, pin, reference_equilibrium, reference_sensitivities


def rod(length, mass):
    inertia = np.diag([1e-4, mass * length ** 2 / 12, mass * length ** 2 / 12])
    return dict(mass=mass, com=[length / 2, 0, 0], inertia=inertia)


def four_bar_with_spring(closure="point"):
    m = soadyn.Model()
    m.gravity = np.array([0.0, -G, 0.0])
    z = soadyn.Joint.revolute([0, 0, 1])
    m.add_body("crank", "world", z, **rod(A, MASSES["crank"]))
    m.add_body("coupler", "crank", z, placement=(np.eye(3), [A, 0, 0]), **rod(B, MASSES["coupler"]))
    m.add_body("rocker", "world", z, placement=(np.eye(3), [D, 0, 0]), **rod(C, MASSES["rocker"]))
    m.add_loop("pin", "coupler", "rocker", closure, placement_a=(np.eye(3), [B, 0, 0]),
               placement_b=(np.eye(3), [C, 0, 0]))
    m.add_joint_spring("crank_spring", "crank", K, rest=0.0)
    return m


def assembled(m, theta):
    q = np.zeros(m.nq)
    P, Q = pin(theta)
    q[m.coordinate_names.index("crank")] = theta
    coupler_angle = np.arctan2(Q[1] - P[1], Q[0] - P[0])
    q[m.coordinate_names.index("coupler")] = coupler_angle - theta
    q[m.coordinate_names.index("rocker")] = np.arctan2(Q[1], Q[0] - D)
    return q


@pytest.mark.parametrize("closure", ["point", "revolute"])
def test_four_bar_equilibrium_and_sensitivities_against_the_closed_form(closure):
    m = four_bar_with_spring(closure)
    theta_ref = reference_equilibrium()
    params = ["crank_spring.stiffness", "crank.mass", "coupler.mass", "rocker.mass"]
    eq = soadyn.static_equilibrium(m, assembled(m, theta_ref + 0.2), sensitivities=params)
    crank = m.dof_index("crank") if hasattr(m, "dof_index") else m.dof_names.index("crank")
    assert eq.q[m.coordinate_names.index("crank")] == pytest.approx(theta_ref, abs=1e-9)
    assert eq.stable
    reference = reference_sensitivities(theta_ref)
    for name in params:
        assert eq.sensitivities[name]["q"][crank] == pytest.approx(reference[name], rel=1e-6), name
    # Re-solving the reference with a changed stiffness agrees with the sensitivity (second check).
    step = 1e-3
    moved = (reference_equilibrium(k=K + step) - reference_equilibrium(k=K - step)) / (2 * step)
    assert eq.sensitivities["crank_spring.stiffness"]["q"][crank] == pytest.approx(moved, rel=1e-5)


def test_adjoint_gradient_equals_the_direct_method():
    m = four_bar_with_spring("point")
    params = ["crank_spring.stiffness", "coupler.mass", "rocker.com", "gravity"]
    eq = soadyn.static_equilibrium(m, assembled(m, -1.0), sensitivities=params)
    rng = np.random.default_rng(4)
    dphi_dq, dphi_dnu = rng.normal(size=m.nv), rng.normal(size=m.nloop_equations)
    gradient = soadyn.objective_gradient(m, eq, params, dphi_dq, dphi_dnu)
    for name in params:
        s = eq.sensitivities[name]
        direct = np.tensordot(dphi_dq, s["q"], axes=1) + np.tensordot(dphi_dnu, s["multipliers"], axes=1)
        np.testing.assert_allclose(gradient[name], direct, rtol=1e-9, atol=1e-12)


def test_pendulum_with_torsion_spring_tree():
    """k theta = m g l sin(theta) for a pendulum standing up against a torsion spring; dtheta/dk
    = -theta / (k - m g l cos theta) (implicit function theorem on the closed form)."""
    m_, l_, k_ = 1.3, 0.6, 5.0
    m = soadyn.Model()
    m.gravity = np.array([0.0, -G, 0.0])
    m.add_body("pole", "world", soadyn.Joint.revolute([0, 0, 1]), mass=m_, com=[0, l_, 0], inertia=np.zeros((3, 3)))
    m.add_joint_spring("spring", "pole", k_)
    theta = brentq(lambda t: k_ * t - m_ * G * l_ * np.sin(t), 0.1, 3.0, xtol=1e-15)
    eq = soadyn.static_equilibrium(m, np.array([1.2]), sensitivities=["spring.stiffness", "pole.mass"])
    assert eq.q[0] == pytest.approx(theta, abs=1e-12)
    second = k_ - m_ * G * l_ * np.cos(theta)
    assert eq.sensitivities["spring.stiffness"]["q"][0] == pytest.approx(-theta / second, rel=1e-10)
    assert eq.sensitivities["pole.mass"]["q"][0] == pytest.approx(G * l_ * np.sin(theta) / second, rel=1e-10)
    assert eq.stiffness_eigenvalues[0] == pytest.approx(second, rel=1e-10)


def test_placements_of_loop_models_are_refused():
    m = four_bar_with_spring()
    eq = soadyn.static_equilibrium(m, assembled(m, -1.0))
    with pytest.raises(ValueError, match="coupler.placement"):
        soadyn.objective_gradient(m, eq, ["coupler.placement"], np.zeros(m.nv))


def test_hostile_inputs_are_named():
    m = four_bar_with_spring()
    eq = soadyn.static_equilibrium(m, assembled(m, -1.0))
    with pytest.raises(ValueError, match="no_such.mass"):
        soadyn.objective_gradient(m, eq, ["no_such.mass"], np.zeros(m.nv))
    with pytest.raises(ValueError, match="no_such.mass"):
        soadyn.static_equilibrium(m, assembled(m, -1.0), sensitivities=["no_such.mass"])
    with pytest.raises(ValueError, match="dphi_dq"):
        soadyn.objective_gradient(m, eq, ["coupler.mass"], np.zeros(m.nv + 2))
    with pytest.raises(ValueError, match="dphi_nu|dphi_dnu"):
        soadyn.objective_gradient(m, eq, ["coupler.mass"], np.zeros(m.nv), np.full(m.nloop_equations, np.nan))
