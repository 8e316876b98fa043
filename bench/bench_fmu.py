"""What the FMU layer costs per step: cassini (RK4, 1 ms) stepped through the FMU's fmi3DoStep, through the
C API's soadyn_sim_step and through fmpy's doStep, timed in turn in the same run.

In C (fmu_step_timing.c, compiled here with the system's C compiler; no foreign-function layer in the
loop): the step alone (the C API's soadyn_sim_step(sim, N), N steps in one call), the C API one step per
call, and the FMU's fmi3DoStep one step per call (inputs applied, the step; outputs are evaluated when
read). The FMU's overhead is (DoStep - step alone) / step alone, the issue's measure.

From Python, each call crossing ctypes (their differences include ctypes' per-argument cost):
- C++ step: soadyn_sim_step(sim, 100) per call, divided by 100 (the step alone, the call amortized);
- C API, one step per call: soadyn_sim_step(sim, 1);
- FMU, one step per call: fmi3DoStep(instance, t, 1 ms) on the exported FMU's binary (inputs applied,
  the step, no outputs evaluated: they are evaluated when read);
- fmpy doStep: the same through fmpy's Python wrapper (what a Python master pays).
The FMU's overhead is (FMU - C API) / C++ step: the FMU layer's work beside the step's, the ctypes call
being common to both. Medians of 7 repetitions of 2000 calls, the calls interleaved.

    python bench/bench_fmu.py [--calls 2000] [--repetitions 7] [--out bench/results/fmu.json]
"""
from __future__ import annotations

import argparse
import ctypes
import json
import shutil
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np
from fmpy import extract, read_model_description
from fmpy.fmi3 import FMU3Slave

import soadyn
from soadyn.fmu import export_fmu

DT = 1e-3


def c_api(model_json: str):
    """A soadyn_sim of the model through libsoadyn_c_api.so, and its step function."""
    candidates = sorted(Path(soadyn.__file__).resolve().parents[2].glob("build/*/libsoadyn_c_api.so"))
    if not candidates:
        raise SystemExit("libsoadyn_c_api.so not found under build/: build the project first")
    library = ctypes.CDLL(str(candidates[0]))
    library.soadyn_model_from_json.restype = ctypes.c_void_p
    library.soadyn_sim_create.restype = ctypes.c_void_p
    library.soadyn_sim_create.argtypes = [ctypes.c_void_p, ctypes.c_double, ctypes.c_char_p]
    library.soadyn_sim_step.argtypes = [ctypes.c_void_p, ctypes.c_int]
    model = library.soadyn_model_from_json(model_json.encode())
    sim = library.soadyn_sim_create(model, DT, b"rk4")
    return library, sim


ROOT = Path(__file__).resolve().parents[1]


