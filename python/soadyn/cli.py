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
    args = parser.parse_args(argv)
    if not (args.duration > 0 and args.dt > 0):
        parser.error("--duration and --dt must be positive")
    model = scenes.SCENES[args.scene]()
    print(describe_scene(args.scene, model))
    print(format_result(run_demo(model, args.duration, args.dt)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
