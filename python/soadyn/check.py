"""`soadyn check`: soadyn against DART and Pinocchio on a user's URDF.

At a few seeded random states (configuration, velocity, torques,
accelerations, prescribed masks that switch whole joints), the largest
relative difference max|a - b| / max(1, max|b|) of forward, inverse,
mass-matrix and hybrid dynamics against each oracle.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import _soadyn as core
from .oracles import DartOracle, PinocchioOracle
from .urdf import load_urdf


@dataclass
class Difference:
    quantity: str
    oracle: str
    max_relative: float


def relative_difference(actual, expected) -> float:
    actual, expected = np.asarray(actual), np.asarray(expected)
    return float(np.max(np.abs(actual - expected)) / max(1.0, float(np.max(np.abs(expected)))))


def random_joint_mask(groups, rng: np.random.Generator, nv: int) -> np.ndarray:
    mask = np.zeros(nv, dtype=bool)
    for group in groups:
        mask[group] = rng.uniform() < 0.5
    return mask


def cross_check(path, floating_base: bool = False, states: int = 3, seed: int = 0) -> list[Difference]:
    model = load_urdf(path, floating_base=floating_base)
    pin_oracle = PinocchioOracle(model, path, floating_base)
    dart_oracle = DartOracle(model, path, floating_base)
    worst: dict[tuple[str, str], float] = {}

    def record(quantity, oracle, actual, expected):
        key = (quantity, oracle)
        worst[key] = max(worst.get(key, 0.0), relative_difference(actual, expected))

    rng = np.random.default_rng(seed)
    for k in range(states):
        q = core.random_configuration(model, seed + k)
        v, tau, qdd = rng.normal(size=(3, model.nv))
        record("forward dynamics", "pinocchio", core.forward_dynamics(model, q, v, tau),
               pin_oracle.forward_dynamics(q, v, tau))
        record("inverse dynamics", "pinocchio", core.inverse_dynamics(model, q, v, qdd),
               pin_oracle.inverse_dynamics(q, v, qdd))
        record("mass matrix", "pinocchio", core.mass_matrix(model, q), pin_oracle.mass_matrix(q))
        for mask in (np.zeros(model.nv, bool), np.ones(model.nv, bool),
                     random_joint_mask(dart_oracle.joint_groups(), rng, model.nv)):
            model.set_prescribed(mask)
            u = np.where(mask, qdd, tau)
            ours = core.hybrid_dynamics(model, q, v, u)
            theirs = dart_oracle.hybrid_dynamics(q, v, u, mask)
            record("hybrid qdd", "dart", ours[0], theirs[0])
            record("hybrid tau", "dart", ours[1], theirs[1])
    return [Difference(quantity, oracle, err) for (quantity, oracle), err in worst.items()]


def format_table(rows: list[Difference], tolerance: float) -> str:
    lines = [f"{'quantity':<18} {'oracle':<10} {'max rel. diff':>14}  status"]
    for r in rows:
        status = "ok" if r.max_relative <= tolerance else "ABOVE TOLERANCE"
        lines.append(f"{r.quantity:<18} {r.oracle:<10} {r.max_relative:>14.3e}  {status}")
    return "\n".join(lines)
