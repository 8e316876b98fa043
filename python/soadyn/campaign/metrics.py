"""Per-run summary metrics: a registry of named functions of (model, trajectory, sim).

A metric is computed after a run from the run's model (its dispersed copy), the recorded
Trajectory (every step) and the Simulator at the end. A name is either plain
(`energy_lost`) or a family with an argument after a colon (`max_abs_q:scan_az`); a
metric's check refuses, before any run, a model it cannot measure. Add one with

    @metric("name", unit="m", description="...")
    def name(model, trajectory, sim, arg=None) -> float: ...

in this module (campaign workers import soadyn, and with it this registry).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Optional

import numpy as np

from .._soadyn import kinetic_energy, potential_energy
from .problems import closest, shown


@dataclass(frozen=True)
class Metric:
    name: str
    unit: str
    description: str
    compute: Callable          # (model, trajectory, sim, arg) -> float
    check: Optional[Callable]  # (model, arg): raises ValueError naming what the model lacks
    argument: Optional[str]    # what follows the colon (None: a plain name)


METRICS: dict[str, Metric] = {}
"""{name: Metric} of the metrics a campaign spec may ask for (filled by the @metric registrations below)."""


def metric(name: str, unit: str, description: str, check: Optional[Callable] = None,
           argument: Optional[str] = None):
    """Register the decorated function as metric `name` (a family `name:<argument>` if `argument`).

    unit: the value's unit as the report prints it (e.g. 'm', 'rad', 'J'); description: one line for the report.
    A name registered again replaces the earlier metric.
    """
    def register(fn):
        METRICS[name] = Metric(name, unit, description, fn, check, argument)
        return fn
    return register


def known_names() -> list[str]:
    return [f"{m.name}:<{m.argument}>" if m.argument else m.name for m in METRICS.values()]


def resolve(name, model) -> tuple[Metric, Optional[str]]:
    """The metric and argument `name` selects, checked against `model`; ValueError naming it."""
    if not isinstance(name, str):
        raise ValueError(f"a metric name is a string, got {shown(name)}")
    family, colon, arg = name.partition(":")
    found = METRICS.get(name) or METRICS.get(family)
    if found is None or (found.argument is None and colon) or (found.argument and not arg):
        raise ValueError(f"unknown metric {shown(name)}{closest(name, known_names(), 'metrics')}")
    arg = arg if found.argument else None
    if found.check is not None:
        found.check(model, arg)
    return found, arg


def evaluate(names, model, trajectory, sim) -> dict:
    """{name: value} of every metric in `names` (names already resolved on this model)."""
    out = {}
    for name in names:
        found, arg = resolve(name, model)
        out[name] = float(found.compute(model, trajectory, sim, arg))
    return out


# Helpers

def _flexible_tip(model, body: str) -> tuple[int, int]:
    """(body index, tip node) of a flexible body with a 'tip' attachment (else its last node)."""
    if body not in model.body_names:
        raise ValueError(f"no body {shown(body)} in the model{closest(body, model.body_names, 'bodies')}")
    b = list(model.body_names).index(body)
    if model.n_modes[b] == 0:
        flexible = [n for n, k in zip(model.body_names, model.n_modes) if k > 0]
        raise ValueError(f"body {shown(body)} is not flexible (flexible bodies: {', '.join(flexible) or 'none'})")
    flex = model.flexible_body(body)
    return b, flex.attachments.get("tip", flex.n_nodes - 1)


def _quaternion_slice(model, body: str) -> slice:
    """Where body's (x, y, z, w) attitude quaternion sits in q (a free or spherical joint)."""
    if body not in model.body_names:
        raise ValueError(f"no body {shown(body)} in the model{closest(body, model.body_names, 'bodies')}")
    joint = model.joint_names[list(model.body_names).index(body)]
    coordinates = list(model.coordinate_names)
    try:
        k = coordinates.index(f"{joint}:qx")
    except ValueError:
        raise ValueError(f"body {shown(body)} has no attitude quaternion (its joint is not free or spherical)") \
            from None
    return slice(k, k + 4)


def _first_free_body(model) -> str:
    for body, kind in zip(model.body_names, model.joint_types):
        if kind == "free":
            return body
    raise ValueError("the model has no free-floating body (final_attitude_error measures one)")


def _rotation_angle(q0: np.ndarray, q1: np.ndarray) -> float:
    """Angle (rad, in [0, pi]) of the rotation from attitude q0 to q1, unit quaternions (x, y, z, w)."""
    x0, y0, z0, w0 = q0 / np.linalg.norm(q0)
    x1, y1, z1, w1 = q1 / np.linalg.norm(q1)
    # conj(q0) * q1
    w = w0 * w1 + x0 * x1 + y0 * y1 + z0 * z1
    x = w0 * x1 - x0 * w1 - y0 * z1 + z0 * y1
    y = w0 * y1 - y0 * w1 - z0 * x1 + x0 * z1
    z = w0 * z1 - z0 * w1 - x0 * y1 + y0 * x1
    return float(2.0 * np.arctan2(np.sqrt(x * x + y * y + z * z), abs(w)))