def c_timings(unzipped: Path, token: str, calls: int, repetitions: int) -> dict:
    """Per-step medians (us) of fmu_step_timing.c: the step alone, the C API one step per call, the FMU's
    DoStep; and the FMU's overhead over the step alone (median of the per-repetition ratios)."""
    compiler = shutil.which("cc") or shutil.which("gcc")
    library = next(ROOT.glob("build/*/libsoadyn_c_api.so"))
    program = unzipped / "fmu_step_timing"
    subprocess.run([compiler, "-O2", "-std=c99", f"-I{ROOT / 'third_party' / 'fmi'}", f"-I{ROOT / 'cpp' / 'include'}",
                    str(ROOT / "bench" / "fmu_step_timing.c"), "-o", str(program), str(library),
                    f"-Wl,-rpath,{library.parent}", "-ldl"], check=True)
    binary = next((unzipped / "binaries" / "x86_64-linux").glob("*.so"))
    output = subprocess.run([str(program), str(binary), str(unzipped / "resources"), token,
                             str(unzipped / "resources" / "model.json"), str(DT), str(calls), str(repetitions)],
                            check=True, capture_output=True, text=True).stdout
    rows = [dict(zip(line.split()[::2], map(float, line.split()[1::2]))) for line in output.splitlines()]
    return {"step alone": float(np.median([r["c_api_batched"] for r in rows])),
            "C API, one step per call": float(np.median([r["c_api_one"] for r in rows])),
            "FMU fmi3DoStep": float(np.median([r["fmu"] for r in rows])),
            "overhead": float(np.median([r["fmu"] / r["c_api_batched"] - 1 for r in rows]))}


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--calls", type=int, default=2000)
    parser.add_argument("--repetitions", type=int, default=7)
    parser.add_argument("--out", default=None, help="write the results as JSON here")
    args = parser.parse_args(argv)
    m = soadyn.scenes.cassini()
    folder = Path(tempfile.mkdtemp())
    path = export_fmu(m, folder / "cassini.fmu", step=DT)
    unzipped = extract(str(path))
    description = read_model_description(unzipped)
    fmu = FMU3Slave(guid=description.instantiationToken, unzipDirectory=unzipped, instanceName="bench",
                    modelIdentifier=description.coSimulation.modelIdentifier)
    fmu.instantiate()
    fmu.enterInitializationMode()
    fmu.exitInitializationMode()
    binary = ctypes.CDLL(str(next(Path(unzipped, "binaries", "x86_64-linux").glob("*.so"))))
    do_step = binary.fmi3DoStep
    do_step.restype = ctypes.c_int
    do_step.argtypes = [ctypes.c_void_p, ctypes.c_double, ctypes.c_double, ctypes.c_bool,
                        ctypes.c_void_p, ctypes.c_void_p, ctypes.c_void_p, ctypes.c_void_p]
    instance = fmu.component
    library, sim = c_api(soadyn.io.model_file.model_to_json(m))
    fmu_time = [0.0]

    def fmu_direct():
        do_step(instance, fmu_time[0], DT, True, None, None, None, None)
        fmu_time[0] += DT

    def through_fmpy():
        fmu.doStep(currentCommunicationPoint=fmu_time[0], communicationStepSize=DT)
        fmu_time[0] += DT

    batched = 100
    timings = {"C++ step": [], "C API, one step per call": [], "FMU fmi3DoStep": [], "fmpy doStep": []}
    for _ in range(args.repetitions):
        start = time.perf_counter()
        for _ in range(args.calls // batched):
            library.soadyn_sim_step(sim, batched)
        timings["C++ step"].append((time.perf_counter() - start) / (args.calls // batched * batched) * 1e6)
        start = time.perf_counter()
        for _ in range(args.calls):
            library.soadyn_sim_step(sim, 1)
        timings["C API, one step per call"].append((time.perf_counter() - start) / args.calls * 1e6)
        start = time.perf_counter()
        for _ in range(args.calls):
            fmu_direct()
        timings["FMU fmi3DoStep"].append((time.perf_counter() - start) / args.calls * 1e6)
        start = time.perf_counter()
        for _ in range(args.calls):
            through_fmpy()
        timings["fmpy doStep"].append((time.perf_counter() - start) / args.calls * 1e6)
    medians = {name: float(np.median(values)) for name, values in timings.items()}
    overhead = [(f - c) / s for f, c, s in zip(timings["FMU fmi3DoStep"], timings["C API, one step per call"],
                                               timings["C++ step"])]
    in_c = c_timings(Path(unzipped), description.instantiationToken, args.calls, args.repetitions)
    result = {"scene": "cassini", "integrator": "rk4", "dt": DT, "calls": args.calls, "repetitions": args.repetitions,
              "in_c_median_us": {k: v for k, v in in_c.items() if k != "overhead"},
              "fmu_overhead_in_c": in_c["overhead"],
              "through_ctypes_median_us": medians, "fmu_minus_c_api_over_step_through_ctypes": float(np.median(overhead)),
              "command": "python bench/bench_fmu.py"}
    print(f"cassini, RK4, dt = {DT:g} s; medians of {args.repetitions} x {args.calls} calls (us per step)")
    print("in C:")
    for name in ("step alone", "C API, one step per call", "FMU fmi3DoStep"):
        print(f"  {name:<26} {in_c[name]:8.2f}")
    print(f"  FMU DoStep overhead over the step alone: {100 * in_c['overhead']:+.1f} %")
    print("from Python (one ctypes call per step; fmpy: its wrapper):")
    for name, value in medians.items():
        print(f"  {name:<26} {value:8.2f}")
    fmu.terminate()
    fmu.freeInstance()
    if args.out:
        Path(args.out).write_text(json.dumps(result, indent=2) + "\n")
    return result


if __name__ == "__main__":
    main()
