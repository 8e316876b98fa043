"""One run of a campaign: a pure function of (spec, run_id), the same in a worker, a plain
loop and a replay.

Run i draws its dispersed values, in the spec's order, from
numpy.random.default_rng(SeedSequence(spec.seed, spawn_key=(i,))), which is child i of
SeedSequence(spec.seed).spawn(runs) (whatever `runs` is). The model is built from the spec's
model-file text (once per process, then copied for each run), never from a pickled object.
A run that fails (its dynamics, a parameter the model refuses, a metric) returns status
"failed" with the error's type and message; nothing a run raises stops a campaign.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

import numpy as np

from ..io.model_file import model_from_json
from ..simulator import Simulator
from .dispersions import add_sources_and_events, set_initial, set_parameters
from .metrics import evaluate
from .starts import drive, start_state

_MODELS: dict = {}  # model_sha256 -> Model: the campaign's model, read once per process


@dataclass
class RunOutcome:
    """One run's result as a worker returns it: its table row and, when kept, its decimated trajectory."""

    row: dict                      # run_id, the dispersed values (by column), the metrics, status, message
    trajectory: Optional[dict]     # {"t": (n,), "q": (n, nq), "v": (n, nv)} every trajectory_every steps


def generator(seed: int, run_id: int) -> np.random.Generator:
    """Run `run_id`'s generator: that of SeedSequence(seed).spawn(n)[run_id] for any n > run_id."""
    return np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(run_id,)))


def draw(spec, run_id: int) -> list:
    rng = generator(spec.seed, run_id)
    return [d.draw(rng) for d in spec.dispersions]


def base_model(spec):
    model = _MODELS.get(spec.model_sha256)
    if model is None:
        model = model_from_json(spec.model_json, f"the model of campaign {spec.name!r}")
        if len(_MODELS) >= 4:
            _MODELS.clear()
        _MODELS[spec.model_sha256] = model
    return model


def prepare(spec, values) -> Simulator:
    """The run's Simulator at t = 0: the drawn parameters on a copy of the model, the start state with
    the spec's and the drawn initial values, the scene's drives, then sources and events."""
    model = base_model(spec).copy()
    set_parameters(model, spec.dispersions, values)
    n_events = len(spec.events) + sum(d.kind == "event" for d in spec.dispersions)
    sim = Simulator(model, spec.dt, spec.integrator, event_capacity=64 + 6 * n_events)
    q, v = start_state(spec.scene, model)
    for k, x in spec.initial_q:
        q[k] = x
    for k, x in spec.initial_v:
        v[k] = x
    set_initial(q, v, spec.dispersions, values)
    sim.set_state(q, v)
    drive(sim, spec.scene)
    for kind, target, time in spec.events:
        sim.schedule(time, kind, target)
    add_sources_and_events(sim, q, spec.dispersions, values)
    return sim


def run_one(spec, run_id: int) -> RunOutcome:
    """Run `run_id` of the checked Spec `spec`: its row of the results table and its decimated trajectory
    (soadyn.campaign.run_one checks its arguments first)."""
    values = draw(spec, run_id)
    row = {"run_id": run_id, **dict(zip(spec.dispersion_columns, values))}
    trajectory = None
    try:
        sim = prepare(spec, values)
        trajectory = sim.run(spec.duration)
        metrics = evaluate(spec.metrics, sim._model, trajectory, sim)
    except Exception as error:  # noqa: BLE001 - any failure of one run is that run's result
        partial = getattr(error, "trajectory", trajectory)
        row.update(dict.fromkeys(spec.metrics))
        row.update(status="failed", message=f"{type(error).__name__}: {_one_line(error)}")
        return RunOutcome(row, _decimate(partial, spec.trajectory_every))
    row.update(metrics)
    row.update(status="ok", message="")
    return RunOutcome(row, _decimate(trajectory, spec.trajectory_every))


def run_chunk(spec, run_ids) -> list:
    """run_one for each id (a Dask task: a few tens of runs, so the scheduling costs little per run)."""
    return [run_one(spec, int(i)) for i in run_ids]


def failed_outcome(spec, run_id: int, message: str) -> RunOutcome:
    """The row of a run that never returned (its worker died): drawn values, no metrics."""
    row = {"run_id": run_id, **dict(zip(spec.dispersion_columns, draw(spec, run_id)))}
    row.update(dict.fromkeys(spec.metrics))
    row.update(status="failed", message=message)
    return RunOutcome(row, None)


def _decimate(trajectory, every: int) -> Optional[dict]:
    if not every or trajectory is None:
        return None
    return {"t": trajectory.t[::every].copy(), "q": trajectory.q[::every].copy(), "v": trajectory.v[::every].copy()}


def _one_line(error: BaseException) -> str:
    return " ".join(str(error).split()) or type(error).__name__
