"""The planar four-bar of Saha, Shah & Nandihal, "Evolution of the DeNOC-based
dynamic modelling for multibody systems", Mechanical Sciences 4, 2013
(scenes.four_bar; the paper's Sect. 5, Figs. 16-18).

Inverse dynamics over one crank revolution, the crank prescribed: (a) at a
constant rate and (b) by the paper's cycloidal law (Eq. 34, rest to rest),
sampled every `dt`: the closed configuration and velocity come from the
closed-form position analysis (scenes.four_bar_state), the other joints'
accelerations and the crank's torque from constrained_dynamics. Over a
revolution the mechanism returns to its starting state, so the crank's work
(the trapezoidal integral of torque times rate) is zero up to the quadrature
error: the summary prints it. (c) The free fall of the paper's Fig. 18: from
rest at the starting configuration, no torque, gravity only, RK4 at `dt`
through the Simulator; the summary prints the energy drift and the loop
closure.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import _soadyn as core
from ..scenes import four_bar, four_bar_state
from ..simulator import MotionSource, Simulator

DOFS = ("crank", "coupler", "rocker")


@dataclass
class FourBarRun:
    label: str
    t: np.ndarray              # (N,) s
    q: np.ndarray              # (N, 3) crank, coupler (relative to the crank), rocker, rad
    v: np.ndarray              # (N, 3) rad/s
    crank_torque: np.ndarray   # (N,) N m (zero in the free fall)
    closure: float             # largest |loop residual| along the run, m
    energy: np.ndarray         # (N,) kinetic + potential, J


def crank_revolution(law: MotionSource, label: str, revolution_time: float, dt: float,
                     closure: str = "revolute") -> FourBarRun:
    """Inverse dynamics along one revolution of the crank driven by `law` (a MotionSource of the crank angle)."""
    model = four_bar(closure)
    model.set_prescribed(["crank"])
    t = np.linspace(0.0, revolution_time, int(round(revolution_time / dt)) + 1)
    q, v = np.empty((len(t), 3)), np.empty((len(t), 3))
    torque, energy = np.empty(len(t)), np.empty(len(t))
    residual = 0.0
    for k, time in enumerate(t):
        angle, rate, acceleration = law.sample(time)
        q[k], v[k] = four_bar_state(angle, rate)
        _, tau, _ = core.constrained_dynamics(model, q[k], v[k], np.array([acceleration, 0.0, 0.0]))
        torque[k] = tau[0]
        energy[k] = core.kinetic_energy(model, q[k], v[k]) + core.potential_energy(model, q[k])
        residual = max(residual, float(np.abs(core.loop_residual(model, q[k])).max()))
    return FourBarRun(label, t, q, v, torque, residual, energy)


def constant_rate(revolution_time: float, dt: float) -> FourBarRun:
    rate = 2 * np.pi / revolution_time
    return crank_revolution(MotionSource.constant_velocity(rate), f"constant rate {rate:.3g} rad/s",
                            revolution_time, dt)


def cycloidal(revolution_time: float, dt: float) -> FourBarRun:
    """Saha, Shah & Nandihal 2013, Eq. 34: theta(t) = 2 pi (t/T - sin(2 pi t/T) / (2 pi)), rest to rest."""
    law = MotionSource.cycloidal(0.0, 2 * np.pi, 0.0, revolution_time)
    return crank_revolution(law, "cycloidal (Eq. 34)", revolution_time, dt)


def free_fall(duration: float, dt: float, closure: str = "revolute") -> FourBarRun:
    """From rest at crank angle 0, every joint free (no torque), under gravity; RK4 steps of dt (the
    Simulator projects the state onto the closure after each step)."""
    model = four_bar(closure)
    q0, v0 = four_bar_state(0.0, 0.0)
    sim = Simulator(model, dt, "rk4")
    sim.set_state(q0, v0)
    trajectory = sim.run(duration)
    residual = max(float(np.abs(core.loop_residual(model, q)).max()) for q in trajectory.q)
    energy = np.array([core.kinetic_energy(model, q, v) + core.potential_energy(model, q)
                       for q, v in zip(trajectory.q, trajectory.v)])
    return FourBarRun(f"free fall (RK4, dt {dt:g} s)", trajectory.t, trajectory.q, trajectory.v,
                      np.zeros(len(trajectory.t)), residual, energy)


def crank_work(run: FourBarRun) -> float:
    """Trapezoidal integral of crank torque times crank rate, J."""
    power = run.crank_torque * run.v[:, 0]
    return float(np.sum(0.5 * (power[1:] + power[:-1]) * np.diff(run.t)))


def format_runs(runs: list[FourBarRun]) -> str:
    lines = [f"{'run':<28} {'crank torque (N m)':>22} {'crank work (J)':>15} {'energy change (J)':>18} "
             f"{'closure (m)':>12}"]
    for r in runs:
        torque = f"{r.crank_torque.min():+.4f} .. {r.crank_torque.max():+.4f}"
        lines.append(f"{r.label:<28} {torque:>22} {crank_work(r):>15.2e} {r.energy[-1] - r.energy[0]:>18.2e} "
                     f"{r.closure:>12.1e}")
    return "\n".join(lines)


def plot_runs(driven: list[FourBarRun], fall: FourBarRun | None, path: str) -> None:
    """Joint angles and crank torque of the driven runs (the paper's Fig. 17) and the free fall's
    joint angles (Fig. 18)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    panels = 3 if fall is not None else 2
    fig, axes = plt.subplots(1, panels, figsize=(5 * panels, 4))
    styles = ("-", "--")
    for r, style in zip(driven, styles):
        for k, name in enumerate(DOFS):
            axes[0].plot(r.t, np.degrees(np.unwrap(r.q[:, k])), style, color=f"C{k}", label=f"{name}, {r.label}")
        axes[1].plot(r.t, r.crank_torque, style, color="k", label=r.label)
    axes[0].set_title("joint angles, crank driven (Fig. 17a)")
    axes[0].set_ylabel("angle (deg)")
    axes[1].set_title("crank torque (Fig. 17b)")
    axes[1].set_ylabel("torque (N m)")
    if fall is not None:
        for k, name in enumerate(DOFS):
            axes[2].plot(fall.t, np.degrees(np.unwrap(fall.q[:, k])), color=f"C{k}", label=name)
        axes[2].set_title("free fall (Fig. 18)")
        axes[2].set_ylabel("angle (deg)")
    for ax in axes:
        ax.set_xlabel("time (s)")
        ax.legend(fontsize=7)
        ax.grid(alpha=0.3)
    fig.suptitle("four-bar of Saha, Shah & Nandihal 2013")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
