"""Named parameters (Model.parameter_names / get_parameter / set_parameter) and
soadyn.parameter_sensitivity.

Oracles: Pinocchio's ABA on a Pinocchio model built with the changed parameters
(nobody here wrote it); a soadyn model built from scratch with the changed
parameters (an independent construction path); central differences of the
dynamics for the sensitivities (1e-7 relative)."""
from __future__ import annotations

import dataclasses

import numpy as np
import pinocchio as pin
import pytest

import soadyn
import soadyn.oracles
from support.pinocchio_trees import Mapping, build_pinocchio, build_soadyn, random_specs
from support.robots import robot
from support.trees import random_state, random_tree

FD_RTOL = 1e-7


def skew(w):
    return np.array([[0.0, -w[2], w[1]], [w[2], 0.0, -w[0]], [-w[1], w[0], 0.0]])


def expm(K):
    """exp of a skew-symmetric 3x3 matrix (Rodrigues' formula)."""
    w = np.array([K[2, 1], K[0, 2], K[1, 0]])
    angle = np.linalg.norm(w)
    if angle == 0.0:
        return np.eye(3)
    return np.eye(3) + np.sin(angle) / angle * K + (1 - np.cos(angle)) / angle**2 * K @ K


# ---------------------------------------------------------------------------
# Central differences of the dynamics along each parameter direction
# ---------------------------------------------------------------------------

def directions(name: str, value):
    """(shape of the direction axes, [moved(value, t) per direction]) as parameter_sensitivity defines them."""
    if name.endswith(".mass"):
        return (), [lambda t: value + t]
    if name.endswith(".com") or name == "gravity":
        return (3,), [lambda t, k=k: value + t * np.eye(3)[k] for k in range(3)]
    if name.endswith(".inertia"):
        out = []
        for a in range(3):
            for b in range(3):
                E = np.zeros((3, 3))
                E[a, b] += 0.5
                E[b, a] += 0.5
                out.append(lambda t, E=E: value + t * E)
        return (3, 3), out
    assert name.endswith(".placement")
    R, p = value[:3, :3], value[:3, 3]

    def moved(t, k):
        H = np.eye(4)
        H[:3, :3] = R @ expm(skew(t * np.eye(3)[k])) if k < 3 else R
        H[:3, 3] = p + (t * np.eye(3)[k - 3] if k >= 3 else 0.0)
        return H
    return (6,), [lambda t, k=k: moved(t, k) for k in range(6)]


def outputs(m, q, v, u):
    if m.nloops:
        qdd, tau, wrenches = soadyn.constrained_dynamics(m, q, v, u)
        return qdd, tau, wrenches
    return soadyn.hybrid_dynamics(m, q, v, u)


def central_differences(m, q, v, u, name):
    """Fourth-order central differences (f(-2h) - 8 f(-h) + 8 f(h) - f(2h)) / 12h of every output of the
    dynamics along each direction of `name`."""
    value = m.get_parameter(name)
    shape, moves = directions(name, value)
    # Steps relative to the value for masses and inertias (a 15 g finger, a 0.03 kg m^2 inertia).
    h = 1e-3 * np.max(np.abs(value)) if name.endswith((".mass", ".inertia")) else 1e-4
    work = m.copy()
    columns = []
    for move in moves:
        at = {}
        for k in (-2, -1, 1, 2):
            work.set_parameter(name, move(k * h))
            at[k] = outputs(work, q, v, u)
        columns.append([(at[-2][i] - 8 * at[-1][i] + 8 * at[1][i] - at[2][i]) / (12 * h)
                        for i in range(len(at[1]))])
    return [np.stack([c[k] for c in columns], axis=-1).reshape(columns[0][k].shape + shape)
            for k in range(len(columns[0]))]


def check_against_differences(m, q, v, u, names, errors):
    result = soadyn.parameter_sensitivity(m, q, v, u, names)
    assert list(result) == list(names)
    for name in names:
        fd = central_differences(m, q, v, u, name)
        assert len(result[name]) == len(fd) == (3 if m.nloops else 2)
        for label, ad, ref in zip(("qdd", "tau", "loop wrenches"), result[name], fd):
            assert ad.shape == ref.shape, (name, label, ad.shape, ref.shape)
            assert np.all(np.isfinite(ad))
            scale = max(np.max(np.abs(ref)), 1.0)
            err = np.max(np.abs(ad - ref)) / scale
            errors.append(err)
            assert err <= FD_RTOL, f"{name}: d{label}/dp differs from central differences by {err:.2e} relative"


