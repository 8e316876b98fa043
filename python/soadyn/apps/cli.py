"""Command line: `soadyn demo` (cassini or four-bar), `soadyn check`, `soadyn hil`, `soadyn view`,
`soadyn campaign`.

Every bad argument ends in one line on stderr naming it (argparse's usage
line and `error:`, exit code 2), never a traceback; every output path (a
report, a plot, a results directory) is checked before any work starts and
refused the same way (check_outputs); a run that cannot start
for a reason outside the arguments (a UDP port in use, missing memory) is
one line too, exit code 1.
"""
from __future__ import annotations

import argparse
import contextlib
import io
import json
import math
import sys
import time
from pathlib import Path

from .. import campaign, hil, scenes
from .._soadyn import DynamicsError
from .._version import __version__
from ..campaign.movie import MovieError
from ..check.cross_check import cross_check_report, format_report
from ..io.example_robots import example_robot_files, example_robots_dir, example_robots_version
from ..output_paths import output_problem
from ..simulator import STEP_TOLERANCE, Simulator
from ..viz.headless import MOVIE_EXTENSIONS
from ..viz.sources import BUILT_IN_SCENES, load_any, start_state
from ..viz.viewer import Viewer
from . import four_bar_demo
from .boom_vibration import format_response, gimbal_step_response, plot_response
from .demo import describe_scene, format_result, run_demo
from .fmu_command import add_fmu_parser, run_fmu_command

# Scenes of `soadyn demo` and the file a bare --plot writes.
DEMO_PLOTS = {"cassini": "booms.png", "four-bar": "four_bar.png"}


