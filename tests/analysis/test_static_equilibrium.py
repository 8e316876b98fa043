"""Static equilibrium (soadyn.static_equilibrium) and the stiffness of the loop
reactions (soadyn.loop_force_stiffness).

Oracles: closed-form pendulums (rest angles, holding torques, the stiffness
m g l, negative upside down); MuJoCo settling a damped four-bar closed by an
`equality connect` and a damped two-link arm to rest (configuration and
constraint force); Pinocchio's computeGeneralizedGravity at the equilibrium of
the UR5 (zero on the free joints, the holding torques on the held ones);
scipy minimising the potential energy along the four-bar's closed-form
assembly (self-consistency, on top); central differences of C(q)' nu in the
tangent space for every loop kind, to the world and between bodies.
"""
from __future__ import annotations

import math

import mujoco
import numpy as np
import pinocchio as pin
import pytest
from scipy.optimize import minimize_scalar

import soadyn
from soadyn.oracles import PinocchioOracle
from support.robots import robot
from support.trees import random_rotation, random_tree

G = 9.81
KINDS = ("point", "revolute", "prismatic", "weld", "distance")


# --- loop_force_stiffness against central differences --------------------------------------------

def loop_force_by_differences(m, q, nu, h=1e-6):
    K = np.empty((m.nv, m.nv))
    for k in range(m.nv):
        e = np.zeros(m.nv)
        e[k] = h
        plus = soadyn.loop_jacobian(m, soadyn.integrate(m, q, e, 1.0)).T @ nu
        minus = soadyn.loop_jacobian(m, soadyn.integrate(m, q, -e, 1.0)).T @ nu
        K[:, k] = (plus - minus) / (2 * h)
    return K


def random_tree_with_loop(seed: int, kind: str, to_world: bool):
    """A random tree (every joint kind) with one loop of `kind` from a deep body to the world or to another
    body; the loop need not be closed: d(C' nu)/dq is an identity at every q."""
    m, _ = random_tree(seed, nbodies=8)
    rng = np.random.default_rng(seed)
    a = m.nbodies - 1
    b = None if to_world else m.body_names[int(rng.integers(0, a))]
    placement = lambda: (random_rotation(rng), rng.uniform(-0.3, 0.3, size=3))  # noqa: E731
    m.add_loop(f"{kind}_loop", m.body_names[a], b, kind, placement_a=placement(), placement_b=placement(),
               length=0.4 if kind == "distance" else None)
    return m, soadyn.random_configuration(m, seed + 5), rng.normal(size=m.nloop_equations)


@pytest.mark.parametrize("seed", range(3))
@pytest.mark.parametrize("to_world", [True, False], ids=["to_world", "between_bodies"])
@pytest.mark.parametrize("kind", KINDS)
def test_loop_force_stiffness_matches_central_differences(kind, to_world, seed):
    m, q, nu = random_tree_with_loop(seed, kind, to_world)
    analytic = soadyn.loop_force_stiffness(m, q, nu)
    reference = loop_force_by_differences(m, q, nu)
    assert np.abs(analytic - reference).max() <= 1e-7 * max(1.0, np.abs(reference).max())


@pytest.mark.parametrize("scene,state", [
    (soadyn.scenes.four_bar, lambda: soadyn.scenes.four_bar_state(0.7)),
    (lambda: soadyn.scenes.four_bar("point"), lambda: soadyn.scenes.four_bar_state(2.0)),
    (soadyn.scenes.slider_crank, lambda: soadyn.scenes.slider_crank_state(0.5)),
    (soadyn.scenes.delta_robot, lambda: soadyn.scenes.delta_robot_state((0.05, -0.02, -0.6))),
], ids=["four_bar", "four_bar_point", "slider_crank", "delta_robot"])
def test_loop_force_stiffness_on_the_loop_scenes(scene, state):
    m = scene()
    q, _ = state()
    nu = np.random.default_rng(3).normal(size=m.nloop_equations)
    reference = loop_force_by_differences(m, q, nu)
    assert np.abs(soadyn.loop_force_stiffness(m, q, nu) - reference).max() <= 1e-7 * max(1.0, np.abs(reference).max())


