"""Flexible bodies inside the recursion: forward, inverse and hybrid dynamics,
mass matrix, energy and momentum of trees mixing rigid and modal flexible
bodies, against an independent node-by-node mass matrix (support/flexible_trees.py),
conservation laws, the stiff limit and closed-form frequencies."""
import numpy as np
import pytest

import soadyn
from soadyn import FlexibleBody, scenes
from support.beams import BETA_L, euler_bernoulli_frequencies
from support.energy import flow_derivative, total_energy
from support.flexible_trees import assembled_mass_matrix, random_flexible_body, random_flexible_state, random_flexible_tree

TREES = [(seed, floating) for seed in range(8) for floating in (False, True)]
# Appendage trees: nothing on any flexible body's nodes (the tree-frame sweeps).
APPENDAGE_TREES = [(seed, floating) for seed in range(4) for floating in (False, True)]
DYNAMICS_TREES = [(seed, floating, False) for seed, floating in TREES] + \
    [(seed, floating, True) for seed, floating in APPENDAGE_TREES]
DYNAMICS_IDS = [f"seed{s}-{'floating' if f else 'fixed'}{'-appendages' if a else ''}" for s, f, a in DYNAMICS_TREES]


def modal_mask(m):
    return np.asarray(m.modal, dtype=bool)


def test_random_trees_cover_every_attachment_kind():
    """The trees below exercise clamped, hinged and sliding flexible bodies, children on
    attachment nodes, and children (rigid and flexible) on flexible bodies' frames."""
    kinds, on_node, flexible_on_node = set(), 0, 0
    for seed, floating in TREES:
        _, parts = random_flexible_tree(seed, 8, floating)
        kinds |= {p.joint[0] for p in parts if p.flexible is not None}
        on_node += sum(p.node is not None for p in parts)
        flexible_on_node += sum(p.node is not None and p.flexible is not None for p in parts)
    assert kinds == {"revolute", "prismatic", "fixed"}
    assert on_node >= 10 and flexible_on_node >= 2
    kinds, on_frame = set(), 0
    for seed, floating in APPENDAGE_TREES:
        _, parts = random_flexible_tree(seed, 8, floating, appendages=True)
        flexible = {p.name for p in parts if p.flexible is not None}
        assert all(p.node is None for p in parts)
        kinds |= {(p.joint[0], floating) for p in parts if p.flexible is not None}
        on_frame += sum(p.parent in flexible for p in parts)
    assert {kind for kind, _ in kinds} == {"revolute", "prismatic", "fixed"} and ("fixed", True) in kinds
    assert on_frame >= 2


@pytest.mark.parametrize("seed,floating", TREES)
def test_mass_matrix_matches_assembled_node_energy(seed, floating):
    m, parts = random_flexible_tree(seed, 8, floating)
    q, v, _ = random_flexible_state(m, seed)
    expected = assembled_mass_matrix(m, parts, q)
    M = soadyn.mass_matrix(m, q)
    scale = np.abs(expected).max()
    assert np.abs(M - expected).max() <= 1e-9 * scale
    assert soadyn.kinetic_energy(m, q, v) == pytest.approx(0.5 * v @ expected @ v, rel=1e-9)


@pytest.mark.parametrize("seed,floating,appendages", DYNAMICS_TREES, ids=DYNAMICS_IDS)
def test_forward_and_inverse_dynamics_agree_with_dense_equations(seed, floating, appendages):
    """ABA = M^-1 (tau - h), with M from the node assembly; RNEA(ABA) = tau."""
    m, parts = random_flexible_tree(seed, 8, floating, damping=True, appendages=appendages)
    q, v, rng = random_flexible_state(m, seed)
    tau = rng.normal(size=m.nv)
    M = assembled_mass_matrix(m, parts, q)
    h = soadyn.bias_forces(m, q, v)
    qdd = soadyn.forward_dynamics(m, q, v, tau)
    expected = np.linalg.solve(M, tau - h)
    assert np.abs(qdd - expected).max() <= 1e-9 * max(1.0, np.abs(expected).max())
    back = soadyn.inverse_dynamics(m, q, v, qdd)
    assert np.abs(back - tau).max() <= 1e-9 * max(1.0, np.abs(tau).max())


