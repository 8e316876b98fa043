"""What a [[dispersions]] entry disperses, checked against the model, and how a drawn value is applied.

An entry names one of:
- `parameter = "bus.mass"`: a model parameter (Model.parameter_names); an array parameter takes an
  element index: `"bus.com[2]"`, `"bus.inertia[0,0]"` (an off-diagonal element sets both (i, j) and
  (j, i)), `"fuel_slosh.placement[2,3]"` (a placement's translation column only), `"gravity[2]"`;
- `initial = "q:<coordinate>"` or `"v:<DOF>"`: one entry of the start state (Model.coordinate_names,
  Model.dof_names);
- `event = "lock <DOF or joint>"` or `"release <DOF or joint>"`: the time of that event (s);
- `source = "velocity:<DOF>"` (the DOF driven at this constant velocity from t = 0, from where it
  starts; it replaces a scene's drive of that DOF) or `"input:<DOF>"` (a constant generalized force
  on a regular DOF).
"""
from __future__ import annotations

import re
from dataclasses import dataclass

import numpy as np

from ..simulator import MotionSource
from .distributions import DISTRIBUTION_KEYS, Distribution, parse_distribution
from .problems import closest, shown

KINDS = ("parameter", "initial", "event", "source")
ENTRY_KEYS = frozenset({"name", "distribution", *KINDS, *(k for keys in DISTRIBUTION_KEYS.values() for k in keys)})
EVENT_KINDS = ("lock", "release")
SOURCE_KINDS = ("velocity", "input")
_ELEMENT = re.compile(r"^\s*([^\[\]\s]+)\s*(?:\[\s*(\d{1,9})\s*(?:,\s*(\d{1,9})\s*)?\])?\s*$")


@dataclass(frozen=True)
class Dispersion:
    column: str           # the column of the results table holding the drawn value
    kind: str             # parameter, initial, event or source
    mode: str             # initial: q or v; event: lock or release; source: velocity or input; parameter: ""
    target: str           # parameter name, coordinate, DOF or joint
    index: tuple          # parameter: the element (() for a scalar); initial, source: (coordinate or DOF index,)
    distribution: Distribution
    text: str             # the entry's target as written (normalized)

    def draw(self, rng) -> float:
        return self.distribution.draw(rng)

    def to_dict(self) -> dict:
        entry = {self.kind: self.text}
        if self.column != self.text:
            entry["name"] = self.column
        entry.update(self.distribution.to_dict())
        return entry


def parse_dispersion(entry, where: str, model, start, problems):
    """One [[dispersions]] entry checked against `model` and the start state `start` = (q, v): its
    Dispersion, or None after adding every problem of the entry to `problems` (each naming `where`,
    what the entry disperses, and the key at fault)."""
    if not isinstance(entry, dict):
        problems.add(f"{where}: must be a table, got {type(entry).__name__}")
        return None
    found = len(problems.messages)
    kind = problems.check(_kind, entry, where)
    if kind is not None:
        where = f"{where} ({kind} {shown(entry[kind])})"
    for key in sorted(set(entry) - ENTRY_KEYS, key=str):
        problems.add(f"{where}: unknown key {shown(key)}{closest(key, sorted(ENTRY_KEYS))}")
    target = problems.check(_TARGETS[kind], entry[kind], where, model, start) if kind is not None else None
    if target is not None:
        mode, dispersed, index, text, nominal = target
    column = entry.get("name", text if target is not None else "")
    if "name" in entry and (not isinstance(column, str) or not column.strip()):
        problems.add(f"{where}: name must be a non-empty string, got {shown(column)}")
    # With the target at fault there is no nominal value: 1 stands in, so that the distribution's
    # own problems are found now (a relative scale's are found once the target is right).
    distribution = parse_distribution(entry, nominal if target is not None else 1.0, where, problems)
    if len(problems.messages) > found:
        return None
    return Dispersion(column, kind, mode, dispersed, index, distribution, text)


def _kind(entry: dict, where: str) -> str:
    """What the entry disperses: parameter, initial, event or source, given as a string."""
    kinds = [k for k in KINDS if k in entry]
    if len(kinds) != 1:
        raise ValueError(f"{where}: give exactly one of {', '.join(KINDS)} (what is dispersed)"
                         + (f", got {' and '.join(kinds)}" if kinds else ""))
    if not isinstance(entry[kinds[0]], str):
        raise ValueError(f"{where}: {kinds[0]} must be a string, got {shown(entry[kinds[0]])}")
    return kinds[0]


