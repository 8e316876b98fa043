"""The checks of each table of a campaign spec (spec.py runs them in order and assembles the Spec).

A check either raises ValueError naming the item at fault (a spec's problems.Problems records it)
or, where a table can hold several problems at once, adds each to `problems` and returns what it
could read (None for an item at fault).
"""
from __future__ import annotations

import math
import os
import sys
from pathlib import Path
from typing import Optional

from .. import scenes
from ..bounded_input import MAX_INPUT_BYTES
from ..hil.events import parse_event
from ..io.model_file import ModelFileError, model_from_json, model_to_json
from ..simulator import Simulator
from .dispersions import parse_dispersion
from .metrics import resolve
from .problems import Problems, closest, finite_number, shown, spec_error
from .starts import SCENE_NAMES

TOP_KEYS = ("name", "seed", "runs", "model", "simulation", "initial", "dispersions", "outputs")
SIMULATION_KEYS = ("duration", "dt", "rate", "integrator", "events")
INTEGRATORS = ("euler", "rk4", "dopri5")
RESERVED_COLUMNS = ("run_id", "status", "message")
MAX_RUNS = 10**8


def regular_file_text(path: Path) -> str:
    """The UTF-8 text of a regular file; OSError for a directory, a device or a pipe (which may
    never end), ValueError for bytes that are not UTF-8."""
    if path.exists() and not path.is_file():
        raise OSError(0, "not a regular file")
    size = path.stat().st_size
    if size > MAX_INPUT_BYTES:
        raise OSError(0, f"{size} bytes, more than the {MAX_INPUT_BYTES} bytes (512 MiB) soadyn reads from one file")
    return path.read_text(encoding="utf-8")


# The top-level keys

def check_name(raw: dict, source: str) -> str:
    name = raw.get("name", Path(source).stem if source != "<dict>" else "campaign")
    if not isinstance(name, str) or not name.strip():
        raise ValueError(f"name must be a non-empty string, got {shown(name)}")
    return name


def check_seed(raw: dict) -> int:
    if "seed" not in raw:
        raise ValueError("seed is required (an integer >= 0: run i draws from SeedSequence(seed).spawn(runs)[i])")
    seed = raw["seed"]
    if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        raise ValueError(f"seed must be an integer >= 0, got {shown(seed)}")
    return seed


def check_runs(raw: dict) -> int:
    if "runs" not in raw:
        raise ValueError("runs is required (the number of runs, >= 1)")
    return runs_in_range(raw["runs"], "runs", None)


def runs_in_range(value, what: str, source: Optional[str]) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or not 1 <= value <= MAX_RUNS:
        message = f"{what} must be an integer in 1..{MAX_RUNS}, got {shown(value)}"
        raise spec_error(source, message) if source else ValueError(message)
    return value


def check_keys(table: dict, keys, where: str, problems: Problems) -> None:
    for key in sorted(set(table) - set(keys), key=str):
        problems.add(f"{where}: unknown key {shown(key)}{closest(key, keys)}")


def _table(raw: dict, key: str, required: bool = False) -> dict:
    if key not in raw:
        if required:
            raise ValueError(f"[{key}] is required")
        return {}
    if not isinstance(raw[key], dict):
        raise ValueError(f"{key} must be a table ([{key}]), got {shown(raw[key])}")
    return raw[key]


# [model]

