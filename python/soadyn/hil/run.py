"""run_hil: step a Simulator at a fixed wall-clock rate in C++ while the main thread shows the progress;
scene_simulator: the built-in scenes set up for it."""
from __future__ import annotations

import math
import os
import threading

import numpy as np

from .. import _soadyn as core
from .._soadyn import HilRunner
from ..progress import progress_bar
from ..scenes import LOOP_SCENE_STARTS, SCENES, drive_cassini
from ..simulator import Simulator
from .report import HilReport

RECORDED_SAMPLES = 2000  # rows of state history kept for the plot
PROGRESS_INTERVAL = 0.1  # seconds between progress-bar refreshes
STATE_INTERVAL = 1.0 / 30  # seconds between on_state calls (a viewer's frame rate)
MAX_STEPS = 10**8  # one run keeps 16 bytes of timings per step: at most 1.6 GB
COMMAND_POLICIES = ("clamp", "reject", "stop")
MAX_PACKETS_PER_STEP = 16  # datagrams read per step at most (the rest wait for the next step)
MAX_FLOOR_PERIODS = 10000  # periods of the machine's floor after a paced run, at most
FLOOR_MODES = ("interleaved", "after")  # where run_hil times the machine's floor

# Statuses whose index is a loop: a step whose closure projection failed, and closure
# accelerations the prescribed motion contradicts.
LOOP_STATUSES = ("loop closure not reached", "loop-closure equations cannot be met")


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
            floor_periods: int | None = None, divergence_guard: bool = True, floor: str = "interleaved",
            preemption_margin_us: float = 10.0, warm_up: bool = True) -> HilReport:
    """Run `sim` for `duration` simulated seconds, one step per 1/rate wall seconds.

    The simulation is real time when sim.dt == 1/rate. `udp_port` (None: no
    UDP; 0: any free port) binds 127.0.0.1 for commands; sensor packets go
    to `udp_destination_port` if given, else to the command sender. Commands
    are accepted from 127.0.0.1:`udp_command_port` only (None: the
    destination port if given; 0 or no destination: the first valid sender,
    latched); others are counted and ignored. At most `max_packets_per_step`
    datagrams are read per step. `command_limits` (None: a * M_ii at the
    start, see the HIL guide (docs/guides/hil.md); a number for every DOF; nv numbers; or a dict
    {DOF name: limit} over the defaults; inf: no limit) bound every command
    value, and `command_policy` says what a value beyond its limit does:
    'clamp' (saturate, counted per DOF), 'reject' (keep the previous command)
    or 'stop' (end the run, status "command out of range").
    `realtime=False` runs as fast as possible (no sleeping; lateness 0, no
    misses). Ctrl-C stops the loop and returns the report so far
    (`interrupted`). `spin_us` > 0 busy-waits that long before each deadline
    instead of sleeping (a warm core: lower and steadier step times, at the
    cost of that share of a core); while spinning, `warm_up` evaluates the
    dynamics once shortly before each deadline (changing nothing the step
    reads), so the step finds its data in the caches. `fifo_priority` (1-99) runs the loop's
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
    Every step's wall time (`compute_us`) is timed beside the loop thread's
    own CPU time (`cpu_us`) and its involuntary context switches: a step whose
    wall time exceeds its CPU time by more than `preemption_margin_us`, or that
    was switched out, was pre-empted, and a deadline miss is ours only when
    the step's own CPU time exceeded the period (`misses`). `floor_periods`
    periods (None: every step's, at most MAX_FLOOR_PERIODS after the run; 0:
    none) time the machine's floor (HilRunner: register arithmetic of the
    first steps' median length, paced like the steps). `floor="interleaved"`
    times it at the midpoint of the steps' own periods, so step and floor see
    the same phases of the machine and the run takes no longer; "after" times
    it in the periods after a completed run. The report's `floor_us` gives
    the step's tail over the floor's (1: the step's tail is the machine's).
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

    rate in steps per s, duration in simulated s, spin_us in microseconds, ports 0..65535. Raises ValueError
    naming the argument for a rate, duration, port, priority, CPU or limit out of range and for an unknown DOF
    in command_limits or command_policy, and RuntimeError naming the address when the UDP port cannot be bound
    (already in use).
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
    if floor not in FLOOR_MODES:
        raise ValueError(f"floor {floor!r}: choose one of {', '.join(FLOOR_MODES)}")
    if not (math.isfinite(preemption_margin_us) and preemption_margin_us >= 0):
        raise ValueError(f"preemption_margin_us must be a finite number >= 0, got {preemption_margin_us}")
    if floor_periods is None:
        floor_periods = steps if floor == "interleaved" else min(steps, MAX_FLOOR_PERIODS)
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
                       max_packets_per_step=int(max_packets_per_step), floor_periods=int(floor_periods),
                       floor=floor, preemption_margin_us=float(preemption_margin_us), warm_up=bool(warm_up))
    if command_limits is not None:
        runner.command_limits = resolve_command_limits(command_limits, runner.command_limits, sim._dof_names)
    sim.divergence_guard = divergence_guard  # the runner turned it on
    if on_start is not None:
        on_start(runner)
    watcher = _StateWatcher(runner, on_state, report_errors) if on_state is not None else None
    interrupted, exception = _run_with_progress(runner, steps, progress, sim.dt, watcher,
                                                state_interval if watcher else PROGRESS_INTERVAL,
                                                interleaved_floor=floor == "interleaved")
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


def _run_with_progress(runner, steps: int, show: bool, dt: float, watcher=None, interval: float = PROGRESS_INTERVAL,
                       interleaved_floor: bool = True):
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
            _update_progress(bar, runner, dt, interleaved_floor)
            if watcher is not None:
                watcher()
    except KeyboardInterrupt:
        interrupted = True
        runner.request_stop()
        worker.join()
    finally:
        _update_progress(bar, runner, dt, interleaved_floor)
        bar.close()
        if watcher is not None:
            watcher()  # the final state
    return interrupted, errors[0] if errors else None


def _update_progress(bar, runner, dt: float, interleaved: bool = True) -> None:
    done = runner.steps_done
    bar.update(done - bar.n)
    misses = runner.deadline_misses
    ours = runner.misses_ours
    postfix = {"t": f"{done * dt:.2f}s", "misses": f"{ours} ours, {misses - ours} machine's" if misses else 0}
    if runner.udp_port is not None:
        postfix["rx"] = runner.packets_received
        postfix["saturated"] = runner.commands_saturated
        postfix["rejected"] = runner.commands_rejected
    if bar.total and done >= bar.total and not interleaved:
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
        cpu_us=_cpu(s), preempted_steps=s.preempted_steps, involuntary_switches=s.involuntary_switches,
        lateness_us=_percentiles(s, "lateness", ("p50", "p99", "max")),
        packets=_packets(s), commands=_commands(s, runner.command_limits, dof_names),
        wall_seconds=s.wall_seconds, sim_time=float(sim.time), status=s.status,
        failed_step=(s.exception_step if s.exception_step >= 0 else s.failed_step) if failed else None,
        failed_dof=dof_names[s.failed_dof] if failed and not loop_failed and 0 <= s.failed_dof < len(dof_names) else None,
        failed_loop=loop_names[s.failed_dof] if loop_failed and 0 <= s.failed_dof < len(loop_names) else None,
        loop_drift=dict(zip(("max_position", "max_velocity"), sim.max_loop_drift)) if loop_names else None,
        interrupted=interrupted,
        energy={"start": energy0, "end": energy1}, momentum={"start": momentum0, "end": momentum1},
        scheduling={**_scheduling(s.realtime), "warm_up": s.warm_up},
        dof_names=dof_names, compute_ns=runner.compute_ns, lateness_ns=runner.lateness_ns, t=t, q=q, v=v,
        error=_describe(exception) if exception is not None else None,
        report_errors=report_errors, exception=exception,
        misses={"compute": s.misses_compute_overrun, "machine": s.misses_late_wakeup,
                "machine_preempted": s.misses_preempted},
        floor_us=_floor(s), floor_ns=runner.floor_ns if s.floor_periods else None, cpu_ns=runner.cpu_ns,
        dynamics_floor_ns=runner.dynamics_floor_ns if s.floor_periods else None,
        final_state={"t": float(sim.time), "q": [float(x) for x in sim.q], "v": [float(x) for x in sim.v]})


def _floor(s) -> dict | None:
    if not s.floor_periods:
        return None
    return {"mode": "interleaved" if s.floor_interleaved else "after", "periods": s.floor_periods,
            "target": s.floor_target_us, "p50": s.floor_p50_us, "p99": s.floor_p99_us,
            "p999": s.floor_p999_us, "max": s.floor_max_us,
            "tail_ratio": s.compute_p999_us / s.floor_p999_us if s.floor_p999_us > 0 else None,
            "dynamics": _dynamics_floor(s)}


def _dynamics_floor(s) -> dict:
    """The dynamics floor of the same periods: percentiles (us), its own spread and the step's tail over it."""
    p50, p999 = s.dynamics_floor_p50_us, s.dynamics_floor_p999_us
    return {"evaluations": s.dynamics_floor_evaluations, "p50": p50, "p99": s.dynamics_floor_p99_us, "p999": p999,
            "max": s.dynamics_floor_max_us, "spread": p999 / p50 if p50 > 0 else None,
            "tail_ratio": s.compute_p999_us / p999 if p999 > 0 else None}


def _cpu(s) -> dict:
    """The step's own CPU time: percentiles (us) and the spread of its work, p99.9 / p50."""
    return {**_percentiles(s, "cpu", ("p50", "p99", "p999", "max")),
            "spread": s.cpu_p999_us / s.cpu_p50_us if s.cpu_p50_us > 0 else None,
            "preemption_margin": s.preemption_margin_us}


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