def test_loop_force_stiffness_of_a_tree_is_zero_and_bad_multipliers_are_named():
    m, _ = random_tree(1, nbodies=4)
    q = soadyn.random_configuration(m, 1)
    assert not soadyn.loop_force_stiffness(m, q, np.zeros(0)).any()
    m, q, nu = random_tree_with_loop(0, "revolute", True)
    nu[2] = np.nan
    with pytest.raises(ValueError, match=r"revolute_loop\[2\]"):
        soadyn.loop_force_stiffness(m, q, nu)


# --- closed form: pendulums ----------------------------------------------------------------------

def pendulum(mass=2.0, com=(0.0, 0.0, -0.5)):
    m = soadyn.Model()
    m.add_body("link", None, soadyn.Joint.revolute([0, 1, 0]), mass=mass, com=list(com), inertia=np.eye(3) * 0.01)
    return m


def double_pendulum(m1=1.5, m2=0.8, l1=0.7, c1=0.3, c2=0.45):
    m = soadyn.Model()
    m.add_body("upper", None, soadyn.Joint.revolute([0, 1, 0]), mass=m1, com=[0, 0, -c1], inertia=np.eye(3) * 0.01)
    m.add_body("lower", "upper", soadyn.Joint.revolute([0, 1, 0]), placement=(np.eye(3), [0, 0, -l1]), mass=m2,
               com=[0, 0, -c2], inertia=np.eye(3) * 0.01)
    return m, (m1, m2, l1, c1, c2)


# Newton finds the stationary point of its basin: below the horizontal the hanging one, above it the top.
@pytest.mark.parametrize("start", [0.3, -0.9, 1.0])
def test_pendulum_hangs_straight_down_with_stiffness_m_g_l(start):
    r = soadyn.static_equilibrium(pendulum(), [start])
    assert r.converged and r.iterations >= 1
    assert abs(math.remainder(r.q[0], 2 * math.pi)) < 1e-12
    assert r.stiffness_eigenvalues == pytest.approx([2.0 * G * 0.5], rel=1e-12)
    assert r.stable


@pytest.mark.parametrize("start", [3.0, -2.0])
def test_pendulum_upside_down_is_unstable(start):
    r = soadyn.static_equilibrium(pendulum(), [start])
    assert abs(math.remainder(r.q[0] - math.pi, 2 * math.pi)) < 1e-12
    assert r.stiffness_eigenvalues == pytest.approx([-2.0 * G * 0.5], rel=1e-12)
    assert not r.stable


def test_pendulum_with_offset_com_hangs_with_the_com_below_the_pivot():
    # R_y(t) (x, 0, -z) has x cos t - z sin t = 0 at tan t = x / z; stiffness m g |com|.
    x, z, mass = 0.2, 0.45, 1.3
    r = soadyn.static_equilibrium(pendulum(mass, (x, 0.0, -z)), [0.0])
    assert r.q[0] == pytest.approx(math.atan2(x, z), abs=1e-12)
    assert r.stiffness_eigenvalues == pytest.approx([mass * G * math.hypot(x, z)], rel=1e-12)


def test_double_pendulum_hangs_straight_with_the_closed_form_stiffness():
    m, (m1, m2, l1, c1, c2) = double_pendulum()
    r = soadyn.static_equilibrium(m, [0.4, -0.7])
    assert np.abs(r.q).max() < 1e-12
    # V = -g (m1 c1 cos t1 + m2 (l1 cos t1 + c2 cos(t1 + t2))): its Hessian at t = 0.
    hessian = G * np.array([[m1 * c1 + m2 * (l1 + c2), m2 * c2], [m2 * c2, m2 * c2]])
    assert r.stiffness_eigenvalues == pytest.approx(np.linalg.eigvalsh(hessian), rel=1e-12)
    # The joint wrenches carry the weights: the upper hinge holds both links.
    assert r.joint_wrenches[0][5] == pytest.approx((m1 + m2) * G, rel=1e-12)
    assert r.joint_wrenches[1][5] == pytest.approx(m2 * G, rel=1e-12)


