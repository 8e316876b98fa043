"""`soadyn fmu MODEL --out plant.fmu`: export a model as a co-simulation FMU (soadyn.fmu.export_fmu)."""
from __future__ import annotations

import argparse

from ..fmu import FMI_VERSIONS, FmuError, export_fmu
from ..fmu.export import INTEGRATORS


def add_fmu_parser(sub) -> argparse.ArgumentParser:
    fmu = sub.add_parser("fmu", help="export a model as an FMU (FMI 3.0 or 2.0 co-simulation) for HIL rigs and "
                                     "system simulators")
    fmu.add_argument("model", help="a built-in scene, a model file (.json), an MJCF (.xml) or URDF (.urdf) file, or an "
                                   "example robot's name")
    fmu.add_argument("--out", required=True, metavar="PLANT.fmu", help="the FMU file to write")
    fmu.add_argument("--fmi", type=int, default=3, choices=FMI_VERSIONS, help="FMI version (default 3)")
    fmu.add_argument("--step", type=float, default=1e-3,
                     help="communication step of the default experiment, s (default 0.001)")
    fmu.add_argument("--substeps", type=int, default=1,
                     help="internal steps per communication step (default 1): the FMU integrates at step / substeps")
    fmu.add_argument("--integrator", default="rk4", choices=INTEGRATORS, help="(default rk4)")
    fmu.add_argument("--outputs", nargs="+", default=[], metavar="frame.NAME",
                     help="extra outputs: a body's or frame's pose, velocities and acceleration (frame.tool ...)")
    fmu.add_argument("--wrench", action="append", default=[], metavar="FRAME",
                     help="a body or frame taking an external wrench input wrench.FRAME.tx ... .fz (repeatable)")
    fmu.add_argument("--input-kind", action="append", default=[], metavar="DOF=KIND",
                     help="what u.DOF gives when the DOF is prescribed: acceleration (default), velocity or "
                          "position (repeatable)")
    fmu.add_argument("--name", default=None, help="the FMU's modelName (default the model's file or scene name)")
    return fmu


def run_fmu_command(args, parser: argparse.ArgumentParser) -> int:
    kinds = {}
    for item in args.input_kind:
        dof, equals, kind = item.partition("=")
        if not equals or not dof:
            parser.error(f"--input-kind {item!r}: expected DOF=KIND (KIND: acceleration, velocity or position)")
        kinds[dof] = kind
    try:
        path = export_fmu(args.model, args.out, fmi=args.fmi, step=args.step, substeps=args.substeps,
                          integrator=args.integrator, outputs=args.outputs, name=args.name, wrenches=args.wrench,
                          input_kinds=kinds)
    except (FmuError, ValueError, OSError) as error:
        parser.error(str(error))
    print(f"wrote {path}: FMI {args.fmi}.0 co-simulation, internal step {args.step / args.substeps:g} s "
          f"({args.integrator})")
    return 0
