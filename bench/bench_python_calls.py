"""Per-call time of the Python dynamics calls on small models: the fast entry
(f(model, q, v, x) with float64 arrays, bindings/fast_calls.cpp) and the general
pybind11 function behind it. Median over blocks of calls, in microseconds per
call. To judge a change to the binding, run it with both builds back to back.

Writes bench/results/python_calls.json.
Usage: python bench/bench_python_calls.py [--blocks 300] [--calls 2000]
"""
from __future__ import annotations

import argparse
import statistics
import sys
import time

import soadyn
from fixtures import free_base_arm, one_revolute_body, one_state
from report import Table, write


def per_call_us(fn, args, blocks: int, calls: int) -> float:
    samples = []
    for _ in range(blocks):
        start = time.perf_counter()
        for _ in range(calls):
            fn(*args)
        samples.append((time.perf_counter() - start) / calls * 1e6)
    return statistics.median(samples)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--blocks", type=int, default=300)
    parser.add_argument("--calls", type=int, default=2000)
    args = parser.parse_args()
    table = Table("Python per call (us)", ["model", "call", "fast entry", "general function"],
                  {"fast entry": ".3f", "general function": ".3f"}, key=2, summary=True)
    for name, model in (("1 revolute body", one_revolute_body()), ("free base + 6 revolute", free_base_arm())):
        q, v, x = one_state(model, 0)
        for fn in (soadyn.hybrid_dynamics, soadyn.forward_dynamics, soadyn.inverse_dynamics):
            fast = per_call_us(fn, (model, q, v, x), args.blocks, args.calls)
            general = per_call_us(fn.__self__, (model, q, v, x), args.blocks, args.calls)
            print(table.add(name, fn.__name__, fast, general), flush=True)
    table.print()
    pybind11 = getattr(soadyn._soadyn, "_pybind11_version", None)
    write("python_calls", "Python call overhead: the fast entry and the general function", [table],
          {"blocks": args.blocks, "calls": args.calls, "pybind11": pybind11},
          ["Per-call time: median over blocks of calls, one model state (configuration of seed 1, v and x uniform "
           "in [-1, 1], seed 0)."])
    return 0


if __name__ == "__main__":
    sys.exit(main())
