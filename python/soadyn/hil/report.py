"""The outcome of a HIL run (HilReport): its JSON form, the table `soadyn hil` prints, and its plot."""
from __future__ import annotations

import json
import math
from dataclasses import dataclass, field

import numpy as np

from .. import _soadyn as core


@dataclass
class HilReport:
    """The outcome of run_hil. Times are wall-clock; `steps` may be below
    `requested_steps` when the simulation failed (`status`) or was interrupted."""

    rate_hz: float
    realtime: bool
    requested_steps: int
    steps: int
    deadline_misses: int
    compute_us: dict
    lateness_us: dict
    packets: dict
    wall_seconds: float
    sim_time: float
    status: str
    failed_step: int | None
    failed_dof: str | None
    interrupted: bool
    energy: dict
    momentum: dict
    scheduling: dict  # real-time scheduling asked for and granted, and whether the caches were warmed (format_scheduling)
    commands: dict  # command limits, policy, saturated and rejected counts
    dof_names: list = field(repr=False)
    compute_ns: np.ndarray = field(repr=False)
    lateness_ns: np.ndarray = field(repr=False)
    t: np.ndarray = field(repr=False)  # recorded times
    q: np.ndarray = field(repr=False)  # recorded configurations, one row per time
    v: np.ndarray = field(repr=False)  # recorded velocities
    error: str | None = None  # what a step raised (status "exception in a step"), as "Type: message"
    report_errors: list = field(default_factory=list)  # measurements that could not be made, and why
    exception: BaseException | None = field(default=None, repr=False)  # the exception a step raised
    failed_loop: str | None = None  # the loop whose closure projection failed (status "loop closure not reached")
    # Models with loops: the largest closure residuals the integrator left before the projection of a step,
    # {"max_position": ..., "max_velocity": ...}; None without loops.
    loop_drift: dict | None = None
    # Deadline misses by cause: "compute" (ours: the step's own CPU time exceeded the period, or a backlog of our
    # own) and "machine" (woken or let run too late, or pre-empted: "machine_preempted" of them); "compute" and
    # "machine" add up to deadline_misses.
    misses: dict = field(default_factory=dict)
    # The step's own CPU time (the loop thread's CPU clock, same window as compute_us): {"p50", "p99", "p999",
    # "max"} in us, "spread" = p99.9 / p50 (the step's work varying by itself) and the "preemption_margin" (us).
    cpu_us: dict = field(default_factory=dict)
    preempted_steps: int = 0  # steps whose wall time exceeded their CPU time by the margin, or switched out
    involuntary_switches: int = 0  # of the loop's thread during the steps
    cpu_ns: np.ndarray | None = field(default=None, repr=False)
    # The state at the end of the run, {"t", "q", "v"}: after a failed step, the last good one (a failed step
    # leaves the state as it was before it).
    final_state: dict | None = None
    # The machine's floor (paced runs; None otherwise): register arithmetic of the first steps' median length,
    # paced like the steps, "mode" "interleaved" (at the midpoint of the steps' own periods) or "after" (in the
    # periods after the run): {"mode", "periods", "target", "p50", "p99", "p999", "max"} in us, and
    # "tail_ratio" = compute p99.9 / floor p99.9 (1: the step's tail is the machine's). Its "dynamics" entry is
    # the dynamics floor of the same periods: "evaluations" of the dynamics at the present state per period (the
    # whole number closest to the same length), {"p50", "p99", "p999", "max"} in us, "spread" = its p99.9 / p50
    # (what the machine does to memory-touching work of no data dependence) and "tail_ratio" = compute p99.9 /
    # its p99.9.
    floor_us: dict | None = None
    floor_ns: np.ndarray | None = field(default=None, repr=False)
    dynamics_floor_ns: np.ndarray | None = field(default=None, repr=False)

    @property
    def ok(self) -> bool:
        """Whether the run ended as asked (status "ok": every step done, not stopped or failed)."""
        return self.status == "ok"

    def to_dict(self) -> dict:
        """The summary as JSON-ready data (no per-step arrays)."""
        keys = ["rate_hz", "realtime", "requested_steps", "steps", "deadline_misses", "compute_us", "cpu_us",
                "preempted_steps", "involuntary_switches", "lateness_us",
                "packets", "commands", "wall_seconds", "sim_time", "status", "failed_step", "failed_dof", "error",
                "interrupted", "energy", "momentum", "scheduling", "report_errors", "failed_loop", "loop_drift",
                "misses", "floor_us"]
        return _finite_or_none({k: getattr(self, k) for k in keys})

    def to_json(self, indent: int | None = 2) -> str:
        """Strict JSON: a non-finite number (an unlimited DOF, a NaN energy) is null."""
        return json.dumps(self.to_dict(), indent=indent, allow_nan=False)