@pytest.mark.parametrize("hold", ["upper", 0, ["upper"]])
def test_double_pendulum_held_at_its_upper_joint(hold):
    m, (m1, m2, l1, c1, c2) = double_pendulum()
    m.set_prescribed("lower")  # the model's flags play no part: only `hold` fixes DOFs
    r = soadyn.static_equilibrium(m, [0.5, 0.3], hold=hold)
    assert r.q[0] == 0.5 and r.q[1] == pytest.approx(-0.5, abs=1e-12)  # the lower link hangs vertically
    assert list(r.holding_forces) == ["upper"]
    assert r.holding_forces["upper"] == pytest.approx(G * (m1 * c1 + m2 * l1) * math.sin(0.5), rel=1e-12)
    assert r.stiffness_eigenvalues == pytest.approx([m2 * G * c2], rel=1e-12)


# --- MuJoCo: damped mechanisms settled to rest ---------------------------------------------------

# Four-bar in the x-z plane (gravity -z, hinges about y), body frames world-aligned at q = 0, which is a
# closed assembly: ground O = (0, 0, 0) to O2 = (0.5, 0, 0), crank O -> P, coupler P -> Q, rocker O2 -> Q.
FOUR_BAR_P = np.array([0.15, 0.0, 0.26])
FOUR_BAR_Q = np.array([0.62, 0.0, 0.42])
FOUR_BAR_O2 = np.array([0.5, 0.0, 0.0])
LINK_MASSES = (0.7, 1.2, 0.9)


def _xyz(v) -> str:
    return " ".join(f"{x:.17g}" for x in v)


def mj_hinge(name, pos, com, mass, damping, inner="") -> str:
    """A body on a hinge about y with a point-like inertia at `com` (statics needs only mass and COM)."""
    return (f'<body name="{name}" pos="{_xyz(pos)}"><joint name="{name}" type="hinge" axis="0 1 0" '
            f'damping="{damping}"/><inertial pos="{_xyz(com)}" mass="{mass}" diaginertia="0.01 0.01 0.01"/>'
            f'{inner}</body>')


def mj_model(bodies: str, equality: str = "") -> str:
    return (f'<mujoco><option timestep="0.001" gravity="0 0 -9.81" integrator="implicitfast"/>'
            f'<worldbody>{bodies}</worldbody><equality>{equality}</equality></mujoco>')


def mujoco_four_bar_xml() -> str:
    P, Q, O2 = FOUR_BAR_P, FOUR_BAR_Q, FOUR_BAR_O2
    ma, mb, mc = LINK_MASSES
    coupler = mj_hinge("coupler", P, (Q - P) / 2, mb, 0.5)
    bodies = mj_hinge("crank", np.zeros(3), P / 2, ma, 0.5, coupler) + mj_hinge("rocker", O2, (Q - O2) / 2, mc, 0.5)
    return mj_model(bodies, f'<connect body1="coupler" body2="rocker" anchor="{_xyz(Q - P)}" solref="0.002 1"/>')


def soadyn_four_bar():
    P, Q, O2 = FOUR_BAR_P, FOUR_BAR_Q, FOUR_BAR_O2
    ma, mb, mc = LINK_MASSES
    m = soadyn.Model()
    y = soadyn.Joint.revolute([0, 1, 0])
    inertia = np.eye(3) * 0.01
    m.add_body("crank", None, y, mass=ma, com=P / 2, inertia=inertia)
    m.add_body("coupler", "crank", y, placement=(np.eye(3), P), mass=mb, com=(Q - P) / 2, inertia=inertia)
    m.add_body("rocker", None, y, placement=(np.eye(3), O2), mass=mc, com=(Q - O2) / 2, inertia=inertia)
    m.add_loop("pin", "coupler", "rocker", "point", placement_a=(np.eye(3), Q - P), placement_b=(np.eye(3), Q - O2))
    return m


