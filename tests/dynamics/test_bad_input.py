"""Bad input raises a clear exception naming the item at fault; nothing crashes."""
import numpy as np
import pytest

import soadyn


@pytest.fixture
def model():
    m = soadyn.Model()
    m.add_body("base", None, soadyn.Joint.free(), mass=1.0, inertia=[1, 1, 1])
    m.add_body("elbow", "base", soadyn.Joint.revolute([0, 0, 1]), mass=1.0, inertia=[1, 1, 1])
    return m


@pytest.fixture
def state(model):
    return soadyn.neutral_configuration(model), np.zeros(model.nv)


def add(m, **kw):
    args = dict(name="new", parent=None, joint=soadyn.Joint.free(), mass=1.0, inertia=[1, 1, 1])
    args.update(kw)
    return m.add_body(args.pop("name"), args.pop("parent"), args.pop("joint"), **args)


@pytest.mark.parametrize("fn", [soadyn.forward_dynamics, soadyn.inverse_dynamics, soadyn.hybrid_dynamics])
def test_wrong_length_names_argument_and_expected_size(model, state, fn):
    q, v = state
    with pytest.raises(ValueError, match=r"q has shape \(6,\), expected \(8,\)"):
        fn(model, q[:-2], v, v)
    with pytest.raises(ValueError, match=r"v has shape \(7,\), expected \(7,\)|v has shape \(6,\), expected \(7,\)"):
        fn(model, q, v[:-1], v)
    with pytest.raises(ValueError, match=r"has shape \(7, 1\)"):
        fn(model, q, v, v[:, None])


@pytest.mark.parametrize("bad", [np.zeros(8, dtype=complex), np.array(["a"] * 8), np.zeros(8, dtype=bool), None, "q"])
def test_wrong_dtype(model, state, bad):
    _, v = state
    with pytest.raises(TypeError, match="q must"):
        soadyn.forward_dynamics(model, bad, v, v)


def test_integer_and_list_inputs_are_accepted(model, state):
    q, v = state
    out = soadyn.forward_dynamics(model, list(q), [0] * model.nv, np.zeros(model.nv, dtype=np.int32))
    assert out.dtype == np.float64 and np.all(np.isfinite(out))


@pytest.mark.parametrize("value, word", [(np.nan, "NaN"), (np.inf, "infinite"), (-np.inf, "infinite")])
def test_non_finite_entries_name_the_dof(model, state, value, word):
    q, v = state
    tau = v.copy()
    tau[6] = value
    with pytest.raises(ValueError, match=rf"tau\[6\] \('elbow'\) is {word}"):
        soadyn.forward_dynamics(model, q, v, tau)
    q2 = q.copy()
    q2[1] = value
    with pytest.raises(ValueError, match=rf"q\[1\] \('base:py'\) is {word}"):
        soadyn.mass_matrix(model, q2)


def test_quaternion_off_unit_norm_names_the_joint(model, state):
    q, v = state
    q[3:7] *= 1 + 1e-5
    with pytest.raises(ValueError, match="quaternion of joint 'base' has norm"):
        soadyn.forward_dynamics(model, q, v, v)
    q[3:7] /= 1 + 1e-5
    q[3:7] *= 1 + 0.5 * soadyn.QUATERNION_TOLERANCE  # within the documented tolerance
    soadyn.forward_dynamics(model, q, v, v)


def test_external_wrench_shape_and_values(model, state):
    q, v = state
    with pytest.raises(ValueError, match=r"f_ext must have shape \(2, 6\)"):
        soadyn.inverse_dynamics(model, q, v, v, f_ext=np.zeros((2, 3)))
    f = np.zeros((2, 6))
    f[1, 4] = np.nan
    with pytest.raises(ValueError, match=r"f_ext\[1, 4\] \('elbow'\) is NaN"):
        soadyn.inverse_dynamics(model, q, v, v, f_ext=f)


