"""Hostile campaign specs, each drawn from one integer seed, for the spec loader
(soadyn.campaign.load_spec) alone: no run is simulated.

A case starts from the example spec (python/soadyn/campaign/examples/cassini.toml)
and mutates it: items that fit added (events, a rate, a model file, start
states, sources and every kind of dispersion); values replaced by NaN, inf,
5e-324, 1e308, huge integers, strings, lists, tables or deep nestings; keys
dropped, renamed (a letter changed) or added; then, as text, lines dropped or duplicated (a duplicate key),
characters changed, garbage bytes inserted, the text cut short. Or the case is
random bytes, or random TOML-like text. The property: load_spec returns a Spec
whose numbers are finite and whose description can be stored (JSON without
NaN), or raises SpecError whose message names the file and, for every problem,
the item at fault; anything else (another exception, a crash, a hang) fails.
The quick test is tests/fuzz/test_campaign_spec_fuzz.py; the long campaign
bench/fuzz_campaign.py --surface spec.
"""
from __future__ import annotations

import copy
import json
import math
import os
import re
import tempfile

import numpy as np

try:
    import tomllib
except ImportError:  # Python < 3.11
    import tomli as tomllib

from soadyn.campaign import EXAMPLES, SpecError, load_spec
from soadyn.campaign.tables import INTEGRATORS, MAX_RUNS

EXAMPLE = EXAMPLES["cassini-example"].read_text(encoding="utf-8")
# What every problem of a SpecError starts with: the item at fault.
ITEM = re.compile(r"(the spec|\[(model|simulation|initial|outputs)\]|dispersions(\[\d+\])?|name|seed|runs|"
                  r"model|simulation|initial|outputs|column|two columns|not valid TOML|cannot read the spec|"
                  r"a spec is|a run cannot be set up)(?=[ :(]|$)")
HOSTILE = [math.nan, math.inf, -math.inf, 5e-324, -5e-324, 1e308, -1e308, 0.0, -0.0, 0, -1, 2**63 - 1, -2**63,
           10**30, 2**70, "", "abc", "cassini", "rk4", "bus.mass", "lock scan_az at 0.5", "\u00e9\u0000x", [], [1, 2],
           ["a"], {}, {"x": 1}, True, False, 1e-300, 0.5, 1000]
# Keys a spec knows, and values some of them take: added to any table (mostly one they do not belong to).
KNOWN_KEYS = ["name", "seed", "runs", "model", "simulation", "initial", "dispersions", "outputs", "scene", "file",
              "duration", "dt", "rate", "integrator", "events", "q", "v", "metrics", "trajectory_every",
              "parameter", "event", "source", "distribution", "mean", "std", "scale", "low", "high", "median", "sigma"]
PLAUSIBLE = ["lock scan_el at 0.5", ["lock scan_el at 0.5"], ["release turntable at 0.1"], ["lock nothing at inf"],
             "velocity:turntable", "input:wheel_1", "input:turntable", "velocity:bus:wx", "q:scan_el", "v:scan_az",
             "q:bus:qw", {"scan_az": 0.1}, {"scan_az": 1e308}, {"bus:qw": math.nan}, "model.json", "/dev/zero",
             ".", "bus.inertia[0,2]", "bus.com[99999999999]", "gravity[2]", "lock magnetometer_boom:mode1",
             "normal", "uniform", "lognormal", "euler", "dopri5", "pendulum-chain", "four-bar", 1000, 0.001, 3,
             ["max_abs_q:scan_az", "final_energy"], ["attitude_error:bus", "peak_tip_deflection:bus"]]
# Items that fit where they go (table, key, value): the checks of events, rates, model files, start
# states, sources and the other kinds of dispersions, which the example does not use.
FITTING = [("simulation", "events", ["lock scan_el at 0.5", "release scan_el at 0.8"]),
           ("simulation", "events", ["lock magnetometer_boom:mode1 at 0.1"]),
           ("simulation", "events", ["lock turntable at 1e308"]), ("simulation", "rate", 1000),
           ("simulation", "integrator", "dopri5"), ("model", "file", "model.json"), ("model", "file", "/dev/zero"),
           ("initial", "q", {"scan_el": 0.2, "bus:qw": 0.5}), ("initial", "v", {"bus:wx": 1e308}),
           ("outputs", "metrics", ["max_abs_q:scan_az", "final_energy", "attitude_error:bus"]),
           ("outputs", "trajectory_every", 10)]
ENTRIES = [{"source": "velocity:turntable", "distribution": "normal", "mean": 0.3, "std": 0.01},
           {"source": "input:wheel_1", "distribution": "uniform", "low": -1.0, "high": 1.0},
           {"source": "input:turntable", "distribution": "normal", "mean": 0.0, "std": 1.0},
           {"initial": "q:scan_el", "distribution": "uniform", "scale": 0.1},
           {"initial": "v:scan_az", "distribution": "lognormal", "sigma": 0.1},
           {"event": "release turntable", "distribution": "uniform", "low": 0.1, "high": 0.2},
           {"parameter": "bus.inertia[0,2]", "distribution": "normal", "std": 1.0},
           {"parameter": "gravity[2]", "distribution": "uniform", "low": -1e308, "high": 1e308}]
