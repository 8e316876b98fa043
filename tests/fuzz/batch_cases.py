"""Hostile cases for soadyn.batch, each drawn from one integer seed.

A case takes a small model (a random tree of fuzz.api_cases, a pendulum
chain, the four-bar, a flexible cantilever on a hinge), a batch of 0 to 6
states, or of 16 or 19 (packets from soadyn.batch.packet_minimum_rows() rows
on), and spoils the arrays: complex, string, boolean and object arrays,
nested lists (ragged ones too), float32, integer and Fortran-ordered arrays,
a NaN or infinite row, a huge finite row, wrong shapes (a row or a column too
many or too few, a missing or an extra axis), the thread count (0, -1,
True, 1.5, "2", 2**40, numpy integers) and the lanes (1, 4, 0, 2, True,
"4", 4.0, 2**40). It then makes one batched call
(forward_dynamics, inverse_dynamics, hybrid_dynamics, mass_matrix,
dynamics_derivatives) or a rollout (hostile initial states, controls, step,
step count, integrator, record_every, per-run parameters and event times).

The property (support.forked.judged): finite results of the documented shape
or a documented error with a message naming the argument at fault; never a
crash, a hang, a silent NaN or a complex or string array read as numbers.
Besides, as soadyn.batch promises: each row of a batched result is what the
single call gives on that row, bit for bit (checked on the first rows; the
mass matrix four rows per pass to the last bits), and a
rollout's successful runs are finite and each failed run carries its message.
"""
from __future__ import annotations

import numpy as np

import soadyn
from soadyn import batch
from fuzz.api_cases import EXPECTED_ERRORS, hostile_float, random_model
from fuzz.loop_cases import hostile_wrenches
from support.forked import judged

CALLS = ("forward_dynamics", "inverse_dynamics", "hybrid_dynamics", "mass_matrix", "dynamics_derivatives",
         "rollout")
THREADS = (None, 1, 2, 3, np.int64(2), 0, -1, True, 1.5, "2", 2 ** 40)
INTEGRATORS = ("rk4", "euler", "dopri5", "leapfrog", 3)
CHECKED_ROWS = 2
LANES = (1, 4, np.int64(4), 0, 2, 8, True, "4", 4.0, 2 ** 40)
# Every batched result equals the single call bit for bit, but the mass matrix four rows per pass: the
# baseline kernel's, within this fraction of the row's largest entry of the single call's AVX2 FMA kernel
# (tests/batch/test_batch_lanes.py).
MASS_MATRIX_TOLERANCE = 1e-14


def batch_model(rng: np.random.Generator) -> soadyn.Model:
    r = rng.uniform()
    if r < 0.45:
        m = random_model(rng)
    elif r < 0.75:
        m = soadyn.scenes.pendulum_chain(int(rng.integers(1, 5)))
    elif r < 0.9:
        m = soadyn.scenes.four_bar()
    else:
        m = soadyn.Model()
        m.add_flexible_body("beam", None, soadyn.FlexibleBody.cantilever_beam(1.0, 20.0, 1.0, 1, 4),
                            soadyn.Joint.revolute((0.0, 1.0, 0.0)))
    if m.nv and rng.uniform() < 0.3:
        m.set_prescribed((rng.uniform(size=m.nv) < 0.5) & ~np.asarray(m.modal, dtype=bool))
    return m