def test_singular_articulated_inertia_names_the_dof(model, state):
    add(model, name="ghost", parent="elbow", joint=soadyn.Joint.revolute([1, 0, 0]), mass=0.0, inertia=np.zeros(3))
    q = soadyn.neutral_configuration(model)
    v = np.zeros(model.nv)
    with pytest.raises(soadyn.DynamicsError, match="regular DOF 'ghost' is singular"):
        soadyn.forward_dynamics(model, q, v, v)
    with pytest.raises(soadyn.DynamicsError, match="'ghost'"):
        soadyn.hybrid_dynamics(model, q, v, v)
    model.set_prescribed("ghost")  # prescribed, the massless body is fine
    soadyn.hybrid_dynamics(model, q, v, v)


def test_zero_mass_free_floating_body_is_singular():
    m = soadyn.Model()
    m.add_body("dust", None, soadyn.Joint.free(), mass=0.0)
    with pytest.raises(soadyn.DynamicsError, match="dust:"):
        soadyn.forward_dynamics(m, soadyn.neutral_configuration(m), np.zeros(6), np.zeros(6))


@pytest.mark.parametrize(
    "mass, inertia, com, dof",
    [
        # A point mass: nothing resists a rotation about its origin.
        (2.0, [0.0, 0.0, 0.0], [0.0, 0.0, 0.0], "rod:wx"),
        # A thin rod along z: no inertia about its axis, the third rotation.
        (2.0, [1.0, 1.0, 0.0], [0.0, 0.0, 0.0], "rod:wz"),
        # The same rod along y with its centre of mass off the origin: the rotation about
        # y through the centre of mass is free, and the free joint's DOFs reach it first
        # at the x translation (the pivot order of P = L D L', rotations first).
        (2.0, [1.0, 0.0, 1.0], [0.0, 0.0, 0.5], "rod:vx"),
    ],
)
def test_singular_free_body_names_its_first_singular_dof(mass, inertia, com, dof):
    m = soadyn.Model()
    m.add_body("rod", None, soadyn.Joint.free(), mass=mass, inertia=inertia, com=com)
    q = soadyn.neutral_configuration(m)
    for call in (lambda: soadyn.forward_dynamics(m, q, np.zeros(6), np.zeros(6)),
                 lambda: soadyn.hybrid_dynamics(m, q, np.zeros(6), np.zeros(6))):
        with pytest.raises(soadyn.DynamicsError, match=f"'{dof}' is singular"):
            call()


@pytest.mark.parametrize(
    "inertia, dof",
    [
        # A point mass on the joint's centre: neither axis moves anything.
        ([0.0, 0.0, 0.0], "pendulum:1"),
        # A thin rod along y: no inertia about the second axis (y at zero angles).
        ([1.0, 0.0, 1.0], "pendulum:2"),
    ],
)
def test_singular_universal_joint_names_its_first_singular_dof(inertia, dof):
    m = soadyn.Model()
    m.add_body("base", None, soadyn.Joint.revolute([0, 0, 1]), mass=5.0, inertia=[1.0, 1.0, 1.0])
    m.add_body("pendulum", "base", soadyn.Joint.universal([1, 0, 0], [0, 1, 0]), mass=2.0, inertia=inertia)
    q = soadyn.neutral_configuration(m)
    zeros = np.zeros(m.nv)
    for call in (lambda: soadyn.forward_dynamics(m, q, zeros, zeros),
                 lambda: soadyn.hybrid_dynamics(m, q, zeros, zeros)):
        with pytest.raises(soadyn.DynamicsError, match=f"'{dof}' is singular"):
            call()