def _parameter(text, where, model, start):
    match = _ELEMENT.match(text)
    if not match:
        raise ValueError(f"{where}: expected a parameter name with an optional element index, e.g. 'bus.com[2]'")
    name = match.group(1)
    names = list(model.parameter_names)
    if name not in names:
        raise ValueError(f"{where}: unknown parameter {shown(name)}{closest(name, names, 'parameters')}")
    value = np.asarray(model.get_parameter(name), dtype=float)
    index = tuple(int(g) for g in match.groups()[1:] if g is not None)
    if value.ndim == 0:
        if index:
            raise ValueError(f"{where}: {name} is a number; it takes no index")
        return "", name, (), name, float(value)
    if len(index) != value.ndim or any(i >= n for i, n in zip(index, value.shape)):
        example = f"{name}[{','.join('0' for _ in value.shape)}]"
        raise ValueError(f"{where}: {name} has shape {value.shape}: give one element, e.g. {example}"
                         + (f" (got index {list(index)})" if index else ""))
    if name.endswith(".placement") and not (index[1] == 3 and index[0] < 3):
        raise ValueError(f"{where}: only a placement's translation can be dispersed: {name}[i,3] with i in 0..2")
    text = f"{name}[{','.join(str(i) for i in index)}]"
    return "", name, index, text, float(value[index])


def _initial(text, where, model, start):
    mode, _, name = text.partition(":")
    if mode not in ("q", "v") or not name:
        raise ValueError(f"{where}: expected 'q:<coordinate>' or 'v:<DOF>'")
    names = list(model.coordinate_names if mode == "q" else model.dof_names)
    if name not in names:
        what = "coordinate" if mode == "q" else "DOF"
        raise ValueError(f"{where}: unknown {what} {shown(name)}{closest(name, names, what + 's')}")
    k = names.index(name)
    return mode, name, (k,), text, float(start[0 if mode == "q" else 1][k])


def _event(text, where, model, start):
    parts = text.split()
    if len(parts) != 2 or parts[0] not in EVENT_KINDS:
        raise ValueError(f"{where}: expected 'lock <DOF or joint>' or 'release <DOF or joint>'")
    kind, target = parts
    dofs = _dof_indices(model, target, where)
    try:
        model._require_regular_modal_dofs(dofs)
    except ValueError as error:
        raise ValueError(f"{where}: {error}") from None
    return kind, target, (), f"{kind} {target}", None


def _source(text, where, model, start):
    mode, _, dof = text.partition(":")
    if mode not in SOURCE_KINDS or not dof:
        raise ValueError(f"{where}: expected 'velocity:<DOF>' or 'input:<DOF>'")
    dofs = _dof_indices(model, dof, where)
    if len(dofs) != 1:
        raise ValueError(f"{where}: {shown(dof)} names {len(dofs)} DOFs; a source drives one DOF")
    k = dofs[0]
    if mode == "velocity":
        try:
            model._require_regular_modal_dofs(dofs)
        except ValueError as error:
            raise ValueError(f"{where}: {error}") from None
        coordinates = list(model.coordinate_names)
        if dof not in coordinates:
            raise ValueError(f"{where}: {shown(dof)} has no coordinate of its own (a DOF of a free, spherical or "
                             f"planar joint); a velocity source drives a 1-DOF joint's coordinate")
        return mode, dof, (coordinates.index(dof),), text, None
    if model.prescribed[k]:
        raise ValueError(f"{where}: {shown(dof)} is prescribed; an input acts on a regular DOF")
    return mode, dof, (k,), text, None


_TARGETS = {"parameter": _parameter, "initial": _initial, "event": _event, "source": _source}


def _dof_indices(model, target: str, where: str) -> list[int]:
    try:
        return list(model._dof_indices(target))
    except ValueError:
        names = list(model.dof_names) + [j for j in model.joint_names if j not in model.dof_names]
        raise ValueError(f"{where}: unknown DOF or joint {shown(target)}{closest(target, names, 'DOFs and joints')}") \
            from None


# Applying drawn values (one run; the order of the spec).

def set_parameters(model, dispersions, values) -> None:
    """The drawn parameter values on `model` (a copy of the campaign's model)."""
    for d, x in zip(dispersions, values):
        if d.kind != "parameter":
            continue
        if not d.index:
            model.set_parameter(d.target, x)
            continue
        value = np.array(model.get_parameter(d.target), dtype=float)
        value[d.index] = x
        if d.target.endswith(".inertia"):
            value[d.index[::-1]] = x
        model.set_parameter(d.target, value)


def set_initial(q: np.ndarray, v: np.ndarray, dispersions, values) -> None:
    for d, x in zip(dispersions, values):
        if d.kind == "initial":
            (q if d.mode == "q" else v)[d.index[0]] = x


def add_sources_and_events(sim, q: np.ndarray, dispersions, values) -> None:
    """Velocity sources and inputs from t = 0, then the dispersed events, in the spec's order."""
    for d, x in zip(dispersions, values):
        if d.kind == "source" and d.mode == "velocity":
            sim.prescribe(d.target, MotionSource.constant_velocity(x, float(q[d.index[0]]), 0.0))
        elif d.kind == "source":
            sim.set_input(d.target, x)
    for d, x in zip(dispersions, values):
        if d.kind == "event":
            sim.schedule(x, d.mode, d.target)