@pytest.mark.parametrize("seed,floating,appendages", DYNAMICS_TREES, ids=DYNAMICS_IDS)
def test_hybrid_dynamics_matches_partitioned_solve(seed, floating, appendages):
    """Jain & Rodriguez 1993, Eq. 12 on the dense M and h, hinge DOFs randomly prescribed, modal DOFs regular."""
    m, parts = random_flexible_tree(seed, 8, floating, damping=True, appendages=appendages)
    q, v, rng = random_flexible_state(m, seed)
    M = assembled_mass_matrix(m, parts, q)
    h = soadyn.bias_forces(m, q, v)
    modal = modal_mask(m)
    for trial in range(3):
        mask = (rng.uniform(size=m.nv) < [0.3, 0.7, 1.0][trial]) & ~modal
        m.set_prescribed(mask)
        u = rng.normal(size=m.nv)
        qdd, tau = soadyn.hybrid_dynamics(m, q, v, u)
        p, r = mask, ~mask
        qdd_r = np.linalg.solve(M[np.ix_(r, r)], u[r] - h[r] - M[np.ix_(r, p)] @ u[p])
        full = np.where(mask, u, 0.0)
        full[r] = qdd_r
        assert np.abs(qdd - full).max() <= 1e-9 * max(1.0, np.abs(full).max())
        expected_tau = M @ full + h
        assert np.abs(tau - expected_tau).max() <= 1e-9 * max(1.0, np.abs(expected_tau).max())
    m.set_prescribed(np.zeros(m.nv, dtype=bool))


@pytest.mark.parametrize("seed,appendages", [(seed, a) for seed in range(4) for a in (False, True)])
def test_velocity_terms_match_lagrange_equations_of_the_assembled_mass_matrix(seed, appendages):
    """Fixed-base trees (coordinates = DOFs): the velocity terms h(q, v) - h(q, 0) equal
    Lagrange's  dM/dt v - 1/2 d(v'Mv)/dq,  with M from the node assembly and its
    derivatives by central differences. This checks every gyroscopic term, workless ones
    (which the energy rate cannot see) included."""
    m, parts = random_flexible_tree(seed, 8, floating=False, appendages=appendages)
    q, v, _ = random_flexible_state(m, seed)
    assert m.nq == m.nv
    step = 1e-6
    dM = []
    for j in range(m.nq):
        e = np.zeros(m.nq)
        e[j] = step
        dM.append((assembled_mass_matrix(m, parts, q + e) - assembled_mass_matrix(m, parts, q - e)) / (2 * step))
    expected = sum(dM[j] @ v * v[j] for j in range(m.nq)) - 0.5 * np.array([v @ dM[i] @ v for i in range(m.nq)])
    velocity_terms = soadyn.bias_forces(m, q, v) - soadyn.bias_forces(m, q, np.zeros(m.nv))
    assert np.abs(velocity_terms - expected).max() <= 1e-6 * max(1.0, np.abs(expected).max())


@pytest.mark.parametrize("seed,floating,appendages", DYNAMICS_TREES[:8] + DYNAMICS_TREES[len(TREES):],
                         ids=DYNAMICS_IDS[:8] + DYNAMICS_IDS[len(TREES):])
def test_energy_rate_equals_power_minus_modal_damping(seed, floating, appendages):
    """d/dt (T + V_gravity + V_strain) = v . tau - eta_dot' C eta_dot along the flow:
    the velocity terms of the recursion are consistent with the energies."""
    for damping in (False, True):
        m, parts = random_flexible_tree(seed, 8, floating, damping=damping, appendages=appendages)
        q, v, rng = random_flexible_state(m, seed)
        tau = rng.normal(size=m.nv)
        qdd = soadyn.forward_dynamics(m, q, v, tau)
        dissipated = 0.0
        for part in parts:
            if part.flexible is not None:
                i = m.body_names.index(part.name)
                k = m.dof_names.index(f"{part.name}:mode1")
                eta_dot = v[k:k + part.flexible.n_modes]
                dissipated += eta_dot @ part.flexible.damping @ eta_dot
        assert (dissipated > 0) == damping
        rate = flow_derivative(total_energy, m, q, v, qdd)
        expected = v @ tau - dissipated
        assert abs(rate - expected) <= 1e-6 * max(1.0, abs(expected), total_energy(m, q, v))


@pytest.mark.parametrize("seed", range(4))
def test_momentum_of_free_floating_flexible_tree_is_conserved(seed):
    m, _ = random_flexible_tree(seed, 8, floating=True, damping=True)
    m.gravity = [0.0, 0.0, 0.0]
    q, v, _ = random_flexible_state(m, seed)
    qdd = soadyn.forward_dynamics(m, q, v, np.zeros(m.nv))
    h = soadyn.momentum(m, q, v)
    dh = flow_derivative(lambda mm, qq, vv: soadyn.momentum(mm, qq, vv), m, q, v, qdd)
    assert np.abs(dh).max() <= 1e-6 * np.abs(h).max()


