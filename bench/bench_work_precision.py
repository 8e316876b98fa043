"""Work-precision diagrams: plots the CSV of the C++ program bench_work_precision
(error at t = 1 s against a tight Dormand-Prince reference, against CPU time per simulated
second, for every integrator, step size and scalar) and writes
bench/results/work_precision.md and bench/results/work_precision.png.

Usage: python bench/bench_work_precision.py BUILD/bench/bench_work_precision
"""
from __future__ import annotations

import csv
import io
import subprocess
import sys
from collections import defaultdict
from pathlib import Path

HERE = Path(__file__).resolve().parent
STYLE = {"euler": "o-", "rk4": "s-", "dopri5": "^-"}


def recommendation_at_1khz(rows, scenes) -> list[str]:
    """Which setting a real-time user should choose at 1 kHz, from the measured 1 ms rows."""
    at_1ms = {(r["scene"], r["integrator"], r["scalar"]): r for r in rows if float(r["dt"]) == 1e-3}

    def us(scene, integrator, scalar):
        r = at_1ms[(scene, integrator, scalar)]
        return float(r["cpu_s_per_sim_s"]) * 1e3  # us per 1 ms step

    def err(scene, integrator, scalar):
        return float(at_1ms[(scene, integrator, scalar)]["error"])

    lines = ["## Choosing a setting at 1 kHz", "",
             "| scene | rk4 double: error, us per step | euler double | rk4 float |", "|---|---|---|---|"]
    for scene in scenes:
        lines.append(f"| {scene} | {err(scene, 'rk4', 'double'):.1e}, {us(scene, 'rk4', 'double'):.1f} | "
                     f"{err(scene, 'euler', 'double'):.1e}, {us(scene, 'euler', 'double'):.1f} | "
                     f"{err(scene, 'rk4', 'float'):.1e}, {us(scene, 'rk4', 'float'):.1f} |")
    import math
    worst_rk4 = max(us(scene, "rk4", "double") for scene in scenes)
    gains = [math.log10(err(sc, "euler", "double") / max(err(sc, "rk4", "double"), 1e-300)) for sc in scenes]
    float_errors = [err(sc, "rk4", "float") for sc in scenes]
    float_speed = [us(sc, "rk4", "double") / us(sc, "rk4", "float") for sc in scenes]
    lines += ["",
              f"Choose **RK4 in double at the 1 ms step**. It costs at most {worst_rk4:.0f} us per step on these "
              f"scenes ({worst_rk4 / 10:.0f} % of the 1 ms budget), and its error after 1 s is "
              f"{min(gains):.0f} to {max(gains):.0f} orders of magnitude below explicit Euler's. Euler saves three "
              "of the four evaluations, but it is first order: its error shrinks only in proportion to the step. "
              f"Float runs at {min(float_speed):.2f} to {max(float_speed):.2f} times the speed of double (the "
              "same sweeps in another scalar type), and its rounding floors RK4's error at "
              f"{min(float_errors):.0e} to {max(float_errors):.0e}. Dormand-Prince adapts its sub-steps to the "
              "state, so the cost of a 1 ms step varies from step to step. A fixed-rate loop wants RK4's fixed "
              "cost: four evaluations every step, so the slowest step stays close to the median."]
    return lines


def main() -> int:
    if len(sys.argv) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    output = subprocess.run([sys.argv[1]], check=True, capture_output=True, text=True).stdout
    text = "".join(line for line in output.splitlines(keepends=True) if not line.startswith("#drift,"))
    drift = [line.split(",")[1:] for line in output.splitlines() if line.startswith("#drift,")]
    rows = list(csv.DictReader(io.StringIO(text)))
    (HERE / "results").mkdir(exist_ok=True)
    (HERE / "results" / "work_precision.csv").write_text(text)
    series = defaultdict(list)
    for r in rows:
        series[(r["scene"], r["integrator"], r["scalar"])].append(
            (float(r["cpu_s_per_sim_s"]), float(r["error"]), float(r["dt"]), float(r["rtol"])))
    scenes = list(dict.fromkeys(r["scene"] for r in rows))

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, len(scenes), figsize=(5 * len(scenes), 4.2))
    for ax, scene in zip(axes, scenes):
        for (s, integrator, scalar), points in series.items():
            if s != scene:
                continue
            points = [p for p in points if p[1] < float("inf")]
            ax.loglog([p[0] for p in points], [max(p[1], 1e-16) for p in points], STYLE[integrator],
                      fillstyle="full" if scalar == "double" else "none",
                      label=f"{integrator} ({scalar})", alpha=0.9 if scalar == "double" else 0.6)
        ax.axvline(1.0, color="0.6", lw=0.8, ls=":")
        ax.set_title(scene)
        ax.set_xlabel("CPU seconds per simulated second")
        ax.set_ylabel("max coordinate error at t = 1 s")
        ax.legend(fontsize=7)
    fig.suptitle("work-precision: fixed steps 10 ms .. 0.2 ms (euler, rk4); tolerances 1e-4 .. 1e-10 (dopri5)")
    fig.tight_layout()
    fig.savefig(HERE / "results" / "work_precision.png", dpi=110)

    lines = ["# Work-precision", "",
             "Error: largest coordinate error at t = 1 s against Dormand-Prince in double (0.1 ms output "
             "step, rtol 1e-13). Cost: CPU seconds per simulated second, median of 3 runs "
             "(1 ms steps at 1 kHz must cost well under 1.0 to run in real time).", "",
             "Energy drift (pendulum chain, the one conservative scene): (E(1 s) - E(0)) / (E(0) - E(rest)).", "",
             "| scene | integrator | scalar | step (s) | rtol | error | CPU s / sim s | us per step | energy drift |",
             "|---|---|---|---:|---:|---:|---:|---:|---:|"]
    for r in rows:
        us_per_step = float(r["cpu_s_per_sim_s"]) * float(r["dt"]) * 1e6
        drift_1s = float(r["energy_drift"])
        lines.append(f"| {r['scene']} | {r['integrator']} | {r['scalar']} | {float(r['dt']):g} | "
                     f"{float(r['rtol']) or '-'} | {float(r['error']):.2e} | {float(r['cpu_s_per_sim_s']):.4f} | "
                     f"{us_per_step:.1f} | {'-' if drift_1s != drift_1s else f'{drift_1s:+.1e}'} |")
    lines += ["", "## Energy drift over 100 s", "",
              "10-link pendulum chain from 0.3 rad per joint, 1 ms steps (dopri5: 1 ms output steps, rtol 1e-10), "
              "double: (E(t) - E(0)) / (E(0) - E(rest)).", "",
              "| integrator | " + " | ".join(f"{10 * (k + 1)} s" for k in range(10)) + " |",
              "|---|" + "---:|" * 10]
    for name, *values in drift:
        lines.append(f"| {name} | " + " | ".join(f"{float(x):+.1e}" for x in values) + " |")
    lines += ["", "Semi-implicit Euler updates the velocity, then the position with the new velocity. With a mass "
              "matrix that depends on the configuration this is not a symplectic method (it is one only for a "
              "constant mass matrix), so its energy error is first order in the step and is not bounded: it "
              "wanders with the chain's motion. The same update written on Pinocchio's ABA gives the same energy "
              "to 1e-12 (tests/test_simulator_energy.py): the drift is the method's, not a defect.",
              "", *recommendation_at_1khz(rows, scenes)]
    (HERE / "results" / "work_precision.md").write_text("\n".join(lines) + "\n")
    print("wrote bench/results/work_precision.{md,png,csv}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