def settle(model_xml: str, seconds: float):
    mj = mujoco.MjModel.from_xml_string(model_xml)
    data = mujoco.MjData(mj)
    mujoco.mj_step(mj, data, nstep=int(seconds / mj.opt.timestep))
    assert np.abs(data.qvel).max() < 1e-9, "MuJoCo has not come to rest"
    return mj, data


def test_four_bar_equilibrium_matches_mujoco_at_rest():
    mj, data = settle(mujoco_four_bar_xml(), 60.0)
    m = soadyn_four_bar()
    # Started 0.2 rad away from MuJoCo's rest, off the closure (soadyn.assemble closes it first).
    r = soadyn.static_equilibrium(m, data.qpos + np.array([0.2, -0.2, 0.1]))
    assert r.stable and r.iterations >= 2
    # MuJoCo's connect is soft (solref 2 ms): its pin yields by about weight / stiffness (3e-6 rad here).
    assert np.abs(r.q - data.qpos).max() < 5e-6
    # The pin force on the coupler: MuJoCo's connect rows are p_coupler - p_rocker in world axes, so
    # efc_force is the force on body1 (the coupler), as loop_wrenches' force (B's side on A's side).
    assert data.nefc == 3
    np.testing.assert_allclose(r.loop_wrenches[0, 3:], data.efc_force[:3], atol=2e-4 * np.abs(data.efc_force).max())
    # The generalized constraint forces carry the weights.
    np.testing.assert_allclose(soadyn.loop_jacobian(m, r.q).T @ r.multipliers, data.qfrc_constraint,
                               atol=1e-4 * np.abs(data.qfrc_constraint).max())


def mujoco_arm_xml(coms) -> str:
    lower = mj_hinge("lower", [0, 0, -0.6], coms[1], 0.6, 2)
    return mj_model(mj_hinge("upper", np.zeros(3), coms[0], 1.1, 2, lower))


def test_two_link_arm_with_offset_coms_matches_mujoco_at_rest():
    coms = (np.array([0.12, 0.0, -0.3]), np.array([-0.2, 0.0, -0.25]))
    _, data = settle(mujoco_arm_xml(coms), 60.0)
    m = soadyn.Model()
    y = soadyn.Joint.revolute([0, 1, 0])
    m.add_body("upper", None, y, mass=1.1, com=coms[0], inertia=np.eye(3) * 0.01)
    m.add_body("lower", "upper", y, placement=(np.eye(3), [0, 0, -0.6]), mass=0.6, com=coms[1],
               inertia=np.eye(3) * 0.01)
    r = soadyn.static_equilibrium(m, [0.0, 0.0])
    assert r.stable
    np.testing.assert_allclose(r.q, data.qpos, atol=1e-9)


# --- Pinocchio: gravity at the equilibrium ----------------------------------------------------------

def test_ur5_equilibrium_against_pinocchio_gravity():
    path, _ = robot("ur5")
    m = soadyn.load_urdf(str(path))
    oracle = PinocchioOracle(m, str(path), False)
    hold = ["shoulder_pan_joint", "shoulder_lift_joint", "wrist_2_joint", "wrist_3_joint"]
    r = soadyn.static_equilibrium(m, soadyn.random_configuration(m, 3), hold=hold)
    g = oracle.from_pin(pin.computeGeneralizedGravity(oracle.model, oracle.data, oracle.q(r.q)))
    scale = np.abs(g).max()
    assert scale > 1.0
    for k, name in enumerate(m.dof_names):
        expected = r.holding_forces[name] if name in hold else 0.0
        assert abs(g[k] - expected) <= 1e-10 * scale, name
    # Held joints keep their values.
    q0 = soadyn.random_configuration(m, 3)
    for name in hold:
        k = m.dof_names.index(name)
        assert r.q[k] == q0[k]


# --- the four-bar scene (gravity -y in its plane) and scipy ------------------------------------------

