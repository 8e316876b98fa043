"""The closed-loop scenes (scenes.four_bar, slider_crank, delta_robot) against
references written here from the physics, never from soadyn:

- four-bar and slider-crank: Lagrange's equations of the planar linkage in
  absolute link angles (kinetic and potential energy of uniform slender
  rods), closed by the in-plane loop equation and its Jacobian (for the
  four-bar, the form of Saha, Shah & Nandihal, "Evolution of the DeNOC-based
  dynamic modelling for multibody systems", Mechanical Sciences 4, 2013,
  Eq. 52b), solved as one dense KKT system for accelerations, the crank
  torque and the pin force;
- the Delta robot: Pinocchio's constraintDynamics on the same robot built
  from the documented dimensions (one CONTACT_3D constraint per ball joint);
- power balance along a driven revolution: crank torque times crank rate
  equals the rate of change of kinetic plus potential energy;
- the scenes' closed-form states close the loops in position and velocity;
- `soadyn demo --scene four-bar`: its driven revolutions, its free fall (the
  Simulator) against the reference's motion integrated here, its figure and
  its command line.
"""
from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import soadyn
from soadyn import scenes
from support.closed_loops import pinocchio_solution
from support.pinocchio_trees import BodySpec, Mapping, build_pinocchio

G = 9.81
RTOL = 1e-9
# Saha, Shah & Nandihal 2013, Sect. 5: crank, coupler, output link (rocker), ground (m); masses (kg).
CRANK, COUPLER, ROCKER, GROUND = 0.038, 0.1152, 0.1152, 0.0895
M_CRANK, M_COUPLER, M_ROCKER = 1.5, 5.0, 3.0
# The slider-crank of the scene (documented in scenes.hpp).
SC_CRANK, SC_ROD, SC_OFFSET, SC_M_CRANK, SC_M_ROD, SC_M_SLIDER = 0.05, 0.2, 0.02, 1.0, 1.5, 0.8

ANGLES = np.linspace(0.0, 2 * np.pi, 13)[:-1] + 0.05


def e(x):
    return np.array([np.cos(x), np.sin(x)])


def n(x):
    return np.array([-np.sin(x), np.cos(x)])


def cycloidal(t, T=1.0):
    """Saha, Shah & Nandihal 2013, Eq. 34, one revolution in T: angle, rate, acceleration."""
    w = 2 * np.pi / T
    return (2 * np.pi * (t / T - np.sin(w * t) / (2 * np.pi)), 2 * np.pi / T * (1 - np.cos(w * t)),
            2 * np.pi / T * w * np.sin(w * t))


# ---------------------------------------------------------------------------
# Planar linkages in absolute angles x = (crank, second link, third body)
# ---------------------------------------------------------------------------

class PlanarLinkage:
    """A crank (length a, mass m1) hinged at the origin, a uniform rod (length b, mass m2) hinged to its tip,
    and a third body (x3: the rocker's angle or the slider's position) whose point meets the rod's tip.
    Gravity -G along y. Lagrange: M(x) x'' + h(x, x') = Q + A' lam, A x'' = -(A' x') x' (the closure's
    second derivative without accelerations); lam is the force the third body applies on the rod's tip."""

    def __init__(self, a, m1, b, m2):
        self.a, self.m1, self.b, self.m2 = a, m1, b, m2

    def two_links(self, x, xd):
        """M (3x3), h (3): the crank and rod's part, with the rod's centre at a e(x0) + b/2 e(x1)."""
        a, b, m1, m2 = self.a, self.b, self.m1, self.m2
        c = m2 * a * b / 2
        M = np.zeros((3, 3))
        M[0, 0] = m1 * a * a / 3 + m2 * a * a
        M[0, 1] = M[1, 0] = c * np.cos(x[0] - x[1])
        M[1, 1] = m2 * b * b / 3
        h = np.array([c * np.sin(x[0] - x[1]) * xd[1] ** 2 + (m1 / 2 + m2) * G * a * np.cos(x[0]),
                      -c * np.sin(x[0] - x[1]) * xd[0] ** 2 + m2 * G * b / 2 * np.cos(x[1]), 0.0])
        return M, h

    def solve(self, x, xd, tau, crank_acceleration=None):
        """(x'', crank torque, lam): every joint free under the torques tau (absolute-angle generalized
        forces), or the crank prescribed at crank_acceleration and its torque unknown."""
        M, h = self.dynamics(x, xd)
        A, gamma = self.closure(x, xd)
        K = np.zeros((5, 5))
        K[:3, :3], K[:3, 3:], K[3:, :3] = M, -A.T, A
        rhs = np.r_[np.asarray(tau, float) - h, gamma]
        if crank_acceleration is not None:  # unknown crank torque in place of the crank's acceleration
            rhs -= K[:, 0] * crank_acceleration
            K[:, 0] = 0.0
            K[0, 0] = -1.0
        z = np.linalg.solve(K, rhs)
        if crank_acceleration is None:
            return z[:3], 0.0, z[3:]
        return np.r_[crank_acceleration, z[1:3]], z[0] + tau[0], z[3:]


