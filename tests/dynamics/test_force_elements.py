"""Force elements (joint springs, point springs with force-law tables, dampers) against oracles nobody here
wrote: MuJoCo's passive forces (hinge/slide joints with stiffness, damping and springref; spatial tendons
between two sites with stiffness, damping and springlength) and its RK4 trajectories; closed-form physics
(mass-spring frequency, damped oscillator, static deflection of an inverted pendulum held by a torsion spring
solved by scipy); scipy's PchipInterpolator for the force-law table; energy conservation without damping and
an energy decay equal to the integrated damping power."""
from __future__ import annotations

import textwrap
import warnings

import mujoco
import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.interpolate import PchipInterpolator
from scipy.optimize import brentq

import soadyn
from soadyn import Joint, Model, Simulator

# The MuJoCo chain: (body, parent, joint type, axis, position in parent, mass, com, principal inertia,
# stiffness, damping, springref) and the sites (name, body, position).
CHAIN = [
    ("b1", None, "hinge", (0, 1, 0), (0, 0, 0), 1.2, (0.1, 0, -0.2), (0.02, 0.03, 0.015), 3.0, 0.4, 0.2),
    ("b2", "b1", "hinge", (1, 0, 0), (0, 0, -0.4), 0.8, (0, 0.05, -0.15), (0.01, 0.012, 0.008), 5.0, 0.2, -0.3),
    ("b3", "b2", "slide", (0, 0, 1), (0.1, 0, -0.3), 0.5, (0.02, 0, -0.05), (0.004, 0.005, 0.006), 40.0, 1.0, 0.05),
    ("b4", "b3", "hinge", (0.6, 0, 0.8), (0, 0.1, -0.1), 0.3, (0, 0, -0.1), (0.003, 0.002, 0.004), 0.0, 0.5, 0.0),
]
SITES = [("anchor", None, (0.3, 0.2, 0.5)), ("s1", "b1", (0.05, 0.1, -0.3)), ("s2", "b2", (0.0, -0.1, -0.2)),
         ("s3", "b3", (0.02, 0.03, -0.1)), ("s4", "b4", (0.05, 0.0, -0.2))]
# Spatial tendons: (name, site a, site b, stiffness, damping, spring length).
TENDONS = [("t1", "anchor", "s3", 20.0, 0.7, 0.4), ("t2", "s1", "s2", 15.0, 0.3, 0.25),
           ("t3", "s2", "s4", 8.0, 0.0, 0.1)]


def _v(x):
    return " ".join(repr(float(c)) for c in x)


def mujoco_chain(springs: bool = True) -> mujoco.MjModel:
    def body_xml(name):
        spec = next(c for c in CHAIN if c[0] == name)
        _, _, kind, axis, pos, mass, com, inertia, k, c, ref = spec
        passive = f'stiffness="{k}" damping="{c}" springref="{ref}"' if springs else ""
        sites = "".join(f'<site name="{s}" pos="{_v(p)}"/>' for s, b, p in SITES if b == name)
        children = "".join(body_xml(ch[0]) for ch in CHAIN if ch[1] == name)
        return (f'<body name="{name}" pos="{_v(pos)}"><joint name="j_{name}" type="{kind}" axis="{_v(axis)}" '
                f'{passive}/><inertial pos="{_v(com)}" mass="{mass}" diaginertia="{_v(inertia)}"/>'
                f'{sites}{children}</body>')
    world_sites = "".join(f'<site name="{s}" pos="{_v(p)}"/>' for s, b, p in SITES if b is None)
    tendons = "".join(f'<spatial name="{n}" stiffness="{k}" damping="{c}" springlength="{L0}">'
                      f'<site site="{a}"/><site site="{b}"/></spatial>' for n, a, b, k, c, L0 in TENDONS)
    xml = (f'<mujoco><compiler angle="radian"/><option gravity="0 0 -9.81" integrator="RK4"/><worldbody>{world_sites}{body_xml("b1")}'
           f'</worldbody>{"<tendon>" + tendons + "</tendon>" if springs else ""}</mujoco>')
    return mujoco.MjModel.from_xml_string(xml)