def _finite_or_none(x):
    if isinstance(x, float):
        return x if math.isfinite(x) else None
    if isinstance(x, dict):
        return {k: _finite_or_none(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_finite_or_none(v) for v in x]
    return x


def format_scheduling(s: dict) -> str:
    """One line: what real-time scheduling the loop asked for and got."""
    parts = []
    if s["fifo_priority"] > 0:
        parts.append(f"SCHED_FIFO {s['fifo_priority']}" if s["fifo_granted"]
                     else f"SCHED_FIFO {s['fifo_priority']} refused ({s['fifo_refused']})")
    if s["cpu"] >= 0:
        parts.append(f"on CPU {s['cpu']}" if s["cpu_granted"] else f"CPU {s['cpu']} refused ({s['cpu_refused']})")
    if s["lock_memory"]:
        parts.append("memory locked" if s["memory_locked"] else f"memory lock refused ({s['lock_refused']})")
    text = ", ".join(parts) if parts else "default (no real-time priority, pinning or memory lock asked for)"
    return text + ("; caches warmed before each deadline" if s.get("warm_up") else "")


def format_table(r: HilReport) -> str:
    """The timing table printed by `soadyn hil`.

    The steps and deadline misses, the scheduling granted, the step's compute time and the lateness (p50, p99,
    p99.9, max in microseconds), the machine's floor when it was timed, packet and command counts, the energy
    (J) and the momentum's change; the HIL guide explains how to read it.
    """
    c, lat, p, cmd = r.compute_us, r.lateness_us, r.packets, r.commands
    mode = "real time" if r.realtime else "as fast as possible"
    e0, e1, h0, h1 = r.energy["start"], r.energy["end"], r.momentum["start"], r.momentum["end"]
    energy = f"{e0:.6g} -> {e1:.6g}" if e0 is not None and e1 is not None else "not measured (see report_errors)"
    momentum = (f"largest change {max(abs(a - b) for a, b in zip(h1, h0)):.3e}" if h0 is not None and h1 is not None
                else "not measured (see report_errors)")
    saturated = ", ".join(f"{name} {n}" for name, n in cmd["saturated_dofs"].items())
    lines = [
        f"steps            {r.steps} of {r.requested_steps} at {r.rate_hz:g} Hz ({mode}), "
        f"{r.sim_time:.3f} s simulated in {r.wall_seconds:.3f} s",
        f"deadline misses  {r.deadline_misses}"
        + (f" ({r.misses['compute']} ours: CPU time over the period; {r.misses['machine']} the machine's: woken or "
           f"run late, {r.misses['machine_preempted']} of them pre-empted)" if r.deadline_misses else ""),
        f"scheduling       {format_scheduling(r.scheduling)}",
        f"compute   us     p50 {c['p50']:8.1f}   p99 {c['p99']:8.1f}   p99.9 {c['p999']:8.1f}   max {c['max']:8.1f}"
        "   (wall clock)",
        *([f"cpu       us     p50 {u['p50']:8.1f}   p99 {u['p99']:8.1f}   p99.9 {u['p999']:8.1f}   max {u['max']:8.1f}"
           f"   (the thread's own; p99.9 / p50 " + _ratio(u["spread"]) + ")"]
          if (u := r.cpu_us) else []),
        f"pre-empted       {r.preempted_steps} steps (wall time over CPU time by more than "
        f"{r.cpu_us.get('preemption_margin', 0):g} us, or switched out), {r.involuntary_switches} involuntary switches",
        f"lateness  us     p50 {lat['p50']:8.1f}   p99 {lat['p99']:8.1f}   max {lat['max']:8.1f}",
        *([f"machine   us     p50 {f['p50']:8.1f}   p99 {f['p99']:8.1f}   p99.9 {f['p999']:8.1f}   max {f['max']:8.1f}"
           f"   (floor, {f['mode']}: {f['periods']} periods of {f['target']:.1f} us register arithmetic; "
           "step p99.9 / floor p99.9 " + _ratio(f["tail_ratio"]) + ")",
           f"dynamics  us     p50 {d['p50']:8.1f}   p99 {d['p99']:8.1f}   p99.9 {d['p999']:8.1f}   max {d['max']:8.1f}"
           f"   (dynamics floor: {d['evaluations']} evaluations at the present state per period; its p99.9 / p50 "
           + _ratio(d["spread"]) + ", step p99.9 / its p99.9 " + _ratio(d["tail_ratio"]) + ")"]
          if (f := r.floor_us) and (d := f["dynamics"]) else []),
        f"packets          received {p['received']}, dropped {p['dropped']}, sent {p['sent']}, "
        f"rejected sender {p['rejected_sender']}, stale {p['stale']}, kernel drops {p['kernel_drops']}, "
        f"send failures {p['send_failures']}, steps at the read bound {p['steps_left_pending']}",
        f"commands         policy {cmd['policy']}: saturated {cmd['saturated']}"
        + (f" ({saturated})" if saturated else "") + f", rejected {cmd['rejected']}",
        f"energy    J      {energy}",
        f"momentum         {momentum}",
        *([f"loop drift       before projection: max {r.loop_drift['max_position']:.2e} (position), "
           f"{r.loop_drift['max_velocity']:.2e} (velocity); closure projected to the tolerance after every step"]
          if r.loop_drift else []),
        f"status           {r.status}" + (f" at step {r.failed_step}" if r.failed_step is not None else "")
        + (f" (DOF '{r.failed_dof}')" if r.failed_dof else "") + (f" (loop '{r.failed_loop}')" if r.failed_loop else "")
        + (f": {r.error}" if r.error else "")
        + (" (interrupted)" if r.interrupted else ""),
    ]
    return "\n".join(lines)


def _ratio(x) -> str:
    return f"{x:.2f}" if x is not None else "n/a"


def require_matplotlib():
    """The matplotlib module, or an ImportError saying how to install it."""
    try:
        import matplotlib
    except ImportError:
        raise ImportError("plotting needs matplotlib: pip install 'soadyn[plot]'") from None
    return matplotlib


def plot_report(r: HilReport, path, model=None, max_dofs: int = 6) -> None:
    """A PNG with the compute-time and lateness histograms, the velocities of
    the `max_dofs` DOFs that moved most, and (given the model) the energy.

    Times in microseconds, velocities in the DOFs' units (rad/s, m/s), energy in J. Raises ImportError saying
    how to install matplotlib when it is missing, and OSError naming the path when the PNG cannot be written.
    """
    matplotlib = require_matplotlib()
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, 2, figsize=(12, 8))
    _histogram(axes[0, 0], r.compute_ns / 1e3, "compute time per step (us)", 1e6 / r.rate_hz)
    _histogram(axes[0, 1], r.lateness_ns / 1e3, "lateness of the wake-up (us)", None)
    _velocity_history(axes[1, 0], r, max_dofs)
    _energy_history(axes[1, 1], r, model)
    fig.suptitle(f"soadyn HIL: {r.steps} steps at {r.rate_hz:g} Hz, {r.deadline_misses} deadline misses")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def _histogram(ax, values_us, label: str, period_us: float | None) -> None:
    if len(values_us):
        ax.hist(values_us, bins=100, log=True)
    if period_us is not None:
        ax.axvline(period_us, color="red", linestyle="--", label="period")
        ax.legend()
    ax.set_xlabel(label)
    ax.set_ylabel("steps")


def _velocity_history(ax, r: HilReport, max_dofs: int) -> None:
    if len(r.t):
        moved = np.ptp(r.v, axis=0)
        for k in np.argsort(-moved)[:max_dofs]:
            ax.plot(r.t, r.v[:, k], label=r.dof_names[k])
        ax.legend(fontsize="small")
    ax.set_xlabel("simulation time (s)")
    ax.set_ylabel("velocity (rad/s or m/s)")


def _energy_history(ax, r: HilReport, model) -> None:
    if model is not None and len(r.t):
        energy = [core.kinetic_energy(model, q, v) + core.potential_energy(model, q) for q, v in zip(r.q, r.v)]
        ax.plot(r.t, energy)
    ax.set_xlabel("simulation time (s)")
    ax.set_ylabel("kinetic + potential energy (J)")