class FourBar(PlanarLinkage):
    """x = (crank angle, coupler angle, rocker angle), all from the ground line; the rocker (length c,
    mass m3) is hinged at (g, 0). Closure f = a e(x0) + b e(x1) - c e(x2) - (g, 0) = 0."""

    def __init__(self):
        super().__init__(CRANK, M_CRANK, COUPLER, M_COUPLER)
        self.c, self.m3, self.g = ROCKER, M_ROCKER, GROUND

    def dynamics(self, x, xd):
        M, h = self.two_links(x, xd)
        M[2, 2] = self.m3 * self.c ** 2 / 3
        h[2] = self.m3 * G * self.c / 2 * np.cos(x[2])
        return M, h

    def closure(self, x, xd):
        A = np.column_stack([self.a * n(x[0]), self.b * n(x[1]), -self.c * n(x[2])])
        gamma = self.a * xd[0] ** 2 * e(x[0]) + self.b * xd[1] ** 2 * e(x[1]) - self.c * xd[2] ** 2 * e(x[2])
        return A, gamma

    def residual(self, x):
        return self.a * e(x[0]) + self.b * e(x[1]) - self.c * e(x[2]) - np.array([self.g, 0.0])


class SliderCrank(PlanarLinkage):
    """x = (crank angle, rod angle, slider position on the line y = offset)."""

    def __init__(self):
        super().__init__(SC_CRANK, SC_M_CRANK, SC_ROD, SC_M_ROD)

    def dynamics(self, x, xd):
        M, h = self.two_links(x, xd)
        M[2, 2] = SC_M_SLIDER
        return M, h

    def closure(self, x, xd):
        A = np.column_stack([self.a * n(x[0]), self.b * n(x[1]), [-1.0, 0.0]])
        return A, self.a * xd[0] ** 2 * e(x[0]) + self.b * xd[1] ** 2 * e(x[1])

    def residual(self, x):
        return self.a * e(x[0]) + self.b * e(x[1]) - np.array([x[2], SC_OFFSET])


# soadyn's coordinates are (crank, second link relative to the crank, third): x = T q.
TO_ABSOLUTE = np.array([[1.0, 0, 0], [1, 1, 0], [0, 0, 1]])


def compare_planar(reference, model, q, v, crank_acceleration, crank_torque):
    """soadyn's constrained_dynamics against the reference, the crank prescribed and free."""
    x, xd = TO_ABSOLUTE @ q, TO_ABSOLUTE @ v
    # The crank prescribed: the other joints' accelerations, the crank's torque, the pin force.
    model.set_prescribed(["crank"])
    qdd, tau, wrench = soadyn.constrained_dynamics(model, q, v, np.array([crank_acceleration, 0.0, 0.0]))
    xdd, torque, lam = reference.solve(x, xd, np.zeros(3), crank_acceleration)
    np.testing.assert_allclose(TO_ABSOLUTE @ qdd, xdd, rtol=RTOL, atol=RTOL * np.abs(xdd).max())
    assert abs(tau[0] - torque) <= RTOL * abs(torque)
    np.testing.assert_allclose(wrench[0, 3:5], lam, rtol=RTOL, atol=RTOL * np.abs(lam).max())
    assert np.abs(wrench[0, [0, 1, 2, 5]]).max() <= RTOL * np.abs(lam).max()
    # Every joint free, a torque on the crank (in absolute angles the crank's torque acts on x0 alone).
    model.set_prescribed(["crank"], False)
    qdd, tau, wrench = soadyn.constrained_dynamics(model, q, v, np.array([crank_torque, 0.0, 0.0]))
    xdd, _, lam = reference.solve(x, xd, np.array([crank_torque, 0.0, 0.0]))
    np.testing.assert_allclose(TO_ABSOLUTE @ qdd, xdd, rtol=RTOL, atol=RTOL * np.abs(xdd).max())
    np.testing.assert_allclose(wrench[0, 3:5], lam, rtol=RTOL, atol=RTOL * np.abs(lam).max())
    return qdd