def soadyn_chain(springs: bool = True) -> Model:
    m = Model()
    for name, parent, kind, axis, pos, mass, com, inertia, k, c, ref in CHAIN:
        joint = Joint.revolute(np.array(axis, float)) if kind == "hinge" else Joint.prismatic(np.array(axis, float))
        m.add_body(name, parent, joint, placement=np.array(pos, float), mass=mass, com=com, inertia=inertia)
        if springs:
            m.add_joint_spring(f"spring_{name}", name, k, damping=c, rest=ref)
    if springs:
        where = {s: (b or "world", np.array(p, float)) for s, b, p in SITES}
        for n, a, b, k, c, L0 in TENDONS:
            m.add_point_spring(n, where[a][0], where[b][0], k, damping=c, rest_length=L0,
                               placement_a=where[a][1], placement_b=where[b][1])
    return m


def random_states(n, seed):
    rng = np.random.default_rng(seed)
    for _ in range(n):
        yield rng.uniform(-1.0, 1.0, 4) * np.array([1.5, 1.5, 0.2, 2.0]), rng.normal(size=4)


@pytest.mark.parametrize("seed", [1, 2])
def test_passive_forces_and_accelerations_equal_mujoco(seed):
    mj, mj_rigid = mujoco_chain(), mujoco_chain(springs=False)
    data, data_rigid = mujoco.MjData(mj), mujoco.MjData(mj_rigid)
    m, rigid = soadyn_chain(), soadyn_chain(springs=False)
    for q, v in random_states(20, seed):
        data.qpos[:], data.qvel[:] = q, v
        mujoco.mj_forward(mj, data)
        data_rigid.qpos[:], data_rigid.qvel[:] = q, v
        mujoco.mj_forward(mj_rigid, data_rigid)
        assert np.abs(data.qfrc_passive).max() > 1.0  # the springs do act
        # bias_forces is h minus the force elements' generalized force
        passive = soadyn.bias_forces(rigid, q, v) - soadyn.bias_forces(m, q, v)
        np.testing.assert_allclose(passive, data.qfrc_passive, rtol=0, atol=1e-10)
        np.testing.assert_allclose(soadyn.bias_forces(rigid, q, v), data_rigid.qfrc_bias, rtol=0, atol=1e-10)
        tau = np.random.default_rng(seed).normal(size=4)
        data.qfrc_applied[:] = tau
        mujoco.mj_forward(mj, data)
        np.testing.assert_allclose(soadyn.forward_dynamics(m, q, v, tau), data.qacc, rtol=0, atol=1e-9)
        data.qfrc_applied[:] = 0
        # inverse dynamics returns the actuators' share: M qdd + h - Q
        qdd = np.random.default_rng(seed + 7).normal(size=4)
        tau_id = soadyn.inverse_dynamics(m, q, v, qdd)
        np.testing.assert_allclose(soadyn.forward_dynamics(m, q, v, tau_id), qdd, rtol=0, atol=1e-9)


def test_tendon_length_and_potential_equal_mujoco():
    mj = mujoco_chain()
    data = mujoco.MjData(mj)
    m = soadyn_chain()
    for q, v in random_states(10, 3):
        data.qpos[:], data.qvel[:] = q, v
        mujoco.mj_forward(mj, data)
        mujoco.mj_energyPos(mj, data)  # needs mjENBL_ENERGY; compute the springs' potential by hand instead
        expected = sum(0.5 * k * (L - L0) ** 2 for (n, a, b, k, c, L0), L in zip(TENDONS, data.ten_length))
        expected += sum(0.5 * spec[8] * (qi - spec[10]) ** 2 for spec, qi in zip(CHAIN, q))
        assert soadyn.force_element_potential(m, q) == pytest.approx(expected, rel=1e-12, abs=1e-12)
        power = sum(c * Ld ** 2 for (n, a, b, k, c, L0), Ld in zip(TENDONS, data.ten_velocity))
        power += sum(spec[9] * vi ** 2 for spec, vi in zip(CHAIN, v))
        assert soadyn.dissipated_power(m, q, v) == pytest.approx(power, rel=1e-12)


