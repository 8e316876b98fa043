"""Command line: `soadyn demo`."""
from __future__ import annotations

import argparse
import sys

from . import scenes
from .demo import describe_scene, format_result, run_demo


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="soadyn", description="O(N) hybrid multibody dynamics.")
    sub = parser.add_subparsers(dest="command", required=True)
    demo = sub.add_parser("demo", help="fly a built-in scene for a few seconds and report")
    demo.add_argument("--scene", default="cassini", choices=["cassini"], help="built-in scene (default cassini)")
    demo.add_argument("--duration", type=float, default=2.0, help="simulated seconds (default 2)")
    demo.add_argument("--dt", type=float, default=1e-3, help="step in seconds (default 0.001)")
    demo.add_argument("--boom-duration", type=float, default=20.0,
                      help="simulated seconds of the boom-vibration run after a gimbal step (default 20; 0 skips it)")
    demo.add_argument("--plot", metavar="OUT.png", help="plot the booms' tip deflections (needs matplotlib)")
    check = sub.add_parser("check", help="compare soadyn with DART and Pinocchio on a URDF")
    check.add_argument("urdf", help="path of the URDF file")
    check.add_argument("--floating", action="store_true", help="add a free-floating root joint")
    check.add_argument("--states", type=int, default=3, help="random states to compare (default 3)")
    check.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    check.add_argument("--tolerance", type=float, default=1e-9,
                       help="largest accepted relative difference (default 1e-9); above it the exit code is 1")
    hil_parser = add_hil_parser(sub)
    args = parser.parse_args(argv)
    if args.command == "check":
        return run_check(args)
    if args.command == "hil":
        return run_hil_command(args, hil_parser)
    if not (args.duration > 0 and args.dt > 0):
        parser.error("--duration and --dt must be positive")
    if not args.boom_duration >= 0:
        parser.error("--boom-duration must not be negative")
    model = scenes.SCENES[args.scene]()
    print(describe_scene(args.scene, model))
    print(format_result(run_demo(model, args.duration, args.dt)))
    if args.boom_duration > 0:
        from .boom_vibration import format_response, gimbal_step_response, plot_response

        response = gimbal_step_response(scenes.SCENES[args.scene](), duration=args.boom_duration, dt=args.dt)
        print(format_response(response))
        if args.plot:
            plot_response(response, args.plot)
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
    return hil


def run_hil_command(args, parser) -> int:
    from . import hil

    if not (args.rate > 0 and args.duration >= 0):
        parser.error("--rate must be positive and --duration non-negative")
    for option, port in (("--udp", args.udp), ("--udp-peer", args.udp_peer)):
        if port is not None and not 0 <= port <= 65535:
            parser.error(f"{option} {port}: a port is in 0..65535")
    try:
        events = [hil.parse_event(text) for text in args.event]
        sim = hil.scene_simulator(args.scene, args.rate, args.integrator, events)
    except ValueError as error:
        parser.error(f"argument --event: {error}")
    if args.plot:
        hil.require_matplotlib()  # fail before the run, not after it
    print(describe_scene(args.scene, sim._model))
    for event in events:
        print(f"event: {event}")
    if args.udp is not None:
        print(f"commands on 127.0.0.1:{args.udp}")
    try:
        report = hil.run_hil(sim, args.rate, args.duration, udp_port=args.udp, progress=not args.no_progress,
                             realtime=not args.as_fast_as_possible, udp_destination_port=args.udp_peer,
                             spin_us=args.spin_us, fifo_priority=args.fifo_priority, cpu=args.cpu,
                             lock_memory=args.lock_memory)
    except ValueError as error:  # spin, priority or CPU out of range: the message names it
        parser.error(str(error))
    except RuntimeError as error:  # the UDP port could not be bound
        parser.exit(1, f"soadyn hil: {error}\n")
    print(hil.format_table(report))
    write_hil_outputs(args, events, sim, report)
    return 0 if report.ok else 1


def write_hil_outputs(args, events, sim, report) -> None:
    import json

    from . import hil

    if args.report:
        summary = {"scene": args.scene, "integrator": args.integrator, "events": [str(e) for e in events],
                   **report.to_dict()}
        with open(args.report, "w") as out:
            json.dump(summary, out, indent=2)
    if args.plot:
        hil.plot_report(report, args.plot, sim._model)


def run_check(args) -> int:
    from .check import cross_check, format_table

    rows = cross_check(args.urdf, floating_base=args.floating, states=args.states, seed=args.seed)
    print(f"{args.urdf} ({'floating' if args.floating else 'fixed'} base), {args.states} random states")
    print(format_table(rows, args.tolerance))
    return 0 if all(r.max_relative <= args.tolerance for r in rows) else 1


if __name__ == "__main__":
    sys.exit(main())
