"""Linear scaling: C++ time per body of the hybrid algorithm on chains and random trees of
10, 100 and 1000 bodies (every DOF regular, every DOF prescribed, half the DOFs prescribed).

Timed in C++ (timing.time_cpp over 64 random states). The sizes are timed in rounds, each
round timing the three sizes of a row back to back. The table gives each size's median over
rounds, and the flatness as the median over rounds of the ratio within a round (max / min time
per body), the sizes of one round having seen the same machine; and the flatness of each
size's fastest round (max / min of the per-size minima), the least disturbed by the host.

Writes bench/results/scaling.json and bench/results/scaling.png.
Usage: python bench/bench_scaling.py [--rounds 21]
"""
from __future__ import annotations

import argparse
import sys

import numpy as np

from fixtures import dof_mask, numbered_states, pendulum_chain, revolute_tree
from report import RESULTS, Table, write
from timing import time_cpp

SIZES = (10, 100, 1000)
MODES = ("all regular", "all prescribed", "50 % prescribed")
ROUNDS = 21


def models(n):
    """Chains, and random trees of revolute joints (a fixed joint mix, so only the size changes)."""
    yield "revolute chain", pendulum_chain(n)
    yield "random revolute tree", revolute_tree(n)


def timing_cases(model, n):
    """(mode, mask, states, calls) for one model: configurations 0-63, v, u and the half mask drawn with seed n."""
    rng = np.random.default_rng(n)
    states = numbered_states(model, rng)
    masks = (np.zeros(model.nv, bool), np.ones(model.nv, bool), dof_mask(model.nv, rng, 0.5))
    return [(mode, mask, states, max(200, 200000 // n)) for mode, mask in zip(MODES, masks)]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=ROUNDS, help="rounds over the sizes (fewer: a smoke run)")
    rounds = parser.parse_args().rounds
    # (kind, mode) -> [(n, model, mask, states, calls) for each size]: the sizes of one row are timed back
    # to back, so they see the same machine.
    rows = {}
    for n in SIZES:
        for kind, model in models(n):
            for mode, mask, states, calls in timing_cases(model, n):
                rows.setdefault((kind, mode), []).append((n, model, mask, states, calls))
    samples = {}  # (kind, mode, n) -> us per body, one per round
    for r in range(rounds):
        for (kind, mode), sizes in rows.items():
            for n, model, mask, (q, v, u), calls in sizes:
                model.set_prescribed(mask)
                samples.setdefault((kind, mode, n), []).append(time_cpp(model, "hybrid", q, v, u, calls, 3) / n)
        print(f"round {r + 1}/{rounds} done", flush=True)
    results = {}  # (kind, mode) -> [median us per body for each size]
    for (kind, mode, n), ts in samples.items():
        results.setdefault((kind, mode), []).append(float(np.median(ts)))
    flatness = {row: float(np.median([max(per_size) / min(per_size) for per_size in
                                      zip(*(samples[row + (n,)] for n in SIZES))])) for row in results}
    fastest = {row: [min(samples[row + (n,)]) for n in SIZES] for row in results}
    table = Table("C++ time per body (us) of hybrid_dynamics", [
        "model", "DOF modes", *(f"{n} bodies" for n in SIZES), "max / min", "fastest rounds' max / min"],
        headline=["max / min", "fastest rounds' max / min"], key=2)
    table.formats = {c: ".3f" for c in table.columns[2:2 + len(SIZES)]}
    table.formats.update({"max / min": ".2f", "fastest rounds' max / min": ".2f"})
    for (kind, mode), ts in results.items():
        table.add(kind, mode, *ts, flatness[(kind, mode)], max(fastest[(kind, mode)]) / min(fastest[(kind, mode)]))
    table.print()
    notes = [f"Times: medians over {rounds} rounds (each round times the sizes of a row back to back; per entry the "
             "median of 3 repetitions over 64 random states, one C++ loop). max / min: the median over rounds of "
             "the ratio within a round; the fastest rounds' max / min: the same ratio of each size's fastest round.",
             "With a random half of the DOFs prescribed, the share of bodies whose whole root path is prescribed "
             "(handled like RNEA) shrinks as trees grow deeper, so that row's cost per body rises towards the "
             "all-regular cost: a property of the mask, not of the scaling."]
    write("scaling", "Linear scaling: C++ time per body of hybrid_dynamics", [table],
          {"sizes": list(SIZES), "rounds": rounds, "repetitions": 3, "states": 64}, notes)
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(7, 4))
    for (kind, mode), ts in results.items():
        ax.plot(SIZES, ts, marker="o", label=f"{kind}, {mode}")
    ax.set_xscale("log")
    ax.set_xlabel("bodies")
    ax.set_ylabel("time per body (us)")
    ax.set_ylim(bottom=0)
    ax.set_title("hybrid_dynamics: time per body")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(RESULTS / "scaling.png", dpi=120)
    print("wrote bench/results/scaling.png")
    return 0


if __name__ == "__main__":
    sys.exit(main())
