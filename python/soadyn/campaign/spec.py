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

Every problem names its item (`dispersions[2] (parameter 'bus.mas')`); one SpecError, naming the file,
lists every problem of a spec at once.
"""
from __future__ import annotations

import dataclasses
import hashlib
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Optional

from ..bounded_input import MAX_NESTING_DEPTH
from .problems import Problems, shown, spec_error
from .simulate import prepare
from .starts import start_state
from .tables import (TOP_KEYS, check_dispersions, check_events, check_initial, check_keys, check_metrics, check_model,
                     check_name, check_runs, check_seed, check_simulation, check_step_count, check_trajectory_every,
                     regular_file_text, runs_in_range, unique_columns, unique_dispersions)

FORMAT = "soadyn-campaign"
FORMAT_VERSION = 1
EXAMPLES_DIR = Path(__file__).parent / "examples"
EXAMPLES = {"cassini-example": EXAMPLES_DIR / "cassini.toml"}
"""{name: path} of the bundled campaign specs, which `soadyn campaign run NAME` takes by name."""


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
        """The results table's column of each dispersion, in the spec's order."""
        return [d.column for d in self.dispersions]

    @property
    def columns(self) -> list:
        """Every column of the results table: run_id, the dispersions', the metrics', status, message."""
        return ["run_id", *self.dispersion_columns, *self.metrics, "status", "message"]

    def identity(self) -> dict:
        """What decides every run's result: the spec without `runs` (run i does not depend on it) and
        with the model file's text (its hash) in place of its path."""
        ident = {k: v for k, v in self.normalized.items() if k != "runs"}
        ident["model"] = {"scene": self.scene} if self.scene else {"file_sha256": self.model_sha256}
        ident["model_sha256"] = self.model_sha256
        return ident

    def with_runs(self, runs: int) -> "Spec":
        """This spec with `runs` runs (run i's draws do not depend on it); SpecError for a count out of range."""
        runs = runs_in_range(runs, "runs (override)", self.source)
        return dataclasses.replace(self, runs=runs, normalized={**self.normalized, "runs": runs})


def load_spec(spec, runs: Optional[int] = None, base_dir=None, model_json: Optional[str] = None) -> Spec:
    """A checked Spec from a TOML file path, a built-in example name (EXAMPLES), a dict of the
    TOML's content (model files relative to `base_dir`, default the current directory) or a Spec.
    `runs` overrides the spec's number of runs. `model_json` replaces the model the spec names
    (a replay uses the text the campaign stored). One SpecError lists every problem found, each
    naming its item."""
    if isinstance(spec, Spec):
        return spec if runs is None else spec.with_runs(runs)
    text = None
    if isinstance(spec, dict):
        source, raw = "<dict>", spec
        base = Path(base_dir) if base_dir is not None else Path.cwd()
    elif isinstance(spec, (str, os.PathLike)):
        source = os.fspath(spec)
        path = EXAMPLES[spec] if isinstance(spec, str) and spec in EXAMPLES and not _exists(spec) else Path(spec)
        text = _read(path, source)
        raw = parse_toml(text, source)
        base = path.parent
    else:
        raise TypeError(f"a campaign spec is a TOML path, an example name, a dict or a Spec, got {type(spec).__name__}")
    checked = check_spec(raw, source, base, model_json)
    checked = dataclasses.replace(checked, text=text)
    return checked if runs is None else checked.with_runs(runs)


def _exists(path) -> bool:
    try:
        return Path(path).exists()
    except (OSError, ValueError):  # ValueError: a NUL byte in the path
        return False


def _read(path: Path, source: str) -> str:
    try:
        return regular_file_text(path)
    except (OSError, ValueError) as error:  # ValueError: not UTF-8, or a NUL byte in the path
        known = f" (built-in examples: {', '.join(EXAMPLES)})" if not _exists(path) else ""
        raise spec_error(source, f"cannot read the spec: {getattr(error, 'strerror', None) or error}{known}") \
            from None


def parse_toml(text: str, source: str) -> dict:
    try:
        import tomllib
    except ImportError:  # Python < 3.11
        try:
            import tomli as tomllib
        except ImportError:
            raise spec_error(source, "not valid TOML: reading TOML needs Python 3.11 or the tomli package") from None
    too_deep = f"not valid TOML: arrays or tables nested more than the {MAX_NESTING_DEPTH} levels soadyn reads"
    try:
        raw = tomllib.loads(text)
    except ValueError as error:  # TOMLDecodeError, or an integer of more digits than Python converts
        raise spec_error(source, f"not valid TOML: {' '.join(str(error).split())}") from None
    except RecursionError:
        raise spec_error(source, too_deep) from None
    if nesting_depth(raw) > MAX_NESTING_DEPTH:  # dotted keys (a.a.a... = 1) nest without the parser recursing
        raise spec_error(source, too_deep)
    return raw


