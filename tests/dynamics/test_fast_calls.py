"""forward_dynamics, inverse_dynamics, hybrid_dynamics and constrained_dynamics
have a fast entry for the call a stepping loop makes, f(model, q, v, x) with
float64 arrays; every other call goes to the general function. Both must give
the same numbers and the same errors."""
import inspect
import sys

import numpy as np
import pytest

import soadyn
from soadyn import _soadyn

CALLS = [soadyn.forward_dynamics, soadyn.inverse_dynamics, soadyn.hybrid_dynamics]


@pytest.fixture
def model():
    # A free base (quaternion in q), a ball joint and revolute joints, half of them prescribed.
    m = soadyn.Model()
    m.add_body("base", None, soadyn.Joint.free(), mass=3.0, inertia=[0.3, 0.4, 0.5], com=[0.1, 0, 0])
    m.add_body("shoulder", "base", soadyn.Joint.spherical(), placement=[0, 0, 0.4], mass=1.0,
               inertia=[0.1, 0.1, 0.05], com=[0, 0, 0.2])
    m.add_body("elbow", "shoulder", soadyn.Joint.revolute([0, 1, 0]), placement=[0, 0, 0.5], mass=0.7,
               inertia=[0.05, 0.05, 0.01], com=[0, 0, 0.2])
    m.add_body("wrist", "elbow", soadyn.Joint.revolute([1, 0, 0]), placement=[0, 0, 0.4], mass=0.3,
               inertia=[0.01, 0.01, 0.01], com=[0, 0.05, 0])
    m.set_prescribed(["elbow", "shoulder"])
    return m


@pytest.fixture
def state(model):
    rng = np.random.default_rng(7)
    q = soadyn.random_configuration(model, 3)
    return q, rng.uniform(-1, 1, model.nv), rng.uniform(-2, 2, model.nv)


def general(fn):
    return fn.__self__  # the pybind11 function the fast entry hands other calls to


def as_tuple(result):
    return result if isinstance(result, tuple) else (result,)


@pytest.mark.parametrize("fn", CALLS)
def test_fast_and_general_calls_agree_bit_for_bit(model, state, fn):
    fast = as_tuple(fn(model, *state))
    for other in (general(fn)(model, *state), fn(model, *state, None), fn(model, *state[:2], state[2], f_ext=None)):
        for a, b in zip(fast, as_tuple(other)):
            assert a.dtype == np.float64 and a.shape == (model.nv,)
            np.testing.assert_array_equal(a, b)


@pytest.mark.parametrize("fn", CALLS)
def test_other_layouts_and_types_take_the_general_path_with_the_same_result(model, state, fn):
    q, v, x = state
    expected = as_tuple(fn(model, q, v, x))
    strided = np.empty((model.nv, 2))
    strided[:, 0] = v
    for args in ((q, strided[:, 0], x), (q, v, x.astype(">f8")), (list(q), list(v), tuple(x)),
                 (q.astype(np.longdouble), v, x)):
        for a, b in zip(as_tuple(fn(model, *args)), expected):
            np.testing.assert_array_equal(a, b)


@pytest.mark.parametrize("fn", CALLS)
def test_errors_are_the_general_functions(model, state, fn):
    q, v, x = state
    bad = x.copy()
    bad[6] = np.nan
    name = {"forward_dynamics": "tau", "inverse_dynamics": "qdd", "hybrid_dynamics": "u"}[fn.__name__]
    with pytest.raises(ValueError, match=rf"{name}\[6\] \('shoulder:wx'\) is NaN"):
        fn(model, q, v, bad)
    q_off = q.copy()
    q_off[3:7] *= 1.1
    with pytest.raises(ValueError, match="quaternion of joint 'base'"):
        fn(model, q_off, v, x)
    with pytest.raises(ValueError, match=r"v has shape \(10,\), expected \(11,\)"):
        fn(model, q, v[:-1], x)
    with pytest.raises(TypeError):
        fn("not a model", q, v, x)
    with pytest.raises(TypeError):
        fn(model, q, v)


def test_singular_inertia_raises_through_the_fast_entry():
    m = soadyn.Model()
    m.add_body("massless", None, soadyn.Joint.revolute([0, 0, 1]), mass=0.0, inertia=[0, 0, 0])
    q, v = soadyn.neutral_configuration(m), np.zeros(1)
    for fn in (soadyn.forward_dynamics, soadyn.hybrid_dynamics):
        with pytest.raises(soadyn.DynamicsError, match="DOF 'massless'"):
            fn(m, q, v, np.ones(1))


def test_a_plain_extension_model_takes_the_fast_path_too():
    plain = _soadyn._Model()  # not the Python subclass soadyn.Model
    plain._add_body("wheel", "", soadyn.Joint.revolute([0, 0, 1]), np.eye(3), np.zeros(3), 2.0, np.zeros(3),
                    np.diag([2.5, 2.5, 4.0]))
    out = soadyn.forward_dynamics(plain, np.zeros(1), np.zeros(1), np.ones(1))
    np.testing.assert_allclose(out, [0.25], rtol=1e-15)  # tau / I_zz


@pytest.mark.parametrize("fn", CALLS)
def test_no_references_leak(model, state, fn):
    q, v, x = state
    before = [sys.getrefcount(o) for o in (model, q, v, x)]
    for _ in range(1000):
        fn(model, q, v, x)
        fn(model, q, v, x, None)
    assert [sys.getrefcount(o) for o in (model, q, v, x)] == before