def build_parser() -> tuple[argparse.ArgumentParser, dict[str, argparse.ArgumentParser]]:
    """The `soadyn` parser and its commands' parsers by name (the CLI reference of the manual is made from
    them)."""
    parser = argparse.ArgumentParser(prog="soadyn", description="O(N) hybrid multibody dynamics.")
    parser.add_argument("--version", action="version", version=f"soadyn {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="{demo,check,hil,view,campaign,robots,fmu}")
    demo = sub.add_parser("demo", help="fly a built-in scene for a few seconds and report")
    demo.add_argument("--scene", default="cassini", choices=list(DEMO_PLOTS),
                      help="built-in scene (default cassini); four-bar: the crank-rocker of Saha, Shah & Nandihal 2013")
    demo.add_argument("--duration", type=float, default=2.0,
                      help="simulated seconds (default 2; four-bar: of the free fall)")
    demo.add_argument("--dt", type=float, default=1e-3, help="step in seconds (default 0.001)")
    demo.add_argument("--boom-duration", type=float, default=20.0,
                      help="simulated seconds of the boom-vibration run after a gimbal step (default 20; 0 skips it)")
    demo.add_argument("--revolution", type=float, default=1.0,
                      help="four-bar: seconds per crank revolution of the driven runs (default 1)")
    demo.add_argument("--plot", metavar="OUT.png", nargs="?", const="",
                      help="plot (needs matplotlib): cassini the booms' tip deflections, four-bar the joint angles "
                           "and crank torque; without a file name: " + ", ".join(DEMO_PLOTS.values()))
    check = sub.add_parser("check", help="compare soadyn with every oracle (Pinocchio, DART, MuJoCo) that can load "
                                         "a URDF or MJCF file")
    check.add_argument("file", help="path of the URDF or MJCF file")
    check.add_argument("--floating", action="store_true",
                       help="add a free-floating root joint (MJCF: to bodies attached to the world without a joint)")
    check.add_argument("--states", type=int, default=3, help="random states to compare (default 3)")
    check.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    check.add_argument("--tolerance", type=float, default=1e-9,
                       help="largest accepted relative difference (default 1e-9); above it the exit code is 1")
    view = sub.add_parser("view", help="draw a model in the browser (viser): a scene name, a model file (.json), "
                                       "an MJCF (.xml) or a URDF (.urdf)")
    view.add_argument("model", help="cassini, four-bar, slider-crank, delta-robot, a .json, .xml or .urdf file, "
                                    "or an example robot's name (soadyn robots lists them: ur5_robot, talos_reduced)")
    view.add_argument("--host", default="127.0.0.1", help="address to serve on (default 127.0.0.1)")
    view.add_argument("--port", type=int, default=8080, help="port (default 8080; 0: any free port)")
    view.add_argument("--simulate", type=float, default=0.0, metavar="SECONDS",
                      help="simulate this long from the shown state (RK4, 1 ms) and replay it with a time slider")
    view.add_argument("--duration", type=float, default=None,
                      help="serve this many seconds, then exit (default: until Ctrl-C)")
    add_exaggeration_option(view, "--exaggeration")
    add_picture_options(view)
    robots = sub.add_parser("robots", help="list the built-in scenes and the example robots installed here, with their "
                                           "paths")
    commands = {"demo": demo, "check": check, "hil": add_hil_parser(sub), "view": view,
                "campaign": add_campaign_parser(sub), "robots": robots, "fmu": add_fmu_parser(sub)}
    return parser, commands


def main(argv: list[str] | None = None) -> int:
    parser, commands = build_parser()
    args = parser.parse_args(argv)
    if args.command is None:
        parser.error("a command is required: demo, check, hil, view, campaign, robots or fmu (soadyn COMMAND --help for "
                     "its options)")
    if args.command == "campaign":
        return run_campaign_command(args, commands["campaign"])
    if args.command == "check":
        return run_check(args, commands["check"])
    if args.command == "hil":
        return run_hil_command(args, commands["hil"])
    if args.command == "view":
        return run_view(args, commands["view"])
    if args.command == "robots":
        print(format_robots())
        return 0
    if args.command == "fmu":
        return run_fmu_command(args, commands["fmu"])
    return run_demo_command(args, commands["demo"])


def format_robots() -> str:
    """`soadyn robots`: the built-in scenes, and example-robot-data's URDFs with their full paths."""
    lines = [f"built-in scenes (soadyn view NAME): {', '.join(BUILT_IN_SCENES)}"]
    files, version = example_robot_files(), example_robots_version()
    if not files:
        lines.append("example-robot-data is not installed here: pip install example-robot-data")
        return "\n".join(lines)
    lines.append(f"example-robot-data {version}: {len(files)} URDF files in {example_robots_dir()} "
                 f"(soadyn view NAME, or its path where two share a name)")
    width = max(len(path.stem) for path in files)
    lines += [f"  {path.stem:<{width}}  {path}" for path in files]
    return "\n".join(lines)


def finite(parser, option: str, value: float, least: float, inclusive: bool = False) -> None:
    """argparse error naming `option` unless `value` is finite and above `least` (or equal, if inclusive)."""
    if not (math.isfinite(value) and (value >= least if inclusive else value > least)):
        bound = f">= {least:g}" if inclusive else f"> {least:g}"
        parser.error(f"argument {option}: must be a finite number {bound}, got {value}")


def run_demo_command(args, parser) -> int:
    finite(parser, "--duration", args.duration, 0.0)
    finite(parser, "--dt", args.dt, 0.0)
    finite(parser, "--boom-duration", args.boom_duration, 0.0, inclusive=True)
    finite(parser, "--revolution", args.revolution, 0.0)
    if args.plot is not None:
        require_plotting(parser)
        args.plot = args.plot or DEMO_PLOTS[args.scene]
        check_outputs(parser, ("--plot", args.plot))
    if args.scene == "four-bar":
        return run_four_bar_demo(args)
    model = scenes.SCENES[args.scene]()
    print(describe_scene(args.scene, model))
    print(format_result(run_demo(model, args.duration, args.dt)))
    if args.boom_duration > 0:
        response = gimbal_step_response(scenes.SCENES[args.scene](), duration=args.boom_duration, dt=args.dt)
        print(format_response(response))
        if args.plot:
            plot_response(response, args.plot)
            print(f"plot written to {args.plot}")
    return 0


def run_four_bar_demo(args) -> int:
    model = scenes.four_bar()
    print(describe_scene(args.scene, model))
    print(f"loop coupler_rocker: revolute cut, {model.nloop_equations} equations; one crank revolution in "
          f"{args.revolution:g} s, sampled every {args.dt:g} s")
    driven = [four_bar_demo.constant_rate(args.revolution, args.dt),
              four_bar_demo.cycloidal(args.revolution, args.dt)]
    fall = four_bar_demo.free_fall(args.duration, args.dt)
    print(four_bar_demo.format_runs(driven + [fall]))
    if args.plot:
        four_bar_demo.plot_runs(driven, fall, args.plot)
        print(f"plot written to {args.plot}")
    return 0


def add_hil_parser(sub) -> argparse.ArgumentParser:
    hil = sub.add_parser("hil", help="step a built-in scene in real time, optionally with a UDP controller")
    hil.add_argument("--scene", default="cassini", choices=sorted(scenes.SCENES),
                     help="built-in scene (default cassini)")
    hil.add_argument("--rate", type=float, default=1000.0,
                     help="steps per wall-clock second; dt = 1/rate (default 1000)")
    hil.add_argument("--duration", type=float, default=10.0, help="simulated seconds (default 10)")
    hil.add_argument("--integrator", default="rk4", choices=["euler", "rk4", "dopri5"], help="(default rk4)")
    hil.add_argument("--event", action="append", default=[], metavar="'lock|release DOF at T'",
                     help="lock or release a DOF or joint at simulation time T (repeatable)")
    hil.add_argument("--udp", type=int, metavar="PORT", help="receive actuator commands on 127.0.0.1:PORT")
    hil.add_argument("--udp-peer", type=int, default=0, metavar="PORT",
                     help="send sensor packets to 127.0.0.1:PORT (default: to the last command's sender)")
    hil.add_argument("--report", metavar="OUT.json", help="write the report as JSON")
    hil.add_argument("--plot", metavar="OUT.png", help="plot timings and state histories (needs matplotlib)")
    hil.add_argument("--no-progress", action="store_true", help="no progress bar")
    hil.add_argument("--as-fast-as-possible", action="store_true", help="do not pace the steps (benchmarking)")
    hil.add_argument("--spin-us", type=float, default=0.0, metavar="US",
                     help="busy-wait the last US microseconds before each step instead of sleeping "
                          "(warm core, steadier step times; costs that share of a core)")
    hil.add_argument("--fifo-priority", type=int, default=0, metavar="1-99",
                     help="run the loop under SCHED_FIFO at this priority (needs CAP_SYS_NICE or an rtprio "
                          "limit; refused requests are reported, not fatal)")
    hil.add_argument("--cpu", type=int, default=-1, metavar="K", help="pin the loop's thread to CPU K")
    hil.add_argument("--lock-memory", action="store_true",
                     help="lock the process's memory (mlockall) while the loop runs")
    hil.add_argument("--udp-command-port", type=int, metavar="PORT",
                     help="accept commands only from 127.0.0.1:PORT (default: the --udp-peer port if given, else "
                          "the first sender, latched for the run); others are counted as rejected")
    hil.add_argument("--max-packets-per-step", type=int, default=16, metavar="N",
                     help="read at most N datagrams per step, the rest at the next steps (default 16)")
    hil.add_argument("--command-limit", action="append", default=[], metavar="LIMIT|DOF=LIMIT",
                     help="largest |command| of every DOF, or of one DOF (repeatable; default 1000 M_ii per DOF, "
                          "see the HIL guide, docs/guides/hil.md; inf: no limit)")
    hil.add_argument("--floor-periods", type=int, default=None, metavar="N",
                     help="time the machine's floor over N periods (default: every step's period when interleaved, "
                          "at most 10000 after the run; 0: none)")
    hil.add_argument("--floor", default="interleaved", choices=["interleaved", "after"],
                     help="time the floor at the midpoint of the steps' own periods (default: the same phases of "
                          "the machine, no extra time) or in the periods after the run")
    hil.add_argument("--no-warm-up", action="store_true",
                     help="while spinning, do not evaluate the dynamics once before each deadline to warm the caches")
    hil.add_argument("--preemption-margin-us", type=float, default=10.0, metavar="US",
                     help="a step whose wall time exceeds its CPU time by more than this was pre-empted (default 10)")
    hil.add_argument("--view", action="store_true",
                     help="draw the run live in the browser (viser), from snapshots the loop publishes without waiting")
    hil.add_argument("--view-host", default="127.0.0.1", help="address the viewer serves on (default 127.0.0.1)")
    hil.add_argument("--view-port", type=int, default=8080, help="the viewer's port (default 8080; 0: any free port)")
    add_exaggeration_option(hil, "--view-exaggeration")
    hil.add_argument("--command-policy", default="clamp", choices=["clamp", "reject", "stop"],
                     help="a command beyond its limit is clamped (default), rejected, or stops the run")
    hil.add_argument("--no-divergence-guard", action="store_true",
                     help="do not stop a run whose integration diverges (status 'diverging', before the state is "
                          "non-finite; on by default)")
    return hil


CAMPAIGN_USAGE = """soadyn campaign SPEC.toml|EXAMPLE --out DIR [--scheduler ADDRESS | --workers N] [--runs N]
                       [--chunk N] [--no-progress] [--no-dashboard]
       soadyn campaign replay DIR RUN_ID
       soadyn campaign report DIR [--plots DIR] [--no-plots] [--movie METRIC]"""


def add_campaign_parser(sub) -> argparse.ArgumentParser:
    parser = sub.add_parser(
        "campaign", usage=CAMPAIGN_USAGE,
        help="Monte Carlo campaign of a spec on Dask (local cluster or --scheduler); replay a run; report",
        description="Run the campaign a spec describes (a TOML file, or a built-in example: cassini-example) "
                    "and write its results to DIR, resuming there if an earlier campaign of the same spec "
                    "stopped; `replay DIR RUN_ID` recomputes one run and compares it with the stored one; "
                    "`report DIR` prints a summary table and writes histograms and scatter plots (PNG).")
    parser.add_argument("words", nargs="+", metavar="SPEC.toml|replay|report",
                        help="a spec file or example name; or replay DIR RUN_ID; or report DIR")
    parser.add_argument("--out", metavar="DIR", help="results directory (created; resumed if it holds this spec)")
    parser.add_argument("--scheduler", metavar="ADDRESS",
                        help="run on this Dask scheduler (tcp://host:port) instead of a local cluster")
    parser.add_argument("--workers", type=int, metavar="N",
                        help="worker processes of the local cluster (default: one per core)")
    parser.add_argument("--runs", type=int, metavar="N", help="number of runs instead of the spec's")
    parser.add_argument("--chunk", type=int, metavar="N",
                        help="runs per Dask task (default: enough tasks to spread the runs, at most 50 runs each)")
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")
    parser.add_argument("--no-dashboard", action="store_true", help="local cluster: no Dask dashboard")
    parser.add_argument("--plots", metavar="DIR",
                        help="report: where the PNGs and summary.md go (default DIR/report)")
    parser.add_argument("--no-plots", action="store_true", help="report: the table only")
    parser.add_argument("--movie", metavar="METRIC",
                        help="report: also a movie (MP4, headless Chromium) of the run with the largest METRIC")
    return parser


def run_campaign_command(args, parser) -> int:
    words = args.words
    if words[0] in ("replay", "report"):
        used = [option for option, value in (("--out", args.out), ("--scheduler", args.scheduler),
                                             ("--workers", args.workers), ("--runs", args.runs),
                                             ("--chunk", args.chunk)) if value is not None]
        if used:
            parser.error(f"argument {used[0]}: not an option of `campaign {words[0]}`")
        if words[0] == "replay":
            return run_campaign_replay(words[1:], parser)
        return run_campaign_report(words[1:], args, parser)
    if len(words) > 1:
        parser.error(f"unrecognized arguments: {' '.join(words[1:])} (a campaign takes one spec; "
                     f"or: replay DIR RUN_ID, report DIR)")
    report_only = [name for name, given in (("--plots", args.plots is not None), ("--no-plots", args.no_plots),
                                            ("--movie", args.movie is not None)) if given]
    if report_only:
        parser.error(f"argument {report_only[0]}: an option of `campaign report` only")
    if args.out is None:
        parser.error("argument --out: required: the results directory of the campaign")
    for option, value in (("--workers", args.workers), ("--runs", args.runs), ("--chunk", args.chunk)):
        if value is not None and value < 1:
            parser.error(f"argument {option}: must be >= 1, got {value}")
    if args.scheduler is not None and args.workers is not None:
        parser.error("argument --workers: sizes the local cluster; with --scheduler the cluster has its own workers")
    check_outputs(parser, ("--out", args.out, True))
    try:
        spec = campaign.load_spec(words[0], runs=args.runs)
    except campaign.SpecError as error:
        parser.error(f"argument SPEC: {one_line(error)}")
    try:
        campaign.run(spec, args.scheduler, out=args.out, workers=args.workers, chunk_size=args.chunk,
            progress=not args.no_progress, dashboard=not args.no_dashboard)
    except campaign.ResultsDirectoryError as error:
        parser.error(f"argument --out: {one_line(error)}")
    except campaign.CampaignError as error:
        parser.exit(1, f"soadyn campaign: error: {one_line(error)}\n")
    except KeyboardInterrupt:
        parser.exit(130, f"soadyn campaign: interrupted; the finished runs are in {args.out}: the same command "
                         f"resumes the campaign\n")
    return 0


def run_campaign_replay(words, parser) -> int:
    if len(words) != 2:
        parser.error(f"replay takes DIR RUN_ID, got {len(words)} argument{'s' * (len(words) != 1)}")
    out, text = words
    try:
        run_id = int(text)
    except ValueError:
        parser.error(f"argument RUN_ID: an integer is required, got {text!r}")
    try:
        result = campaign.replay(out, run_id)
    except campaign.CampaignError as error:
        parser.error(f"argument DIR: {one_line(error)}")
    except ValueError as error:
        parser.error(f"argument RUN_ID: {one_line(error)}")
    print(campaign.format_replay(result))
    return 0 if result.equal or not result.stored else 1


def run_campaign_report(words, args, parser) -> int:
    if len(words) != 1:
        parser.error(f"report takes DIR, got {len(words)} arguments")
    if not args.no_plots:
        require_plotting(parser, "--plots")
        if args.plots is not None:
            check_outputs(parser, ("--plots", args.plots, True))
        elif Path(words[0]).is_dir():  # else the report's own error names DIR
            check_outputs(parser, ("--plots (default DIR/report)", str(Path(words[0]) / "report"), True))
    try:
        result = campaign.report(words[0], plots_dir=args.plots, plots=not args.no_plots, movie=args.movie)
    except MovieError as error:
        parser.error(f"argument --movie: {one_line(error)}")
    except campaign.CampaignError as error:
        parser.error(f"argument DIR: {one_line(error)}")
    except (OSError, RuntimeError, ValueError) as error:
        parser.exit(1, f"soadyn campaign report: error: {one_line(error)}\n")
    print(f"{result.finished} of {result.runs} runs finished, {result.failed} failed")
    print(campaign.format_summary(result.summary))
    if result.plots:
        print(f"{len(result.plots)} plots and the table written to {result.table_path.parent}")
    if result.movie is not None:
        path, run_id, value = result.movie
        print(f"the run with the largest {args.movie} (run {run_id}, {value:.6g}) replayed in {path}")
    return 0


def add_exaggeration_option(parser, option: str) -> None:
    parser.add_argument(option, type=float, default=1.0, metavar="FACTOR",
                        help="draw flexible bodies' deformation this many times larger (default 1; a slider too)")


def add_picture_options(view) -> None:
    """soadyn view's replay and export options (pictures need Chromium: soadyn.viz.headless)."""
    view.add_argument("--trajectory", metavar="FILE.npz",
                      help="replay this trajectory (arrays t and q, as Trajectory.save writes) instead of --simulate")
    view.add_argument("--trail", action="append", default=[], metavar="FRAME",
                      help="draw the path of this body or frame over the replay (repeat for several)")
    view.add_argument("--speed", type=float, default=1.0,
                      help="replay speed: simulated seconds per second (default 1)")
    view.add_argument("--follow", action="store_true", help="keep the camera on a free-floating base")
    view.add_argument("--no-axes", dest="axes", action="store_false", help="do not draw body and frame axes")
    view.add_argument("--screenshot", metavar="OUT.png",
                      help="write a PNG of the first state, framed on the model, and exit (headless Chromium)")
    view.add_argument("--movie", metavar="OUT.mp4",
                      help="write a movie (.mp4 or .gif) of the replay (--trajectory or --simulate) and exit")
    view.add_argument("--html", metavar="OUT.html",
                      help="write a standalone page that replays the scene offline (with the replay, if any) and exit")
    view.add_argument("--width", type=int, default=1280, help="picture width in pixels (default 1280)")
    view.add_argument("--height", type=int, default=720, help="picture height in pixels (default 720)")
    view.add_argument("--fps", type=float, default=30.0, help="movie and page frames per second (default 30)")


def open_viewer(parser, model, host: str, port: int, q, exaggeration: float, what: str, axes: bool = True,
                environment: bool = True):
    """A Viewer, or a one-line error: viser missing, a port in use, a bad factor."""
    if not 0 <= port <= 65535:
        parser.error(f"argument {what}: {port} is not a port number (0-65535)")
    try:
        return Viewer(model, host=host, port=port, q=q, exaggeration=exaggeration, frames=axes,
                      environment=environment)
    except ImportError as exc:
        parser.exit(1, f"soadyn: the viewer needs viser (pip install 'soadyn[view]'): {exc}\n")
    except (OSError, ValueError) as exc:
        parser.exit(1, f"soadyn: cannot start the viewer: {one_line(exc)}\n")


def parse_command_limits(texts: list[str], dof_names: list[str]) -> dict | None:
    """--command-limit values as {DOF: limit} (LIMIT sets every DOF; a later value wins), or None.
    Raises ValueError naming the text at fault."""
    limits: dict[str, float] = {}
    for text in texts:
        name, _, value = text.rpartition("=")
        try:
            limit = float(value)
        except ValueError:
            raise ValueError(f"{text!r}: expected LIMIT or DOF=LIMIT with a number") from None
        if not limit >= 0:
            raise ValueError(f"{text!r}: a limit is >= 0 (inf: no limit)")
        if name and name not in dof_names:
            raise ValueError(f"{text!r}: no DOF named {name!r}")
        limits.update({name: limit} if name else dict.fromkeys(dof_names, limit))
    return limits or None


def check_hil_arguments(args, parser) -> None:
    finite(parser, "--rate", args.rate, 0.0)
    finite(parser, "--duration", args.duration, 0.0, inclusive=True)
    steps = round(args.duration * args.rate)
    if abs(args.duration * args.rate - steps) > STEP_TOLERANCE:
        parser.error(f"argument --duration: {args.duration:g} s at --rate {args.rate:g} is not a whole number of "
                     f"steps ({args.duration * args.rate:.9g})")
    if steps > hil.MAX_STEPS:
        parser.error(f"argument --duration: {args.duration:g} s at --rate {args.rate:g} is {steps:.3g} steps, more "
                     f"than the {hil.MAX_STEPS:.0e} one run records (16 bytes of timings per step)")
    for option, port in (("--udp", args.udp), ("--udp-peer", args.udp_peer), ("--udp-command-port", args.udp_command_port)):
        if port is not None and not 0 <= port <= 65535:
            parser.error(f"argument {option}: {port} is not a port (0..65535)")
    if args.max_packets_per_step < 1:
        parser.error(f"argument --max-packets-per-step: must be >= 1, got {args.max_packets_per_step}")
    if args.floor_periods is not None and not 0 <= args.floor_periods <= hil.MAX_STEPS:
        parser.error(f"argument --floor-periods: must be in [0, {hil.MAX_STEPS:.0e}], got {args.floor_periods}")
    if not (math.isfinite(args.spin_us) and 0 <= args.spin_us < 1e6 / args.rate):
        parser.error(f"argument --spin-us: must be in [0, {1e6 / args.rate:g}) (the step period), got {args.spin_us}")
    check_outputs(parser, ("--report", args.report), ("--plot", args.plot))


def run_hil_command(args, parser) -> int:
    check_hil_arguments(args, parser)
    try:
        events = [hil.parse_event(text) for text in args.event]
        sim = hil.scene_simulator(args.scene, args.rate, args.integrator, events)
    except ValueError as error:
        parser.error(f"argument --event: {error}")
    try:
        limits = parse_command_limits(args.command_limit, sim._dof_names)
    except ValueError as error:
        parser.error(f"argument --command-limit: {error}")
    if args.plot:
        require_plotting(parser)  # fail before the run, not after it
    print(describe_scene(args.scene, sim._model))
    for event in events:
        print(f"event: {event}")

    def announce(runner) -> None:
        if runner.udp_port is not None:
            print(f"commands on 127.0.0.1:{runner.udp_port}", flush=True)

    viewer = None
    if args.view:
        finite(parser, "--view-exaggeration", args.view_exaggeration, 0.0, inclusive=True)
        viewer = open_viewer(parser, sim._model, args.view_host, args.view_port, sim.q, args.view_exaggeration,
                             "--view-port")
        print(f"viewer at {viewer.url}", flush=True)

    try:
        report = hil.run_hil(sim, args.rate, args.duration, udp_port=args.udp, progress=not args.no_progress,
                             realtime=not args.as_fast_as_possible, udp_destination_port=args.udp_peer,
                             spin_us=args.spin_us, fifo_priority=args.fifo_priority, cpu=args.cpu,
                             lock_memory=args.lock_memory, command_limits=limits,
                             command_policy=args.command_policy, udp_command_port=args.udp_command_port,
                             max_packets_per_step=args.max_packets_per_step, on_start=announce,
                             on_state=(lambda step, t, q, v: viewer.show(q)) if viewer else None,
                             floor_periods=args.floor_periods, divergence_guard=not args.no_divergence_guard,
                             floor=args.floor, preemption_margin_us=args.preemption_margin_us,
                             warm_up=not args.no_warm_up)
    except ValueError as error:  # priority, CPU or a command limit out of range: the message names it
        parser.error(str(error))
    except (RuntimeError, MemoryError) as error:  # the UDP port could not be bound; no memory for the run
        parser.exit(1, f"soadyn hil: {type(error).__name__ if isinstance(error, MemoryError) else 'error'}: {error}\n")
    finally:
        if viewer is not None:
            viewer.close()
    write_hil_outputs(args, events, sim, report)
    return 0 if report.ok else 1


def check_outputs(parser, *outputs) -> None:
    """Every output of a command, checked before any work: (option, path) for a file, (option, path,
    True) for a directory (created with its parents); a one-line error naming the option, the path
    and why it cannot be written. An option not given (None or "") is skipped."""
    for option, path, *directory in outputs:
        problem = output_problem(path, bool(directory and directory[0])) if path else None
        if problem:
            parser.error(f"argument {option}: {path}: {problem}")


def require_plotting(parser, option: str = "--plot") -> None:
    try:
        hil.require_matplotlib()
    except ImportError as error:
        parser.error(f"argument {option}: {error}")


def write_hil_outputs(args, events, sim, report) -> None:
    """The report first (what was measured is kept whatever follows), then the table and the plot."""
    if args.report:
        summary = {"scene": args.scene, "integrator": args.integrator, "events": [str(e) for e in events],
                   **report.to_dict()}
        with open(args.report, "w") as out:
            json.dump(summary, out, indent=2, allow_nan=False)
    print(hil.format_table(report))
    if args.plot:
        hil.plot_report(report, args.plot, sim._model)


def run_check(args, parser) -> int:
    if args.states < 1:
        parser.error(f"argument --states: must be >= 1, got {args.states}")
    if not (math.isfinite(args.tolerance) and args.tolerance >= 0):
        parser.error(f"argument --tolerance: must be a finite number >= 0, got {args.tolerance}")
    try:
        report = cross_check_report(args.file, floating_base=args.floating, states=args.states, seed=args.seed)
    except (OSError, ValueError, ImportError) as error:  # unreadable or bad file (UrdfError, MjcfError), or no oracle
        parser.exit(2, f"soadyn check: error: {args.file}: {one_line(error)}\n")
    except Exception as error:  # noqa: BLE001 - a model one of the libraries cannot compute: one line, exit 1
        parser.exit(1, f"soadyn check: error: {args.file}: {type(error).__name__}: {one_line(error)}\n")
    base = "floating base" if args.floating else "base as in the file"
    print(f"{args.file}: {report.format}, {base}, {args.states} random states")
    print(format_report(report, args.tolerance))
    return 0 if report.passed(args.tolerance) else 1


def one_line(error: BaseException) -> str:
    return " ".join(str(error).split()) or type(error).__name__



def view_replay(args, parser, model, q, v):
    """The trajectory soadyn view replays: --trajectory's file, a --simulate run, or None."""
    if args.trajectory is not None:
        if args.simulate > 0:
            parser.error("argument --trajectory: give --trajectory or --simulate, not both")
        return args.trajectory
    if args.simulate > 0:
        sim = Simulator(model, dt=1e-3)
        sim.set_state(q, v)
        return sim.run(args.simulate)
    return None


def check_exports(args, parser) -> None:
    """argparse errors, before any work, for what soadyn view cannot write."""
    if args.movie is not None:
        if args.trajectory is None and args.simulate <= 0:
            parser.error("argument --movie: needs a replay (--trajectory FILE.npz or --simulate SECONDS)")
        if not args.movie.lower().endswith(MOVIE_EXTENSIONS):
            parser.error(f"argument --movie: write a {' or '.join(MOVIE_EXTENSIONS)} file, not '{args.movie}'")
    for path in (args.screenshot, args.movie, args.html):
        problem = output_problem(path) if path is not None else None
        if problem:
            parser.error(f"cannot write '{path}': {problem}")
    for option in ("--width", "--height"):
        size = getattr(args, option[2:])
        if not 16 <= size <= 8192:
            parser.error(f"argument {option}: must be 16 to 8192 pixels, got {size}")


def export_view(args, parser, viewer, replay) -> int:
    """soadyn view --screenshot/--movie/--html: write each, say where, exit (1 with the reason on failure)."""
    written = []
    try:
        if args.screenshot is not None:
            viewer.save_png(args.screenshot, args.width, args.height)
            written.append(args.screenshot)
        if args.movie is not None:
            frames = viewer.save_movie(args.movie, replay, args.fps, args.width, args.height, args.speed)
            written.append(f"{args.movie} ({frames} frames)")
        if args.html is not None:
            viewer.save_html(args.html, replay, args.fps)
            written.append(args.html)
    except (RuntimeError, ValueError, OSError, TimeoutError) as exc:
        print(f"soadyn view: {args.model}: {one_line(exc)}", file=sys.stderr)
        return 1
    print(f"soadyn view: {args.model}: wrote {', '.join(written)}", flush=True)
    return 0


def run_view(args, parser) -> int:
    """soadyn view: serve the model (and an optional replay) until Ctrl-C or --duration, or write pictures."""
    finite(parser, "--simulate", args.simulate, 0.0, inclusive=True)
    if args.duration is not None:
        finite(parser, "--duration", args.duration, 0.0, inclusive=True)
    for option in ("--speed", "--fps"):
        finite(parser, option, getattr(args, option[2:]), 0.0, inclusive=False)
    exporting = any(x is not None for x in (args.screenshot, args.movie, args.html))
    check_exports(args, parser)
    try:
        model = load_any(args.model)
    except (ValueError, OSError) as exc:
        parser.error(f"argument model: {exc}")
    finite(parser, "--exaggeration", args.exaggeration, 0.0, inclusive=True)
    try:
        q, v = start_state(args.model, model)
    except (ValueError, DynamicsError) as exc:
        print(f"soadyn view: {args.model}: cannot start: {exc}", file=sys.stderr)
        return 1
    quiet = contextlib.redirect_stdout(io.StringIO()) if exporting else contextlib.nullcontext()
    with quiet:  # viser's banner says where it serves: nothing to say when only writing files
        viewer = open_viewer(parser, model, "127.0.0.1" if exporting else args.host, 0 if exporting else args.port,
                             q, args.exaggeration, "--port", args.axes, environment=not exporting)
    try:
        if args.follow and viewer.follow_checkbox is not None:
            viewer.follow_checkbox.value = True
        replay = view_replay(args, parser, model, q, v)
        if replay is not None:
            viewer.play(replay, speed=args.speed, trails=args.trail)
    except (DynamicsError, ValueError) as exc:
        viewer.close()
        print(f"soadyn view: {args.model}: {one_line(exc)}", file=sys.stderr)
        return 1
    if exporting:
        try:
            return export_view(args, parser, viewer, replay)
        finally:
            with contextlib.redirect_stdout(io.StringIO()):
                viewer.close()
    print(f"soadyn view: {args.model} at {viewer.url} ({model.nbodies} bodies, {len(viewer.visuals)} visuals)",
          flush=True)
    try:
        deadline = math.inf if args.duration is None else time.monotonic() + args.duration
        while time.monotonic() < deadline:
            time.sleep(min(0.1, max(0.0, deadline - time.monotonic())))
    except KeyboardInterrupt:
        pass
    finally:
        viewer.close()
    return 0


if __name__ == "__main__":
    sys.exit(main())