# ---------------------------------------------------------------------------
# Names, round trips, construction
# ---------------------------------------------------------------------------

def test_parameter_names_cover_every_body_and_gravity():
    m, _ = random_tree(3, 6)
    expected = [f"{b}.{p}" for b in m.body_names for p in ("mass", "com", "inertia", "placement")] + ["gravity"]
    assert m.parameter_names == expected


def test_get_set_round_trip_and_change():
    m, _ = random_tree(4, 8)
    for name in m.parameter_names:
        value = m.get_parameter(name)
        m.set_parameter(name, value)
        assert np.array_equal(m.get_parameter(name), value), name
    m.set_parameter("b2.mass", 2.5)
    assert m.get_parameter("b2.mass") == 2.5
    m.set_parameter("b2.com", [0.1, -0.2, 0.3])
    assert np.array_equal(m.get_parameter("b2.com"), [0.1, -0.2, 0.3])
    I = np.diag([0.3, 0.4, 0.5])
    m.set_parameter("b2.inertia", I)
    assert np.array_equal(m.get_parameter("b2.inertia"), I)
    R = expm(skew([0.2, -0.1, 0.4]))
    m.set_parameter("b2.placement", (R, [1.0, 2.0, 3.0]))
    H = m.get_parameter("b2.placement")
    assert np.allclose(H[:3, :3], R, rtol=0, atol=1e-15) and np.array_equal(H[:3, 3], [1.0, 2.0, 3.0])
    assert np.array_equal(H[3], [0, 0, 0, 1])
    m.set_parameter("gravity", [0.0, -9.81, 0.0])
    assert np.array_equal(m.gravity, [0.0, -9.81, 0.0])
    assert np.array_equal(m.get_parameter("gravity"), [0.0, -9.81, 0.0])


def changed_specs(specs, rng):
    """The specs with new mass, com, inertia and placement on two bodies."""
    out = list(specs)
    for i in (1, len(specs) - 1):
        s = out[i]
        turn = expm(skew(rng.normal(size=3)))  # a rotated, scaled physical inertia stays physical
        out[i] = dataclasses.replace(s, mass=s.mass * 1.7, com=s.com + rng.uniform(-0.1, 0.1, 3),
                                     inertia=1.3 * turn @ s.inertia @ turn.T,
                                     rotation=s.rotation @ expm(skew(rng.normal(size=3) * 0.3)),
                                     translation=s.translation + rng.uniform(-0.2, 0.2, 3))
    return out


def apply_specs(m, specs):
    for s in specs:
        m.set_parameter(f"{s.name}.mass", s.mass)
        m.set_parameter(f"{s.name}.com", s.com)
        m.set_parameter(f"{s.name}.inertia", s.inertia)
        m.set_parameter(f"{s.name}.placement", (s.rotation, s.translation))


@pytest.mark.parametrize("seed,floating", [(0, True), (1, False), (2, True), (5, False)])
def test_set_parameter_equals_construction_and_pinocchio(seed, floating):
    """set_parameter, then hybrid dynamics under a mixed mask, equals a model built with the new parameters;
    forward dynamics equals Pinocchio's ABA on a Pinocchio model built with them."""
    rng = np.random.default_rng(seed + 40)
    specs = random_specs(seed, floating)
    new = changed_specs(specs, rng)
    m = build_soadyn(specs)
    apply_specs(m, new)
    m.set_parameter("gravity", [1.0, -2.0, -9.0])
    fresh = build_soadyn(new)
    fresh.gravity = [1.0, -2.0, -9.0]
    q = soadyn.random_configuration(m, seed)
    v, u = rng.normal(size=m.nv), rng.normal(size=m.nv)
    # Pinocchio: all regular (ABA).
    model = build_pinocchio(new, [1.0, -2.0, -9.0])
    mapping = Mapping(fresh, model, new)
    ours = soadyn.forward_dynamics(m, q, v, u)
    theirs = pin.aba(model, model.createData(), mapping.q(q), mapping.v(v), mapping.v(u))
    assert np.max(np.abs(mapping.v(ours) - theirs)) <= 1e-10 * max(1.0, np.max(np.abs(theirs)))
    before = soadyn.forward_dynamics(build_soadyn(specs), q, v, u)
    assert np.max(np.abs(before - ours)) > 1e-3  # the change matters
    # A fresh construction, mixed mask.
    mask = rng.uniform(size=m.nv) < 0.5
    for model_ in (m, fresh):
        model_.set_prescribed(mask, True)
    a, b = soadyn.hybrid_dynamics(m, q, v, u), soadyn.hybrid_dynamics(fresh, q, v, u)
    for x, y in zip(a, b):
        assert np.max(np.abs(x - y)) <= 1e-12 * max(1.0, np.max(np.abs(y)))


