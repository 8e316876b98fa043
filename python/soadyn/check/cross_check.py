"""`soadyn check`: soadyn against every oracle that can load a user's URDF or MJCF file.

At a few seeded random states (configuration, velocity, torques,
accelerations, prescribed masks that switch whole joints), the largest
relative difference max|a - b| / max(1, max|b|) of forward, inverse,
mass-matrix and hybrid dynamics against each oracle:
- URDF: Pinocchio (forward, inverse, mass matrix), DART (hybrid dynamics),
  MuJoCo's URDF importer (forward, inverse, mass matrix; mujoco_oracle.py).
- MJCF (a '.xml'/'.mjcf' file or one whose root element is <mujoco>):
  MuJoCo, the compiler load_mjcf reads it with (forward, inverse, mass
  matrix, springs, dampers and armature included), and Pinocchio's own MJCF
  parser (rigid part: force elements set to zero; pinocchio_mjcf.py). DART's
  MJCF reader is not used: it infers inertias and splits multi-joint bodies
  its own way, with its own DOF names, so nothing maps it to the file's
  joints.
An oracle that cannot load or map a file is listed as not compared, with
its reason; the file fails the check only if a compared quantity is above
tolerance or no oracle could be compared.
"""
from __future__ import annotations

import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .. import _soadyn as core
from ..io.mjcf import MjcfIgnoredWarning, load_mjcf_with_map
from ..io.urdf import load_urdf
from .mujoco_oracle import MujocoOracle, urdf_in_mujoco
from .oracles import DartOracle, PinocchioOracle
from .pinocchio_mjcf import PinocchioMjcfOracle

DART_MJCF = ("its MJCF reader infers inertias and splits multi-joint bodies its own way, with its own DOF "
             "names: nothing maps it to the file's joints")


@dataclass
class Difference:
    quantity: str
    oracle: str
    max_relative: float


@dataclass
class CheckReport:
    path: str
    format: str                                         # "URDF" or "MJCF"
    rows: list = field(default_factory=list)            # Difference per (quantity, oracle)
    not_compared: list = field(default_factory=list)    # (oracle, reason)

    def passed(self, tolerance: float) -> bool:
        return bool(self.rows) and all(r.max_relative <= tolerance for r in self.rows)

    def verdict(self, tolerance: float) -> str:
        compared = sorted({r.oracle for r in self.rows})
        worst = max((r.max_relative for r in self.rows), default=float("nan"))
        skipped = f"; not compared: {', '.join(o for o, _ in self.not_compared)}" if self.not_compared else ""
        if not self.rows:
            return f"FAIL: no oracle could load {self.path}{skipped}"
        word = "PASS" if self.passed(tolerance) else "FAIL"
        return (f"{word}: {self.format} {Path(self.path).name} against {', '.join(compared)}: largest relative "
                f"difference {worst:.1e} (tolerance {tolerance:g}){skipped}")


def relative_difference(actual, expected) -> float:
    actual, expected = np.asarray(actual), np.asarray(expected)
    return float(np.max(np.abs(actual - expected)) / max(1.0, float(np.max(np.abs(expected)))))


def random_joint_mask(groups, rng: np.random.Generator, nv: int) -> np.ndarray:
    mask = np.zeros(nv, dtype=bool)
    for group in groups:
        mask[group] = rng.uniform() < 0.5
    return mask


def is_mjcf(path) -> bool:
    path = Path(path)
    if path.suffix.lower() in (".xml", ".mjcf"):
        return True
    try:
        with open(path, "rb") as f:
            head = f.read(4096).decode("utf-8", "replace")
    except OSError:
        return False
    return "<mujoco" in head and "<robot" not in head


def random_states(model, states: int, seed: int):
    """(q, v, tau, qdd, rng) at `states` seeded random states."""
    rng = np.random.default_rng(seed)
    for k in range(states):
        v, tau, qdd = rng.normal(size=(3, model.nv))
        yield core.random_configuration(model, seed + k), v, tau, qdd, rng


class _Worst:
    def __init__(self):
        self.worst: dict = {}

    def record(self, quantity, oracle, actual, expected):
        key = (quantity, oracle)
        self.worst[key] = max(self.worst.get(key, 0.0), relative_difference(actual, expected))

    def tree_dynamics(self, oracle_name, model, oracle, q, v, tau, qdd):
        self.record("forward dynamics", oracle_name, core.forward_dynamics(model, q, v, tau),
                    oracle.forward_dynamics(q, v, tau))
        self.record("inverse dynamics", oracle_name, core.inverse_dynamics(model, q, v, qdd),
                    oracle.inverse_dynamics(q, v, qdd))
        self.record("mass matrix", oracle_name, core.mass_matrix(model, q), oracle.mass_matrix(q))

    def rows(self) -> list:
        return [Difference(quantity, oracle, err) for (quantity, oracle), err in self.worst.items()]


