"""Property-based tests of the URDF loader (hypothesis), small enough for CI.

- Any bytes, any text, any mutation of a valid file (a value replaced by
  NaN, inf, 1e308, garbage or the wrong number of components; an element
  dropped, duplicated or renamed): load_urdf returns a Model or raises
  UrdfError, nothing else, and a Model it returns has finite masses.
- Random valid trees (revolute, continuous, prismatic and fixed joints at
  random origins, axes and physical inertias, some links without <inertial>):
  the model equals Pinocchio's (mass matrix and inverse dynamics at a random
  state, DOFs matched by name), or, when a moving link has no inertia at all,
  the UrdfError names it.
"""
import math
import tempfile
import warnings
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings, strategies as st

import soadyn
from soadyn.check import relative_difference
from soadyn.oracles import PinocchioOracle
from fuzz.urdf_cases import mutate

FUZZ = settings(max_examples=150, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow])


def load(text, floating=False, inertia="strict", binary=False):
    """load_urdf on `text`: the Model, or the UrdfError; any other exception fails the test."""
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "fuzz.urdf"
        path.write_bytes(text) if binary else path.write_text(text, encoding="utf-8", errors="surrogatepass")
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                model = soadyn.load_urdf(path, floating_base=floating, inertia=inertia)
        except soadyn.UrdfError as error:
            assert str(path) in str(error)
            return error
    assert all(math.isfinite(m) and m >= 0 for m in model.masses)
    return model


@FUZZ
@given(st.binary(max_size=400))
def test_any_bytes(data):
    load(data, binary=True)


@FUZZ
@given(st.text(alphabet=st.sampled_from(list("<>/=\"' robotlinkjointnameparentchild0123456789.-e")), max_size=300))
def test_any_text_of_urdf_characters(text):
    load(text)


# ---- random valid trees ----------------------------------------------------

numbers = st.floats(-1.0, 1.0, allow_nan=False)
vectors = st.tuples(numbers, numbers, numbers)


def fmt(values):
    return " ".join(repr(float(v)) for v in values)


@st.composite
def inertials(draw):
    if draw(st.integers(0, 4)) == 0:
        return ""  # no <inertial>
    a, b = draw(st.floats(0.01, 1.0)), draw(st.floats(0.01, 1.0))
    c = draw(st.floats(abs(a - b), a + b))  # principal moments obeying the triangle inequality
    mass = draw(st.floats(0.1, 10.0))
    return (f"<inertial><origin xyz='{fmt(draw(vectors))}' rpy='{fmt(draw(vectors))}'/><mass value='{mass!r}'/>"
            f"<inertia ixx='{a!r}' iyy='{b!r}' izz='{c!r}' ixy='0' ixz='0' iyz='0'/></inertial>")


@st.composite
def trees(draw):
    n = draw(st.integers(1, 7))
    links = [f"<link name='l{k}'>{draw(inertials())}</link>" for k in range(n + 1)]
    joints = []
    for k in range(1, n + 1):
        kind = draw(st.sampled_from(["revolute", "continuous", "prismatic", "fixed"]))
        axis = draw(vectors.filter(lambda a: np.linalg.norm(a) > 0.1))
        joints.append(f"<joint name='j{k}' type='{kind}'><parent link='l{draw(st.integers(0, k - 1))}'/>"
                      f"<child link='l{k}'/><origin xyz='{fmt(draw(vectors))}' rpy='{fmt(draw(vectors))}'/>"
                      f"<axis xyz='{fmt(axis)}'/><limit lower='-3' upper='3' effort='1' velocity='1'/></joint>")
    order = draw(st.permutations(links + joints))  # element order must not matter
    return "<robot name='fuzz'>" + "".join(order) + "</robot>"


@settings(max_examples=60, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow])
@given(trees(), st.booleans(), st.integers(0, 2**31))
def test_random_trees_match_pinocchio(text, floating, seed):
    result = load(text, floating)
    if isinstance(result, soadyn.UrdfError):
        assert "a moving link has no <inertial>" in str(result) and "inertia='repair'" in str(result)
        return
    model = result
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "tree.urdf"
        path.write_text(text)
        oracle = PinocchioOracle(model, path, floating)
        if model.nv == 0:
            assert oracle.model.nv == 0
            return
        q = soadyn.random_configuration(model, seed)
        v, qdd = np.random.default_rng(seed).normal(size=(2, model.nv))
        assert relative_difference(soadyn.mass_matrix(model, q), oracle.mass_matrix(q)) < 1e-9
        assert relative_difference(soadyn.inverse_dynamics(model, q, v, qdd), oracle.inverse_dynamics(q, v, qdd)) < 1e-9


# ---- mutations of a valid file ----------------------------------------------

@st.composite
def mutated(draw):
    return mutate(draw(trees()), lambda items: draw(st.sampled_from(items)))


@FUZZ
@given(mutated(), st.booleans(), st.sampled_from(["strict", "repair", "accept"]))
def test_mutated_files(text, floating, inertia):
    load(text, floating, inertia)


@pytest.mark.parametrize("value, overflows", [("1e200", True), ("1e308", True), ("1e150", False), ("1e-300", False)])
def test_huge_and_tiny_values_are_finite_or_refused(value, overflows):
    """A huge centre of mass offset overflows mass * com: refused by name, never a model with inf inside."""
    text = (f"<robot name='r'><link name='a'/><link name='b'><inertial><origin xyz='{value} 0 0'/><mass value='2'/>"
            f"<inertia ixx='1' iyy='1' izz='1' ixy='0' ixz='0' iyz='0'/></inertial></link>"
            f"<joint name='j' type='continuous'><parent link='a'/><child link='b'/></joint></robot>")
    result = load(text)
    if overflows:  # mass * |com|^2 = 2e400
        assert isinstance(result, soadyn.UrdfError)
        assert "link 'b' (joint 'j')" in str(result) and "not finite" in str(result)
    else:
        assert result.masses == [2.0]
