"""Campaign specs: a TOML file (or the dict it holds) read and checked completely before any run.

    name = "cassini-example"        # optional (default: the file's stem)
    seed = 1                        # run i draws from SeedSequence(seed).spawn(runs)[i]
    runs = 1000

    [model]
    scene = "cassini"               # a built-in scene, or file = "model.json" (relative to this file)

    [simulation]
    duration = 1.0                  # s, a whole number of steps
    dt = 0.001                      # or rate = 1000 (steps per s)
    integrator = "rk4"              # euler, rk4, dopri5
    events = ["lock scan_el at 0.5"]    # optional fixed events

    [initial]                       # optional: start-state entries over the scene's start
    q = { scan_az = 0.1 }
    v = { scan_az = 0.0 }

    [[dispersions]]                 # any number, drawn in this order
    parameter = "bus.mass"          # or initial = "q:<coord>" / "v:<DOF>", event = "lock <DOF>",
    distribution = "normal"         #    source = "velocity:<DOF>" / "input:<DOF>" (dispersions.py)
    scale = 0.05                    # normal: mean (default nominal) and std, or scale (std / |nominal|);
                                    # uniform: low and high, or scale; lognormal: median (default nominal), sigma
    [outputs]
    metrics = ["peak_boom_tip_deflection", "final_attitude_error"]   # metrics.py
    trajectory_every = 0            # keep every k-th step of each run's trajectory (0: none)

Every error is a SpecError naming the file and the item (`dispersions[2] (parameter 'bus.mas')`).
"""
from __future__ import annotations

import dataclasses
import hashlib
import math
import numbers
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Optional

from .. import scenes
from ..model_file import ModelFileError, model_from_json, model_to_json
from .dispersions import parse_dispersion
from .errors import SpecError
from .metrics import resolve
from .starts import SCENE_NAMES, start_state

FORMAT = "soadyn-campaign"
FORMAT_VERSION = 1
TOP_KEYS = ("name", "seed", "runs", "model", "simulation", "initial", "dispersions", "outputs")
SIMULATION_KEYS = ("duration", "dt", "rate", "integrator", "events")
INTEGRATORS = ("euler", "rk4", "dopri5")
RESERVED_COLUMNS = ("run_id", "status", "message")
MAX_RUNS = 10**8
EXAMPLES_DIR = Path(__file__).parent / "examples"
EXAMPLES = {"cassini-example": EXAMPLES_DIR / "cassini.toml"}


@dataclass(frozen=True)
class Spec:
    """A checked campaign spec; also what a worker receives (plain data and the model-file text)."""

    name: str
    seed: int
    runs: int
    source: str                       # the spec file, example name or "<dict>"
    model_json: str                   # the model-file text every run builds its model from
    model_sha256: str
    scene: Optional[str]              # the built-in scene (its start state and drives), or None for a file
    dt: float
    duration: float
    integrator: str
    events: tuple                     # ((kind, target, time), ...) fixed events
    initial_q: tuple                  # ((coordinate index, value), ...)
    initial_v: tuple
    dispersions: tuple                # (Dispersion, ...)
    metrics: tuple                    # metric names
    trajectory_every: int
    coordinate_names: tuple
    dof_names: tuple
    normalized: dict                  # the spec as a TOML-shaped dict with every number resolved
    text: Optional[str] = None        # the TOML text it was read from

    @property
    def dispersion_columns(self) -> list:
        return [d.column for d in self.dispersions]

    @property
    def columns(self) -> list:
        return ["run_id", *self.dispersion_columns, *self.metrics, "status", "message"]

    def identity(self) -> dict:
        """What decides every run's result: the spec without `runs` (run i does not depend on it) and
        with the model file's text (its hash) in place of its path."""
        ident = {k: v for k, v in self.normalized.items() if k != "runs"}
        ident["model"] = {"scene": self.scene} if self.scene else {"file_sha256": self.model_sha256}
        ident["model_sha256"] = self.model_sha256
        return ident

    def with_runs(self, runs: int) -> "Spec":
        runs = _runs(runs, "runs (override)", self.source)
        return dataclasses.replace(self, runs=runs, normalized={**self.normalized, "runs": runs})