def spoiled(rng: np.random.Generator, x: np.ndarray, spoil: float = 0.3):
    """x (a float array with a leading batch axis), or now and then spoiled: hostile entries or rows,
    another dtype, layout or type, another shape."""
    r = rng.uniform() / spoil
    if r >= 1.0:
        return x
    x = x.copy()
    if r < 0.3 and x.size:
        row = int(rng.integers(len(x)))
        if rng.uniform() < 0.5:
            x[row] = float(rng.choice([np.nan, np.inf, -np.inf, 1e200, -1e308]))
        else:
            x.reshape(len(x), -1)[row, rng.integers(x[0].size)] = hostile_float(rng)
        return x
    if r < 0.6:
        return [lambda: x + 1j, lambda: x.astype(str), lambda: x != 0, lambda: x.astype(object),
                lambda: x.astype(bytes), lambda: x.astype(np.float32), lambda: np.round(x).astype(np.int32),
                lambda: np.asfortranarray(x), lambda: x.tolist()][rng.integers(9)]()
    if r < 0.7 and x.ndim == 2 and len(x) > 1:
        return [list(row) for row in x[:-1]] + [list(x[-1, :-1])]  # a ragged nested list
    axis = int(rng.integers(x.ndim))
    if r < 0.85:  # one entry more or fewer along an axis
        if x.shape[axis] and rng.uniform() < 0.5:
            return np.delete(x, -1, axis=axis)
        return np.zeros(tuple(size + (k == axis) for k, size in enumerate(x.shape)))
    return x[None] if rng.uniform() < 0.5 else x.reshape(-1)


def states(rng: np.random.Generator, m: soadyn.Model, n: int):
    Q = np.array([soadyn.random_configuration(m, int(rng.integers(1 << 30))) for _ in range(n)]).reshape(n, m.nq)
    return Q, rng.normal(size=(n, m.nv)), rng.normal(size=(n, m.nv))


def threads(rng: np.random.Generator):
    return None if rng.uniform() < 0.8 else THREADS[rng.integers(len(THREADS))]


def lanes(rng: np.random.Generator):
    return None if rng.uniform() < 0.7 else LANES[rng.integers(len(LANES))]


def same_row(row: np.ndarray, alone: np.ndarray, exact: bool) -> bool:
    if exact or not np.all(np.isfinite(alone)):
        return np.array_equal(row, alone)
    scale = np.max(np.abs(alone), initial=0.0)
    return bool(np.all(np.abs(row - alone) <= MASS_MATRIX_TOLERANCE * scale))


def single_rows(m: soadyn.Model, name: str, Q, V, X, F, result, exact: bool) -> None:
    """Each of the first rows of a batched result equals the single call on that row: bit for bit when
    `exact`, else within MASS_MATRIX_TOLERANCE of the row's largest entry."""
    outputs = result if isinstance(result, tuple) else (result,)
    for k in range(min(CHECKED_ROWS, len(Q))):
        f = None if F is None else F[k]
        try:
            single = soadyn.mass_matrix(m, Q[k]) if name == "mass_matrix" else \
                getattr(soadyn, name)(m, Q[k], V[k], X[k], f)
        except EXPECTED_ERRORS as e:
            raise AssertionError(f"batch.{name} returned row {k}, where the single call raises "
                                 f"{type(e).__name__}: {e}") from e
        single = single if isinstance(single, tuple) else (single,)
        for i, (row, alone) in enumerate(zip(outputs, single)):
            if not same_row(row[k], alone, exact):
                raise AssertionError(f"batch.{name} row {k}, output {i}, differs from the single call: "
                                     f"{row[k]!r} != {alone!r}")


def batched(rng: np.random.Generator, m: soadyn.Model, name: str):
    n = int(rng.choice([0, 1, 2, 3, 6, 16, 19]))
    Q, V, X = states(rng, m, n)
    F = None if name == "mass_matrix" else hostile_wrenches(rng, m)
    F = None if F is None else np.broadcast_to(np.asarray(F), (n, *np.shape(F))) if rng.uniform() < 0.8 else F
    arrays = {"Q": spoiled(rng, Q), "V": spoiled(rng, V), "X": spoiled(rng, X, 0.2), "f_ext": F}
    spoil_free = all(a is b for a, b in zip(arrays.values(), (Q, V, X)))
    width = lanes(rng)
    if name == "mass_matrix":
        arrays = {"Q": arrays["Q"]}
        result = batch.mass_matrix(m, arrays["Q"], threads=threads(rng), lanes=width)
    else:
        result = getattr(batch, name)(m, *arrays.values(), threads=threads(rng), lanes=width)
    if spoil_free:
        single_rows(m, name, Q, V, X, None if F is None else np.asarray(F, dtype=float), result,
                    exact=name != "mass_matrix" or n < batch.packet_minimum_rows() or
                    (width is not None and not isinstance(width, bool) and width == 1))
    return result, arrays


