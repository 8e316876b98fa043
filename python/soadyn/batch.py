"""Batched dynamics and parallel rollouts, computed in C++ on a pool of threads.

Every function takes arrays with a leading batch dimension and returns arrays
with one: row k is what the single call (``soadyn.forward_dynamics`` ...)
returns at row k, bit for bit — the same algorithm on the same numbers, run
by one of `threads` threads (1 to MAX_THREADS; None: one per hardware thread)
with its own preallocated Data. The GIL is released while they compute. Inputs
are checked first, with errors naming the array, the row and the coordinate or
DOF; as the single calls do, every array argument must hold real numbers (a
complex, string, bytes, boolean or object array raises TypeError naming the
argument and its dtype, never cast) and have the documented shape (ValueError
naming the argument, the expected shape and the shape given); a row whose
dynamics fail raises DynamicsError naming the first failing row.

`lanes` sets how many rows one pass of the algorithm computes: on processors with AVX2 and FMA the forward,
inverse and hybrid dynamics and the mass matrix take four rows per pass (``widest_lanes()``, the default),
lanes=1 one row per pass. Both give the same results, bit for bit, and report the same failing rows with the
same errors; a rigid tree's mass matrix four rows per pass is the baseline kernel's, which differs from the
single call's AVX2 FMA kernel in the last bits (docs/guides/batch.md). The derivatives take one row per pass
whatever the lanes, and so does a call of fewer rows than
``packet_minimum_rows()`` (one packet): its results are the single call's, the mass matrix included.
Rollouts step four runs side by side when the runs share everything but their initial states and torques.

`rollout` steps many independent simulations of one model in parallel (the
equivalent of MuJoCo's rollout): different initial states, torques, shared
prescribed motions, per-run parameter values (``m.parameter_names``) and
per-run lock/release event times, each run equal bit for bit to the same
calls on one Simulator. A run that fails is reported (``ok``, ``failed_step``,
``messages``), never raised: its later samples are NaN and its message says
why.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from . import _soadyn
from .simulator import MotionSource

__all__ = ["forward_dynamics", "inverse_dynamics", "hybrid_dynamics", "mass_matrix", "dynamics_derivatives",
           "rollout", "RolloutResult", "widest_lanes", "packet_minimum_rows"]


MAX_THREADS = 1024  # a pool larger than this is refused: no machine this runs on has that many cores


def _threads(threads) -> int:
    if threads is None:
        return 0
    if isinstance(threads, bool) or not isinstance(threads, (int, np.integer)) or not 1 <= threads <= MAX_THREADS:
        raise ValueError(f"threads must be an integer from 1 to {MAX_THREADS} or None (one per hardware thread), "
                         f"got {threads!r}")
    return int(threads)


def widest_lanes() -> int:
    """Rows per pass of the batched calls' packet path on this processor: 4 with AVX2 and FMA, 1 without them
    (or with the environment variable SOADYN_BASELINE_KERNELS set)."""
    return _soadyn._batch_widest_lanes()


def packet_minimum_rows() -> int:
    """The fewest rows a batched call runs four per pass, one packet's: a call of fewer rows runs one row per
    pass whatever its lanes."""
    return _soadyn._batch_packet_minimum_rows()


def _lanes(lanes) -> int:
    if lanes is None:
        return 0
    widest = widest_lanes()
    allowed = (1, 4) if widest == 4 else (1,)
    if isinstance(lanes, bool) or not isinstance(lanes, (int, np.integer)) or int(lanes) not in allowed:
        why = "" if widest == 4 else " (this processor runs no packets: it lacks AVX2 and FMA, or " \
                                     "SOADYN_BASELINE_KERNELS is set)"
        raise ValueError(f"lanes must be {' or '.join(map(str, allowed))} or None (the widest, {widest}){why}, "
                         f"got {lanes!r}")
    return int(lanes)


def _shape_text(shape: tuple) -> str:
    items = ["n" if size is None else str(size) for size in shape]
    return f"({items[0]},)" if len(items) == 1 else f"({', '.join(items)})"  # (), (n,), (n, 3)


def _real_array(name: str, x, *shapes: tuple, note: str = "") -> np.ndarray:
    """x as a C-contiguous float64 array, checked as the single calls check theirs: real numbers only
    (integer or floating dtypes; complex, strings, bytes, objects and booleans raise TypeError naming
    `name` and the dtype) and, when `shapes` are given, one of them (None: any size on that axis;
    otherwise ValueError naming `name`, the expected shapes and the shape given; `note` follows them)."""
    if type(x) is np.ndarray:
        a = x
    else:
        try:
            a = np.asarray(x)
        except (TypeError, ValueError) as exc:  # ragged nested sequences
            raise TypeError(f"{name} must be an array of real numbers: {exc}") from None
    if a.dtype.kind not in "fiu":
        raise TypeError(f"{name} must be an array of real numbers, got dtype {a.dtype}")
    if shapes:
        for shape in shapes:
            if _fits(shape, a.shape):
                break
        else:
            expected = " or ".join(_shape_text(shape) for shape in shapes)
            raise ValueError(f"{name} must have shape {expected}{note}, got {a.shape}")
    return np.asarray(a, dtype=float, order="C")


def _fits(shape: tuple, actual: tuple) -> bool:
    """Whether an array of shape `actual` has `shape` (None: any size on that axis). Loops, not generators:
    the batched calls check three or four arrays per call, and small batches are common."""
    if len(shape) != len(actual):
        return False
    for expected, size in zip(shape, actual):
        if expected is not None and expected != size:
            return False
    return True


def _rows(name: str, x, width: int, n: int | None = None) -> np.ndarray:
    """x as a C-contiguous (n, width) float64 array; the message names `name`."""
    return _real_array(name, x, (n, width), note=" (a leading batch dimension)")


def _wrenches(m, f_ext, n: int):
    if f_ext is None:
        return None
    return _real_array("f_ext", f_ext, (n, m.nbodies, 6)).reshape(n, 6 * m.nbodies)


def _binding_rows(name: str, x, width: int, n: int | None = None):
    """x for a binding that converts real arrays itself (to C-contiguous float64): x as it is when it already
    is an (n, width) numpy array of real numbers, since the checks of _rows cost more than a small batch's
    dynamics; otherwise _rows(name, x, width, n), which names what is wrong."""
    if (type(x) is np.ndarray and x.ndim == 2 and x.dtype.kind in "fiu" and x.shape[1] == width and
            (n is None or len(x) == n)):
        return x
    return _rows(name, x, width, n)


def _state_batch(m, Q, V, X, x_name: str):
    nv = m.nv
    q = _binding_rows("Q", Q, m.nq)
    n = len(q)
    return q, _binding_rows("V", V, nv, n), _binding_rows(x_name, X, nv, n), n


def forward_dynamics(m, Q, V, TAU, f_ext=None, threads=None, lanes=None) -> np.ndarray:
    """QDD (n, nv): forward dynamics (every DOF regular) of n states. Q (n, nq), V and TAU (n, nv),
    f_ext None or (n, nbodies, 6) body-frame wrenches [torque; force] about the body origins.

    Units and frames as the single call's. Raises TypeError for an array that is not of real numbers, ValueError
    naming the array, the row and the coordinate or DOF for a wrong shape or a non-finite entry, and
    DynamicsError naming the first row whose dynamics fail; threads outside 1..MAX_THREADS, or lanes other than
    None, 1 or widest_lanes(), raises ValueError.
    """
    q, v, tau, n = _state_batch(m, Q, V, TAU, "TAU")
    return _soadyn._batch_forward_dynamics(m, q, v, tau, _wrenches(m, f_ext, n), n, _threads(threads), _lanes(lanes))


def inverse_dynamics(m, Q, V, QDD, f_ext=None, threads=None, lanes=None) -> np.ndarray:
    """TAU (n, nv): inverse dynamics of n states and accelerations.

    Units and frames as the single call's. Raises TypeError for an array that is not of real numbers, ValueError
    naming the array, the row and the coordinate or DOF for a wrong shape or a non-finite entry, and
    DynamicsError naming the first row whose dynamics fail; threads outside 1..MAX_THREADS, or lanes other than
    None, 1 or widest_lanes(), raises ValueError.
    """
    q, v, qdd, n = _state_batch(m, Q, V, QDD, "QDD")
    return _soadyn._batch_inverse_dynamics(m, q, v, qdd, _wrenches(m, f_ext, n), n, _threads(threads), _lanes(lanes))


def hybrid_dynamics(m, Q, V, U, f_ext=None, threads=None, lanes=None) -> tuple[np.ndarray, np.ndarray]:
    """(QDD, TAU), each (n, nv): hybrid dynamics under the model's prescribed flags (U: torques of
    regular DOFs, accelerations of prescribed ones).

    Units and frames as the single call's. Raises TypeError for an array that is not of real numbers, ValueError
    naming the array, the row and the coordinate or DOF for a wrong shape or a non-finite entry, and
    DynamicsError naming the first row whose dynamics fail; threads outside 1..MAX_THREADS, or lanes other than
    None, 1 or widest_lanes(), raises ValueError.
    """
    q, v, u, n = _state_batch(m, Q, V, U, "U")
    return _soadyn._batch_hybrid_dynamics(m, q, v, u, _wrenches(m, f_ext, n), n, _threads(threads), _lanes(lanes))


def mass_matrix(m, Q, threads=None, lanes=None) -> np.ndarray:
    """M (n, nv, nv) at n configurations.

    Units and frames as the single call's. Raises TypeError for an array that is not of real numbers, ValueError
    naming the array, the row and the coordinate or DOF for a wrong shape or a non-finite entry, and
    DynamicsError naming the first row whose dynamics fail; threads outside 1..MAX_THREADS, or lanes other than
    None, 1 or widest_lanes(), raises ValueError.
    """
    q = _binding_rows("Q", Q, m.nq)
    return _soadyn._batch_mass_matrix(m, q, q.shape[0], _threads(threads), _lanes(lanes))


def dynamics_derivatives(m, Q, V, U, f_ext=None, threads=None, lanes=None) -> tuple[np.ndarray, ...]:
    """(dqdd_dq, dqdd_dv, dqdd_du, dtau_dq, dtau_dv, dtau_du), each (n, nv, nv): soadyn.dynamics_derivatives
    of n states (q-derivatives in the tangent space), by the same algorithm the single call chooses.

    Units and frames as the single call's. Raises TypeError for an array that is not of real numbers, ValueError
    naming the array, the row and the coordinate or DOF for a wrong shape or a non-finite entry, and
    DynamicsError naming the first row whose dynamics fail; threads outside 1..MAX_THREADS, or lanes other than
    None, 1 or widest_lanes(), raises ValueError.
    """
    q, v, u, n = _state_batch(m, Q, V, U, "U")
    return _soadyn._batch_dynamics_derivatives(m, q, v, u, _wrenches(m, f_ext, n), n, _threads(threads), _lanes(lanes))


@dataclass
class RolloutResult:
    """Stacked trajectories of a rollout: t (rows,), q (runs, rows, nq), v (runs, rows, nv); per run `ok`,
    `failed_step` (-1 when it did not fail) and `messages` (empty when ok). The samples of a failed run
    after its failure are NaN. `side_by_side`: how many runs stepped four side by side (lanes 4); the
    others stepped one by one."""

    t: np.ndarray
    q: np.ndarray
    v: np.ndarray
    ok: np.ndarray
    failed_step: np.ndarray
    messages: list = field(default_factory=list)
    side_by_side: int = 0


def _controls_and_sources(m, controls_or_sources, runs: int, steps: int):
    """(controls array or None, per-run flag, [(dof, MotionSource)]) from an array or a {DOF: MotionSource}."""
    if controls_or_sources is None:
        return None, False, []
    if isinstance(controls_or_sources, dict):
        sources = []
        for dof, source in controls_or_sources.items():
            if not isinstance(source, MotionSource):
                raise TypeError(f"source for {dof!r} must be a soadyn.MotionSource, got {type(source).__name__}")
            sources.extend((index, source) for index in m._dof_indices(dof))
        return None, False, sources
    u = _real_array("controls", controls_or_sources, (steps, m.nv), (runs, steps, m.nv),
                    note=" (shared by every run or one per run)")
    per_run = u.ndim == 3
    if not np.all(np.isfinite(u)):
        index = tuple(int(i) for i in np.argwhere(~np.isfinite(u))[0])
        raise ValueError(f"controls{list(index)} ('{m.dof_names[index[-1]]}') is not finite")
    return u, per_run, []


def _whole(name: str, x, minimum: int) -> int:
    """x as an int >= minimum (a whole float such as 10.0 is accepted); ValueError naming `name` otherwise."""
    whole = isinstance(x, (int, np.integer, float, np.floating)) and not isinstance(x, bool) and \
        float(x).is_integer() and x >= minimum
    if not whole or not x < 2 ** 62:
        raise ValueError(f"{name} must be a whole number >= {minimum}, got {x!r}")
    return int(x)


def _parameters(m, parameters, runs: int):
    """(table entries, runs x width column-major values) from {name: (runs, *shape) values}."""
    if not parameters:
        return [], None
    names = list(m.parameter_names)
    entries, blocks = [], []
    for name, values in parameters.items():
        if name not in names:
            raise ValueError(f"unknown parameter {name!r} (the model's: {', '.join(names)})")
        shape = np.shape(m.get_parameter(name))
        x = _real_array(f"values of parameter {name!r}", values, (runs, *shape))
        entries.append(names.index(name))
        width = int(np.prod(shape, dtype=int))  # each run's value, column-major (the C++ layout)
        blocks.append(np.asarray([np.asarray(x[r]).flatten(order="F") for r in range(runs)]).reshape(runs, width))
    return entries, np.ascontiguousarray(np.hstack(blocks))


def _events(m, events, runs: int):
    if not events:
        return [], None
    kinds, times = [], []
    for event in events:
        if not isinstance(event, (tuple, list)) or len(event) != 3:
            raise ValueError(f"event {event!r}: expected (kind, DOF, times)")
        kind, dof, when = event
        if kind not in ("lock", "release"):
            raise ValueError(f"event {event!r}: the kind must be 'lock' or 'release'")
        if isinstance(dof, str):
            index = m.dof_index(dof)  # -1 for a name the model does not have
        elif isinstance(dof, (int, np.integer)) and not isinstance(dof, bool) and 0 <= dof < m.nv:
            index = int(dof)
        else:
            index = -1
        if index < 0:
            raise ValueError(f"event {kind} {dof!r}: not a DOF name or an index below nv = {m.nv}")
        t = np.broadcast_to(_real_array(f"times of event {kind} {dof!r}", when, (), (runs,),
                                        note=f" (one time for all runs or {runs} times)"), (runs,))
        if not np.all(np.isfinite(t)):
            raise ValueError(f"event {kind} {dof!r}: its times must be finite")
        kinds.append((kind, index))
        times.append(t)
    return kinds, np.ascontiguousarray(np.stack(times, axis=1))


def rollout(m, x0s, controls_or_sources=None, dt: float = 1e-3, steps: int = 1000, integrator: str = "rk4",
            parameters: dict | None = None, events=None, record_every: int = 1, threads=None,
            lanes=None) -> RolloutResult:
    """Simulate len(x0s) runs of `m` in parallel, each from its state x0s[r] = [q, v] (nq + nv values).

    controls_or_sources: None; torques of the regular DOFs per step, (steps, nv) shared by every run or
    (runs, steps, nv), held during each step (prescribed DOFs' entries ignored); or {DOF: MotionSource}
    prescribing motions shared by every run (C++ sources only: a Python-function source would need the
    GIL). parameters: {parameter name: (runs, *shape) values} set on each run's copy of the model.
    events: [(kind, DOF, times)] with kind 'lock' or 'release' and one time per run (or one for all).
    Samples every `record_every` steps (which must divide `steps`), the start included. With lanes 4 (the default
    where the processor has AVX2 and FMA), runs of a tree without loops, rigid or flexible, step four side by
    side, sources included, each equal bit for bit to its run alone; with parameters, each of the four holds its
    own values (four runs whose values change a property the model derives from them, such as a placement's
    rotation being the identity, step one by one); with events, runs whose events fall due in the same steps step
    four side by side, whatever their order. Other runs step one by one; the result's `side_by_side` counts the first kind.

    dt in s; torques in N or N m, states as the single calls'. Raises TypeError or ValueError naming the
    argument (and the run, row or DOF) for a wrong type, shape, a non-finite entry, an unknown DOF or parameter,
    a dt that is not finite and positive, or a record_every that does not divide steps. A run whose dynamics
    fail is not raised: RolloutResult reports it (ok, failed_step, messages) and its later samples are NaN.
    """
    width = _lanes(lanes)
    x0 = _rows("x0s", x0s, m.nq + m.nv)
    runs = x0.shape[0]
    steps = _whole("steps", steps, 0)
    record_every = _whole("record_every", record_every, 1)
    if steps % record_every:
        raise ValueError(f"record_every must divide steps ({steps}), got {record_every}")
    dt = float(_real_array("dt", dt, ()))
    if not isinstance(integrator, str):
        raise TypeError(f"integrator must be a str ('rk4', 'euler' or 'dopri5'), got {type(integrator).__name__}")
    if not (np.isfinite(dt) and dt > 0):
        raise ValueError(f"dt must be a finite number > 0, got {dt!r}")
    if not np.isfinite(dt * max(steps, 1)):
        raise ValueError(f"dt ({dt!r}) times steps ({steps}) is beyond floating point: the run's times would overflow")
    controls, per_run, sources = _controls_and_sources(m, controls_or_sources, runs, steps)
    entries, values = _parameters(m, parameters, runs)
    kinds, times = _events(m, events, runs)
    q, v, failed, messages, side_by_side = _soadyn._batch_rollout(
        m, x0, runs, controls, per_run, dt, steps, integrator, record_every, entries, values,
        sources, kinds, times, _threads(threads), width)
    failed = np.asarray(failed, dtype=np.int64)
    t = np.arange(steps // record_every + 1) * (dt * record_every)
    return RolloutResult(t, q, v, np.array([not text for text in messages]), failed, list(messages), side_by_side)