def test_trajectory_equals_mujoco_rk4():
    dt, steps = 1e-3, 1500
    mj = mujoco_chain()
    mj.opt.timestep = dt
    data = mujoco.MjData(mj)
    q0, v0 = np.array([0.5, -0.4, 0.1, 1.0]), np.array([0.3, -1.0, 0.2, 0.5])
    data.qpos[:], data.qvel[:] = q0, v0
    for _ in range(steps):
        mujoco.mj_step(mj, data)
    sim = Simulator(soadyn_chain(), dt, "rk4")
    sim.set_state(q0, v0)
    tr = sim.run(steps * dt)
    assert np.abs(tr.q[-1] - q0).max() > 0.1  # it moved
    np.testing.assert_allclose(tr.q[-1], data.qpos, rtol=0, atol=1e-9)
    np.testing.assert_allclose(tr.v[-1], data.qvel, rtol=0, atol=1e-8)


def test_hybrid_and_joint_wrenches_include_the_springs():
    """Prescribed DOFs report the actuators' share; joint wrenches balance the springs' forces too."""
    m = soadyn_chain()
    q, v = np.array([0.3, -0.2, 0.05, 0.7]), np.array([0.4, 0.1, -0.3, 0.2])
    qdd = np.array([0.5, -1.0, 2.0, 0.3])
    tau = soadyn.inverse_dynamics(m, q, v, qdd)
    m.set_prescribed(["b2", "b4"])
    u = np.where([False, True, False, True], qdd, tau)
    qdd_h, tau_h = soadyn.hybrid_dynamics(m, q, v, u)
    np.testing.assert_allclose(qdd_h, qdd, rtol=0, atol=1e-10)
    np.testing.assert_allclose(tau_h, tau, rtol=0, atol=1e-10)
    assert tau_h[0] == u[0] and tau_h[2] == u[2]  # given torques copied through exactly
    m.set_prescribed(["b1", "b2", "b3", "b4"])
    qdd_p, tau_p = soadyn.hybrid_dynamics(m, q, v, qdd)
    np.testing.assert_allclose(tau_p, tau, rtol=0, atol=1e-10)


def test_static_deflection_of_an_inverted_pendulum_with_a_torsion_spring():
    """Rod up, torsion spring k < m g l: equilibrium k theta = m g l sin(theta) (scipy's root), reached by a
    damped simulation, with zero generalized force there."""
    mass, length, k, c = 2.0, 0.5, 6.0, 3.0
    m = Model()
    m.add_body("rod", None, Joint.revolute(np.array([1.0, 0, 0])), mass=mass, com=(0, 0, length),
               inertia=(1e-3, 1e-3, 1e-3))
    m.add_joint_spring("torsion", "rod", k, damping=c)
    theta = brentq(lambda t: k * t - mass * 9.81 * length * np.sin(t), 0.1, np.pi - 1e-6, xtol=1e-15)
    # q = -theta leans the rod towards +y; by symmetry both signs are equilibria
    assert abs(soadyn.bias_forces(m, np.array([theta]), np.zeros(1))[0]) < 1e-12
    sim = Simulator(m, 2e-3, "rk4")
    sim.set_state(np.array([0.2]), np.zeros(1))
    tr = sim.run(30.0)
    assert tr.q[-1, 0] == pytest.approx(theta, abs=1e-9)


def test_mass_spring_frequency_and_damped_decay():
    """A mass on a slide between a joint spring and a point spring to a wall: x'' = -(k1 + k2)/m x - c/m x',
    its closed form at every recorded time."""
    mass, k1, k2, c = 1.5, 30.0, 24.0, 0.9
    m = Model()
    m.gravity = np.zeros(3)
    m.add_body("cart", None, Joint.prismatic(np.array([1.0, 0, 0])), mass=mass, inertia=(0.1, 0.1, 0.1))
    m.add_joint_spring("coil", "cart", k1, damping=c)
    m.add_point_spring("cable", "world", "cart", k2, placement_a=np.array([-2.0, 0, 0]))  # rest: 2 m
    omega0 = np.sqrt((k1 + k2) / mass)
    zeta = c / (2 * np.sqrt((k1 + k2) * mass))
    wd = omega0 * np.sqrt(1 - zeta**2)
    x0 = 0.3
    sim = Simulator(m, 1e-3, "rk4")
    sim.set_state(np.array([x0]), np.zeros(1))
    tr = sim.run(5.0)
    t = tr.t
    x = np.exp(-zeta * omega0 * t) * x0 * (np.cos(wd * t) + zeta * omega0 / wd * np.sin(wd * t))
    np.testing.assert_allclose(tr.q[:, 0], x, rtol=0, atol=1e-9)