def check_model(raw: dict, base: Path, model_json: Optional[str]) -> tuple:
    """(model, model-file text, scene or None, the normalized [model] table)."""
    table = _table(raw, "model", required=True)
    unknown = sorted(set(table) - {"scene", "file"}, key=str)
    if unknown:
        raise ValueError(f"[model]: unknown key {shown(unknown[0])}{closest(unknown[0], ('scene', 'file'))}")
    if ("scene" in table) == ("file" in table):
        raise ValueError("[model]: give scene (a built-in scene) or file (a model file), one of the two")
    scene = table.get("scene")
    if scene is not None:
        if not isinstance(scene, str) or scene not in SCENE_NAMES:
            raise ValueError(f"[model]: unknown scene {shown(scene)}{closest(scene, SCENE_NAMES, 'scenes')}")
        text = model_json if model_json is not None else model_to_json(scenes.SCENES[scene]())
        normalized = {"scene": scene}
    else:
        file = table["file"]
        if not isinstance(file, str):
            raise ValueError(f"[model]: file must be a path string, got {shown(file)}")
        normalized = {"file": file}
        text = model_json if model_json is not None else _model_text(base, file)
    try:
        model = model_from_json(text, f"[model] {scene or file}")
    except ModelFileError as error:
        raise ValueError(str(error)) from None
    return model, text, scene, normalized


def _model_text(base: Path, file: str) -> str:
    path = base / file
    try:
        return regular_file_text(path)
    except (OSError, ValueError) as error:  # ValueError: not UTF-8, or a NUL byte in the path
        raise ValueError(f"[model]: cannot read the model file {shown(os.fspath(path))}: "
                         f"{getattr(error, 'strerror', None) or error}") from None


# [simulation]

def check_simulation(raw: dict, problems: Problems) -> tuple:
    """(duration, dt, integrator, event texts), None for each one at fault."""
    table = problems.check(_table, raw, "simulation", True)
    if table is None:
        return None, None, None, []
    check_keys(table, SIMULATION_KEYS, "[simulation]", problems)
    duration = problems.check(_positive, table, "duration", "[simulation]", True)
    dt = problems.check(_step, table)
    integrator = table.get("integrator", "rk4")
    if not isinstance(integrator, str) or integrator not in INTEGRATORS:
        problems.add(f"[simulation]: integrator must be one of {', '.join(INTEGRATORS)}, got {shown(integrator)}")
        integrator = None
    events = table.get("events", [])
    if not isinstance(events, list):
        problems.add(f"[simulation]: events must be a list of 'lock|release <DOF> at <s>', got {shown(events)}")
        events = []
    return duration, dt, integrator, events


def _step(table: dict) -> float:
    """dt from dt or rate."""
    if ("dt" in table) == ("rate" in table):
        raise ValueError("[simulation]: give dt (s) or rate (steps per s), one of the two")
    if "dt" in table:
        return _positive(table, "dt", "[simulation]")
    rate = _positive(table, "rate", "[simulation]")
    dt = 1.0 / rate
    if not (math.isfinite(dt) and dt > 0):
        raise ValueError(f"[simulation]: rate {rate!r} gives a step of {dt!r} s: give a rate in "
                         f"({1 / sys.float_info.max:g}, {sys.float_info.max:g})")
    return dt


def _positive(table: dict, key: str, where: str, required: bool = False) -> float:
    if key not in table:
        if required:
            raise ValueError(f"{where}: {key} is required")
        return math.nan
    value = finite_number(table[key])
    if value is None or not value > 0:
        raise ValueError(f"{where}: {key} must be a finite number > 0, got {shown(table[key])}")
    return value


def check_step_count(model, duration: float, dt: float) -> int:
    try:
        steps = Simulator(model, dt, "euler").steps_in(duration)  # the count does not depend on the integrator
    except ValueError as error:
        raise ValueError(f"[simulation] duration and dt: {error}") from None
    if steps == 0:
        raise ValueError(f"[simulation] duration and dt: duration {duration!r} s is shorter than one step of "
                         f"dt = {dt!r} s")
    return steps


def check_events(texts: list, model, problems: Problems) -> tuple:
    events = []
    for i, text in enumerate(texts):
        where = f"[simulation] events[{i}]"
        if not isinstance(text, str):
            problems.add(f"{where}: must be a string 'lock|release <DOF> at <s>', got {shown(text)}")
            continue
        try:
            event = parse_event(text)
            model._require_regular_modal_dofs(model._dof_indices(event.target))
        except ValueError as error:
            problems.add(f"{where}: {error}")
            continue
        events.append((event.kind, event.target, float(event.time)))
    return tuple(events)