def test_energy_is_conserved_without_damping_over_a_simulation():
    m, _ = random_flexible_tree(3, 8, floating=True)
    q, v, _ = random_flexible_state(m, 3)
    v *= 0.5
    sim = soadyn.Simulator(m, 1e-3, "dopri5")
    sim.rtol, sim.atol = 1e-11, 1e-12
    sim.set_state(q, v)
    e0, h0 = total_energy(m, sim.q, sim.v), soadyn.momentum(m, sim.q, sim.v)
    sim.run(0.2)
    assert abs(total_energy(m, sim.q, sim.v) - e0) <= 1e-8 * abs(e0)
    m.gravity = [0.0, 0.0, 0.0]
    sim = soadyn.Simulator(m, 1e-3, "dopri5")
    sim.rtol, sim.atol = 1e-11, 1e-12
    sim.set_state(q, v)
    h0 = soadyn.momentum(m, sim.q, sim.v)
    sim.run(0.2)
    assert np.abs(soadyn.momentum(m, sim.q, sim.v) - h0).max() <= 1e-8 * np.abs(h0).max()


def test_locking_a_hinge_of_a_flexible_tree_keeps_momentum_and_reports_energy():
    m, _ = random_flexible_tree(5, 8, floating=True)
    m.gravity = [0.0, 0.0, 0.0]
    q, v, _ = random_flexible_state(m, 5)
    sim = soadyn.Simulator(m, 1e-3, "rk4")
    sim.set_state(q, v)
    h0, t0 = soadyn.momentum(m, sim.q, sim.v), soadyn.kinetic_energy(m, sim.q, sim.v)
    hinge = next(n for n, modal in zip(m.dof_names, m.modal) if not modal and not n.startswith("b0"))
    sim.lock(hinge)
    assert sim.v[m.dof_index(hinge)] == 0.0
    assert np.abs(soadyn.momentum(m, sim.q, sim.v) - h0).max() <= 1e-12 * np.abs(h0).max()
    t1 = soadyn.kinetic_energy(m, sim.q, sim.v)
    assert t1 < t0 and sim.energy_lost == pytest.approx(t0 - t1, rel=1e-10)


def test_cantilever_scene_frequencies_match_euler_bernoulli():
    """The first three bending frequencies of the clamped beam, within 0.5 %."""
    L, EI, mu = 2.0, 50.0, 1.5
    m = scenes.cantilever_beam(L, EI, mu, 3)
    assert m.dof_names == [f"beam:mode{k}" for k in range(1, 7)] and m.frame_names == ["beam:tip"]
    w = soadyn.natural_frequencies(m, np.zeros(m.nq))
    expected = euler_bernoulli_frequencies(BETA_L[:3], L, EI, mu)
    for plane in (0, 1):
        err = np.abs(w[plane::2] / expected - 1)
        assert err.max() < 0.005, err


def lumped_rigid_inertia(body):
    """Mass, centre of mass and inertia about it of the undeformed lumped body."""
    mass = body.masses.sum()
    com = body.masses @ body.nodes / mass
    inertia = body.rotary_inertias.sum(axis=0)
    for r, mj in zip(body.nodes - com, body.masses):
        inertia += mj * (r @ r * np.eye(3) - np.outer(r, r))
    return mass, com, inertia


def beam_pendulum(EI, flexible=True):
    """A beam on a horizontal hinge (y axis) at its root, hanging under gravity at q = pi/2."""
    body = FlexibleBody.cantilever_beam(1.0, EI, 2.0, 2, n_nodes=40)
    m = soadyn.Model()
    if flexible:
        m.add_flexible_body("beam", None, body, soadyn.Joint.revolute([0, 1, 0]))
    else:
        m.add_body("beam", None, soadyn.Joint.revolute([0, 1, 0]), None, *lumped_rigid_inertia(body))
    return m


