"""Per-call time of the Python dynamics calls on small models: the fast
entry (f(model, q, v, x) with float64 arrays, bindings/fast_calls.cpp) and
the general pybind11 function behind it. Median over blocks of calls, in
microseconds per call; run before and after a change to the binding, on the
same machine, back to back.

    python bench/bench_python_calls.py [--blocks 300] [--calls 2000]
"""
from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

import soadyn


def one_body() -> soadyn.Model:
    m = soadyn.Model()
    m.add_body("wheel", None, soadyn.Joint.revolute([0, 0, 1]), mass=2.0, inertia=[2.5, 2.5, 4.0])
    return m


def arm() -> soadyn.Model:
    m = soadyn.Model()
    m.add_body("base", None, soadyn.Joint.free(), mass=3.0, inertia=[0.3, 0.4, 0.5], com=[0.1, 0, 0])
    parent = "base"
    for k in range(6):
        m.add_body(f"link{k}", parent, soadyn.Joint.revolute([0, 1, 0] if k % 2 else [0, 0, 1]),
                   placement=[0, 0, 0.3], mass=1.0, inertia=[0.02, 0.02, 0.01], com=[0, 0, 0.15])
        parent = f"link{k}"
    m.set_prescribed(["link1", "link3"])
    return m


def per_call_us(fn, args, blocks: int, calls: int) -> float:
    samples = []
    for _ in range(blocks):
        start = time.perf_counter()
        for _ in range(calls):
            fn(*args)
        samples.append((time.perf_counter() - start) / calls * 1e6)
    return statistics.median(samples)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--blocks", type=int, default=300)
    parser.add_argument("--calls", type=int, default=2000)
    args = parser.parse_args()
    print(f"pybind11 {soadyn._soadyn._pybind11_version if hasattr(soadyn._soadyn, '_pybind11_version') else '?'}")
    print("| model | call | fast entry (us) | general function (us) |")
    print("|---|---|---:|---:|")
    for name, model in (("1 revolute body", one_body()), ("free base + 6 revolute", arm())):
        rng = np.random.default_rng(0)
        q = soadyn.random_configuration(model, 1)
        v, x = rng.uniform(-1, 1, (2, model.nv))
        for fn in (soadyn.hybrid_dynamics, soadyn.forward_dynamics, soadyn.inverse_dynamics):
            fast = per_call_us(fn, (model, q, v, x), args.blocks, args.calls)
            general = per_call_us(fn.__self__, (model, q, v, x), args.blocks, args.calls)
            print(f"| {name} | {fn.__name__} | {fast:.3f} | {general:.3f} |")


if __name__ == "__main__":
    main()