# [initial], [[dispersions]], [outputs]

def check_initial(raw: dict, model, problems: Problems) -> tuple:
    """((coordinate index, value), ...), ((DOF index, value), ...) of [initial] q and v."""
    initial = problems.check(_table, raw, "initial", default={})
    check_keys(initial, ("q", "v"), "[initial]", problems)
    return (_initial_values(initial, "q", list(model.coordinate_names), problems),
            _initial_values(initial, "v", list(model.dof_names), problems))


def _initial_values(initial: dict, key: str, names: list, problems: Problems) -> tuple:
    values = initial.get(key, {})
    if not isinstance(values, dict):
        problems.add(f"[initial]: {key} must be a table of name = value, got {shown(values)}")
        return ()
    what = "coordinate" if key == "q" else "DOF"
    out = []
    for name, value in values.items():
        if name not in names:
            problems.add(f"[initial] {key}: unknown {what} {shown(name)}{closest(name, names, what + 's')}")
        elif finite_number(value) is None:
            problems.add(f"[initial] {key}.{name}: must be a finite number, got {shown(value)}")
        else:
            out.append((names.index(name), finite_number(value)))
    return tuple(out)


def check_dispersions(raw: dict, model, start, problems: Problems) -> list:
    """The Dispersion of each entry, None for an entry at fault (its problems recorded)."""
    entries = raw.get("dispersions", [])
    if not isinstance(entries, list):
        problems.add(f"dispersions must be an array of tables ([[dispersions]]), got {shown(entries)}")
        return []
    return [parse_dispersion(e, f"dispersions[{i}]", model, start, problems) for i, e in enumerate(entries)]


def check_metrics(raw: dict, model, problems: Problems) -> Optional[list]:
    """The metric names of [outputs] (None if metrics is not a list)."""
    outputs = problems.check(_table, raw, "outputs", True, default={})
    check_keys(outputs, ("metrics", "trajectory_every"), "[outputs]", problems)
    names = outputs.get("metrics", [])
    if not isinstance(names, list):
        problems.add(f"[outputs]: metrics must be a list of names, got {shown(names)}")
        return None
    for i, name in enumerate(names):
        problems.check(_metric, name, model, f"[outputs] metrics[{i}]")
    return names


def _metric(name, model, where: str) -> None:
    try:
        resolve(name, model)
    except ValueError as error:
        raise ValueError(f"{where}: {error}") from None


def check_trajectory_every(raw: dict) -> int:
    outputs = raw.get("outputs")
    every = outputs.get("trajectory_every", 0) if isinstance(outputs, dict) else 0
    if isinstance(every, bool) or not isinstance(every, int) or every < 0:
        raise ValueError(f"[outputs]: trajectory_every must be an integer >= 0 (0: no trajectories), "
                         f"got {shown(every)}")
    return every


def unique_dispersions(dispersions: list, problems: Problems) -> list:
    """The dispersions (None: an entry at fault) that disperse what no earlier one does; a problem
    for each of the others."""
    seen, distinct = {}, []
    for i, d in enumerate(dispersions):
        if d is None:
            continue
        key = (d.kind, d.mode, d.target, d.index)
        if key in seen:
            problems.add(f"dispersions[{i}] ({d.kind} {shown(d.text)}): disperses what dispersions[{seen[key]}] "
                         f"already does")
        else:
            seen[key] = i
            distinct.append(d)
    return distinct


def unique_columns(dispersed: list, metric_names: list, problems: Problems) -> None:
    seen = set()
    for column in [*dispersed, *(m for m in metric_names if isinstance(m, str))]:
        if column in RESERVED_COLUMNS:
            problems.add(f"column {shown(column)} is reserved (run_id, status, message): give the dispersion a name")
        elif column in seen:
            problems.add(f"two columns are named {shown(column)}: give a dispersion a distinct name, or list a "
                         f"metric once")
        seen.add(column)