def load_spec(spec, runs: Optional[int] = None, base_dir=None, model_json: Optional[str] = None) -> Spec:
    """A checked Spec from a TOML file path, a built-in example name (EXAMPLES), a dict of the
    TOML's content (model files relative to `base_dir`, default the current directory) or a Spec.
    `runs` overrides the spec's number of runs. `model_json` replaces the model the spec names
    (a replay uses the text the campaign stored). SpecError names the item at fault."""
    if isinstance(spec, Spec):
        return spec if runs is None else spec.with_runs(runs)
    text = None
    if isinstance(spec, dict):
        source, raw = "<dict>", spec
        base = Path(base_dir) if base_dir is not None else Path.cwd()
    elif isinstance(spec, (str, os.PathLike)):
        path = Path(spec)
        if isinstance(spec, str) and spec in EXAMPLES and not path.exists():
            path = EXAMPLES[spec]
        source = os.fspath(spec)
        try:
            text = path.read_text(encoding="utf-8")
        except (OSError, UnicodeDecodeError) as error:
            known = f" (built-in examples: {', '.join(EXAMPLES)})" if not path.exists() else ""
            raise SpecError(f"{source}: cannot read the spec: {error.strerror or error}{known}") from None
        raw = parse_toml(text, source)
        base = path.parent
    else:
        raise TypeError(f"a campaign spec is a TOML path, an example name, a dict or a Spec, got {type(spec).__name__}")
    checked = check_spec(raw, source, base, model_json)
    checked = dataclasses.replace(checked, text=text)
    return checked if runs is None else checked.with_runs(runs)


def parse_toml(text: str, source: str) -> dict:
    try:
        import tomllib
    except ImportError:  # Python < 3.11
        try:
            import tomli as tomllib
        except ImportError:
            raise SpecError(f"{source}: reading a TOML spec needs Python 3.11 or the tomli package") from None
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as error:
        raise SpecError(f"{source}: not valid TOML: {error}") from None


def check_spec(raw: dict, source: str, base: Path, model_json: Optional[str] = None) -> Spec:
    """Every check of a spec's content; SpecError naming `source` and the item."""
    try:
        return _check(raw, source, base, model_json)
    except SpecError:
        raise
    except ValueError as error:
        raise SpecError(f"{source}: {error}") from None


