"""Throughput of the batched calls against the number of threads and the
packet width (`lanes`: four states per pass on processors with AVX2 and FMA,
against one), and against Pinocchio's parallel ABA (`abaInParallel`, OpenMP,
with its ModelPool) in the same run: forward dynamics of a batch of random
states, from Python, one call per batch for both libraries. The settings of both libraries are timed in turn
within each repetition, so that they see the same phase of a shared host; a ratio is the median of the ratios
within repetitions. Also the rollouts' runs per
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
BLOCK = 3  # timed calls per setting and repetition, after one untimed call


def rates_in_turn(calls: dict, items: int, repeats: int) -> dict[object, list[float]]:
    """Items per second of each named call fn(), the calls timed in turn within each of `repeats` repetitions
    (measure.py): each setting gets one untimed call, which lets the previous setting's threads go quiet and
    its own settle, then BLOCK timed ones back to back. Returns {name: [the median of each repetition]}."""
    samples = {name: [] for name in calls}
    for _ in range(repeats):
        for name, fn in calls.items():
            fn()
            samples[name].append(statistics.median(items / t for t in run_seconds(fn, BLOCK)))
    return samples


def soadyn_calls(name: str, rows: int) -> dict:
    """batch.forward_dynamics by (threads, lanes): one row per pass on one thread, and the widest packet on
    each number of threads (the model keeps a pool per thread count)."""
    m = load_robot(name)
    Q, V, T = numbered_states(m, 0, rows)
    widest = batch.widest_lanes()
    settings = [(1, 1)] + [(k, widest) for k in THREADS]
    return {("soadyn", k, lanes): lambda k=k, lanes=lanes: batch.forward_dynamics(m, Q, V, T, threads=k, lanes=lanes)
            for k, lanes in settings}


def pinocchio_calls(name: str, rows: int) -> dict:
    """abaInParallel on 1 and 2 threads ({} without it); Pinocchio's random configurations within +-pi (+-1
    for a free root's position and quaternion), v and tau uniform in [-1, 1] (seed 0)."""
    import pinocchio as pin

    if not hasattr(pin, "abaInParallel"):
        return {}
    model = pinocchio_robot(name)
    model.lowerPositionLimit[:] = -np.pi
    model.upperPositionLimit[:] = np.pi
    if robot(name)[1]:
        model.lowerPositionLimit[:7] = -1.0
        model.upperPositionLimit[:7] = 1.0
    q = np.asfortranarray(np.stack([pin.randomConfiguration(model) for _ in range(rows)], axis=1))
    rng = np.random.default_rng(0)
    v, tau = (np.asfortranarray(rng.uniform(-1, 1, (model.nv, rows))) for _ in range(2))
    pools = {k: pin.ModelPool(model, k) for k in THREADS}
    a = np.zeros((model.nv, rows), order="F")
    return {("pinocchio", k): (lambda k=k: pin.abaInParallel(k, pools[k], q, v, tau, a)) for k in THREADS}


def median_ratio(samples: dict, a, b) -> float:
    """The median over repetitions of the rate of `a` over the rate of `b` in the same repetition."""
    return statistics.median(x / y for x, y in zip(samples[a], samples[b]))


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


def rollout_rates(m: soadyn.Model, x0: np.ndarray, repeats: int, **options) -> tuple[dict, int]:
    """Runs per second by (threads, lanes) of rollouts of `m` from the states x0 (rates_in_turn), and the runs
    the packet path stepped side by side; `options` as batch.rollout's (parameters, integrator, events)."""
    widest = batch.widest_lanes()
    settings = [(1, 1)] + [(k, widest) for k in THREADS]
    calls = {(k, lanes): (lambda k=k, lanes=lanes: batch.rollout(m, x0, None, dt=1e-3, steps=100, threads=k,
                                                                 lanes=lanes, **options))
             for k, lanes in settings}
    side_by_side = batch.rollout(m, x0, None, dt=1e-3, steps=100, lanes=widest, **options).side_by_side
    return rates_in_turn(calls, len(x0), repeats), side_by_side


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
        peer = pinocchio_calls(name, args.rows)
        r = rates_in_turn({**soadyn_calls(name, args.rows), **peer}, args.rows, args.repeats)
        one, packet, two = ("soadyn", 1, 1), ("soadyn", 1, widest), ("soadyn", 2, widest)
        theirs = ((statistics.median(r[("pinocchio", 1)]), statistics.median(r[("pinocchio", 2)]),
                   median_ratio(r, ("pinocchio", 2), ("pinocchio", 1)), median_ratio(r, two, ("pinocchio", 2)))
                  if peer else (None,) * 4)
        print(rates.add(name, statistics.median(r[one]), statistics.median(r[packet]), median_ratio(r, packet, one),
                        statistics.median(r[two]), median_ratio(r, two, packet), *theirs), flush=True)
    rollouts = Table(f"Rollouts (RK4 unless said, 100 steps of 1 ms per run, {args.runs} runs per call), runs per "
                     "second", ["scene", "1 thread lanes=1", f"1 thread lanes={widest}", "packet speed-up",
                                f"2 threads lanes={widest}", "thread speed-up", "runs side by side"],
                     headline=["packet speed-up"])
    rollouts.formats = {c: ",.0f" for c in rollouts.columns[1:]}
    rollouts.formats.update({"packet speed-up": ".2f", "thread speed-up": ".2f"})
    flexible, rigid, talos = cassini(), cassini_without(RIGID_CASSINI_LEFT_OUT), load_robot("talos")
    for scene, model, x0, options in (
            ("cassini (two flexible booms)", flexible, cassini_states(flexible, args.runs), {}),
            ("cassini rigid (without its booms)", rigid, cassini_states(rigid, args.runs), {}),
            ("cassini rigid, each run its own bus mass", rigid, cassini_states(rigid, args.runs),
             {"parameters": bus_masses(rigid, args.runs)}),
            ("cassini rigid, DOPRI5", rigid, cassini_states(rigid, args.runs), {"integrator": "dopri5"}),
            ("cassini rigid, a wheel locking at one of four times", rigid, cassini_states(rigid, args.runs),
             {"events": wheel_lock(args.runs)}),
            ("talos from random states", talos, random_states(talos, args.runs), {})):
        r, side_by_side = rollout_rates(model, x0, max(3, args.repeats // 10), **options)
        one, packet, two = (1, 1), (1, widest), (2, widest)
        print(rollouts.add(scene, statistics.median(r[one]), statistics.median(r[packet]), median_ratio(r, packet, one),
                           statistics.median(r[two]), median_ratio(r, two, packet), side_by_side), flush=True)
    for table in (rates, rollouts):
        table.print()
    write("batch", "Batched forward dynamics and rollouts against threads", [rates, rollouts],
          {"rows": args.rows, "repeats": args.repeats, "runs": args.runs, "rollout_repeats": max(3, args.repeats // 10),
           "threads": list(THREADS), "widest_lanes": widest},
          [f"Calls per second (higher is better): the settings, soadyn's and Pinocchio's, are timed in turn within "
           f"each repetition (one untimed call, then {BLOCK} timed ones back to back); a rate is the median over "
           "repetitions of each repetition's median, a ratio the median over repetitions of the ratio within each."])
    return 0


if __name__ == "__main__":
    sys.exit(main())