# ---------------------------------------------------------------------------
# Four-bar
# ---------------------------------------------------------------------------

def test_four_bar_scene_structure():
    for closure, rows in (("revolute", 5), ("point", 3)):
        m = scenes.four_bar(closure)
        assert m.body_names == ["crank", "coupler", "rocker"] and m.dof_names == ["crank", "coupler", "rocker"]
        assert m.loop_names == ["coupler_rocker"] and m.nloop_equations == rows
        assert np.allclose(m.gravity, (0.0, -G, 0.0))
        assert m.masses == [M_CRANK, M_COUPLER, M_ROCKER]
        assert soadyn.loop_rank(m, scenes.four_bar_state(0.3)[0]) == 2
    with pytest.raises(ValueError, match="four_bar: closure must be 'revolute' or 'point', got 'weld'"):
        scenes.four_bar("weld")


@pytest.mark.parametrize("closure", ["revolute", "point"])
@pytest.mark.parametrize("phase", range(4))
def test_four_bar_matches_lagrange_along_a_cycloidal_revolution(closure, phase):
    """At 3 of 12 instants each (phase picks them) of a cycloidal revolution in 1 s."""
    m, ref = scenes.four_bar(closure), FourBar()
    for t in np.arange(12)[phase::4] / 12 + 0.01:
        angle, rate, acceleration = cycloidal(t)
        q, v = scenes.four_bar_state(angle, rate)
        assert np.abs(ref.residual(TO_ABSOLUTE @ q)).max() < 1e-15
        compare_planar(ref, m, q, v, acceleration, crank_torque=0.3 * np.cos(angle))


def test_four_bar_closure_jacobian_is_eq_52b():
    """soadyn's loop Jacobian is the closed-form one; the paper's Eq. 52b (the chain crank, coupler,
    rocker cut at the rocker's ground pivot, relative angles, a3 the rocker) annihilates the same rates."""
    m = scenes.four_bar("revolute")
    a1, a2, a3 = CRANK, COUPLER, ROCKER
    for angle in ANGLES:
        q, v = scenes.four_bar_state(angle, 1.0 + angle)
        C = soadyn.loop_jacobian(m, q)
        A, _ = FourBar().closure(TO_ABSOLUTE @ q, TO_ABSOLUTE @ v)
        np.testing.assert_allclose(C[:2], A @ TO_ABSOLUTE, rtol=0, atol=1e-15)
        assert np.abs(C[2:]).max() == 0.0  # no out-of-plane translation, no tilt of the pin's axis
        # Eq. 52b: rocker seen from the coupler's tip, theta3 = (rocker + pi) - (crank + coupler).
        t1, t12 = q[0], q[0] + q[1]
        t123 = q[2] + np.pi
        J = np.array([[-a1 * np.sin(t1) - a2 * np.sin(t12) - a3 * np.sin(t123), -a2 * np.sin(t12) - a3 * np.sin(t123),
                       -a3 * np.sin(t123)],
                      [a1 * np.cos(t1) + a2 * np.cos(t12) + a3 * np.cos(t123), a2 * np.cos(t12) + a3 * np.cos(t123),
                       a3 * np.cos(t123)]])
        rates = np.array([v[0], v[1], v[2] - v[0] - v[1]])
        assert np.abs(J @ rates).max() < 1e-14
        # and the chain closes at the rocker's ground pivot
        assert np.abs(a1 * e(t1) + a2 * e(t12) + a3 * e(t123) - [GROUND, 0.0]).max() < 1e-15