def test_force_law_is_scipy_pchip_with_linear_extrapolation():
    """A jounce stop: the slide's generalized force is -F(L), F scipy's PchipInterpolator of the table
    continued linearly with the end slopes; the potential is the integral of F from the first length."""
    lengths = np.array([0.2, 0.5, 0.8, 0.9, 1.0, 1.3])
    forces = np.array([-50.0, -5.0, 0.0, 0.0, 30.0, 400.0])
    m = Model()
    m.add_body("cart", None, Joint.prismatic(np.array([1.0, 0, 0])), mass=1.0, inertia=(0.1, 0.1, 0.1))
    m.add_point_spring("stop", "world", "cart", 0.0, force_law=(lengths, forces),
                       placement_a=np.array([-1.0, 0, 0]))
    rigid = Model()
    rigid.add_body("cart", None, Joint.prismatic(np.array([1.0, 0, 0])), mass=1.0, inertia=(0.1, 0.1, 0.1))
    pchip = PchipInterpolator(lengths, forces)
    d_lo, d_hi = pchip.derivative()(lengths[[0, -1]])

    def reference(L):
        if L < lengths[0]:
            return forces[0] + d_lo * (L - lengths[0]), forces[0] * (L - lengths[0]) + d_lo * (L - lengths[0])**2 / 2
        if L > lengths[-1]:
            x = L - lengths[-1]
            return forces[-1] + d_hi * x, pchip.integrate(lengths[0], lengths[-1]) + forces[-1] * x + d_hi * x**2 / 2
        return pchip(L), pchip.integrate(lengths[0], L)

    for L in np.concatenate([np.linspace(0.05, 1.6, 157), lengths]):
        q = np.array([L - 1.0])
        F, V = reference(L)
        Q = soadyn.bias_forces(rigid, q, np.zeros(1))[0] - soadyn.bias_forces(m, q, np.zeros(1))[0]
        assert Q == pytest.approx(-F, rel=1e-12, abs=1e-11)
        assert soadyn.force_element_potential(m, q) == pytest.approx(V, rel=1e-12, abs=1e-12)


def energy(m, q, v):
    return soadyn.kinetic_energy(m, q, v) + soadyn.potential_energy(m, q)


def test_energy_is_conserved_without_damping_and_falls_by_the_dissipated_work():
    m = soadyn_chain()
    lengths, forces = np.array([0.3, 0.45, 0.6]), np.array([0.0, 2.0, 40.0])
    m.add_point_spring("bumper", "world", "b4", 0.0, force_law=(lengths, forces),
                       placement_a=np.array([0.0, 0.0, -0.6]))
    undamped = Model()
    undamped._copy_from(m)
    q0, v0 = np.array([0.4, -0.3, 0.1, 0.8]), np.array([0.5, 0.2, -0.4, 1.0])
    # the same model without damping: rebuild with every damping at zero
    plain = Model()
    for name, parent, kind, axis, pos, mass, com, inertia, k, c, ref in CHAIN:
        joint = Joint.revolute(np.array(axis, float)) if kind == "hinge" else Joint.prismatic(np.array(axis, float))
        plain.add_body(name, parent, joint, placement=np.array(pos, float), mass=mass, com=com, inertia=inertia)
        plain.add_joint_spring(f"spring_{name}", name, k, rest=ref)
    where = {s: (b or "world", np.array(p, float)) for s, b, p in SITES}
    for n, a, b, k, c, L0 in TENDONS:
        plain.add_point_spring(n, where[a][0], where[b][0], k, rest_length=L0, placement_a=where[a][1],
                               placement_b=where[b][1])
    plain.add_point_spring("bumper", "world", "b4", 0.0, force_law=(lengths, forces),
                           placement_a=np.array([0.0, 0.0, -0.6]))
    sim = Simulator(plain, 5e-4, "rk4")
    sim.set_state(q0, v0)
    tr = sim.run(2.0)
    e = [energy(plain, q, v) for q, v in zip(tr.q, tr.v)]
    assert max(e) - min(e) < 1e-8 * abs(e[0]) + 1e-9
    assert soadyn.dissipated_power(plain, q0, v0) == 0.0
    # with damping: E(T) - E(0) = -int P dt (Simpson's rule on the recorded states)
    sim = Simulator(m, 5e-4, "rk4")
    sim.set_state(q0, v0)
    tr = sim.run(2.0)
    power = np.array([soadyn.dissipated_power(m, q, v) for q, v in zip(tr.q, tr.v)])
    h = tr.t[1] - tr.t[0]
    n = len(power) - 1
    assert n % 2 == 0
    work = h / 3 * (power[0] + power[-1] + 4 * power[1:-1:2].sum() + 2 * power[2:-1:2].sum())
    drop = energy(m, tr.q[0], tr.v[0]) - energy(m, tr.q[-1], tr.v[-1])
    assert drop > 1.0
    assert drop == pytest.approx(work, rel=1e-7)