def hostile_parameters(rng: np.random.Generator, m: soadyn.Model, runs: int) -> dict | None:
    if rng.uniform() < 0.6 or not m.parameter_names:
        return None
    name = m.parameter_names[rng.integers(len(m.parameter_names))]
    value = np.asarray(m.get_parameter(name), dtype=float)
    values = np.broadcast_to(value, (runs, *value.shape)).copy()
    if runs and rng.uniform() < 0.5:
        values.reshape(runs, -1)[rng.integers(runs), rng.integers(max(value.size, 1))] = hostile_float(rng)
    return {name if rng.uniform() < 0.9 else "no_such_body.mass": spoiled(rng, values, 0.2)}


def hostile_events(rng: np.random.Generator, m: soadyn.Model, runs: int):
    if rng.uniform() < 0.7 or not m.nv:
        return None
    times = rng.uniform(0.0, 0.02, runs) if rng.uniform() < 0.7 else hostile_float(rng)
    kind = "lock" if rng.uniform() < 0.5 else ["release", "break", None][rng.integers(3)]
    dof = int(rng.integers(m.nv)) if rng.uniform() < 0.9 else [m.nv, -1, "no_such_dof"][rng.integers(3)]
    return [(kind, dof, spoiled(rng, np.asarray(times), 0.2))]


def rolled_out(rng: np.random.Generator, m: soadyn.Model):
    runs, steps = int(rng.choice([0, 1, 2, 3])), int(rng.choice([0, 1, 5, 10]))
    Q, V, _ = states(rng, m, runs)
    x0s = spoiled(rng, np.hstack([Q, 0.1 * V]))
    controls = None if rng.uniform() < 0.5 else spoiled(
        rng, rng.normal(size=(steps, m.nv) if rng.uniform() < 0.5 else (runs, steps, m.nv)))
    dt = 1e-3 if rng.uniform() < 0.8 else [hostile_float(rng), "0.001", 1e-3 + 0j][rng.integers(3)]
    record_every = 1 if rng.uniform() < 0.8 else [2, 3, 0, -1, 1.5, None][rng.integers(6)]
    integrator = "rk4" if rng.uniform() < 0.6 else INTEGRATORS[rng.integers(len(INTEGRATORS))]
    parameters = hostile_parameters(rng, m, runs)
    result = batch.rollout(m, x0s, controls, dt, steps if rng.uniform() < 0.9 else [-1, 2.5, np.nan][rng.integers(3)],
                           integrator, parameters, hostile_events(rng, m, runs), record_every, threads(rng))
    arrays = {"x0s": x0s, "controls": controls, "dt": dt} | {f"parameter {k}": v for k, v in (parameters or {}).items()}
    ok = np.asarray(result.ok, dtype=bool)
    silent = [r for r in range(len(ok)) if not ok[r] and not result.messages[r]]
    if silent:
        raise AssertionError(f"rollout run {silent[0]} failed without a message")
    return (result.t, result.q[ok], result.v[ok]), arrays


def call(rng: np.random.Generator):
    """One batched call or rollout with hostile arguments: (name, result, array arguments)."""
    m = batch_model(rng)
    name = CALLS[rng.integers(len(CALLS))]
    return (name, *(rolled_out(rng, m) if name == "rollout" else batched(rng, m, name)))


def run_case(seed: int) -> str:
    """Runs case `seed`; returns 'ok' or the name of the documented error raised.
    Raises AssertionError or an unexpected exception when the property fails."""
    rng = np.random.default_rng(seed)
    return judged(lambda: call(rng))