def nesting_depth(value) -> int:
    """How many levels of tables and arrays `value` nests (0 for a plain value), without recursion."""
    deepest, stack = 0, [(value, 0)]
    while stack:
        item, depth = stack.pop()
        children = item.values() if isinstance(item, dict) else item if isinstance(item, list) else None
        if children is None:
            continue
        deepest = max(deepest, depth + 1)
        if deepest > MAX_NESTING_DEPTH:
            break
        stack.extend((child, depth + 1) for child in children)
    return deepest


def check_spec(raw: dict, source: str, base: Path, model_json: Optional[str] = None) -> Spec:
    """Every check of a spec's content; one SpecError naming `source` and listing every problem.
    The checks that need the model (names of DOFs, parameters, metrics) wait for a model that loads;
    a trial set-up of a run waits for a spec without other problems."""
    problems = Problems(source)
    if not isinstance(raw, dict):
        problems.add(f"a spec is a table of keys, got {shown(raw)}")
        problems.raise_if_any()
    spec = _check(raw, problems, base, model_json)
    problems.raise_if_any()
    problems.check(_trial, spec)
    problems.raise_if_any()
    return spec


def _check(raw, problems: Problems, base, model_json) -> Optional[Spec]:
    check = problems.check
    check_keys(raw, TOP_KEYS, "the spec", problems)
    name = check(check_name, raw, problems.source)
    seed = check(check_seed, raw)
    runs = check(check_runs, raw)
    loaded = check(check_model, raw, base, model_json)
    duration, dt, integrator, event_texts = check_simulation(raw, problems)
    every = check(check_trajectory_every, raw)
    if loaded is None:
        return None
    model, text, scene, normalized_model = loaded
    if duration is not None and dt is not None:
        check(check_step_count, model, duration, dt)
    events = check_events(event_texts, model, problems)
    q0, v0 = start_state(scene, model)
    initial_q, initial_v = check_initial(raw, model, problems)
    for k, x in initial_q:
        q0[k] = x
    for k, x in initial_v:
        v0[k] = x
    parsed = check_dispersions(raw, model, (q0, v0), problems)
    metric_names = check_metrics(raw, model, problems)
    if metric_names == [] and every == 0:
        problems.add("[outputs]: nothing to keep: give metrics, trajectory_every > 0, or both")
    distinct = unique_dispersions(parsed, problems)
    unique_columns([d.column for d in distinct], metric_names or [], problems)
    if problems.messages:
        return None
    dispersions = tuple(parsed)
    normalized = {"name": name, "seed": seed, "runs": runs, "model": normalized_model,
                  "simulation": {"duration": duration, "dt": dt, "integrator": integrator,
                                 "events": [f"{k} {t} at {time!r}" for k, t, time in events]},
                  "initial": {"q": {model.coordinate_names[k]: x for k, x in initial_q},
                              "v": {model.dof_names[k]: x for k, x in initial_v}},
                  "dispersions": [d.to_dict() for d in dispersions],
                  "outputs": {"metrics": list(metric_names), "trajectory_every": every}}
    sha = hashlib.sha256(text.encode("utf-8")).hexdigest()
    return Spec(name=name, seed=seed, runs=runs, source=problems.source, model_json=text, model_sha256=sha,
                scene=scene, dt=dt, duration=duration, integrator=integrator, events=events, initial_q=initial_q,
                initial_v=initial_v, dispersions=dispersions, metrics=tuple(metric_names), trajectory_every=every,
                coordinate_names=tuple(model.coordinate_names), dof_names=tuple(model.dof_names),
                normalized=normalized)


def _trial(spec: Spec) -> None:
    """Set up (not step) a run of the nominal model with the other dispersions at the centres of
    their distributions: sources and events the simulator refuses are found before any run. (A
    dispersed parameter value the model refuses fails that run only.)"""
    others = tuple(d for d in spec.dispersions if d.kind != "parameter")
    centres = [d.distribution.a if d.distribution.kind != "uniform" else
               0.5 * (d.distribution.a + d.distribution.b) for d in others]
    try:
        prepare(dataclasses.replace(spec, dispersions=others), centres)
    except Exception as error:  # noqa: BLE001 - named in the message
        raise ValueError(f"a run cannot be set up at the distributions' centres: {type(error).__name__}: "
                         f"{' '.join(str(error).split())}") from None