KEY_CHARACTERS = "abcdefghijklmnopqrstuvwxyz_.[]"
TOML_CHARACTERS = list("[]{}=\"'.,#\n abcdefgnrstuvwxyz0123456789_-+e") + ["nan", "inf", "true", "[[", "]]"]


class Raw(str):
    """A value written into the TOML text as it is."""


# Integers beyond 64 bits (tomllib reads them), up to 8000 bits, one with more digits than Python converts,
# and arrays and tables nested deeper than Python's recursion limit.
RAW_VALUES = [Raw("0x" + "f" * 40), Raw("0x" + "f" * 2000), Raw("-" + "9" * 400), Raw("9" * 5000),
              Raw("[" * 3000 + "]" * 3000), Raw("{x = " * 3000 + "1" + "}" * 3000), Raw("[" * 200 + "]" * 200)]


def toml_value(x) -> str:
    """x as a TOML value (tables inline)."""
    if isinstance(x, bool):
        return "true" if x else "false"
    if isinstance(x, Raw):
        return str(x)
    if isinstance(x, int):
        return str(x)
    if isinstance(x, float):
        return "nan" if math.isnan(x) else ("inf" if x > 0 else "-inf") if math.isinf(x) else repr(x)
    if isinstance(x, str):
        return json.dumps(x)
    if isinstance(x, list):
        return "[" + ", ".join(toml_value(v) for v in x) + "]"
    return "{" + ", ".join(f"{json.dumps(str(k))} = {toml_value(v)}" for k, v in x.items()) + "}"


def toml_text(spec: dict) -> str:
    """A spec as TOML: top-level keys, one [table] per table, [[dispersions]] for a list of tables."""
    lines = [f"{json.dumps(k)} = {toml_value(v)}" for k, v in spec.items()
             if not isinstance(v, dict) and not (k == "dispersions" and _tables(v))]
    for key, value in spec.items():
        if isinstance(value, dict):
            lines += [f"[{json.dumps(key)}]"] + [f"{json.dumps(k)} = {toml_value(v)}" for k, v in value.items()]
        elif key == "dispersions" and _tables(value):
            for entry in value:
                lines += ["[[dispersions]]"] + [f"{json.dumps(k)} = {toml_value(v)}" for k, v in entry.items()]
    return "\n".join(lines) + "\n"


def _tables(value) -> bool:
    return isinstance(value, list) and bool(value) and all(isinstance(v, dict) for v in value)


def hostile_value(rng: np.random.Generator):
    r = rng.uniform()
    if r < 0.1:  # deep nesting
        depth = int(rng.integers(2, 60))
        value = [] if rng.uniform() < 0.5 else {}
        for _ in range(depth):
            value = [value] if rng.uniform() < 0.5 else {"x": value}
        return value
    if r < 0.15:
        return "x" * int(rng.integers(100, 5000))
    if r < 0.2:
        return float(rng.normal() * 10.0 ** rng.integers(-310, 309))
    if r < 0.25:
        return RAW_VALUES[rng.integers(len(RAW_VALUES))]
    return copy.deepcopy(HOSTILE[rng.integers(len(HOSTILE))])  # a case never changes the shared list


def misspelled(rng: np.random.Generator, key: str) -> str:
    if not key:
        return "x"
    k = int(rng.integers(len(key)))
    return key[:k] + KEY_CHARACTERS[rng.integers(len(KEY_CHARACTERS))] + key[k + 1:]


def places(spec: dict) -> list:
    """(container, key) of every value in the spec, nested tables and lists included."""
    found = []

    def walk(container):
        for key in (range(len(container)) if isinstance(container, list) else list(container)):
            found.append((container, key))
            if isinstance(container[key], (dict, list)):
                walk(container[key])

    walk(spec)
    return found


def add_fitting(spec: dict, rng: np.random.Generator) -> None:
    """One to three items that fit where they go, in place."""
    for _ in range(int(rng.integers(1, 4))):
        k = int(rng.integers(len(FITTING) + len(ENTRIES)))
        if k < len(FITTING):
            table, key, value = FITTING[k]
            spec.setdefault(table, {})[key] = copy.deepcopy(value)
        else:
            spec.setdefault("dispersions", []).append(copy.deepcopy(ENTRIES[k - len(FITTING)]))


