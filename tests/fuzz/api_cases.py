"""Hostile cases for the public Python API, each drawn from one integer seed.

A case builds a small model (valid or not: NaN, huge, tiny, negative and
mistyped parameters) and makes one public call with hostile arguments
(NaN, inf, 1e200, 1e-300, wrong shapes, dtypes and types). The property every
case must keep: the call returns finite numbers of the documented shape, or
raises one of the documented errors with a message; never another exception,
never a crash, never a silent NaN. The same cases serve the quick property
test (tests/fuzz/test_fuzz_api.py, hypothesis) and the long campaign
(bench/fuzz_campaign.py, each case in its own process).
"""
from __future__ import annotations

import numpy as np

import soadyn

# Errors the API documents for bad input or unsolvable states (RuntimeError
# only for races between threads: never in these single-threaded cases).
EXPECTED_ERRORS = (ValueError, TypeError, soadyn.DynamicsError)

HOSTILE_FLOATS = (0.0, -0.0, 1.0, -1.0, 1e-300, -1e-300, 1e200, -1e200, 1e308, np.nan, np.inf, -np.inf, 5e-324)
JOINTS = ("revolute", "prismatic", "helical", "universal", "cylindrical", "planar", "spherical", "free", "fixed",
          "translation")


class NonFiniteResult(AssertionError):
    """A call returned NaN or infinity without raising."""


def hostile_float(rng: np.random.Generator) -> float:
    if rng.uniform() < 0.3:
        return float(HOSTILE_FLOATS[rng.integers(len(HOSTILE_FLOATS))])
    return float(rng.normal() * 10.0 ** rng.integers(-3, 4))


def hostile_vector(rng: np.random.Generator, n: int, spoil: float = 0.15):
    """Mostly ordinary numbers; with some probability one hostile entry, a
    wrong length, dtype or type."""
    x = rng.normal(size=n)
    r = rng.uniform()
    if r < spoil and n > 0:
        x[rng.integers(n)] = hostile_float(rng)
    elif r < spoil + 0.03:
        return rng.normal(size=n + int(rng.choice([-1, 1])))
    elif r < spoil + 0.05:
        return x.astype(complex) if rng.uniform() < 0.5 else x.astype(str)
    elif r < spoil + 0.06:
        return [None] * n
    elif r < spoil + 0.08:
        return x.reshape(1, -1) if n else x
    elif r < spoil + 0.09:
        return x.astype(np.float32)
    return x


def random_joint(rng: np.random.Generator) -> soadyn.Joint:
    kind = JOINTS[rng.integers(len(JOINTS))]
    axis = rng.normal(size=3)
    if rng.uniform() < 0.05:
        axis[rng.integers(3)] = hostile_float(rng)
    J = soadyn.Joint
    if kind in ("revolute", "prismatic", "cylindrical"):
        return getattr(J, kind)(axis)
    if kind == "helical":
        return J.helical(axis, hostile_float(rng) if rng.uniform() < 0.1 else float(rng.normal()))
    if kind == "universal":
        return J.universal(axis, rng.normal(size=3))
    return getattr(J, kind)()


def random_model(rng: np.random.Generator) -> soadyn.Model:
    """1-6 bodies; parameters occasionally hostile (bodies whose parameters are
    refused are skipped, which is itself checked: the refusal must be one of
    the documented errors)."""
    m = soadyn.Model()
    if rng.uniform() < 0.1:
        m.gravity = [hostile_float(rng), 0.0, -9.81]
    for k in range(int(rng.integers(1, 7))):
        parent = None if m.nbodies == 0 or rng.uniform() < 0.2 else int(rng.integers(m.nbodies))
        mass = float(rng.uniform(0.1, 3.0)) if rng.uniform() > 0.1 else hostile_float(rng)
        com = rng.uniform(-0.3, 0.3, 3)
        inertia = rng.uniform(0.05, 0.2, 3)
        translation = rng.uniform(-0.5, 0.5, 3)
        if rng.uniform() < 0.1:
            (com if rng.uniform() < 0.5 else inertia)[rng.integers(3)] = hostile_float(rng)
        if rng.uniform() < 0.05:
            translation[rng.integers(3)] = hostile_float(rng)
        try:
            m.add_body(f"b{k}", parent, random_joint(rng), placement=translation, mass=mass, com=com, inertia=inertia)
        except EXPECTED_ERRORS:
            pass
    return m


def check_finite(result, what: str) -> None:
    items = result if isinstance(result, tuple) else (result,)
    for item in items:
        if item is None:
            continue
        if not np.all(np.isfinite(np.asarray(item, dtype=float))):
            raise NonFiniteResult(f"{what} returned a non-finite result without raising")


def call(rng: np.random.Generator, m: soadyn.Model):
    """One public call with hostile arguments; returns (name, result)."""
    q = soadyn.random_configuration(m, int(rng.integers(1 << 30))) if rng.uniform() < 0.8 else \
        hostile_vector(rng, m.nq, spoil=1.0)
    if rng.uniform() < 0.1:
        q = hostile_vector(rng, m.nq)
    v, x = hostile_vector(rng, m.nv), hostile_vector(rng, m.nv)
    if rng.uniform() < 0.2 and isinstance(v, np.ndarray) and v.dtype.kind == "f":
        with np.errstate(over="ignore"):
            v = v * 1e150
    f_ext = None
    if rng.uniform() < 0.3:
        f_ext = hostile_vector(rng, 6 * m.nbodies)
        if isinstance(f_ext, np.ndarray) and f_ext.size % 6 == 0:
            f_ext = f_ext.reshape(-1, 6)
    if rng.uniform() < 0.3 and m.nv:
        mask = rng.uniform(size=m.nv) < 0.5
        m.set_prescribed(mask if rng.uniform() < 0.8 else mask.astype(int))
    name = ["forward_dynamics", "inverse_dynamics", "hybrid_dynamics", "mass_matrix", "bias_forces",
            "kinetic_energy", "potential_energy", "momentum", "center_of_mass", "joint_wrenches",
            "forward_kinematics", "integrate"][rng.integers(12)]
    fn = getattr(soadyn, name)
    if name in ("forward_dynamics", "inverse_dynamics", "hybrid_dynamics", "joint_wrenches"):
        return name, fn(m, q, v, x, f_ext)
    if name in ("mass_matrix", "potential_energy", "center_of_mass"):
        return name, fn(m, q)
    if name == "forward_kinematics":
        return name, fn(m, q, v if rng.uniform() < 0.5 else None)
    if name == "integrate":
        return name, fn(m, q, v, hostile_float(rng) if rng.uniform() < 0.2 else 1e-3)
    return name, fn(m, q, v)


def run_case(seed: int) -> str:
    """Runs case `seed`; returns 'ok' or the name of the expected error raised.
    Raises NonFiniteResult or an unexpected exception when the property fails."""
    rng = np.random.default_rng(seed)
    try:
        m = random_model(rng)
        name, result = call(rng, m)
    except EXPECTED_ERRORS as e:
        if not str(e):
            raise AssertionError(f"{type(e).__name__} without a message") from e
        return type(e).__name__
    check_finite(result, name)
    return "ok"