def potential_along_assembly(m, theta):
    q, _ = soadyn.scenes.four_bar_state(theta)
    return soadyn.potential_energy(m, q)


@pytest.mark.parametrize("closure", ["revolute", "point"])
def test_four_bar_scene_equilibrium_minimises_the_potential_energy(closure):
    m = soadyn.scenes.four_bar(closure)
    grid = np.linspace(-math.pi, math.pi, 73)
    low = grid[int(np.argmin([potential_along_assembly(m, t) for t in grid]))]
    best = minimize_scalar(lambda t: potential_along_assembly(m, t), bracket=(low - 0.1, low, low + 0.1), tol=1e-12)
    q_start, _ = soadyn.scenes.four_bar_state(best.x + 0.3)
    r = soadyn.static_equilibrium(m, q_start)
    assert np.abs(soadyn.loop_residual(m, r.q)).max() < 1e-12
    assert r.q[0] == pytest.approx(best.x, abs=1e-6)
    assert r.stable and r.stiffness_eigenvalues.shape == (1,)
    # The reduced stiffness is V'' along the assembly per unit |dq/dtheta|^2 (tangent coordinates).
    h = 1e-4
    second = (potential_along_assembly(m, r.q[0] + h) - 2 * potential_along_assembly(m, r.q[0])
              + potential_along_assembly(m, r.q[0] - h)) / h**2
    _, rate = soadyn.scenes.four_bar_state(r.q[0], 1.0)
    assert r.stiffness_eigenvalues[0] == pytest.approx(second / (rate @ rate), rel=1e-5)
    # Equilibrium: G = C' nu, and the constrained dynamics at rest does not move.
    G_static = soadyn.inverse_dynamics(m, r.q, np.zeros(3), np.zeros(3))
    np.testing.assert_allclose(soadyn.loop_jacobian(m, r.q).T @ r.multipliers, G_static,
                               atol=1e-12 * np.abs(G_static).max())
    qdd = soadyn.constrained_dynamics(m, r.q, np.zeros(3), np.zeros(3))[0]
    assert np.abs(qdd).max() < 1e-9


def test_four_bar_scene_held_crank_reports_its_holding_torque():
    m = soadyn.scenes.four_bar()
    q0, _ = soadyn.scenes.four_bar_state(0.7)
    r = soadyn.static_equilibrium(m, q0, hold="crank")
    assert r.q[0] == 0.7 and r.iterations == 0 and r.stiffness_eigenvalues.size == 0
    # The crank torque that holds the mechanism: dV/dtheta along the assembly (virtual work).
    h = 1e-5
    dV = (potential_along_assembly(m, 0.7 + h) - potential_along_assembly(m, 0.7 - h)) / (2 * h)
    assert r.holding_forces["crank"] == pytest.approx(dV, rel=1e-8)


# --- failures and hostile input -----------------------------------------------------------------------

def test_free_floating_body_has_no_equilibrium_and_no_stiffness():
    m = soadyn.Model()
    m.add_body("block", None, soadyn.Joint.free(), mass=1.0, inertia=np.eye(3))
    q0 = soadyn.neutral_configuration(m)
    with pytest.raises(soadyn.DynamicsError, match="no stiffness along .*block"):
        soadyn.static_equilibrium(m, q0)
    m.gravity = [0.0, 0.0, 0.0]
    with pytest.raises(soadyn.DynamicsError, match="not isolated"):
        soadyn.static_equilibrium(m, q0)


def test_not_converging_names_the_dof():
    m, _ = double_pendulum()
    with pytest.raises(soadyn.DynamicsError, match="did not converge in 1 iterations: DOF '(upper|lower)'"):
        soadyn.static_equilibrium(m, [2.0, -2.5], max_iterations=1)