@pytest.mark.parametrize("fn, params", [
    (soadyn.forward_dynamics, ["model", "q", "v", "tau", "f_ext"]),
    (soadyn.inverse_dynamics, ["model", "q", "v", "qdd", "f_ext"]),
    (soadyn.hybrid_dynamics, ["model", "q", "v", "u", "f_ext", "joint_wrenches"]),
    (soadyn.constrained_dynamics, ["model", "q", "v", "u", "f_ext", "joint_wrenches"]),
])
def test_signature_and_documentation(fn, params):
    assert list(inspect.signature(fn).parameters) == params
    assert fn.__doc__ == general(fn).__doc__.split("\n\n", 1)[1]
    assert fn.__module__ == "soadyn._soadyn"


# constrained_dynamics: the same fast entry, on a model with loops (the fixture's tree with the wrist's tip
# held to the world by a point loop, and the wrist tied to the base by a distance loop).

@pytest.fixture
def loop_model(model):
    model.add_loop("tip", "wrist", None, "point", placement_a=[0, 0, 0.2])
    model.add_loop("strut", "wrist", "base", "distance", placement_a=[0.1, 0, 0.1], placement_b=[0.2, 0.1, 0])
    return model


def test_constrained_fast_and_general_calls_agree_bit_for_bit(loop_model, state):
    fn = soadyn.constrained_dynamics
    fast = fn(loop_model, *state)
    assert [a.shape for a in fast] == [(loop_model.nv,), (loop_model.nv,), (2, 6)]
    assert np.abs(fast[2]).max() > 0  # the loops carry force
    for other in (general(fn)(loop_model, *state), fn(loop_model, *state, None),
                  fn(loop_model, *state[:2], state[2], f_ext=None), fn(loop_model, *state, joint_wrenches=True)[:3]):
        for a, b in zip(fast, other):
            np.testing.assert_array_equal(a, b)


def test_constrained_errors_are_the_general_functions(loop_model, state):
    q, v, u = state
    bad = u.copy()
    bad[6] = np.nan
    with pytest.raises(ValueError, match=r"u\[6\] \('shoulder:wx'\) is NaN"):
        soadyn.constrained_dynamics(loop_model, q, v, bad)
    with pytest.raises(ValueError, match=r"v has shape \(10,\), expected \(11,\)"):
        soadyn.constrained_dynamics(loop_model, q, v[:-1], u)
    huge = v.copy()
    huge[-1] = 1e200  # finite input that overflows: the general function names the DOF
    with pytest.raises(soadyn.DynamicsError, match="constrained_dynamics"):
        soadyn.constrained_dynamics(loop_model, q, huge, u)


def test_constrained_no_references_leak(loop_model, state):
    q, v, u = state
    before = [sys.getrefcount(o) for o in (loop_model, q, v, u)]
    for _ in range(1000):
        soadyn.constrained_dynamics(loop_model, q, v, u)
    assert [sys.getrefcount(o) for o in (loop_model, q, v, u)] == before


# pybind11's private API (bindings/pybind11_private.hpp): what the fast entry reads must be what numpy and
# pybind11's public API say, and the pybind11 it was built with must lie in the range pyproject.toml allows.

def _pybind11_requirement():
    import pathlib
    import re
    text = (pathlib.Path(__file__).resolve().parents[2] / "pyproject.toml").read_text()
    match = re.search(r'"pybind11>=([0-9.]+),<([0-9]+)"', text)
    assert match, "pyproject.toml must bound pybind11 as \"pybind11>=X.Y,<N\""
    return tuple(int(k) for k in match.group(1).split(".")), int(match.group(2))


def test_built_with_a_pybind11_inside_the_bounded_range():
    low, next_major = _pybind11_requirement()
    built = tuple(int(k) for k in _soadyn._pybind11_version.split("."))
    assert low <= built and built[0] < next_major, (built, low, next_major)


@pytest.mark.parametrize("array, fast", [
    (np.arange(5.0), True),
    (np.arange(5.0)[::-1].copy(), True),
    (np.arange(10.0)[::2], False),               # strided
    (np.arange(5.0).astype(">f8"), False),       # big-endian
    (np.arange(5, dtype=np.float32), False),
    (np.arange(5), False),
    (np.zeros((2, 3)), True),                    # 2-D: fields read, shape (2, 3)
    (np.asfortranarray(np.zeros((2, 3))), False),
])
def test_private_array_fields_match_numpy(array, fast):
    fields = _soadyn._probe_array_fields(array)
    assert fields["data"] == array.ctypes.data
    assert fields["shape"] == array.shape
    assert fields["float64"] == (array.dtype.kind == "f" and array.dtype.itemsize == 8)
    assert fields["big_endian"] == (array.dtype.byteorder == ">")
    assert fields["c_contiguous_and_aligned"] == (array.flags.c_contiguous and array.flags.aligned)
    is_fast = (fields["float64"] and not fields["big_endian"] and fields["c_contiguous_and_aligned"])
    assert is_fast == fast


def test_private_array_probe_refuses_non_arrays():
    for obj in ([1.0, 2.0], (1.0,), 3.0, "abc", None):
        assert _soadyn._probe_array_fields(obj) is None


def test_private_instance_value_is_pybind11s_object(model):
    plain = _soadyn._Model()
    for m in (model, plain):  # the Python subclass soadyn.Model and the extension class itself
        fast, general = _soadyn._probe_model_handles(m)
        assert fast != 0 and fast == general
    for other in ("not a model", soadyn.Joint.free(), soadyn.MotionSource.constant_velocity(1.0)):
        assert _soadyn._probe_model_handles(other) == (0, 0)