def mutate_values(spec: dict, rng: np.random.Generator) -> None:
    """One to six changes of values and keys, in place."""
    for _ in range(int(rng.integers(1, 7))):
        container, key = places(spec)[rng.integers(len(places(spec)))]
        action = rng.uniform()
        if action < 0.55:
            container[key] = hostile_value(rng)
        elif action < 0.7:
            del container[key]
        elif isinstance(container, dict) and action < 0.85:
            container[misspelled(rng, key)] = container.pop(key)
        elif isinstance(container, dict) and action < 0.9:
            container[misspelled(rng, key)] = hostile_value(rng)
        elif isinstance(container, dict):
            value = PLAUSIBLE[rng.integers(len(PLAUSIBLE))] if rng.uniform() < 0.7 else hostile_value(rng)
            container[KNOWN_KEYS[rng.integers(len(KNOWN_KEYS))]] = copy.deepcopy(value)
        else:
            container.append(container[key])  # a list entry twice: a dispersion twice


def mutate_text(text: str, rng: np.random.Generator) -> str:
    """One to three changes of the text: a line dropped or duplicated, a character changed, garbage
    inserted, the text cut short."""
    for _ in range(int(rng.integers(1, 4))):
        lines = text.split("\n")
        k = int(rng.integers(len(lines)))
        action = rng.uniform()
        if action < 0.25:
            del lines[k]
        elif action < 0.5:
            lines.insert(k, lines[k])  # a duplicate key, or a second table of a name
        elif action < 0.75 and lines[k]:
            i = int(rng.integers(len(lines[k])))
            lines[k] = lines[k][:i] + TOML_CHARACTERS[rng.integers(len(TOML_CHARACTERS))] + lines[k][i + 1:]
        elif action < 0.9:
            lines.insert(k, "".join(TOML_CHARACTERS[i] for i in rng.integers(len(TOML_CHARACTERS), size=20)))
        else:
            return "\n".join(lines)[: int(rng.integers(len(text) + 1))]
        text = "\n".join(lines)
    return text


def case_bytes(seed: int) -> bytes:
    """The spec file of case `seed`."""
    rng = np.random.default_rng(seed)
    r = rng.uniform()
    if r < 0.05:
        return rng.bytes(int(rng.integers(0, 400)))
    if r < 0.1:
        return "".join(TOML_CHARACTERS[i] for i in rng.integers(len(TOML_CHARACTERS), size=int(rng.integers(400)))) \
            .encode()
    text = EXAMPLE
    if r < 0.8:
        spec = tomllib.loads(EXAMPLE)
        if rng.uniform() < 0.5:
            add_fitting(spec, rng)
        if rng.uniform() < 0.9:
            mutate_values(spec, rng)
        text = toml_text(spec)
    if rng.uniform() < 0.35:
        text = mutate_text(text, rng)
    data = text.encode("utf-8", errors="surrogatepass")
    if rng.uniform() < 0.03:
        k = int(rng.integers(len(data) + 1))
        data = data[:k] + rng.bytes(int(rng.integers(1, 8))) + data[k:]
    return data


def check_spec(spec) -> None:
    """What an accepted spec must hold: finite numbers, and a description the results directory can store."""
    numbers = [spec.dt, spec.duration] + [x for d in spec.dispersions for x in (d.distribution.a, d.distribution.b)]
    numbers += [x for _, x in spec.initial_q + spec.initial_v] + [t for *_, t in spec.events]
    if not all(math.isfinite(x) for x in numbers) or not spec.dt > 0 or not spec.duration > 0:
        raise AssertionError(f"accepted a spec with a non-finite or non-positive number: {numbers[:8]}")
    if not 1 <= spec.runs <= MAX_RUNS or spec.integrator not in INTEGRATORS:
        raise AssertionError(f"accepted runs = {spec.runs!r}, integrator = {spec.integrator!r}")
    json.dumps(spec.normalized, allow_nan=False)
    json.dumps(spec.identity(), allow_nan=False)


def check_refusal(error: SpecError, source: str) -> None:
    """A refusal names the file, then each problem its item, on one line."""
    message = str(error)
    if not message.startswith(f"{source}: ") or "\n" in message:
        raise AssertionError(f"a SpecError not naming the file on one line: {message[:300]!r}")
    for problem in error.problems:
        if not ITEM.match(problem):
            raise AssertionError(f"a problem not naming its item: {problem[:300]!r}")


def run_case(seed: int) -> str:
    """Loads the spec of case `seed`; returns 'ok' or 'SpecError'. Raises AssertionError when the
    property fails, or the unexpected exception."""
    data = case_bytes(seed)
    descriptor, path = tempfile.mkstemp(suffix=".toml", prefix=f"spec-{seed}-")
    try:
        with os.fdopen(descriptor, "wb") as file:
            file.write(data)
        try:
            spec = load_spec(path)
        except SpecError as error:
            check_refusal(error, path)
            return "SpecError"
        check_spec(spec)
        return "ok"
    finally:
        os.unlink(path)