def test_springs_on_a_closed_loop_conserve_energy():
    """The four-bar with a crank spring and a point spring across the linkage, no damping: constrained
    dynamics in the Simulator (projection onto the closure) keeps kinetic + potential energy."""
    m = soadyn.scenes.four_bar()
    m.add_joint_spring("crank_spring", m.dof_names[0], 5.0)
    m.add_point_spring("diagonal", "world", m.body_names[-1], 40.0, placement_b=np.array([0.1, 0.0, 0.0]))
    q0, v0 = soadyn.scenes.four_bar_state(0.7, 2.0)
    sim = Simulator(m, 2e-4, "rk4")
    sim.set_state(q0, v0)
    tr = sim.run(1.0)
    e = np.array([energy(m, q, v) for q, v in zip(tr.q, tr.v)])
    ke = np.array([soadyn.kinetic_energy(m, q, v) for q, v in zip(tr.q, tr.v)])
    assert ke.max() - ke.min() > 0.1 * ke.max()  # energy moves between forms
    assert np.abs(e - e[0]).max() < 1e-6 * max(1.0, abs(e[0]))


def test_gravity_forces_stay_gravity_only():
    m, rigid = soadyn_chain(), soadyn_chain(springs=False)
    q = np.array([0.3, -0.2, 0.05, 0.7])
    np.testing.assert_allclose(soadyn.gravity_forces(m, q), soadyn.gravity_forces(rigid, q), rtol=0, atol=0)


def test_force_elements_listed():
    m = soadyn_chain()
    elements = soadyn.force_elements(m)
    assert [e["name"] for e in elements] == [f"spring_{c[0]}" for c in CHAIN] + [t[0] for t in TENDONS]
    assert elements[4]["body_a"] == "world" and elements[4]["body_b"] == "b3"
    assert elements[0]["stiffness"] == 3.0 and elements[0]["rest"] == 0.2


def test_rest_length_defaults_to_the_neutral_length():
    m = soadyn_chain(springs=False)
    m.add_point_spring("p", "b1", "b4", 10.0, placement_a=np.array([0.05, 0.1, -0.3]))
    q0 = soadyn.neutral_configuration(m)
    assert soadyn.force_element_potential(m, q0) == 0.0
    assert soadyn.force_elements(m)[0]["rest_length"] > 0.5


# Hostile inputs: every refusal names the element.

@pytest.mark.parametrize("kwargs, message", [
    (dict(stiffness=-1.0), "stiffness"),
    (dict(stiffness=float("nan")), "stiffness"),
    (dict(stiffness=1.0, damping=-0.1), "damping"),
    (dict(stiffness=1.0, damping=float("inf")), "damping"),
    (dict(stiffness=1.0, rest=float("nan")), "rest"),
])
def test_bad_joint_spring_constants_are_refused(kwargs, message):
    m = soadyn_chain(springs=False)
    with pytest.raises(ValueError, match=f"'bad'.*{message}"):
        m.add_joint_spring("bad", "b1", **kwargs)
    assert soadyn.force_elements(m) == []


