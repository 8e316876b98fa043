"""Linear scaling: C++ time per body of the hybrid algorithm on chains and random trees of
10, 100 and 1000 bodies (every DOF regular, every DOF prescribed, half the DOFs prescribed).

Timed in C++ (soadyn._soadyn._time_cpp over 64 random states). The machine's speed drifts,
so the sizes are timed in rounds, each round timing the three sizes of a row back to back.
The table gives each size's median over rounds, and the flatness as the median over rounds
of the ratio within a round (max / min time per body): the sizes of one round see the same
machine, as the peer ratios of bench_robots.py do. It also gives the flatness of the fastest
round of each size (max / min of the per-size minima): a shared host's noise only ever slows
a measurement down, so on a host whose speed swings within seconds the fastest rounds are the
least disturbed (the estimator of bench_robots.py's and bench_round2.py's last columns).
The target: time per body flat within 15 % across the sizes. Writes
bench/results/scaling.md and bench/results/scaling.png. Usage: python bench/bench_scaling.py
"""
from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

import soadyn
from soadyn import scenes
from soadyn._soadyn import _time_cpp

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "tests"))
from trees import random_tree  # noqa: E402  (tests/trees.py: seeded random topologies)

SIZES = (10, 100, 1000)
MODES = ("all regular", "all prescribed", "50 % prescribed")


def models(n):
    """Chains, and random trees of revolute joints (a fixed joint mix, so only the size changes)."""
    yield "revolute chain", scenes.pendulum_chain(n)
    yield "random revolute tree", random_tree(7, n, kinds=("revolute",), floating=False)[0]


ROUNDS = 21


def timing_cases(model, n):
    """(mode, mask, states, calls) for one model."""
    rng = np.random.default_rng(n)
    q = np.array([soadyn.random_configuration(model, k) for k in range(64)])
    v, u = rng.uniform(-1, 1, (64, model.nv)), rng.uniform(-1, 1, (64, model.nv))
    masks = (np.zeros(model.nv, bool), np.ones(model.nv, bool), rng.uniform(size=model.nv) < 0.5)
    return [(mode, mask, (q, v, u), max(200, 200000 // n)) for mode, mask in zip(MODES, masks)]


def main() -> int:
    # (kind, mode) -> [(n, model, mask, states, calls) for each size]: the sizes of one row are timed back
    # to back, so they see the same machine.
    rows = {}
    for n in SIZES:
        for kind, model in models(n):
            for mode, mask, states, calls in timing_cases(model, n):
                rows.setdefault((kind, mode), []).append((n, model, mask, states, calls))
    samples = {}  # (kind, mode, n) -> us per body, one per round
    for r in range(ROUNDS):
        for (kind, mode), sizes in rows.items():
            for n, model, mask, (q, v, u), calls in sizes:
                model.set_prescribed(mask)
                samples.setdefault((kind, mode, n), []).append(_time_cpp(model, "hybrid", q, v, u, calls, 3) / n)
        print(f"round {r + 1}/{ROUNDS} done", flush=True)
    results = {}  # (kind, mode) -> [median us per body for each size]
    for (kind, mode, n), ts in samples.items():
        results.setdefault((kind, mode), []).append(float(np.median(ts)))
    flatness = {row: float(np.median([max(per_size) / min(per_size) for per_size in
                                      zip(*(samples[row + (n,)] for n in SIZES))])) for row in results}
    fastest = {row: [min(samples[row + (n,)]) for n in SIZES] for row in results}
    lines = ["# Linear scaling: C++ time per body (us) of hybrid_dynamics", "",
             "| model | DOF modes | " + " | ".join(f"{n} bodies" for n in SIZES)
             + " | max / min (target <= 1.15) | fastest rounds' max / min |",
             "|---|---|" + "---:|" * (len(SIZES) + 2)]
    for (kind, mode), ts in results.items():
        lines.append(f"| {kind} | {mode} | " + " | ".join(f"{t:.3f}" for t in ts)
                     + f" | **{flatness[(kind, mode)]:.2f}** | **{max(fastest[(kind, mode)]) / min(fastest[(kind, mode)]):.2f}** |")
    lines += ["", f"Times: medians over {ROUNDS} rounds (each round times the sizes of a row back to back; per entry the "
              "median of 3 repetitions over 64 random states, one C++ loop), on a shared machine. max / min: the "
              "median over rounds of the ratio within a round, whose sizes saw the same machine; the fastest "
              "rounds' max / min: the same ratio of each size's fastest round (the least disturbed by the host).",
              "With a random half of the DOFs prescribed, the share of bodies whose whole root path is prescribed "
              "(handled like RNEA) shrinks as trees grow deeper, so that row's cost per body rises towards the "
              "all-regular cost: a property of the mask, not of the scaling.",
              "Command: `python bench/bench_scaling.py`."]
    (HERE / "results").mkdir(exist_ok=True)
    (HERE / "results" / "scaling.md").write_text("\n".join(lines) + "\n")
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
    fig.savefig(HERE / "results" / "scaling.png", dpi=120)
    print("wrote bench/results/scaling.md and scaling.png")
    return 0


if __name__ == "__main__":
    sys.exit(main())