def test_four_bar_point_and_revolute_cuts_agree():
    rng = np.random.default_rng(7)
    revolute, point = scenes.four_bar("revolute"), scenes.four_bar("point")
    for angle in ANGLES:
        q, v = scenes.four_bar_state(angle, rng.normal())
        u = rng.normal(size=3)
        for prescribed in ([], ["crank"], ["rocker"]):
            revolute.set_prescribed(np.isin(revolute.dof_names, prescribed))
            point.set_prescribed(np.isin(point.dof_names, prescribed))
            a, b = soadyn.constrained_dynamics(revolute, q, v, u), soadyn.constrained_dynamics(point, q, v, u)
            for x, y in zip(a, b):
                np.testing.assert_allclose(x, y, rtol=1e-12, atol=1e-12 * np.abs(y).max())


def test_driven_four_bar_crank_power_is_the_rate_of_change_of_energy():
    """tau w = dE/dt along a cycloidal revolution in 1 s: E from the closed-form state (kinetic plus
    potential), its derivative by the 5-point central difference (error O(h^4))."""
    m = scenes.four_bar()
    m.set_prescribed(["crank"])

    def energy(t):
        q, v = scenes.four_bar_state(*cycloidal(t)[:2])
        return soadyn.kinetic_energy(m, q, v) + soadyn.potential_energy(m, q)

    h = 1e-4  # truncation ~1e-12 relative, round-off ~1e-13 here
    power, rate_of_energy = [], []
    for t in np.linspace(0.02, 0.98, 25):
        angle, rate, acceleration = cycloidal(t)
        q, v = scenes.four_bar_state(angle, rate)
        _, tau, _ = soadyn.constrained_dynamics(m, q, v, np.array([acceleration, 0.0, 0.0]))
        power.append(tau[0] * rate)
        rate_of_energy.append((energy(t - 2 * h) - 8 * energy(t - h) + 8 * energy(t + h) - energy(t + 2 * h))
                              / (12 * h))
    power, rate_of_energy = np.array(power), np.array(rate_of_energy)
    assert np.abs(power).max() > 1.0  # the crank does work, not only static holding
    assert np.abs(power - rate_of_energy).max() <= 1e-8 * np.abs(power).max()


# ---------------------------------------------------------------------------
# Slider-crank
# ---------------------------------------------------------------------------

def test_slider_crank_scene_structure():
    m = scenes.slider_crank()
    assert m.body_names == ["crank", "connecting_rod", "slider"] and m.joint_types == ["revolute", "revolute",
                                                                                     "prismatic"]
    assert m.loop_names == ["wrist_pin"] and m.nloop_equations == 5
    assert m.masses == [SC_M_CRANK, SC_M_ROD, SC_M_SLIDER]
    assert scenes.slider_crank("point").nloop_equations == 3


@pytest.mark.parametrize("closure", ["revolute", "point"])
def test_slider_crank_matches_lagrange(closure):
    m, ref = scenes.slider_crank(closure), SliderCrank()
    for angle in ANGLES:
        q, v = scenes.slider_crank_state(angle, 20.0 * np.sin(angle + 1))
        assert np.abs(ref.residual(TO_ABSOLUTE @ q)).max() < 1e-15
        assert soadyn.loop_rank(m, q) == 2
        compare_planar(ref, m, q, v, crank_acceleration=50.0 * np.cos(angle), crank_torque=-2.0)


# ---------------------------------------------------------------------------
# Delta robot against Pinocchio
# ---------------------------------------------------------------------------

# Documented in scenes.hpp: base radius, plate radius, arm, rod, rod spacing (m); masses (kg).
RB, RP, LA, LF, SPACING = 0.2, 0.05, 0.3, 0.7, 0.1
M_ARM, M_ROD, M_PLATE = 0.4, 0.1, 0.5


def _rod_inertia(mass, length):
    return dict(mass=mass, com=np.array([length / 2, 0.0, 0.0]),
                inertia=np.diag([0.0, mass * length ** 2 / 12, mass * length ** 2 / 12]))


