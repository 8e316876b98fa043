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
    check = sub.add_parser("check", help="compare soadyn with DART and Pinocchio on a URDF")
    check.add_argument("urdf", help="path of the URDF file")
    check.add_argument("--floating", action="store_true", help="add a free-floating root joint")
    check.add_argument("--states", type=int, default=3, help="random states to compare (default 3)")
    check.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    check.add_argument("--tolerance", type=float, default=1e-9,
                       help="largest accepted relative difference (default 1e-9); above it the exit code is 1")
    args = parser.parse_args(argv)
    if args.command == "check":
        return run_check(args)
    if not (args.duration > 0 and args.dt > 0):
        parser.error("--duration and --dt must be positive")
    model = scenes.SCENES[args.scene]()
    print(describe_scene(args.scene, model))
    print(format_result(run_demo(model, args.duration, args.dt)))
    return 0


def run_check(args) -> int:
    from .check import cross_check, format_table

    rows = cross_check(args.urdf, floating_base=args.floating, states=args.states, seed=args.seed)
    print(f"{args.urdf} ({'floating' if args.floating else 'fixed'} base), {args.states} random states")
    print(format_table(rows, args.tolerance))
    return 0 if all(r.max_relative <= args.tolerance for r in rows) else 1


if __name__ == "__main__":
    sys.exit(main())
