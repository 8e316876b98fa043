"""Throughput of the batched calls against the number of threads and the
packet width (`lanes`: four states per pass on processors with AVX2 and FMA,
against one), and against Pinocchio's parallel ABA (`abaInParallel`, OpenMP,
with its ModelPool) in the same run: forward dynamics of a batch of random
states, from Python, one call per batch for both libraries. Calls per second are medians over repeats, after
one warm-up call; ratios are taken within this run. Also the rollouts' runs per
second against the packet width and the number of threads: cassini, its
rigid version (with RK4, with each run's own bus mass, with DOPRI5, and with a
reaction wheel locking at one of four times in each run), and talos from
random states.

Writes bench/results/batch.json.
Usage: python bench/bench_batch.py [--rows 2000] [--repeats 30] [--runs 64]
"""
from __future__ import annotations

import argparse
import os
import statistics
import sys

# numpy's BLAS threads spin for a while after each call, taking one of the two cores from the timed calls.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np

import soadyn
from fixtures import ROBOTS, cassini, cassini_without, load_robot, numbered_states, pinocchio_robot, robot
from measure import run_seconds
from report import Table, write
from soadyn import batch

THREADS = (1, 2)


def median_rate(fn, rows: int, repeats: int) -> float:
    """Median calls (rows) per second of fn() over `repeats` runs, after one warm-up."""
    return statistics.median(rows / t for t in run_seconds(fn, repeats, warm_up=True))


def soadyn_rates(name: str, rows: int, repeats: int) -> dict:
    """Rows per second by (threads, lanes): one row per pass on one thread, and the widest packet on each
    number of threads."""
    m = load_robot(name)
    Q, V, T = numbered_states(m, 0, rows)
    widest = batch.widest_lanes()
    settings = [(1, 1)] + [(k, widest) for k in THREADS]
    return {(k, lanes): median_rate(lambda: batch.forward_dynamics(m, Q, V, T, threads=k, lanes=lanes), rows, repeats)
            for k, lanes in settings}


def pinocchio_rates(name: str, rows: int, repeats: int) -> dict | None:
    """abaInParallel's rows per second; Pinocchio's random configurations within +-pi (+-1 for a free root's
    position and quaternion), v and tau uniform in [-1, 1] (seed 0)."""
    import pinocchio as pin

    if not hasattr(pin, "abaInParallel"):
        return None
    model = pinocchio_robot(name)
    model.lowerPositionLimit[:] = -np.pi
    model.upperPositionLimit[:] = np.pi
    if robot(name)[1]:
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


RIGID_CASSINI_LEFT_OUT = ("magnetometer_boom", "plasma_wave_antenna")  # its two flexible booms


def cassini_states(m: soadyn.Model, runs: int) -> np.ndarray:
    """Cassini from rest, the bus's z rate spread over [-0.01, 0.01] rad/s across runs."""
    x0 = np.tile(np.concatenate([soadyn.neutral_configuration(m), np.zeros(m.nv)]), (runs, 1))
    x0[:, m.nq + m.dof_names.index("bus:wz")] = np.linspace(-0.01, 0.01, runs)
    return x0


def random_states(m: soadyn.Model, runs: int) -> np.ndarray:
    """Configuration k from seed k, velocities uniform in [-1, 1] (numbered_states)."""
    q, v, _ = numbered_states(m, 0, runs)
    return np.hstack([q, v])


def rollout_rates(m: soadyn.Model, x0: np.ndarray, repeats: int, **options) -> dict:
    """Runs per second by (threads, lanes) of rollouts of `m` from the states x0, and the runs the packet
    path stepped side by side; `options` as batch.rollout's (parameters, integrator, events)."""
    runs = len(x0)
    widest = batch.widest_lanes()
    settings = [(1, 1)] + [(k, widest) for k in THREADS]
    rates = {(k, lanes): median_rate(lambda: batch.rollout(m, x0, None, dt=1e-3, steps=100, threads=k, lanes=lanes,
                                                           **options), runs, repeats)
             for k, lanes in settings}
    rates["side by side"] = batch.rollout(m, x0, None, dt=1e-3, steps=100, lanes=widest, **options).side_by_side
    return rates


def bus_masses(m: soadyn.Model, runs: int) -> dict:
    """A Monte Carlo campaign's parameters: the bus's mass spread over +-5 % across runs."""
    return {"bus.mass": m.get_parameter("bus.mass") * np.linspace(0.95, 1.05, runs)}