def delta_specs():
    """The Delta robot as BodySpecs (support/pinocchio_trees.py), and its six ball joints (rod index, point on
    the plate)."""
    specs, balls = [], []
    none = np.zeros(3)
    for k in range(3):
        phi = 2 * np.pi * k / 3
        u, w = np.array([np.cos(phi), np.sin(phi), 0.0]), np.array([-np.sin(phi), np.cos(phi), 0.0])
        arm = len(specs)
        specs.append(BodySpec(f"arm_{k + 1}", -1, "revolute", np.array([0.0, 1.0, 0.0]), none, 0.0,
                              np.column_stack([u, w, [0.0, 0.0, 1.0]]), RB * u, **_rod_inertia(M_ARM, LA)))
        for side, offset in (("a", SPACING / 2), ("b", -SPACING / 2)):
            balls.append((len(specs), RP * u + offset * w))
            specs.append(BodySpec(f"rod_{k + 1}{side}", arm, "universal", np.array([0.0, 1.0, 0.0]),
                                  np.array([0.0, 0.0, 1.0]), 0.0, np.eye(3), np.array([LA, offset, 0.0]),
                                  **_rod_inertia(M_ROD, LF)))
    disc = M_PLATE * RP ** 2 / 4
    specs.append(BodySpec("plate", -1, "free", none, none, 0.0, np.eye(3), none, M_PLATE, none,
                          np.diag([disc, disc, 2 * disc])))
    return specs, balls


def delta_case():
    m = scenes.delta_robot()
    specs, balls = delta_specs()
    model = build_pinocchio(specs, m.gravity)
    mapping = Mapping(m, model, specs)
    plate = len(specs) - 1
    rod_end = pin.SE3(np.eye(3), np.array([LF, 0.0, 0.0]))
    constraints = [pin.RigidConstraintModel(pin.ContactType.CONTACT_3D, model, rod + 1, rod_end, plate + 1,
                                            pin.SE3(np.eye(3), ball), pin.ReferenceFrame.LOCAL)
                   for rod, ball in balls]
    return m, model, mapping, constraints


DELTA_STATES = [((0.0, 0.0, -0.6), (0.0, 0.0, 0.0)), ((0.1, -0.05, -0.55), (0.3, -0.2, 0.5)),
                ((-0.12, 0.08, -0.7), (-0.4, 0.6, -0.3)), ((0.05, 0.15, -0.5), (1.0, 0.2, 0.1))]


@pytest.mark.parametrize("position,velocity", DELTA_STATES)
def test_delta_state_closes_the_loops_in_pinocchio_too(position, velocity):
    m, model, mapping, _ = delta_case()
    q, v = scenes.delta_robot_state(position, velocity)
    psi, cv = soadyn.loop_residual(m, q, v)
    assert np.abs(psi).max() < 1e-12 and np.abs(cv).max() < 1e-12
    assert m.nloops == 6 and m.nloop_equations == 18 and soadyn.loop_rank(m, q) == 18
    # Independently: Pinocchio's placements of the rod ends and the plate's balls coincide.
    data = model.createData()
    pin.forwardKinematics(model, data, mapping.q(q), mapping.v(v))
    _, balls = delta_specs()
    plate = model.njoints - 1
    for rod, ball in balls:
        tip = data.oMi[rod + 1].act(np.array([LF, 0.0, 0.0]))
        assert np.abs(tip - data.oMi[plate].act(ball)).max() < 1e-12
    np.testing.assert_allclose(data.oMi[plate].translation, position, atol=1e-15)