def _appendage_on_a_hinge(stiffness, damping):
    """A revolute root carrying, on its frame, a flexible appendage whose modes
    have the given K and C (the tree-frame sweeps)."""
    rng = np.random.default_rng(7)
    n_nodes = 5
    positions = np.column_stack([np.linspace(0.2, 1.0, n_nodes), np.zeros(n_nodes), np.zeros(n_nodes)])
    shapes = rng.normal(scale=0.2, size=(n_nodes, 6, stiffness.shape[0]))
    body = FlexibleBody(positions, np.full(n_nodes, 0.5), np.tile(0.01 * np.eye(3), (n_nodes, 1, 1)), shapes,
                        stiffness, damping)
    m = soadyn.Model()
    m.add_body("hub", None, soadyn.Joint.revolute([0.0, 0.0, 1.0]), None, 2.0, (0.1, 0.0, 0.0), (0.1, 0.1, 0.2))
    m.add_flexible_body("panel", "hub", body)
    return m


@pytest.mark.parametrize("matrix", ["stiffness", "damping"])
def test_a_small_modal_coupling_reaches_the_accelerations(matrix):
    """Diagonal K and C take the O(n_m) elastic forces; a coupling of 1e-8 of
    sqrt(K_kk K_ll) (far above rounding) must not be mistaken for one: the
    accelerations then move by exactly -M^-1 dK eta (or -M^-1 dC eta_dot)."""
    K, C = np.diag([40.0, 90.0, 250.0]), np.diag([0.3, 0.5, 0.9])
    coupled = {"stiffness": K.copy(), "damping": C.copy()}
    extra = 1e-8 * np.sqrt(coupled[matrix][0, 0] * coupled[matrix][2, 2])
    coupled[matrix][0, 2] = coupled[matrix][2, 0] = extra
    m, m_coupled = _appendage_on_a_hinge(K, C), _appendage_on_a_hinge(coupled["stiffness"], coupled["damping"])
    q = np.array([0.4, 0.2, -0.3, 0.25])
    v = np.array([0.7, -1.5, 2.0, 1.2])
    tau = np.array([0.3, 0.0, 0.0, 0.0])
    delta = soadyn.forward_dynamics(m_coupled, q, v, tau) - soadyn.forward_dynamics(m, q, v, tau)
    modal_rate = q[1:] if matrix == "stiffness" else v[1:]
    force_change = np.zeros(4)
    force_change[1:] = -(coupled[matrix] - (K if matrix == "stiffness" else C)) @ modal_rate
    expected = np.linalg.solve(soadyn.mass_matrix(m, q), force_change)
    assert np.abs(expected).max() > 1e-9
    np.testing.assert_allclose(delta, expected, rtol=1e-5, atol=1e-6 * np.abs(expected).max())


def test_stiff_limit_reproduces_the_rigid_pendulum():
    rigid = beam_pendulum(1.0, flexible=False)
    mass, com, inertia = lumped_rigid_inertia(FlexibleBody.cantilever_beam(1.0, 1.0, 2.0, 2, n_nodes=40))
    pivot_inertia = inertia[1, 1] + mass * (com[0] ** 2 + com[2] ** 2)
    closed_form = np.sqrt(mass * 9.81 * com[0] / pivot_inertia)
    hanging = np.array([np.pi / 2])
    assert soadyn.natural_frequencies(rigid, hanging)[0] == pytest.approx(closed_form, rel=1e-8)
    errors = []
    for EI in (1e2, 1e4, 1e6):
        m = beam_pendulum(EI)
        q = np.concatenate([hanging, np.zeros(m.nq - 1)])
        errors.append(abs(soadyn.natural_frequencies(m, q)[0] / closed_form - 1))
    assert errors[2] < 1e-6 and errors[1] < errors[0] and errors[2] < errors[1]
    # Trajectories: the hinge angle converges to the rigid one as the beam stiffens.
    def swing(model):
        sim = soadyn.Simulator(model, 1e-3, "dopri5")
        sim.rtol, sim.atol = 1e-10, 1e-12
        q0 = np.zeros(model.nq)
        q0[0] = np.pi / 2 + 0.4
        sim.set_state(q0, np.zeros(model.nv))
        return sim.run(0.5).q[-1, 0]
    reference = swing(rigid)
    gaps = [abs(swing(beam_pendulum(EI)) - reference) for EI in (1e3, 1e5)]
    assert gaps[1] < 1e-4 and gaps[1] < gaps[0] / 10, gaps


