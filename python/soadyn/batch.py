"""Batched dynamics and parallel rollouts, computed in C++ on a pool of threads.

Every function takes arrays with a leading batch dimension and returns arrays
with one: row k is what the single call (``soadyn.forward_dynamics`` ...)
returns at row k, bit for bit — the same algorithm on the same numbers, run
by one of `threads` threads (None: one per hardware thread) with its own
preallocated Data. The GIL is released while they compute. Inputs are checked
first, with errors naming the array, the row and the coordinate or DOF; a row
whose dynamics fail raises DynamicsError naming the first failing row.

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
           "rollout", "RolloutResult"]


def _threads(threads) -> int:
    if threads is None:
        return 0
    if isinstance(threads, bool) or not isinstance(threads, (int, np.integer)) or threads < 1:
        raise ValueError(f"threads must be a positive integer or None (one per hardware thread), got {threads!r}")
    return int(threads)


def _rows(name: str, x, width: int, n: int | None = None) -> np.ndarray:
    """x as a C-contiguous (n, width) float64 array; the message names `name`."""
    a = np.ascontiguousarray(x, dtype=float)
    if a.ndim != 2 or a.shape[1] != width or (n is not None and a.shape[0] != n):
        expected = f"({'n' if n is None else n}, {width})"
        raise ValueError(f"{name} must have shape {expected} (a leading batch dimension), got {a.shape}")
    return a


def _wrenches(m, f_ext, n: int):
    if f_ext is None:
        return None
    a = np.ascontiguousarray(f_ext, dtype=float)
    if a.shape != (n, m.nbodies, 6):
        raise ValueError(f"f_ext must have shape ({n}, {m.nbodies}, 6), got {a.shape}")
    return a.reshape(n, 6 * m.nbodies)


def _state_batch(m, Q, V, X, x_name: str):
    q = _rows("Q", Q, m.nq)
    n = q.shape[0]
    return q, _rows("V", V, m.nv, n), _rows(x_name, X, m.nv, n), n


def forward_dynamics(m, Q, V, TAU, f_ext=None, threads=None) -> np.ndarray:
    """QDD (n, nv): forward dynamics (every DOF regular) of n states. Q (n, nq), V and TAU (n, nv),
    f_ext None or (n, nbodies, 6) body-frame wrenches [torque; force] about the body origins."""
    q, v, tau, n = _state_batch(m, Q, V, TAU, "TAU")
    return _soadyn._batch_forward_dynamics(m, q, v, tau, _wrenches(m, f_ext, n), n, _threads(threads))


def inverse_dynamics(m, Q, V, QDD, f_ext=None, threads=None) -> np.ndarray:
    """TAU (n, nv): inverse dynamics of n states and accelerations."""
    q, v, qdd, n = _state_batch(m, Q, V, QDD, "QDD")
    return _soadyn._batch_inverse_dynamics(m, q, v, qdd, _wrenches(m, f_ext, n), n, _threads(threads))


def hybrid_dynamics(m, Q, V, U, f_ext=None, threads=None) -> tuple[np.ndarray, np.ndarray]:
    """(QDD, TAU), each (n, nv): hybrid dynamics under the model's prescribed flags (U: torques of
    regular DOFs, accelerations of prescribed ones)."""
    q, v, u, n = _state_batch(m, Q, V, U, "U")
    return _soadyn._batch_hybrid_dynamics(m, q, v, u, _wrenches(m, f_ext, n), n, _threads(threads))


def mass_matrix(m, Q, threads=None) -> np.ndarray:
    """M (n, nv, nv) at n configurations."""
    q = _rows("Q", Q, m.nq)
    return _soadyn._batch_mass_matrix(m, q, q.shape[0], _threads(threads))


def dynamics_derivatives(m, Q, V, U, f_ext=None, threads=None) -> tuple[np.ndarray, ...]:
    """(dqdd_dq, dqdd_dv, dqdd_du, dtau_dq, dtau_dv, dtau_du), each (n, nv, nv): soadyn.dynamics_derivatives
    of n states (q-derivatives in the tangent space), by the same algorithm the single call chooses."""
    q, v, u, n = _state_batch(m, Q, V, U, "U")
    return _soadyn._batch_dynamics_derivatives(m, q, v, u, _wrenches(m, f_ext, n), n, _threads(threads))


@dataclass
class RolloutResult:
    """Stacked trajectories of a rollout: t (rows,), q (runs, rows, nq), v (runs, rows, nv); per run `ok`,
    `failed_step` (-1 when it did not fail) and `messages` (empty when ok). The samples of a failed run
    after its failure are NaN."""

    t: np.ndarray
    q: np.ndarray
    v: np.ndarray
    ok: np.ndarray
    failed_step: np.ndarray
    messages: list = field(default_factory=list)


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
    u = np.ascontiguousarray(controls_or_sources, dtype=float)
    if u.shape == (steps, m.nv):
        per_run = False
    elif u.shape == (runs, steps, m.nv):
        per_run = True
    else:
        raise ValueError(f"controls must have shape ({steps}, {m.nv}) (shared) or ({runs}, {steps}, {m.nv}) "
                         f"(per run), got {u.shape}")
    if not np.all(np.isfinite(u)):
        index = tuple(int(i) for i in np.argwhere(~np.isfinite(u))[0])
        raise ValueError(f"controls{list(index)} ('{m.dof_names[index[-1]]}') is not finite")
    return u, per_run, []


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
        x = np.asarray(values, dtype=float)
        if x.shape != (runs, *shape):
            raise ValueError(f"values of parameter {name!r} must have shape {(runs, *shape)}, got {x.shape}")
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
            index = m.dof_index(dof)
        elif isinstance(dof, (int, np.integer)) and 0 <= dof < m.nv:
            index = int(dof)
        else:
            raise ValueError(f"event {kind} {dof!r}: not a DOF name or an index below nv = {m.nv}")
        t = np.asarray(when, dtype=float)
        if t.shape not in ((), (runs,)):
            raise ValueError(f"event {kind} {dof!r}: one time for all runs or {runs} times, got shape {t.shape}")
        t = np.broadcast_to(t, (runs,))
        if not np.all(np.isfinite(t)):
            raise ValueError(f"event {kind} {dof!r}: its times must be finite")
        kinds.append((kind, index))
        times.append(t)
    return kinds, np.ascontiguousarray(np.stack(times, axis=1))


def rollout(m, x0s, controls_or_sources=None, dt: float = 1e-3, steps: int = 1000, integrator: str = "rk4",
            parameters: dict | None = None, events=None, record_every: int = 1, threads=None) -> RolloutResult:
    """Simulate len(x0s) runs of `m` in parallel, each from its state x0s[r] = [q, v] (nq + nv values).

    controls_or_sources: None; torques of the regular DOFs per step, (steps, nv) shared by every run or
    (runs, steps, nv), held during each step (prescribed DOFs' entries ignored); or {DOF: MotionSource}
    prescribing motions shared by every run (C++ sources only: a Python-function source would need the
    GIL). parameters: {parameter name: (runs, *shape) values} set on each run's copy of the model.
    events: [(kind, DOF, times)] with kind 'lock' or 'release' and one time per run (or one for all).
    Samples every `record_every` steps (which must divide `steps`), the start included.
    """
    runs = int(np.shape(x0s)[0]) if np.ndim(x0s) == 2 else -1
    x0 = _rows("x0s", x0s, m.nq + m.nv)
    if isinstance(steps, bool) or int(steps) != steps or steps < 0:
        raise ValueError(f"steps must be a whole number >= 0, got {steps!r}")
    if isinstance(record_every, bool) or int(record_every) != record_every or record_every < 1 or steps % record_every:
        raise ValueError(f"record_every must be a positive whole number dividing steps ({steps}), got {record_every!r}")
    if not (np.isfinite(dt) and dt > 0):
        raise ValueError(f"dt must be a finite number > 0, got {dt!r}")
    controls, per_run, sources = _controls_and_sources(m, controls_or_sources, runs, int(steps))
    entries, values = _parameters(m, parameters, runs)
    kinds, times = _events(m, events, runs)
    q, v, failed, messages = _soadyn._batch_rollout(
        m, x0, runs, controls, per_run, float(dt), int(steps), integrator, int(record_every), entries, values,
        sources, kinds, times, _threads(threads))
    failed = np.asarray(failed, dtype=np.int64)
    t = np.arange(int(steps) // int(record_every) + 1) * (float(dt) * int(record_every))
    return RolloutResult(t, q, v, np.array([not text for text in messages]), failed, list(messages))