@pytest.mark.parametrize("case", range(len(DELTA_STATES)))
def test_delta_matches_pinocchio_constraint_dynamics(case):
    m, model, mapping, constraints = delta_case()
    q, v = scenes.delta_robot_state(*DELTA_STATES[case])
    rng = np.random.default_rng(case)
    tau = np.zeros(m.nv)
    arms = [m.dof_index(f"arm_{k}") for k in (1, 2, 3)]
    tau[arms] = rng.normal(size=3)
    qdd_pin, lam_pin = pinocchio_solution(model, mapping, constraints, q, v, tau)
    qdd, _, wrenches = soadyn.constrained_dynamics(m, q, v, tau)
    scale = np.abs(qdd_pin).max()
    assert np.abs(qdd - qdd_pin).max() <= RTOL * scale
    # Pinocchio's CONTACT_3D multipliers are the force on the rod's end in the rod's frame.
    poses = soadyn.forward_kinematics(m, q)[0]
    expected = np.array([poses[c.joint1_id - 1][:3, :3] @ lam_pin[3 * k:3 * k + 3] for k, c in enumerate(constraints)])
    assert np.abs(wrenches[:, 3:] - expected).max() <= RTOL * np.abs(expected).max()
    assert np.abs(wrenches[:, :3]).max() == 0.0
    # The arms prescribed at Pinocchio's accelerations: soadyn returns the torques that caused them.
    m.set_prescribed(["arm_1", "arm_2", "arm_3"])
    u = tau.copy()
    u[arms] = qdd_pin[arms]
    qdd_p, tau_p, wrenches_p = soadyn.constrained_dynamics(m, q, v, u)
    assert np.abs(qdd_p - qdd_pin).max() <= RTOL * scale
    assert np.abs(tau_p[arms] - tau[arms]).max() <= RTOL * np.abs(tau[arms]).max()
    assert np.abs(wrenches_p[:, 3:] - expected).max() <= RTOL * np.abs(expected).max()


def test_delta_state_refuses_an_unreachable_plate():
    with pytest.raises(ValueError, match="out of reach of arm_1"):
        scenes.delta_robot_state((0.0, 0.0, -2.0))


# ---------------------------------------------------------------------------
# Scene states close the loops
# ---------------------------------------------------------------------------

@pytest.mark.parametrize("scene,state", [(scenes.four_bar, scenes.four_bar_state),
                                         (scenes.slider_crank, scenes.slider_crank_state)],
                         ids=["four-bar", "slider-crank"])
@pytest.mark.parametrize("closure", ["revolute", "point"])
def test_planar_scene_states_close_the_loop(scene, state, closure):
    m = scene(closure)
    for angle in np.linspace(-np.pi, 3 * np.pi, 29):
        q, v = state(angle, 7.0 * np.cos(angle))
        psi, cv = soadyn.loop_residual(m, q, v)
        assert np.abs(psi).max() < 1e-12 and np.abs(cv).max() < 1e-12


# ---------------------------------------------------------------------------
# soadyn demo --scene four-bar
# ---------------------------------------------------------------------------

def _demo(argv, capsys):
    from soadyn.cli import main

    assert main(["demo", "--scene", "four-bar", "--dt", "0.002", "--duration", "0.2", *argv]) == 0
    return capsys.readouterr().out


def test_four_bar_demo_writes_its_figure_headless(tmp_path, capsys):
    plot = tmp_path / "fb.png"
    out = _demo(["--revolution", "2", "--plot", str(plot)], capsys)
    assert "scene four-bar: 3 bodies" in out and "one crank revolution in 2 s" in out
    assert "constant rate 3.14 rad/s" in out and "cycloidal (Eq. 34)" in out
    assert "free fall (RK4, dt 0.002 s)" in out
    assert f"plot written to {plot}" in out
    assert plot.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and plot.stat().st_size > 20_000
    import matplotlib
    assert matplotlib.get_backend().lower() == "agg"