def test_flexible_model_names_frames_and_refusals():
    body = FlexibleBody.cantilever_beam(1.0, 10.0, 1.0, 1, n_nodes=10)
    m = soadyn.Model()
    m.add_body("hub", None, soadyn.Joint.revolute([0, 0, 1]), None, 2.0, [0, 0, 0], [0.1, 0.1, 0.1])
    m.add_flexible_body("arm", "hub", body, soadyn.Joint.universal([0, 0, 1], [0, 1, 0]))
    m.add_body("tool", "arm:tip", soadyn.Joint.revolute([1, 0, 0]), None, 0.3, [0.05, 0, 0], [1e-3, 1e-3, 1e-3])
    assert m.dof_names == ["hub", "arm:1", "arm:2", "arm:mode1", "arm:mode2", "tool"]
    assert m.coordinate_names == ["hub", "arm:1", "arm:2", "arm:mode1", "arm:mode2", "tool"]
    assert list(m.n_modes) == [0, 2, 0] and list(m.modal) == [False, False, False, True, True, False]
    assert "arm:tip" in m.frame_names
    m.set_prescribed("arm")  # a joint name selects its hinge DOFs only
    assert list(m.prescribed) == [False, True, True, False, False, False]
    with pytest.raises(ValueError, match="'arm:mode1' is a modal coordinate"):
        m.set_prescribed("arm:mode1")
    with pytest.raises(ValueError, match="'arm:mode1' is a modal coordinate"):
        m.set_prescribed(np.ones(m.nv, dtype=bool))
    assert list(m.prescribed) == [False, True, True, False, False, False]  # refused requests change nothing
    with pytest.raises(ValueError, match="cannot be welded to flexible body 'arm'"):
        m.add_body("sensor", "arm:tip", soadyn.Joint.fixed(), None, 0.1)
    with pytest.raises(ValueError, match="cannot be welded to flexible body 'arm'"):
        m.add_body("sensor", "arm", soadyn.Joint.fixed(), None, 0.1)
    m.add_body("arm2:tip", "hub", soadyn.Joint.revolute([1, 0, 0]), None, 0.1, [0, 0, 0], [1e-3, 1e-3, 1e-3])
    with pytest.raises(ValueError, match="attachment frame 'arm2:tip' clashes"):
        m.add_flexible_body("arm2", "hub", FlexibleBody.cantilever_beam(1.0, 10.0, 1.0, 1, n_nodes=10))
    with pytest.raises(TypeError, match="must be a soadyn.FlexibleBody"):
        m.add_flexible_body("beam2", "hub", "not a body")
    assert "arm2" not in m.body_names and m.flexible_body("arm").n_modes == 2
    with pytest.raises(ValueError, match="'hub' is not a flexible body"):
        m.flexible_body("hub")
    sim = soadyn.Simulator(m, 1e-3)
    with pytest.raises(ValueError, match="modal coordinate"):
        sim.lock("arm:mode1")
    with pytest.raises(ValueError, match="modal coordinate"):
        sim.prescribe("arm:mode1", soadyn.MotionSource.constant_velocity(0.1))


def test_undeformed_flexible_body_weighs_its_nodes():
    """Total mass and centre of mass of a model follow the deformation c(eta)."""
    body = FlexibleBody.cantilever_beam(2.0, 10.0, 1.5, 2, n_nodes=20)
    m = soadyn.Model()
    m.add_flexible_body("beam", None, body)
    mass, com, _ = lumped_rigid_inertia(body)
    assert m.masses[0] == pytest.approx(mass, rel=1e-12)
    q = np.zeros(m.nq)
    np.testing.assert_allclose(soadyn.center_of_mass(m, q), com, atol=1e-12)
    q[:] = [0.01, -0.02, 0.003, 0.001]
    shifted = (body.masses @ (body.nodes + np.einsum("jrk,k->jr", body.mode_shapes[:, 3:], q))) / mass
    np.testing.assert_allclose(soadyn.center_of_mass(m, q), shifted, atol=1e-12)
    strain = 0.5 * q @ body.stiffness @ q
    gravity = -mass * np.array([0, 0, -9.81]) @ shifted
    assert soadyn.potential_energy(m, q) == pytest.approx(strain + gravity, rel=1e-12)


def test_tip_force_deflects_the_cantilever_as_euler_bernoulli():
    """A static force F at the tip node: K eta = Psi' w, tip deflection F L^3 / (3 EI)."""
    L, EI, mu, F = 2.0, 50.0, 1.5, 0.7
    body = FlexibleBody.cantilever_beam(L, EI, mu, 4, n_nodes=200)
    tip = body.attachments["tip"]
    body_wrench, modal = body.node_load(tip, np.zeros(body.n_modes), [0, 0, 0, 0, F, 0])
    np.testing.assert_allclose(body_wrench, [0, 0, F * L, 0, F, 0], atol=1e-12)  # moment about the clamp
    eta = np.linalg.solve(body.stiffness, modal)
    deflection = body.mode_shapes[tip][3:] @ eta
    expected = F * L**3 / (3 * EI)
    assert abs(deflection[1] / expected - 1) < 2e-3, deflection[1] / expected
    assert abs(deflection[0]) < 1e-15 and abs(deflection[2]) < 1e-12 * expected