def _check(raw, source, base, model_json) -> Spec:
    _known(raw, TOP_KEYS, "the spec")
    name = raw.get("name", Path(source).stem if source != "<dict>" else "campaign")
    if not isinstance(name, str) or not name.strip():
        raise ValueError(f"name must be a non-empty string, got {name!r}")
    if "seed" not in raw:
        raise ValueError("seed is required (an integer >= 0: run i draws from SeedSequence(seed).spawn(runs)[i])")
    seed = raw["seed"]
    if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        raise ValueError(f"seed must be an integer >= 0, got {seed!r}")
    if "runs" not in raw:
        raise ValueError("runs is required (the number of runs, >= 1)")
    runs = _runs(raw["runs"], "runs", None)

    model_table = _table(raw, "model", required=True)
    _known(model_table, ("scene", "file"), "[model]")
    if ("scene" in model_table) == ("file" in model_table):
        raise ValueError("[model]: give scene (a built-in scene) or file (a model file), one of the two")
    scene = model_table.get("scene")
    if scene is not None:
        if scene not in SCENE_NAMES:
            raise ValueError(f"[model]: unknown scene {scene!r} (scenes: {', '.join(SCENE_NAMES)})")
        text = model_json if model_json is not None else model_to_json(scenes.SCENES[scene]())
        normalized_model = {"scene": scene}
    else:
        file = model_table["file"]
        if not isinstance(file, str):
            raise ValueError(f"[model]: file must be a path string, got {file!r}")
        normalized_model = {"file": file}
        if model_json is not None:
            text = model_json
        else:
            path = base / file
            try:
                text = path.read_text(encoding="utf-8")
            except (OSError, UnicodeDecodeError) as error:
                raise ValueError(f"[model]: cannot read the model file {os.fspath(path)!r}: "
                                 f"{getattr(error, 'strerror', None) or error}") from None
    try:
        model = model_from_json(text, f"[model] {scene or normalized_model['file']}")
    except ModelFileError as error:
        raise ValueError(str(error)) from None
    sha = hashlib.sha256(text.encode("utf-8")).hexdigest()

    sim_table = _table(raw, "simulation", required=True)
    _known(sim_table, SIMULATION_KEYS, "[simulation]")
    duration = _positive(sim_table, "duration", "[simulation]", required=True)
    if ("dt" in sim_table) == ("rate" in sim_table):
        raise ValueError("[simulation]: give dt (s) or rate (steps per s), one of the two")
    dt = _positive(sim_table, "dt", "[simulation]") if "dt" in sim_table else \
        1.0 / _positive(sim_table, "rate", "[simulation]")
    integrator = sim_table.get("integrator", "rk4")
    if integrator not in INTEGRATORS:
        raise ValueError(f"[simulation]: integrator must be one of {', '.join(INTEGRATORS)}, got {integrator!r}")
    from ..simulator import Simulator

    try:
        Simulator(model, dt, integrator).steps_in(duration)
    except ValueError as error:
        raise ValueError(f"[simulation]: duration: {error}") from None
    events = _events(sim_table.get("events", []), model)

    q0, v0 = start_state(scene, model)
    initial = _table(raw, "initial")
    _known(initial, ("q", "v"), "[initial]")
    initial_q = _initial_values(initial, "q", list(model.coordinate_names))
    initial_v = _initial_values(initial, "v", list(model.dof_names))
    for k, x in initial_q:
        q0[k] = x
    for k, x in initial_v:
        v0[k] = x

    entries = raw.get("dispersions", [])
    if not isinstance(entries, list):
        raise ValueError("dispersions must be an array of tables ([[dispersions]])")
    dispersions = tuple(parse_dispersion(e, f"dispersions[{i}]", model, (q0, v0)) for i, e in enumerate(entries))
    _unique_dispersions(dispersions)

    outputs = _table(raw, "outputs", required=True)
    _known(outputs, ("metrics", "trajectory_every"), "[outputs]")
    metric_names = outputs.get("metrics", [])
    if not isinstance(metric_names, list):
        raise ValueError(f"[outputs]: metrics must be a list of names, got {metric_names!r}")
    for i, metric in enumerate(metric_names):
        try:
            resolve(metric, model)
        except ValueError as error:
            raise ValueError(f"[outputs] metrics[{i}]: {error}") from None
    every = outputs.get("trajectory_every", 0)
    if isinstance(every, bool) or not isinstance(every, int) or every < 0:
        raise ValueError(f"[outputs]: trajectory_every must be an integer >= 0 (0: no trajectories), got {every!r}")
    if not metric_names and not every:
        raise ValueError("[outputs]: nothing to keep: give metrics, trajectory_every > 0, or both")
    _unique_columns([d.column for d in dispersions], metric_names)

    normalized = {"name": name, "seed": seed, "runs": runs, "model": normalized_model,
                  "simulation": {"duration": duration, "dt": dt, "integrator": integrator,
                                 "events": [f"{k} {t} at {time!r}" for k, t, time in events]},
                  "initial": {"q": {model.coordinate_names[k]: x for k, x in initial_q},
                              "v": {model.dof_names[k]: x for k, x in initial_v}},
                  "dispersions": [d.to_dict() for d in dispersions],
                  "outputs": {"metrics": list(metric_names), "trajectory_every": every}}
    spec = Spec(name=name, seed=seed, runs=runs, source=source, model_json=text, model_sha256=sha, scene=scene,
                dt=dt, duration=duration, integrator=integrator, events=events, initial_q=initial_q,
                initial_v=initial_v, dispersions=dispersions, metrics=tuple(metric_names), trajectory_every=every,
                coordinate_names=tuple(model.coordinate_names), dof_names=tuple(model.dof_names),
                normalized=normalized)
    _trial(spec)
    return spec