@pytest.mark.parametrize(
    "kw, message",
    [
        (dict(mass=-1.0), "body 'new': mass -1 is negative"),
        (dict(mass=np.nan), "body 'new': mass is not finite"),
        (dict(inertia=[1, 1, 3]), "body 'new': principal moments .* violate the triangle inequality"),
        (dict(inertia=[-1, 1, 1]), "body 'new': inertia is not positive semidefinite"),
        (dict(inertia=[[1, 0.5, 0], [0, 1, 0], [0, 0, 1]]), "body 'new': inertia is not symmetric"),
        (dict(inertia=np.eye(2)), "body 'new': inertia must be 3x3"),
        (dict(com=[0, 0]), "body 'new': com must have 3 components"),
        (dict(com=[0, np.inf, 0]), "body 'new': centre of mass is not finite"),
        (dict(mass=0.0, inertia=[1, 1, 1]), "body 'new': massless body with nonzero inertia"),
        (dict(name="base"), "duplicate body name 'base'"),
        (dict(name="world"), "reserved"),
        (dict(parent="nowhere"), "body 'new': parent 'nowhere' does not exist"),
        (dict(parent=5), "body 'new': parent index 5 does not exist"),
        (dict(joint=soadyn.Joint.revolute([0, 0, 0])), "joint 'new': axis is zero"),
        (dict(joint=soadyn.Joint.prismatic([np.nan, 0, 0])), "joint 'new': axis is not finite"),
        (dict(joint=soadyn.Joint.universal([1, 0, 0], [2, 0, 0])), "joint 'new': universal joint axes are parallel"),
        (dict(joint=soadyn.Joint.revolute([0, 0, 1], name="elbow")), "duplicate joint name 'elbow'"),
        (dict(placement=(np.ones((3, 3)), [0, 0, 0])), "body 'new': placement rotation is not a proper rotation"),
        (dict(placement=(-np.eye(3), [0, 0, 0])), "body 'new': placement rotation is not a proper rotation"),
        (dict(placement=np.zeros(5)), "body 'new': placement must be"),
    ],
)
def test_bad_bodies_are_refused_by_name(model, kw, message):
    with pytest.raises(ValueError, match=message):
        add(model, **kw)
    assert model.nbodies == 2  # nothing half-added


def test_bad_joint_argument_type(model):
    with pytest.raises(TypeError, match="body 'new': joint must be a soadyn.Joint"):
        add(model, joint="revolute")


@pytest.mark.parametrize(
    "selector, error, message",
    [
        ("nope", ValueError, "unknown DOF or joint 'nope'"),
        (42, ValueError, "DOF index 42 is out of range"),
        (np.ones(3, dtype=bool), ValueError, r"prescribed mask has shape \(3,\), expected \(7,\)"),
        ([1.5], TypeError, "neither a name nor an index"),
    ],
)
def test_bad_prescribed_selectors(model, selector, error, message):
    with pytest.raises(error, match=message):
        model.set_prescribed(selector)
    assert not model.prescribed.any()


def test_bad_gravity(model):
    with pytest.raises(ValueError, match=r"gravity\[2\] \('z'\) is NaN"):
        model.gravity = [0, 0, np.nan]
    with pytest.raises(ValueError, match="gravity has shape"):
        model.gravity = [0, 0]


def test_overflowing_prescribed_torque_names_its_dof():
    """A drive whose torque overflows while every acceleration stays finite (the driven turntable is a
    Newton-Euler root beside a regular pendulum): the error names the driven DOF."""
    m = soadyn.Model()
    m.add_body("turntable", None, soadyn.Joint.revolute([0, 0, 1]), mass=1.0, inertia=[1e10, 1e10, 1e10])
    m.add_body("pendulum", None, soadyn.Joint.revolute([1, 0, 0]), mass=1.0, com=[0, 0, -0.5],
               inertia=[0.1, 0.1, 0.1])
    m.set_prescribed("turntable")
    q, v = soadyn.neutral_configuration(m), np.zeros(m.nv)
    with pytest.raises(soadyn.DynamicsError, match="the result for DOF 'turntable' is not finite"):
        soadyn.hybrid_dynamics(m, q, v, np.array([1e300, 0.0]))
    # A moderate drive: the torque is the turntable's axial inertia times its acceleration.
    qdd, tau = soadyn.hybrid_dynamics(m, q, v, np.array([2.0, 0.0]))
    assert qdd[0] == 2.0 and tau[0] == pytest.approx(2e10, rel=1e-12) and np.isfinite(qdd[1])