def _try_oracle(report: CheckReport, name: str, build):
    try:
        return build()
    except Exception as exc:  # noqa: BLE001 - an oracle that cannot load or map the file: reported, not fatal
        report.not_compared.append((name, " ".join(str(exc).split()) or type(exc).__name__))
        return None


def _check_urdf(path, floating_base, states, seed) -> CheckReport:
    report = CheckReport(str(path), "URDF")
    model = load_urdf(path, floating_base=floating_base)
    pin_oracle = PinocchioOracle(model, path, floating_base)
    dart_oracle = DartOracle(model, path, floating_base)
    mujoco_oracle = _try_oracle(report, "mujoco", lambda: MujocoOracle(urdf_in_mujoco(model, path, floating_base)))
    worst = _Worst()
    for q, v, tau, qdd, rng in random_states(model, states, seed):
        worst.tree_dynamics("pinocchio", model, pin_oracle, q, v, tau, qdd)
        if mujoco_oracle is not None:
            worst.tree_dynamics("mujoco", model, mujoco_oracle, q, v, tau, qdd)
        for mask in (np.zeros(model.nv, bool), np.ones(model.nv, bool),
                     random_joint_mask(dart_oracle.joint_groups(), rng, model.nv)):
            model.set_prescribed(mask)
            u = np.where(mask, qdd, tau)
            ours = core.hybrid_dynamics(model, q, v, u)
            theirs = dart_oracle.hybrid_dynamics(q, v, u, mask)
            worst.record("hybrid qdd", "dart", ours[0], theirs[0])
            worst.record("hybrid tau", "dart", ours[1], theirs[1])
        model.set_prescribed(np.zeros(model.nv, bool))
    report.rows = worst.rows()
    return report


def rigid_part(model):
    """A copy of `model` with every force element's stiffness and damping set to zero."""
    bare = model.copy()
    for e in core.force_elements(bare):
        bare.set_parameter(e["name"] + ".stiffness", 0.0)
        bare.set_parameter(e["name"] + ".damping", 0.0)
    return bare


def _check_mjcf(path, floating_base, states, seed) -> CheckReport:
    report = CheckReport(str(path), "MJCF")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", MjcfIgnoredWarning)
        loaded = load_mjcf_with_map(path, floating_base=True if floating_base else None)
    model, rigid = loaded.model, rigid_part(loaded.model)
    mujoco_oracle = MujocoOracle(loaded)
    pin_oracle = _try_oracle(report, "pinocchio", lambda: PinocchioMjcfOracle(loaded, path))
    report.not_compared.append(("dart", DART_MJCF))
    worst = _Worst()
    for q, v, tau, qdd, _ in random_states(model, states, seed):
        worst.tree_dynamics("mujoco", model, mujoco_oracle, q, v, tau, qdd)
        if pin_oracle is not None:
            worst.tree_dynamics("pinocchio", rigid, pin_oracle, q, v, tau, qdd)
    report.rows = worst.rows()
    return report


def cross_check_report(path, floating_base: bool = False, states: int = 3, seed: int = 0) -> CheckReport:
    """The comparison of soadyn with every oracle that can load the URDF or MJCF file `path`."""
    check = _check_mjcf if is_mjcf(path) else _check_urdf
    return check(path, floating_base, states, seed)


def cross_check(path, floating_base: bool = False, states: int = 3, seed: int = 0) -> list[Difference]:
    """The rows of cross_check_report (one per quantity and oracle)."""
    return cross_check_report(path, floating_base, states, seed).rows


def format_table(rows: list[Difference], tolerance: float) -> str:
    lines = [f"{'quantity':<18} {'oracle':<10} {'max rel. diff':>14}  status"]
    for r in rows:
        status = "ok" if r.max_relative <= tolerance else "ABOVE TOLERANCE"
        lines.append(f"{r.quantity:<18} {r.oracle:<10} {r.max_relative:>14.3e}  {status}")
    return "\n".join(lines)


def format_report(report: CheckReport, tolerance: float) -> str:
    lines = [format_table(report.rows, tolerance)]
    lines += [f"not compared: {oracle}: {reason}" for oracle, reason in report.not_compared]
    lines.append(report.verdict(tolerance))
    return "\n".join(lines)