def _trial(spec: Spec) -> None:
    """Set up (not step) a run of the nominal model with the other dispersions at the centres of
    their distributions: sources and events the simulator refuses are found before any run. (A
    dispersed parameter value the model refuses fails that run only.)"""
    from .simulate import prepare

    others = tuple(d for d in spec.dispersions if d.kind != "parameter")
    centres = [d.distribution.a if d.distribution.kind != "uniform" else
               0.5 * (d.distribution.a + d.distribution.b) for d in others]
    try:
        prepare(dataclasses.replace(spec, dispersions=others), centres)
    except Exception as error:  # noqa: BLE001 - named in the message
        raise ValueError(f"a run cannot be set up at the distributions' centres: {type(error).__name__}: "
                         f"{' '.join(str(error).split())}") from None


def _runs(value, what: str, source: Optional[str]) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or not 1 <= value <= MAX_RUNS:
        message = f"{what} must be an integer in 1..{MAX_RUNS}, got {value!r}"
        raise SpecError(f"{source}: {message}") if source else ValueError(message)
    return value


def _known(table: dict, keys, where: str) -> None:
    unknown = sorted(set(table) - set(keys))
    if unknown:
        raise ValueError(f"{where}: unknown key {unknown[0]!r} (known: {', '.join(keys)})")


def _table(raw: dict, key: str, required: bool = False) -> dict:
    if key not in raw:
        if required:
            raise ValueError(f"[{key}] is required")
        return {}
    if not isinstance(raw[key], dict):
        raise ValueError(f"{key} must be a table ([{key}]), got {raw[key]!r}")
    return raw[key]


def _positive(table: dict, key: str, where: str, required: bool = False) -> float:
    if key not in table:
        if required:
            raise ValueError(f"{where}: {key} is required")
        return math.nan
    value = table[key]
    if isinstance(value, bool) or not isinstance(value, numbers.Real) or not (math.isfinite(value) and value > 0):
        raise ValueError(f"{where}: {key} must be a finite number > 0, got {value!r}")
    return float(value)


def _events(texts, model) -> tuple:
    from ..hil import parse_event

    if not isinstance(texts, list):
        raise ValueError(f"[simulation]: events must be a list of 'lock|release <DOF> at <s>', got {texts!r}")
    events = []
    for i, text in enumerate(texts):
        where = f"[simulation] events[{i}]"
        if not isinstance(text, str):
            raise ValueError(f"{where}: must be a string 'lock|release <DOF> at <s>', got {text!r}")
        try:
            event = parse_event(text)
            model._require_regular_modal_dofs(model._dof_indices(event.target))
        except ValueError as error:
            raise ValueError(f"{where}: {error}") from None
        events.append((event.kind, event.target, float(event.time)))
    return tuple(events)


def _initial_values(initial: dict, key: str, names: list) -> tuple:
    values = initial.get(key, {})
    if not isinstance(values, dict):
        raise ValueError(f"[initial]: {key} must be a table of name = value, got {values!r}")
    out = []
    for name, value in values.items():
        if name not in names:
            what = "coordinate" if key == "q" else "DOF"
            raise ValueError(f"[initial] {key}: unknown {what} {name!r} (the model's {what}s: {', '.join(names)})")
        if isinstance(value, bool) or not isinstance(value, numbers.Real) or not math.isfinite(value):
            raise ValueError(f"[initial] {key}.{name}: must be a finite number, got {value!r}")
        out.append((names.index(name), float(value)))
    return tuple(out)


def _unique_dispersions(dispersions) -> None:
    seen = {}
    for i, d in enumerate(dispersions):
        key = (d.kind, d.mode, d.target, d.index)
        if key in seen:
            raise ValueError(f"dispersions[{i}] ({d.kind} {d.text!r}): disperses what dispersions[{seen[key]}] "
                             f"already does")
        seen[key] = i


def _unique_columns(dispersed: list, metric_names: list) -> None:
    seen = set()
    for column in [*dispersed, *metric_names]:
        if column in RESERVED_COLUMNS:
            raise ValueError(f"column {column!r} is reserved (run_id, status, message): give the dispersion a name")
        if column in seen:
            raise ValueError(f"two columns are named {column!r}: give a dispersion a distinct name, "
                             f"or list a metric once")
        seen.add(column)