def test_node_load_changes_momentum_and_energy_as_the_applied_force():
    """A free-floating flexible body pushed at its tip node by a world-fixed force: the
    rate of its linear momentum is the force, its angular momentum changes at the force's
    moment, and its energy at the force's power on the moving tip point (the modal part of
    the load does that work)."""
    body = FlexibleBody.cantilever_beam(1.0, 20.0, 2.0, 2, n_nodes=30)
    m = soadyn.Model()
    m.gravity = [0.0, 0.0, 0.0]
    m.add_flexible_body("beam", None, body, soadyn.Joint.free())
    rng = np.random.default_rng(4)
    q = soadyn.random_configuration(m, 4)
    q[7:] = rng.uniform(-0.05, 0.05, size=body.n_modes)
    v = rng.normal(size=m.nv)
    world_force = np.array([0.3, -1.1, 0.6])
    tip = body.attachments["tip"]

    def tip_point(mm, qq, vv=None):
        pose = soadyn.forward_kinematics(mm, qq)[0][0]  # (poses, velocities): the one body's 4x4 pose
        node = body.node_pose(tip, qq[7:])
        return pose[:3, :3] @ node[:3, 3] + pose[:3, 3], pose[:3, :3] @ node[:3, :3]

    point, R_node = tip_point(m, q)
    wrench, modal = body.node_load(tip, q[7:], np.concatenate([np.zeros(3), R_node.T @ world_force]))
    u = np.zeros(m.nv)
    u[6:] = modal
    qdd = soadyn.forward_dynamics(m, q, v, u, wrench.reshape(1, 6))
    rate = flow_derivative(lambda mm, qq, vv: soadyn.momentum(mm, qq, vv), m, q, v, qdd)
    scale = np.abs(soadyn.momentum(m, q, v)).max()
    np.testing.assert_allclose(rate[3:], world_force, atol=1e-6 * scale)
    np.testing.assert_allclose(rate[:3], np.cross(point, world_force), atol=1e-6 * scale)
    tip_velocity = flow_derivative(lambda mm, qq, vv: tip_point(mm, qq)[0], m, q, v, qdd)
    power = world_force @ tip_velocity
    energy_rate = flow_derivative(lambda mm, qq, vv: soadyn.kinetic_energy(mm, qq, vv) + soadyn.potential_energy(mm, qq),
                                  m, q, v, qdd)
    assert abs(energy_rate - power) <= 1e-6 * max(1.0, abs(power))
    assert abs(wrench @ v[:6] + modal @ v[6:] - power) <= 1e-6 * max(1.0, abs(power))  # virtual power


def test_only_welded_appendages_keep_their_integrals_in_the_root_frame():
    """A flexible body welded to a free root holds its modal integrals in the root's frame
    (Model.appendage_in_root_frame) while nothing sits on its nodes; a body on one of its
    nodes makes it no appendage. Cassini's two booms are such appendages, and its wheels
    and turntable leaves with constant hinge terms (Model.constant_leaf_hinge)."""
    m = soadyn.Model()
    m.add_body("bus", None, soadyn.Joint.free(), mass=10.0, inertia=[1.0, 2.0, 2.5])
    m.add_flexible_body("boom", "bus", random_flexible_body(np.random.default_rng(5)), soadyn.Joint.fixed(),
                        (np.eye(3), [0.2, 0.0, 0.0]))
    assert m.appendage_in_root_frame == [False, True]
    m.add_body("tip", "boom:a", soadyn.Joint.revolute([0.0, 0.0, 1.0]), mass=1.0, inertia=[0.1, 0.1, 0.1])
    assert m.appendage_in_root_frame == [False, False, False]
    cassini = scenes.cassini()
    flagged = lambda flags: [name for name, flag in zip(cassini.body_names, flags) if flag]
    assert flagged(cassini.appendage_in_root_frame) == ["magnetometer_boom", "plasma_wave_antenna"]
    assert flagged(cassini.constant_leaf_hinge) == ["turntable", "wheel_1", "wheel_2", "wheel_3", "wheel_4"]