@pytest.mark.parametrize("kwargs,error,message", [
    (dict(q0=[math.nan, 0.0]), ValueError, "q0 entry 0 .*upper.* not finite"),
    (dict(q0=[0.1, 0.2], hold="elbow"), ValueError, "unknown DOF or joint 'elbow'"),
    (dict(q0=[0.1, 0.2], tol=0.0), ValueError, "tol must be positive"),
    (dict(q0=[0.1, 0.2], tol=-1e-9), ValueError, "tol must be positive"),
    (dict(q0=[0.1, 0.2], tol=math.inf), ValueError, "tol must be positive"),
    (dict(q0=[0.1, 0.2], max_iterations=0), ValueError, "max_iterations"),
    (dict(q0=[0.1]), ValueError, r"q0 has shape \(1,\), expected \(2,\) \(nq\)"),
])
def test_bad_arguments_are_refused(kwargs, error, message):
    m, _ = double_pendulum()
    with pytest.raises(error, match=message):
        soadyn.static_equilibrium(m, **kwargs)


def test_hold_on_a_modal_dof_is_refused():
    m = soadyn.scenes.cantilever_beam(1.0, 100.0, 1.0, 2)
    modal = [n for n, f in zip(m.dof_names, m.modal) if f][0]
    q0 = soadyn.neutral_configuration(m)
    with pytest.raises(ValueError, match="modal"):
        soadyn.static_equilibrium(m, q0, hold=modal)


def test_flexible_cantilever_sags_as_euler_bernoulli():
    """A clamped beam under its own weight (stiffness from the dual-number sweeps): the tip deflection
    is Euler-Bernoulli's mu g L^4 / (8 EI), to the modal model's truncation; gravity's modal force does
    not depend on the deflection, so Newton converges in one step."""
    length, EI, mu, g = 2.0, 3.0e3, 1.5, 9.81
    m = soadyn.scenes.cantilever_beam(length, EI, mu, n_modes=4, n_nodes=200)
    m.gravity = np.array([0.0, 0.0, -g])
    eq = soadyn.static_equilibrium(m, soadyn.neutral_configuration(m))
    beam = m.flexible_body("beam")
    tip = beam.node_pose(beam.attachments["tip"], eq.q)[:3, 3]
    assert tip[2] == pytest.approx(-mu * g * length**4 / (8 * EI), rel=2e-4)
    assert eq.iterations == 1 and eq.stable and np.all(eq.stiffness_eigenvalues > 0)
    # The modal stiffness is the beam's own K: the reduced stiffness's eigenvalues are K's.
    np.testing.assert_allclose(eq.stiffness_eigenvalues, np.sort(np.linalg.eigvalsh(beam.stiffness)), rtol=1e-9)


def test_point_spring_hanging_slider_and_its_sensitivities():
    """A slider on a vertical rail hanging from a point spring (rest length L0, stiffness k) rests at
    z = -(L0 + m g / k); dz/dk = m g / k^2 and dz/dm = -g / k by the direct and the adjoint method."""
    mass, k, L0, g = 2.0, 200.0, 0.5, 9.81
    m = soadyn.Model()
    m.add_body("slider", None, soadyn.Joint.prismatic([0, 0, 1]), mass=mass, com=[0, 0, 0],
               inertia=np.eye(3) * 0.01)
    m.add_point_spring("strut", "slider", None, k, rest_length=L0)
    eq = soadyn.static_equilibrium(m, np.array([-0.3]), sensitivities=["strut.stiffness", "slider.mass"])
    assert eq.q[0] == pytest.approx(-(L0 + mass * g / k), rel=1e-12)
    np.testing.assert_allclose(eq.stiffness_eigenvalues, [k], rtol=1e-12)
    assert eq.sensitivities["strut.stiffness"]["q"][0] == pytest.approx(mass * g / k**2, rel=1e-10)
    assert eq.sensitivities["slider.mass"]["q"][0] == pytest.approx(-g / k, rel=1e-10)
    adjoint = soadyn.objective_gradient(m, eq, ["strut.stiffness"], np.array([1.0]))
    assert float(adjoint["strut.stiffness"]) == pytest.approx(mass * g / k**2, rel=1e-10)