def test_bad_joint_spring_dofs_are_refused():
    m = soadyn_chain(springs=False)
    m.add_body("ball", "b4", Joint.spherical(), mass=1.0, inertia=(0.1, 0.1, 0.1))
    m.add_body("puck", "ball", Joint.planar(), mass=1.0, inertia=(0.1, 0.1, 0.1))
    with pytest.raises(ValueError, match="'s'.*no scalar coordinate"):
        m.add_joint_spring("s", m.dof_names[4], 1.0)
    with pytest.raises(ValueError, match="'s'.*no scalar coordinate"):
        m.add_joint_spring("s", m.dof_names[-1], 1.0)
    with pytest.raises(ValueError, match="'s'.*unknown DOF"):
        m.add_joint_spring("s", "nope", 1.0)
    with pytest.raises(ValueError, match="'s'.*out of range"):
        m.add_joint_spring("s", 99, 1.0)
    with pytest.raises(ValueError, match="'s'.*selects 3 DOFs"):
        m.add_joint_spring("s", "ball", 1.0)
    m.add_joint_spring("s", "b1", 1.0)
    with pytest.raises(ValueError, match="'s'.*already used"):
        m.add_joint_spring("s", "b2", 1.0)
    with pytest.raises(ValueError, match="'s'.*already used"):
        m.add_point_spring("s", "b1", "b2", 1.0)


def test_modal_dofs_are_refused():
    m = soadyn.scenes.cantilever_beam(1.0, 10.0, 1.0, 2)
    modal = [n for n, is_modal in zip(m.dof_names, m.modal) if is_modal]
    with pytest.raises(ValueError, match="'s'.*modal"):
        m.add_joint_spring("s", modal[0], 1.0)


@pytest.mark.parametrize("law, message", [
    (([0.1], [1.0]), "at least 2 points"),
    (([0.1, 0.1, 0.3], [0.0, 1.0, 2.0]), "strictly increasing"),
    (([0.3, 0.2], [0.0, 1.0]), "strictly increasing"),
    (([0.1, 0.2], [0.0, float("nan")]), "not finite"),
    (([0.1, float("inf")], [0.0, 1.0]), "not finite"),
    (([0.1, 0.2, 0.3], [0.0, 1.0]), "differ in size"),
    ("table", "pair"),
])
def test_bad_force_laws_are_refused(law, message):
    m = soadyn_chain(springs=False)
    with pytest.raises(ValueError, match=f"'law'.*{message}"):
        m.add_point_spring("law", "b1", "b2", 0.0, force_law=law)


def test_bad_point_springs_are_refused():
    m = soadyn_chain(springs=False)
    with pytest.raises(ValueError, match="'p'.*'nope' is neither a body nor a frame"):
        m.add_point_spring("p", "b1", "nope", 1.0)
    with pytest.raises(ValueError, match="'p'.*same body"):
        m.add_point_spring("p", "b1", "b1", 1.0, placement_b=np.array([0.1, 0, 0]))
    with pytest.raises(ValueError, match="'p'.*rest_length"):
        m.add_point_spring("p", "b1", "b2", 1.0, rest_length=-1.0)
    with pytest.raises(ValueError, match="'p'.*not finite"):
        m.add_point_spring("p", "b1", "b2", 1.0, placement_a=np.array([np.nan, 0, 0]))
    with pytest.raises(ValueError, match="'p'.*damping"):
        m.add_point_spring("p", "b1", "b2", 1.0, damping=-2.0)
    beam = soadyn.scenes.cantilever_beam(1.0, 10.0, 1.0, 2)
    with pytest.raises(ValueError, match="'p'.*flexible"):
        beam.add_point_spring("p", None, beam.body_names[0], 1.0)
    assert soadyn.force_elements(m) == []


def test_coincident_points_exert_no_force():
    m = Model()
    m.add_body("cart", None, Joint.prismatic(np.array([1.0, 0, 0])), mass=1.0, inertia=(0.1, 0.1, 0.1))
    m.add_point_spring("zero", "world", "cart", 10.0, damping=1.0, rest_length=0.5)
    f = soadyn.bias_forces(m, np.zeros(1), np.ones(1))
    assert np.isfinite(f).all()