@pytest.mark.parametrize("name", ["ur5", "panda"])
def test_robot_mass_change_against_pinocchio(name):
    """A URDF robot: each moving body's parameters as read equal Pinocchio's inertias and joint placements
    (welded links merged in both), and after set_parameter the forward dynamics equal Pinocchio's ABA with
    the same inertias and placements changed."""
    path, floating = robot(name)
    m = soadyn.load_urdf(str(path), floating_base=floating)
    oracle = soadyn.oracles.PinocchioOracle(m, str(path), floating)
    model = oracle.model
    rng = np.random.default_rng(7)
    for i, body in enumerate(m.body_names):
        jid = model.getJointId(m.joint_names[i])
        inertia = model.inertias[jid]
        assert abs(m.get_parameter(f"{body}.mass") - inertia.mass) <= 1e-12 * max(1.0, inertia.mass)
        assert np.allclose(m.get_parameter(f"{body}.com"), inertia.lever, rtol=0, atol=1e-12)
        assert np.allclose(m.get_parameter(f"{body}.inertia"), inertia.inertia, rtol=0, atol=1e-12)
        H = m.get_parameter(f"{body}.placement")
        assert np.allclose(H, model.jointPlacements[jid].homogeneous, rtol=0, atol=1e-12)
        mass = inertia.mass * rng.uniform(0.5, 2.0)
        com = inertia.lever + rng.uniform(-0.05, 0.05, 3)
        I = inertia.inertia * rng.uniform(0.5, 2.0)
        m.set_parameter(f"{body}.mass", mass)
        m.set_parameter(f"{body}.com", com)
        m.set_parameter(f"{body}.inertia", I)
        model.inertias[jid] = pin.Inertia(mass, com, I)
        X = model.jointPlacements[jid]
        R, p = X.rotation @ expm(skew(rng.normal(size=3) * 0.1)), X.translation + rng.uniform(-0.05, 0.05, 3)
        m.set_parameter(f"{body}.placement", (R, p))
        model.jointPlacements[jid] = pin.SE3(R, p)
    oracle.data = model.createData()
    q = soadyn.random_configuration(m, 3)
    v, tau = rng.normal(size=m.nv), rng.normal(size=m.nv)
    ours = soadyn.forward_dynamics(m, q, v, tau)
    theirs = oracle.forward_dynamics(q, v, tau)
    assert np.max(np.abs(ours - theirs)) <= 1e-9 * max(1.0, np.max(np.abs(theirs)))


# ---------------------------------------------------------------------------
# Hostile input
# ---------------------------------------------------------------------------