def _coordinate(model, name: str, what: str = "coordinate") -> int:
    names = list(model.coordinate_names if what == "coordinate" else model.dof_names)
    if name not in names:
        raise ValueError(f"no {what} {shown(name)} in the model{closest(name, names, what + 's')}")
    return names.index(name)


# Built-in metrics

def _check_tip(model, body):
    _flexible_tip(model, body)


@metric("peak_tip_deflection", "m", "largest |translation| of a flexible body's tip node (its 'tip' attachment, "
        "else its last node) from its undeformed place, in the body frame, over the run",
        check=_check_tip, argument="flexible body")
def peak_tip_deflection(model, trajectory, sim, body):
    b, tip = _flexible_tip(model, body)
    flex = model.flexible_body(body)
    end = model.q_index[b + 1]
    eta = trajectory.q[:, end - model.n_modes[b]:end]
    # node_pose's translation is the node's place plus its mode shapes' translation rows times eta:
    # find the peak over the run at once, then measure it with node_pose.
    k = int(np.argmax(np.linalg.norm(eta @ flex.mode_shapes[tip][3:].T, axis=1)))
    rest = flex.node_pose(tip, np.zeros(model.n_modes[b]))[:3, 3]
    return float(np.linalg.norm(flex.node_pose(tip, eta[k])[:3, 3] - rest))


@metric("peak_boom_tip_deflection", "m", "cassini: peak_tip_deflection:magnetometer_boom",
        check=lambda model, arg: _check_tip(model, "magnetometer_boom"))
def peak_boom_tip_deflection(model, trajectory, sim, arg=None):
    return peak_tip_deflection(model, trajectory, sim, "magnetometer_boom")


@metric("attitude_error", "rad", "angle of the rotation from a body's attitude at the start to its attitude "
        "at the end (a free or spherical joint's quaternion)",
        check=_quaternion_slice, argument="body")
def attitude_error(model, trajectory, sim, body):
    s = _quaternion_slice(model, body)
    return _rotation_angle(trajectory.q[0, s], trajectory.q[-1, s])


@metric("final_attitude_error", "rad", "attitude_error of the first free-floating body (cassini: the bus)",
        check=lambda model, arg: _first_free_body(model))
def final_attitude_error(model, trajectory, sim, arg=None):
    return attitude_error(model, trajectory, sim, _first_free_body(model))


@metric("max_hinge_torque", "N m", "largest |generalized force| (N m; N for a slider) on the DOFs "
        "prescribed at the start or at the end of the run (drives and locked DOFs), over the run",
        check=lambda model, arg: None)
def max_hinge_torque(model, trajectory, sim, arg=None):
    held = np.asarray(model.prescribed, dtype=bool) | np.asarray(sim.prescribed, dtype=bool)
    if not held.any() or len(trajectory.tau) == 0:
        return 0.0
    return float(np.max(np.abs(trajectory.tau[:, held])))


@metric("energy_lost", "J", "kinetic energy removed by lock impulses (Simulator.energy_lost)",
        check=lambda model, arg: None)
def energy_lost(model, trajectory, sim, arg=None):
    return float(sim.energy_lost)


@metric("final_energy", "J", "kinetic plus potential energy (soadyn.kinetic_energy + soadyn.potential_energy) "
        "at the end", check=lambda model, arg: None)
def final_energy(model, trajectory, sim, arg=None):
    q, v = trajectory.q[-1], trajectory.v[-1]
    return float(kinetic_energy(model, q, v) + potential_energy(model, q))


@metric("max_abs_q", "rad or m", "largest |q| of one coordinate over the run",
        check=_coordinate, argument="coordinate")
def max_abs_q(model, trajectory, sim, name):
    return float(np.max(np.abs(trajectory.q[:, _coordinate(model, name)])))


@metric("final_q", "rad or m", "one coordinate at the end",
        check=_coordinate, argument="coordinate")
def final_q(model, trajectory, sim, name):
    return float(trajectory.q[-1, _coordinate(model, name)])


@metric("max_abs_v", "rad/s or m/s", "largest |v| of one DOF over the run",
        check=lambda model, name: _coordinate(model, name, "DOF"), argument="DOF")
def max_abs_v(model, trajectory, sim, name):
    return float(np.max(np.abs(trajectory.v[:, _coordinate(model, name, "DOF")])))