URDF = textwrap.dedent("""\
    <robot name="damped">
      <link name="base"/>
      <link name="arm"><inertial><mass value="1.0"/><origin xyz="0 0 -0.3"/>
        <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.001"/></inertial></link>
      <link name="slider"><inertial><mass value="0.5"/>
        <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
      <joint name="shoulder" type="revolute"><parent link="base"/><child link="arm"/><axis xyz="1 0 0"/>
        <limit lower="-3" upper="3" effort="10" velocity="5"/><dynamics damping="0.7" friction="0.2"/></joint>
      <joint name="slide" type="prismatic"><parent link="arm"/><child link="slider"/><axis xyz="0 0 1"/>
        <origin xyz="0 0 -0.6"/><limit lower="-1" upper="1" effort="10" velocity="5"/>
        <dynamics damping="1.5"/></joint>
    </robot>""")


def test_urdf_damping_becomes_joint_dampers_and_friction_is_reported(tmp_path):
    path = tmp_path / "damped.urdf"
    path.write_text(URDF)
    with pytest.warns(soadyn.urdf.UrdfIgnoredWarning, match="'shoulder' \\(friction 0.2\\)") as record:
        m = soadyn.load_urdf(path, joint_damping=True)
    assert len([w for w in record if issubclass(w.category, soadyn.urdf.UrdfIgnoredWarning)]) == 1
    assert [(e["name"], e["dof"], e["stiffness"], e["damping"]) for e in soadyn.force_elements(m)] == [
        ("shoulder", "shoulder", 0.0, 0.7), ("slide", "slide", 0.0, 1.5)]
    # MuJoCo reads <dynamics damping> as joint damping (and friction as a dry-friction constraint, which
    # soadyn ignores): same accelerations before constraints (qacc_smooth)
    mj = mujoco.MjModel.from_xml_path(str(path))
    data = mujoco.MjData(mj)
    for q, v in [(np.array([0.3, 0.1]), np.array([1.0, -0.5])), (np.array([-1.0, 0.2]), np.array([-2.0, 0.7]))]:
        data.qpos[:], data.qvel[:] = q, v
        mujoco.mj_forward(mj, data)
        np.testing.assert_allclose(data.qfrc_passive, -np.array([0.7, 1.5]) * v, rtol=0, atol=1e-12)
        np.testing.assert_allclose(soadyn.forward_dynamics(m, q, v, np.zeros(2)), data.qacc_smooth, rtol=0,
                                   atol=1e-9)


def test_urdf_without_friction_warns_nothing(tmp_path):
    path = tmp_path / "damped.urdf"
    path.write_text(URDF.replace(' friction="0.2"', ""))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert len(soadyn.force_elements(soadyn.load_urdf(path, joint_damping=True))) == 2


def test_urdf_dynamics_are_ignored_by_default(tmp_path):
    """The rigid-body model, as Pinocchio's algorithms use the same file: no dampers, no warning."""
    path = tmp_path / "damped.urdf"
    path.write_text(URDF)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert soadyn.force_elements(soadyn.load_urdf(path)) == []


def test_a_prescribed_crank_reports_its_actuators_share_on_the_four_bar():
    """One prescribed DOF drives the four-bar (no redundant actuation): with a crank spring and a point spring,
    its drive torque is the rigid one with the point spring's wrench as f_ext, minus the crank spring's force
    -k (q - rest) - c v, and the accelerations are the same."""
    k, c, rest = 5.0, 0.3, 0.2
    sprung, rigid = soadyn.scenes.four_bar(), soadyn.scenes.four_bar()
    crank = sprung.dof_names[0]
    sprung.add_joint_spring("crank_spring", crank, k, damping=c, rest=rest)
    for m in (sprung, rigid):
        m.set_prescribed([crank])
    q, v = soadyn.scenes.four_bar_state(0.9, 1.5)
    u = np.zeros(sprung.nv)
    u[0] = 0.7  # the crank's acceleration
    qdd_s, tau_s, *_ = soadyn.constrained_dynamics(sprung, q, v, u)
    qdd_r, tau_r, *_ = soadyn.constrained_dynamics(rigid, q, v, u)
    np.testing.assert_allclose(qdd_s, qdd_r, rtol=0, atol=1e-10)
    spring_force = -k * (q[0] - rest) - c * v[0]
    assert tau_s[0] == pytest.approx(tau_r[0] - spring_force, rel=1e-12, abs=1e-12)