def test_hostile_input_is_refused_by_name_and_changes_nothing():
    m, _ = random_tree(6, 5)
    before = {n: m.get_parameter(n) for n in m.parameter_names}
    with pytest.raises(soadyn.ParameterError, match="unknown parameter 'b9.mass'"):
        m.set_parameter("b9.mass", 1.0)
    with pytest.raises(soadyn.ParameterError, match="unknown parameter 'b1.stiffness'"):
        m.get_parameter("b1.stiffness")
    with pytest.raises(TypeError, match="parameter name must be a str"):
        m.set_parameter(3, 1.0)
    with pytest.raises(soadyn.ParameterError, match=r"'b1.com': expected shape \(3,\), got \(4,\)"):
        m.set_parameter("b1.com", [0.0, 0.0, 0.0, 0.0])
    with pytest.raises(soadyn.ParameterError, match=r"'b1.placement': expected shape \(4, 4\), got \(3, 3\)"):
        m.set_parameter("b1.placement", np.eye(3))
    with pytest.raises(soadyn.ParameterError, match=r"'b1.mass': expected shape \(\), got \(1,\)"):
        m.set_parameter("b1.mass", [1.0])
    with pytest.raises(TypeError):
        m.set_parameter("b1.mass", "heavy")
    with pytest.raises(soadyn.ParameterError, match="'b1.mass': value is not finite"):
        m.set_parameter("b1.mass", float("nan"))
    with pytest.raises(soadyn.ParameterError, match="'gravity': value is not finite"):
        m.set_parameter("gravity", [0.0, np.inf, 0.0])
    with pytest.raises(soadyn.ParameterError, match="'b1.mass': mass -1 is negative"):
        m.set_parameter("b1.mass", -1.0)
    with pytest.raises(soadyn.NonphysicalInertiaError, match="'b1.mass': massless body with nonzero inertia"):
        m.set_parameter("b1.mass", 0.0)
    with pytest.raises(soadyn.ParameterError, match="'b1.inertia': inertia is not symmetric"):
        m.set_parameter("b1.inertia", [[1.0, 0.1, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
    with pytest.raises(soadyn.NonphysicalInertiaError, match="'b1.inertia'.*triangle inequality"):
        m.set_parameter("b1.inertia", np.diag([1.0, 1.0, 3.0]))
    with pytest.raises(soadyn.NonphysicalInertiaError, match="'b1.inertia'.*not positive semidefinite"):
        m.set_parameter("b1.inertia", np.diag([1.0, 1.0, -0.5]))
    with pytest.raises(soadyn.ParameterError, match="'b1.placement': rotation is not a proper rotation"):
        m.set_parameter("b1.placement", np.diag([1.0, 1.0, -1.0, 1.0]))
    with pytest.raises(soadyn.ParameterError, match="'b1.placement': rotation is not a proper rotation"):
        m.set_parameter("b1.placement", (2 * np.eye(3), np.zeros(3)))
    H = np.eye(4)
    H[3, 0] = 1.0
    with pytest.raises(soadyn.ParameterError, match=r"'b1.placement': the last row .* must be \(0, 0, 0, 1\)"):
        m.set_parameter("b1.placement", H)
    with pytest.raises(soadyn.ParameterError, match="'b1.com'.*not finite"):
        m.set_parameter("b1.com", [1e300, 1e300, 1e300])
    after = {n: m.get_parameter(n) for n in m.parameter_names}
    for n in before:
        assert np.array_equal(before[n], after[n]), n


def test_welded_parts_and_flexible_bodies():
    path, floating = robot("panda")
    m = soadyn.load_urdf(str(path), floating_base=floating)
    hand = "panda_hand"
    assert hand in m.frame_names and hand not in m.body_names
    with pytest.raises(soadyn.ParameterError, match="'panda_hand' is welded by a fixed joint to 'panda_link7'"):
        m.get_parameter("panda_hand.mass")
    from support.flexible_trees import random_flexible_tree
    fm = random_flexible_tree(1, n_bodies=4)[0]
    names = fm.parameter_names
    flex_bodies = [b for b in fm.body_names if f"{b}.mass" not in names]
    assert flex_bodies, "the flexible tree has flexible bodies"
    for b in flex_bodies:
        assert f"{b}.placement" in names
        with pytest.raises(soadyn.ParameterError, match=f"flexible body '{b}' has only a placement parameter"):
            fm.get_parameter(f"{b}.mass")


@pytest.mark.parametrize("masked", [False, True], ids=["regular", "mixed"])
def test_sensitivity_flexible_tree(masked):
    """Models with flexible bodies: gravity, the flexible bodies' placements and the rigid bodies'
    parameters, against central differences."""
    from support.flexible_trees import random_flexible_tree
    m = random_flexible_tree(1, n_bodies=5)[0]
    rng = np.random.default_rng(3)
    q = soadyn.integrate(m, soadyn.neutral_configuration(m), 0.3 * rng.normal(size=m.nv), 1.0)
    v, u = rng.normal(size=m.nv), rng.normal(size=m.nv)
    if masked:
        m.set_prescribed((rng.random(m.nv) < 0.4) & ~m.modal)
    flexible = [b for b, n in zip(m.body_names, m.n_modes) if n > 0]
    rigid = [b for b, n in zip(m.body_names, m.n_modes) if n == 0]
    names = ["gravity"] + [f"{b}.placement" for b in flexible] + [f"{rigid[-1]}.mass", f"{rigid[-1]}.com"]
    errors = []
    check_against_differences(m, q, v, u, names, errors)
    assert len(errors) == 2 * len(names)


def test_sensitivity_hostile_input():
    m, _ = random_tree(2, 4)
    q, v, rng = random_state(m, 2)
    with pytest.raises(soadyn.ParameterError, match="unknown parameter 'b7.mass'"):
        soadyn.parameter_sensitivity(m, q, v, np.zeros(m.nv), ["b0.mass", "b7.mass"])
    with pytest.raises(ValueError, match="u"):
        soadyn.parameter_sensitivity(m, q, v, np.zeros(m.nv + 1), ["b0.mass"])
    u = np.zeros(m.nv)
    u[0] = np.nan
    with pytest.raises(ValueError):
        soadyn.parameter_sensitivity(m, q, v, u, ["b0.mass"])


# ---------------------------------------------------------------------------
# Sensitivities against central differences
# ---------------------------------------------------------------------------

@pytest.mark.parametrize("seed,floating", [(0, True), (1, False), (2, True)])
def test_sensitivity_random_trees(seed, floating):
    m, _ = random_tree(seed, 7, floating=floating)
    q, v, rng = random_state(m, seed)
    u = rng.normal(size=m.nv)
    errors = []
    check_against_differences(m, q, v, u, m.parameter_names, errors)
    assert max(errors) > 0.0


@pytest.mark.parametrize("seed", [3, 4])
def test_sensitivity_hybrid_mask(seed):
    m, _ = random_tree(seed, 7)
    q, v, rng = random_state(m, seed)
    m.set_prescribed(rng.uniform(size=m.nv) < 0.5, True)
    assert 0 < int(np.sum(m.prescribed)) < m.nv
    u = rng.normal(size=m.nv)
    check_against_differences(m, q, v, u, m.parameter_names, [])


@pytest.mark.parametrize("name", ["ur5", "panda", "solo12"])
def test_sensitivity_robots(name):
    path, floating = robot(name)
    m = soadyn.load_urdf(str(path), floating_base=floating)
    rng = np.random.default_rng(11)
    q = soadyn.random_configuration(m, 11)
    v, u = rng.normal(size=m.nv), rng.normal(size=m.nv)
    picks = [m.body_names[k] for k in (0, len(m.body_names) // 2, len(m.body_names) - 1)]
    names = [f"{b}.{p}" for b in picks for p in ("mass", "com", "inertia", "placement")] + ["gravity"]
    check_against_differences(m, q, v, u, names, [])


@pytest.mark.parametrize("prescribe_crank", [False, True])
def test_sensitivity_four_bar(prescribe_crank):
    m = soadyn.scenes.four_bar()
    q, v = soadyn.scenes.four_bar_state(0.7, 1.3)
    # The scene's links are planar rods (a zero principal moment): central differences of their inertia
    # would leave the physical set, so the links are given some thickness first.
    for body in m.body_names:
        I = m.get_parameter(f"{body}.inertia")
        m.set_parameter(f"{body}.inertia", I + 0.05 * np.max(np.diag(I)) * np.eye(3))
    u = np.zeros(m.nv)
    if prescribe_crank:
        m.set_prescribed([m.dof_names[0]], True)
        u[0] = 0.4
    else:
        u[0] = 2.0
    # Placements are left out: turning a pin's axis out of the plane changes the rank of the redundant
    # closure equations (5 equations of rank 2), where the dynamics are not differentiable.
    names = [n for n in m.parameter_names if not n.endswith(".placement")]
    check_against_differences(m, q, v, u, names, [])
    dqdd, dtau, dwrench = soadyn.parameter_sensitivity(m, q, v, u, ["gravity"])["gravity"]
    assert dqdd.shape == (m.nv, 3) and dtau.shape == (m.nv, 3) and dwrench.shape == (m.nloops, 6, 3)
