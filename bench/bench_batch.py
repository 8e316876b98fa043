"""Throughput of the batched calls against the number of threads, and against
Pinocchio's parallel ABA (`abaInParallel`, OpenMP, with its ModelPool) in the
same run: forward dynamics of a batch of random states, from Python, one call
per batch for both libraries. Calls per second are medians over repeats;
ratios are taken within this run. Also the rollout's runs per second (cassini,
RK4) against the number of threads.

    python bench/bench_batch.py [--rows 2000] [--repeats 30] [--out bench/results/batch.md]
"""
from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

import soadyn
from soadyn import batch

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "tests"))
from robots import robot  # noqa: E402  (tests/robots.py: example-robot-data paths)

ROBOTS = ["ur5", "panda", "solo12", "talos"]
THREADS = (1, 2)


def median_rate(fn, rows: int, repeats: int) -> float:
    """Median calls (rows) per second of fn() over `repeats` runs, after one warm-up."""
    fn()
    samples = []
    for _ in range(repeats):
        start = time.perf_counter()
        fn()
        samples.append(rows / (time.perf_counter() - start))
    return statistics.median(samples)


def soadyn_rates(name: str, rows: int, repeats: int) -> dict:
    path, floating = robot(name)
    m = soadyn.load_urdf(path, floating_base=floating)
    rng = np.random.default_rng(0)
    Q = np.stack([soadyn.random_configuration(m, k) for k in range(rows)])
    V, T = rng.uniform(-1, 1, (2, rows, m.nv))
    return {k: median_rate(lambda: batch.forward_dynamics(m, Q, V, T, threads=k), rows, repeats) for k in THREADS}


def pinocchio_rates(name: str, rows: int, repeats: int) -> dict | None:
    import pinocchio as pin

    if not hasattr(pin, "abaInParallel"):
        return None
    path, floating = robot(name)
    model = pin.buildModelFromUrdf(str(path), pin.JointModelFreeFlyer()) if floating else pin.buildModelFromUrdf(str(path))
    model.lowerPositionLimit[:] = -np.pi
    model.upperPositionLimit[:] = np.pi
    if floating:
        model.lowerPositionLimit[:7] = -1.0
        model.upperPositionLimit[:7] = 1.0
    q = np.asfortranarray(np.stack([pin.randomConfiguration(model) for _ in range(rows)], axis=1))
    rng = np.random.default_rng(0)
    v, tau = (np.asfortranarray(rng.uniform(-1, 1, (model.nv, rows))) for _ in range(2))
    out = {}
    for k in THREADS:
        pool = pin.ModelPool(model, k)
        a = np.zeros((model.nv, rows), order="F")
        out[k] = median_rate(lambda: pin.abaInParallel(k, pool, q, v, tau, a), rows, repeats)
    return out


def rollout_rates(runs: int, repeats: int) -> dict:
    m = soadyn.scenes.cassini()
    x0 = np.tile(np.concatenate([soadyn.neutral_configuration(m), np.zeros(m.nv)]), (runs, 1))
    x0[:, m.nq + m.dof_names.index("bus:wz")] = np.linspace(-0.01, 0.01, runs)
    return {k: median_rate(lambda: batch.rollout(m, x0, None, dt=1e-3, steps=100, threads=k), runs, repeats)
            for k in THREADS}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rows", type=int, default=2000)
    parser.add_argument("--repeats", type=int, default=30)
    parser.add_argument("--runs", type=int, default=64, help="rollout runs (cassini, 100 RK4 steps each)")
    parser.add_argument("--out", default=str(HERE / "results" / "batch.md"))
    args = parser.parse_args()
    lines = ["# Batched forward dynamics and rollouts against threads", "",
             f"- Date: {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}; source: "
             f"{subprocess.run(['git', 'describe', '--always', '--dirty'], capture_output=True, text=True).stdout.strip()}",
             f"- Command: `python bench/bench_batch.py --rows {args.rows} --repeats {args.repeats} --runs {args.runs}`",
             f"- Machine: {os.cpu_count()} hardware threads; medians of {args.repeats} repeats "
             f"of one call over {args.rows} random states (calls per second, higher is better).", "",
             "| robot | soadyn 1 thread | soadyn 2 threads | soadyn speed-up | Pinocchio abaInParallel 1 | "
             "Pinocchio 2 | Pinocchio speed-up | soadyn 2 / Pinocchio 2 |",
             "|---|---:|---:|---:|---:|---:|---:|---:|"]
    for name in ROBOTS:
        ours = soadyn_rates(name, args.rows, args.repeats)
        peer = pinocchio_rates(name, args.rows, args.repeats)
        row = f"| {name} | {ours[1]:,.0f} | {ours[2]:,.0f} | {ours[2] / ours[1]:.2f}x | "
        row += (f"{peer[1]:,.0f} | {peer[2]:,.0f} | {peer[2] / peer[1]:.2f}x | {ours[2] / peer[2]:.2f}x |" if peer
                else "n/a | n/a | n/a | n/a |")
        lines.append(row)
        print(row, flush=True)
    rollout = rollout_rates(args.runs, max(3, args.repeats // 10))
    lines += ["", f"Rollout (cassini, 15 bodies with two flexible booms, RK4, 100 steps of 1 ms per run, {args.runs} runs "
              "per call): runs per second",
              "", "| 1 thread | 2 threads | speed-up |", "|---:|---:|---:|",
              f"| {rollout[1]:,.0f} | {rollout[2]:,.0f} | {rollout[2] / rollout[1]:.2f}x |"]
    print("\n".join(lines[-5:]))
    Path(args.out).write_text("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
