"""Real-time (hardware-in-the-loop) runs of a Simulator.

`run_hil` steps a Simulator at a fixed wall-clock rate in C++ (a worker
thread, GIL released) while the main thread shows the progress. Optionally a
controller in another process drives the regular DOFs over UDP on 127.0.0.1
(packet format: cpp/include/soadyn/realtime/udp_link.hpp and the HIL guide, docs/guides/hil.md). The
returned HilReport holds the timing statistics, the packet counts, the
energy and momentum of the model at start and end, the per-step timings and a
decimated state history. HilRunner is the bare loop, for callers that need
its UDP port before it runs.

Modules: run.py (run_hil, scene_simulator, the loop's limits), events.py (lock and release events),
report.py (HilReport, its table and plot). Everything is public here as soadyn.hil.<name>.
"""
from .. import _soadyn as core  # the compiled module the runs measure energy and momentum with
from .._soadyn import HilRunner
from .events import HilEvent, parse_event
from .report import HilReport, format_scheduling, format_table, plot_report, require_matplotlib
from .run import (COMMAND_POLICIES, LOOP_STATUSES, MAX_FLOOR_PERIODS, MAX_PACKETS_PER_STEP, MAX_STEPS,
                  PROGRESS_INTERVAL, RECORDED_SAMPLES, STATE_INTERVAL, resolve_command_limits, run_hil,
                  scene_simulator)

__all__ = ["HilEvent", "HilReport", "HilRunner", "format_table", "parse_event", "plot_report", "require_matplotlib",
           "resolve_command_limits", "run_hil", "scene_simulator"]