def wheel_lock(runs: int) -> list:
    """A fault campaign's events: reaction wheel 1 locks at 20, 40, 60 or 80 ms (a quarter of the runs
    each, shuffled), each run at its own time within the step before."""
    rng = np.random.default_rng(1)
    step = rng.permutation(np.resize([20, 40, 60, 80], runs))
    return [("lock", "wheel_1", (step - 1 + rng.uniform(0.1, 0.9, runs)) * 1e-3)]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rows", type=int, default=2000)
    parser.add_argument("--repeats", type=int, default=30)
    parser.add_argument("--runs", type=int, default=64, help="rollout runs (100 RK4 steps each)")
    args = parser.parse_args()
    widest = batch.widest_lanes()
    rates = Table(f"Forward dynamics of {args.rows} random states in one call, calls per second", [
        "robot", "soadyn 1 thread lanes=1", f"soadyn 1 thread lanes={widest}", "packet speed-up",
        f"soadyn 2 threads lanes={widest}", "soadyn thread speed-up", "Pinocchio abaInParallel 1 thread",
        "Pinocchio 2 threads", "Pinocchio speed-up", "soadyn 2 / Pinocchio 2"],
        headline=["packet speed-up", "soadyn 2 / Pinocchio 2"])
    rates.formats = {c: ",.0f" for c in rates.columns[1:]}
    rates.formats.update({c: ".2f" for c in ("packet speed-up", "soadyn thread speed-up", "Pinocchio speed-up",
                                             "soadyn 2 / Pinocchio 2")})
    for name in ROBOTS:
        ours = soadyn_rates(name, args.rows, args.repeats)
        one, packet, two = ours[(1, 1)], ours[(1, widest)], ours[(2, widest)]
        peer = pinocchio_rates(name, args.rows, args.repeats)
        print(rates.add(name, one, packet, packet / one, two, two / packet,
                        *((peer[1], peer[2], peer[2] / peer[1], two / peer[2]) if peer else (None,) * 4)), flush=True)
    rollouts = Table(f"Rollouts (RK4 unless said, 100 steps of 1 ms per run, {args.runs} runs per call), runs per "
                     "second", ["scene", "1 thread lanes=1", f"1 thread lanes={widest}", "packet speed-up",
                                f"2 threads lanes={widest}", "thread speed-up", "runs side by side"],
                     headline=["packet speed-up"])
    rollouts.formats = {c: ",.0f" for c in rollouts.columns[1:]}
    rollouts.formats.update({"packet speed-up": ".2f", "thread speed-up": ".2f"})
    flexible, rigid, talos = cassini(), cassini_without(RIGID_CASSINI_LEFT_OUT), load_robot("talos")
    for scene, model, x0, options in (
            ("cassini (flexible booms: one run per pass)", flexible, cassini_states(flexible, args.runs), {}),
            ("cassini rigid (without its booms)", rigid, cassini_states(rigid, args.runs), {}),
            ("cassini rigid, each run its own bus mass", rigid, cassini_states(rigid, args.runs),
             {"parameters": bus_masses(rigid, args.runs)}),
            ("cassini rigid, DOPRI5", rigid, cassini_states(rigid, args.runs), {"integrator": "dopri5"}),
            ("cassini rigid, a wheel locking at one of four times", rigid, cassini_states(rigid, args.runs),
             {"events": wheel_lock(args.runs)}),
            ("talos from random states", talos, random_states(talos, args.runs), {})):
        r = rollout_rates(model, x0, max(3, args.repeats // 10), **options)
        one, packet, two = r[(1, 1)], r[(1, widest)], r[(2, widest)]
        print(rollouts.add(scene, one, packet, packet / one, two, two / packet, r["side by side"]), flush=True)
    for table in (rates, rollouts):
        table.print()
    write("batch", "Batched forward dynamics and rollouts against threads", [rates, rollouts],
          {"rows": args.rows, "repeats": args.repeats, "runs": args.runs, "rollout_repeats": max(3, args.repeats // 10),
           "threads": list(THREADS), "widest_lanes": widest},
          ["Calls per second (higher is better): medians of the repeats of one call over all the rows, after one "
           "warm-up call."])
    return 0


if __name__ == "__main__":
    sys.exit(main())
