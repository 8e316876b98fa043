"""Real-time (hardware-in-the-loop) runs of a Simulator.

`run_hil` steps a Simulator at a fixed wall-clock rate in C++ (a worker
thread, GIL released) while the main thread shows the progress. Optionally a
controller in another process drives the regular DOFs over UDP on 127.0.0.1
(packet format: cpp/include/soadyn/sim/udp_link.hpp and the README). The
returned HilReport holds the timing statistics, the packet counts, the
energy and momentum of the model at start and end, the per-step timings and a
decimated state history. HilRunner is the bare loop, for callers that need
its UDP port before it runs.
"""
from __future__ import annotations

import json
import math
import os
import re
import threading
from dataclasses import dataclass, field

import numpy as np

from . import _soadyn as core
from ._soadyn import HilRunner
from .progress import progress_bar
from .scenes import LOOP_SCENE_STARTS, SCENES, drive_cassini
from .simulator import Simulator

__all__ = ["HilEvent", "HilReport", "HilRunner", "format_table", "parse_event", "plot_report", "require_matplotlib",
           "resolve_command_limits", "run_hil", "scene_simulator"]

RECORDED_SAMPLES = 2000  # rows of state history kept for the plot
PROGRESS_INTERVAL = 0.1  # seconds between progress-bar refreshes
STATE_INTERVAL = 1.0 / 30  # seconds between on_state calls (a viewer's frame rate)
MAX_STEPS = 10**8  # one run keeps 16 bytes of timings per step: at most 1.6 GB
COMMAND_POLICIES = ("clamp", "reject", "stop")
MAX_PACKETS_PER_STEP = 16  # datagrams read per step at most (the rest wait for the next step)
MAX_FLOOR_PERIODS = 10000  # periods of the machine's floor after a paced run, at most


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
    scheduling: dict  # real-time scheduling asked for and granted (format_scheduling)
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
    # Deadline misses by cause: "compute" (the step's own compute exceeded the period) and "machine" (woken or
    # let run too late); they add up to deadline_misses.
    misses: dict = field(default_factory=dict)
    # The state at the end of the run, {"t", "q", "v"}: after a failed step, the last good one (a failed step
    # leaves the state as it was before it).
    final_state: dict | None = None
    # The machine's floor measured after the run (paced runs; None otherwise): register arithmetic of the steps'
    # median length, paced like the steps: {"periods", "target", "p50", "p99", "p999", "max"} in us, and
    # "tail_ratio" = compute p99.9 / floor p99.9 (1: the step's tail is the machine's).
    floor_us: dict | None = None
    floor_ns: np.ndarray | None = field(default=None, repr=False)

    @property
    def ok(self) -> bool:
        return self.status == "ok"

    def to_dict(self) -> dict:
        """The summary as JSON-ready data (no per-step arrays)."""
        keys = ["rate_hz", "realtime", "requested_steps", "steps", "deadline_misses", "compute_us", "lateness_us",
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


# Statuses whose index is a loop: a step whose closure projection failed, and closure
# accelerations the prescribed motion contradicts.
LOOP_STATUSES = ("loop closure not reached", "loop-closure equations cannot be met")


@dataclass
class HilEvent:
    kind: str  # 'lock' or 'release'
    target: str  # DOF or joint name
    time: float

    def __str__(self) -> str:
        return f"{self.kind} {self.target} at {self.time:g}"


_EVENT = re.compile(r"^\s*(lock|release)\s+(\S+)\s+at\s+(\S+)\s*$")


def parse_event(text: str) -> HilEvent:
    """'lock <dof-or-joint> at <seconds>' or 'release <dof-or-joint> at <seconds>'."""
    match = _EVENT.match(text)
    if not match:
        raise ValueError(f"bad event {text!r}: expected 'lock <dof-or-joint> at <seconds>' "
                         "or 'release <dof-or-joint> at <seconds>'")
    kind, target, when = match.groups()
    try:
        time = float(when)
    except ValueError:
        raise ValueError(f"bad event {text!r}: the time {when!r} is not a number") from None
    if not (math.isfinite(time) and time >= 0):
        raise ValueError(f"bad event {text!r}: the time must be finite and >= 0")
    return HilEvent(kind, target, time)


def scene_simulator(scene: str, rate: float, integrator: str = "rk4", events=()) -> Simulator:
    """A Simulator of a built-in scene stepping at 1/rate, with the events
    scheduled. cassini: the turntable turns at 3 rpm and the engine
    gimbal follows velocity commands (scenes.drive_cassini); pendulum-chain: starts at rest with every joint at 0.3 rad;
    four-bar, slider-crank, delta-robot: start at rest, assembled (scenes.LOOP_SCENE_STARTS), and fall.
    An unknown DOF or joint in an event raises ValueError naming it."""
    if scene not in SCENES:
        raise ValueError(f"unknown scene {scene!r} (choose from {sorted(SCENES)})")
    model = SCENES[scene]()
    sim = Simulator(model, 1.0 / rate, integrator, event_capacity=64 + 6 * len(events))
    if scene == "cassini":
        drive_cassini(sim)
    elif scene == "pendulum-chain":
        sim.set_state(np.full(model.nq, 0.3), np.zeros(model.nv))
    elif scene in LOOP_SCENE_STARTS:
        sim.set_state(*LOOP_SCENE_STARTS[scene][1]())
    for event in events:
        try:
            sim.schedule(event.time, event.kind, event.target)
        except ValueError as error:
            raise ValueError(f"event '{event}': {error}") from None
    return sim


def run_hil(sim: Simulator, rate: float, duration: float, udp_port: int | None = None, progress: bool = True,
            realtime: bool = True, udp_destination_port: int = 0, spin_us: float = 0.0, fifo_priority: int = 0,
            cpu: int = -1, lock_memory: bool = False, command_limits=None, command_policy: str = "clamp",
            udp_command_port: int | None = None, max_packets_per_step: int = MAX_PACKETS_PER_STEP,
            on_start=None, on_state=None, state_interval: float = STATE_INTERVAL,
            floor_periods: int | None = None, divergence_guard: bool = True) -> HilReport:
    """Run `sim` for `duration` simulated seconds, one step per 1/rate wall seconds.

    The simulation is real time when sim.dt == 1/rate. `udp_port` (None: no
    UDP; 0: any free port) binds 127.0.0.1 for commands; sensor packets go
    to `udp_destination_port` if given, else to the command sender. Commands
    are accepted from 127.0.0.1:`udp_command_port` only (None: the
    destination port if given; 0 or no destination: the first valid sender,
    latched); others are counted and ignored. At most `max_packets_per_step`
    datagrams are read per step. `command_limits` (None: a * M_ii at the
    start, see the README; a number for every DOF; nv numbers; or a dict
    {DOF name: limit} over the defaults; inf: no limit) bound every command
    value, and `command_policy` says what a value beyond its limit does:
    'clamp' (saturate, counted per DOF), 'reject' (keep the previous command)
    or 'stop' (end the run, status "command out of range").
    `realtime=False` runs as fast as possible (no sleeping; lateness 0, no
    misses). Ctrl-C stops the loop and returns the report so far
    (`interrupted`). `spin_us` > 0 busy-waits that long before each deadline
    instead of sleeping (a warm core: lower and steadier step times, at the
    cost of that share of a core). `fifo_priority` (1-99) runs the loop's
    thread under SCHED_FIFO, `cpu` pins it to that CPU and `lock_memory`
    locks the process's pages (mlockall), all for the loop's duration only; a
    request the kernel refuses (no privilege) does not stop the run, and the
    report's `scheduling` says what was granted. A failing step (singular
    articulated inertia, NaN) or an exception raised by a Python motion
    source stops the run; the report's `status`, `failed_step`, `failed_dof`
    and `error` say why (the exception itself is `report.exception`), and
    `final_state` holds the last good state. `divergence_guard` (on by
    default; Simulator.divergence_guard) stops a run whose integration
    diverges with status "diverging", naming the DOF, before any value of
    the state is non-finite. A
    measurement that cannot be made at the end (energy of a broken state) is
    None, with the reason in `report_errors`. `on_start(runner)` is called
    once the runner exists (its `udp_port` is bound), before the loop.
    After a paced run, `floor_periods` more periods (None: as many as the
    run's steps, at most MAX_FLOOR_PERIODS; 0: none) time the machine's floor
    (HilRunner: register arithmetic of the steps' median length, paced like
    the steps); the report's `floor_us` and `misses` separate the machine's
    share of the tail and of the misses from the step's own.
    `on_state(step, t, q, v)` (a viewer's `show`, a telemetry writer) is
    called on the calling thread, at most every `state_interval` seconds and
    once more at the end, with the latest state the loop published
    (HilRunner.latest_state: a sequence-locked snapshot the loop writes
    without waiting, so a slow or failing reader never delays a C++ step;
    it holds the GIL while it runs, which a Python motion source also needs). If it
    raises, it is not called again and the report's `report_errors` say why;
    the run goes on.
    Another thread's calls on `sim` wait until the run ends (the runner
    holds the simulator's lock).
    """
    if not (math.isfinite(rate) and rate > 0):
        raise ValueError(f"rate must be a finite positive number of steps per second, got {rate}")
    if not (math.isfinite(duration) and duration >= 0):
        raise ValueError(f"duration must be a finite non-negative number of seconds, got {duration}")
    if not (math.isfinite(spin_us) and 0 <= spin_us * 1e-6 < 1.0 / rate):
        raise ValueError(f"spin_us must be in [0, {1e6 / rate:g}) (the step period), got {spin_us}")
    if command_policy not in COMMAND_POLICIES:
        raise ValueError(f"command_policy {command_policy!r}: choose one of {', '.join(COMMAND_POLICIES)}")
    if not (math.isfinite(state_interval) and state_interval > 0):
        raise ValueError(f"state_interval must be a finite positive number of seconds, got {state_interval}")
    steps = round(duration / sim.dt)
    if steps > MAX_STEPS:
        raise ValueError(f"duration {duration:g} s at dt {sim.dt:g} s is {steps:.3g} steps, more than the {MAX_STEPS:.0e} "
                         "one run records (16 bytes of timings per step): shorten the duration or lower the rate")
    steps = sim.steps_in(duration)  # a whole number of steps, as Simulator.run requires
    if floor_periods is None:
        floor_periods = min(steps, MAX_FLOOR_PERIODS)
    if isinstance(floor_periods, bool) or int(floor_periods) != floor_periods or floor_periods < 0:
        raise ValueError(f"floor_periods must be a whole number >= 0, got {floor_periods!r}")
    report_errors: list[str] = []
    energy0 = _measure(lambda: _energy(sim), "energy at start", report_errors)
    momentum0 = _measure(lambda: _momentum(sim), "momentum at start", report_errors)
    runner = HilRunner(sim, float(rate), steps, udp_port=udp_port, udp_destination_port=udp_destination_port,
                       as_fast_as_possible=not realtime, record_every=max(1, math.ceil(steps / RECORDED_SAMPLES)),
                       spin_us=float(spin_us), fifo_priority=int(fifo_priority), cpu=int(cpu),
                       lock_memory=bool(lock_memory), command_policy=command_policy,
                       udp_command_port=-1 if udp_command_port is None else int(udp_command_port),
                       max_packets_per_step=int(max_packets_per_step), floor_periods=int(floor_periods))
    if command_limits is not None:
        runner.command_limits = resolve_command_limits(command_limits, runner.command_limits, sim._dof_names)
    sim.divergence_guard = divergence_guard  # the runner turned it on
    if on_start is not None:
        on_start(runner)
    watcher = _StateWatcher(runner, on_state, report_errors) if on_state is not None else None
    interrupted, exception = _run_with_progress(runner, steps, progress, sim.dt, watcher,
                                                state_interval if watcher else PROGRESS_INTERVAL)
    return _report(sim, runner, rate, realtime, interrupted, exception, energy0, momentum0, report_errors)


def resolve_command_limits(limits, defaults, dof_names) -> np.ndarray:
    """nv limits from a number, nv numbers, or {DOF name: limit} over `defaults`.
    A name not in `dof_names` or a limit that is NaN or negative raises ValueError naming it."""
    out = np.array(defaults, dtype=float)
    if isinstance(limits, dict):
        for name, limit in limits.items():
            if name not in dof_names:
                raise ValueError(f"command limit for {name!r}: no such DOF (DOFs: {', '.join(dof_names)})")
            out[list(dof_names).index(name)] = _limit(limit, name)
        return out
    values = np.asarray(limits, dtype=float)
    if values.ndim == 0:
        return np.full(len(out), _limit(float(values), "every DOF"))
    if values.shape != out.shape:
        raise ValueError(f"command limits: expected {len(out)} values (one per DOF), got shape {values.shape}")
    for name, limit in zip(dof_names, values):
        _limit(limit, name)
    return values


def _limit(value, name) -> float:
    value = float(value)
    if not value >= 0:
        raise ValueError(f"command limit for {name!r} must be >= 0 (inf: no limit), got {value}")
    return value


def _measure(fn, what: str, errors: list):
    """fn(), or None with "what: Type: message" appended to `errors` when it raises."""
    try:
        return fn()
    except Exception as error:  # noqa: BLE001 - a report keeps what could be measured
        errors.append(f"{what}: {type(error).__name__}: {error}")
        return None


def _energy(sim: Simulator) -> float:
    return float(core.kinetic_energy(sim._model, sim.q, sim.v) + core.potential_energy(sim._model, sim.q))


def _momentum(sim: Simulator) -> list[float]:
    return [float(x) for x in core.momentum(sim._model, sim.q, sim.v)]


class _StateWatcher:
    """Hands the runner's latest published state to `on_state` when it is new; stops calling it after it raised."""

    def __init__(self, runner, on_state, report_errors: list):
        self.runner, self.on_state, self.report_errors = runner, on_state, report_errors
        self.last_step = -1

    def __call__(self) -> None:
        if self.on_state is None:
            return
        latest = self.runner.latest_state()
        if latest is None or latest[0] == self.last_step:
            return
        self.last_step = latest[0]
        try:
            self.on_state(*latest)
        except Exception as error:  # noqa: BLE001 - a failing watcher never stops the run
            self.report_errors.append(f"on_state at step {latest[0]}: {type(error).__name__}: {error} "
                                      "(not called again)")
            self.on_state = None


def _run_with_progress(runner, steps: int, show: bool, dt: float, watcher=None, interval: float = PROGRESS_INTERVAL):
    """Runs the loop in a worker thread while the main thread updates a
    progress bar (and hands states to `watcher` every `interval` s); returns
    (Ctrl-C stopped it, the exception a step raised or None)."""
    errors: list[BaseException] = []

    def work():
        try:
            runner.run()
        except BaseException as error:  # reported in the main thread
            errors.append(error)

    worker = threading.Thread(target=work, name="soadyn-hil", daemon=True)
    bar = progress_bar(steps, unit="step", desc="HIL", disable=not show)
    interrupted = False
    worker.start()
    try:
        while worker.is_alive():
            worker.join(interval)
            _update_progress(bar, runner, dt)
            if watcher is not None:
                watcher()
    except KeyboardInterrupt:
        interrupted = True
        runner.request_stop()
        worker.join()
    finally:
        _update_progress(bar, runner, dt)
        bar.close()
        if watcher is not None:
            watcher()  # the final state
    return interrupted, errors[0] if errors else None


def _update_progress(bar, runner, dt: float) -> None:
    done = runner.steps_done
    bar.update(done - bar.n)
    postfix = {"t": f"{done * dt:.2f}s", "misses": runner.deadline_misses}
    if runner.udp_port is not None:
        postfix["rx"] = runner.packets_received
        postfix["saturated"] = runner.commands_saturated
        postfix["rejected"] = runner.commands_rejected
    if bar.total and done >= bar.total:
        postfix["now"] = "timing the machine's floor"  # the paced pass after the steps (HilRunner)
    bar.set_postfix(postfix, refresh=False)


def _percentiles(s, prefix: str, names) -> dict:
    return {name: getattr(s, f"{prefix}_{name}_us") for name in names}


def _describe(exception: BaseException) -> str:
    """'Type: message', followed by the exception that caused it (a motion source's)."""
    text = f"{type(exception).__name__}: {exception}"
    cause = exception.__cause__
    return text if cause is None else f"{text} (caused by {type(cause).__name__}: {cause})"


def _report(sim, runner, rate, realtime, interrupted, exception, energy0, momentum0, report_errors) -> HilReport:
    s = runner.summary()
    if exception is not None and s.exception_step < 0:  # not raised by a step (a misuse of the runner): not a result
        raise exception
    t, q, v = runner.trajectory()
    failed = s.status != "ok"
    dof_names = list(sim._dof_names)
    loop_failed = failed and s.status in LOOP_STATUSES
    loop_names = list(sim._model.loop_names)
    energy1 = _measure(lambda: _energy(sim), "energy at end", report_errors)
    momentum1 = _measure(lambda: _momentum(sim), "momentum at end", report_errors)
    return HilReport(
        rate_hz=float(rate), realtime=realtime, requested_steps=s.requested_steps, steps=s.steps,
        deadline_misses=s.deadline_misses,
        compute_us=_percentiles(s, "compute", ("p50", "p99", "p999", "max")),
        lateness_us=_percentiles(s, "lateness", ("p50", "p99", "max")),
        packets=_packets(s), commands=_commands(s, runner.command_limits, dof_names),
        wall_seconds=s.wall_seconds, sim_time=float(sim.time), status=s.status,
        failed_step=(s.exception_step if s.exception_step >= 0 else s.failed_step) if failed else None,
        failed_dof=dof_names[s.failed_dof] if failed and not loop_failed and 0 <= s.failed_dof < len(dof_names) else None,
        failed_loop=loop_names[s.failed_dof] if loop_failed and 0 <= s.failed_dof < len(loop_names) else None,
        loop_drift=dict(zip(("max_position", "max_velocity"), sim.max_loop_drift)) if loop_names else None,
        interrupted=interrupted,
        energy={"start": energy0, "end": energy1}, momentum={"start": momentum0, "end": momentum1},
        scheduling=_scheduling(s.realtime),
        dof_names=dof_names, compute_ns=runner.compute_ns, lateness_ns=runner.lateness_ns, t=t, q=q, v=v,
        error=_describe(exception) if exception is not None else None,
        report_errors=report_errors, exception=exception,
        misses={"compute": s.misses_compute_overrun, "machine": s.misses_late_wakeup},
        floor_us=_floor(s), floor_ns=runner.floor_ns if s.floor_periods else None,
        final_state={"t": float(sim.time), "q": [float(x) for x in sim.q], "v": [float(x) for x in sim.v]})


def _floor(s) -> dict | None:
    if not s.floor_periods:
        return None
    return {"periods": s.floor_periods, "target": s.floor_target_us, "p50": s.floor_p50_us, "p99": s.floor_p99_us,
            "p999": s.floor_p999_us, "max": s.floor_max_us,
            "tail_ratio": s.compute_p999_us / s.floor_p999_us if s.floor_p999_us > 0 else None}


def _packets(s) -> dict:
    """The link's counters (all 0 without UDP); kernel_drops is None where SO_MEMINFO is not available."""
    return {"received": s.packets_received, "dropped": s.packets_dropped, "sent": s.packets_sent,
            "rejected_sender": s.packets_rejected_sender, "stale": s.packets_stale,
            "kernel_drops": s.kernel_drops if s.kernel_drops_counted or not s.max_packets_per_step else None,
            "send_failures": s.send_failures, "steps_left_pending": s.steps_left_pending,
            "max_per_step": s.max_packets_per_step}


def _commands(s, limits, dof_names) -> dict:
    return {"policy": s.command_policy, "saturated": s.commands_saturated, "rejected": s.commands_rejected,
            "saturated_dofs": {name: n for name, n in zip(dof_names, s.saturated_per_dof) if n},
            "limits": dict(zip(dof_names, (float(x) for x in limits)))}


def _scheduling(granted: dict) -> dict:
    """The runner's real-time outcome with each refusal's errno as text (None: granted or not asked)."""
    out = {}
    for key, asked, ok, errno in (("fifo", granted["fifo_priority"] > 0, "fifo_granted", "fifo_errno"),
                                  ("cpu", granted["cpu"] >= 0, "cpu_granted", "cpu_errno"),
                                  ("lock", granted["lock_memory"], "memory_locked", "lock_errno")):
        out[ok] = granted[ok]
        out[f"{key}_refused"] = os.strerror(granted[errno]) if asked and not granted[ok] else None
    return {"fifo_priority": granted["fifo_priority"], "cpu": granted["cpu"], "lock_memory": granted["lock_memory"],
            **out}


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
    return ", ".join(parts) if parts else "default (no real-time priority, pinning or memory lock asked for)"


def format_table(r: HilReport) -> str:
    """The timing table printed by `soadyn hil`."""
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
        + (f" ({r.misses['compute']} compute overran the period, {r.misses['machine']} woken or run late)"
           if r.deadline_misses else ""),
        f"scheduling       {format_scheduling(r.scheduling)}",
        f"compute   us     p50 {c['p50']:8.1f}   p99 {c['p99']:8.1f}   p99.9 {c['p999']:8.1f}   max {c['max']:8.1f}",
        f"lateness  us     p50 {lat['p50']:8.1f}   p99 {lat['p99']:8.1f}   max {lat['max']:8.1f}",
        *([f"machine   us     p50 {f['p50']:8.1f}   p99 {f['p99']:8.1f}   p99.9 {f['p999']:8.1f}   max {f['max']:8.1f}"
           f"   (floor: {f['periods']} periods of {f['target']:.1f} us register arithmetic; step p99.9 / floor p99.9 "
           + (f"{f['tail_ratio']:.2f})" if f["tail_ratio"] is not None else "n/a)")] if (f := r.floor_us) else []),
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


def require_matplotlib():
    """The matplotlib module, or an ImportError saying how to install it."""
    try:
        import matplotlib
    except ImportError:
        raise ImportError("plotting needs matplotlib: pip install 'soadyn[plot]'") from None
    return matplotlib


def plot_report(r: HilReport, path, model=None, max_dofs: int = 6) -> None:
    """A PNG with the compute-time and lateness histograms, the velocities of
    the `max_dofs` DOFs that moved most, and (given the model) the energy."""
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