def test_four_bar_demo_bare_plot_writes_four_bar_png(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    out = _demo(["--plot"], capsys)
    assert "plot written to four_bar.png" in out and (tmp_path / "four_bar.png").stat().st_size > 20_000


def test_four_bar_demo_driven_revolutions():
    """Over one revolution the linkage returns to its start: the crank's work is zero; the torque holds
    the linkage against gravity and accelerates it (closed loop to round-off)."""
    from soadyn import four_bar_demo as demo

    for run in (demo.constant_rate(1.0, 1e-3), demo.cycloidal(1.0, 1e-3)):
        assert len(run.t) == 1001 and run.closure < 1e-15
        np.testing.assert_allclose(run.q[-1] - [2 * np.pi, 0.0, 0.0], run.q[0], atol=1e-12)
        assert abs(demo.crank_work(run)) < 1e-9 * np.abs(run.crank_torque * run.v[:, 0]).max()
        assert 1.5 < np.abs(run.crank_torque).max() < 4.0
    assert np.abs(run.v[[0, -1], 0]).max() < 1e-15  # the cycloidal law starts and ends at rest


def _reference_free_fall(q0, duration, h=1e-4):
    """The four-bar released from rest at q0: the reference's free motion (FourBar.solve, no torque)
    integrated by RK4 with step h (error ~1e-12 here); soadyn coordinates every 10 h."""
    ref, to_relative = FourBar(), np.linalg.inv(TO_ABSOLUTE)

    def rate(y):
        return np.r_[y[3:], ref.solve(y[:3], y[3:], np.zeros(3))[0]]

    y, out = np.r_[TO_ABSOLUTE @ q0, np.zeros(3)], []
    for k in range(int(round(duration / h)) + 1):
        if k % 10 == 0:
            out.append(np.r_[to_relative @ y[:3], to_relative @ y[3:]])
        k1 = rate(y)
        k2 = rate(y + h / 2 * k1)
        k3 = rate(y + h / 2 * k2)
        k4 = rate(y + h * k3)
        y = y + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
    return np.array(out)


def test_four_bar_demo_free_fall_follows_lagrange_and_keeps_the_loop_closed():
    """The demo's free fall (the Simulator, RK4 at 1 kHz, projection after each step) against the
    reference's motion integrated independently: its error is RK4's, falling 16-fold per halved step."""
    from soadyn import four_bar_demo as demo

    reference = _reference_free_fall(scenes.four_bar_state(0.0)[0], 0.5)
    model, errors = scenes.four_bar(), []
    for dt in (1e-3, 5e-4):
        run = demo.free_fall(0.5, dt)
        every = int(round(1e-3 / dt))
        assert run.closure < 1e-9
        angle = np.angle(np.exp(1j * (run.q[::every] - reference[:, :3])))
        errors.append(np.abs(angle).max())
        assert np.abs(run.v[::every] - reference[:, 3:]).max() < 1e-4 * np.abs(reference[:, 3:]).max()
        kinetic = max(soadyn.kinetic_energy(model, q, v) for q, v in zip(run.q, run.v))
        assert np.ptp(run.energy) < 1e-6 * kinetic  # 1.2e-7 at 1 kHz, 7e-9 at 2 kHz
    assert np.abs(reference[:, 3:]).max() > 20.0  # the linkage swings fast: a demanding run
    assert errors[0] < 1e-6 and 10 < errors[0] / errors[1] < 25


@pytest.mark.parametrize("argv, line", [
    (["--revolution", "0"], "argument --revolution: must be a finite number > 0, got 0.0"),
    (["--revolution", "nan"], "argument --revolution: must be a finite number > 0, got nan"),
    (["--scene", "delta"], "argument --scene: invalid choice: 'delta'"),
])
def test_four_bar_demo_refuses_bad_arguments(argv, line, capsys):
    from soadyn.cli import main

    with pytest.raises(SystemExit) as exit_info:
        main(["demo", "--scene", "four-bar", *argv])
    assert exit_info.value.code == 2
    err = capsys.readouterr().err
    assert "Traceback" not in err and line in err.strip().splitlines()[-1]


def test_four_bar_demo_console_script():
    import shutil
    import subprocess

    exe = shutil.which("soadyn")
    assert exe, "the soadyn console script is not on PATH"
    result = subprocess.run([exe, "demo", "--scene", "four-bar", "--dt", "0.01", "--duration", "0.1"],
                            capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    assert "cycloidal (Eq. 34)" in result.stdout and "crank torque (N m)" in result.stdout


@pytest.mark.parametrize("call, error, message", [
    (lambda: scenes.four_bar_state(np.nan), ValueError, "four_bar_state: arguments must be finite"),
    (lambda: scenes.slider_crank_state(0.0, np.inf), ValueError, "slider_crank_state: arguments must be finite"),
    (lambda: scenes.four_bar_state("up"), TypeError, "four_bar_state: crank_angle and crank_rate must be real"),
    (lambda: scenes.delta_robot_state((0.0, np.nan, -0.6)), ValueError, "delta_robot_state: arguments must be finite"),
    (lambda: scenes.delta_robot_state((0.0, -0.6)), ValueError, "position and velocity need 3 components"),
    (lambda: scenes.slider_crank("prismatic"), ValueError, "slider_crank: closure must be 'revolute' or 'point'"),
])
def test_scene_helpers_refuse_bad_arguments_by_name(call, error, message):
    with pytest.raises(error, match=message):
        call()
