"""Timing in Python and the statistics every benchmark reports.

A shared host's speed drifts, and its noise only ever slows a measurement
down. So the things compared are timed in turn within each repetition and a
ratio is the median of the ratios within repetitions (median_ratio); the
fastest of many measurements of one side over the fastest of the other
(fastest_ratio) is reported beside it, as the least disturbed estimate.
"""
from __future__ import annotations

import time

import numpy as np


def interleaved_per_call_us(fns: dict, calls: int = 2000, repetitions: int = 7) -> dict[str, list[float]]:
    """Per-call wall time (us) of each named `(fn, (q, v, u))`, fn(q[i], v[i], u[i]) cycling through the rows,
    the functions timed in turn within each repetition. Returns {name: [one sample per repetition]}."""
    samples = {name: [] for name in fns}
    for _ in range(repetitions):
        for name, (fn, (q, v, u)) in fns.items():
            n = len(q)
            start = time.perf_counter()
            for i in range(calls):
                fn(q[i % n], v[i % n], u[i % n])
            samples[name].append((time.perf_counter() - start) / calls * 1e6)
    return samples


def run_seconds(fn, repeats: int, warm_up: bool = False) -> list[float]:
    """Wall seconds of each of `repeats` calls fn() (after one untimed call when `warm_up`)."""
    if warm_up:
        fn()
    seconds = []
    for _ in range(repeats):
        start = time.perf_counter()
        fn()
        seconds.append(time.perf_counter() - start)
    return seconds


def median_ratio(a, b) -> float:
    """Median over repetitions of the ratio a/b measured within each repetition."""
    return float(np.median(np.asarray(a) / np.asarray(b)))


def fastest_ratio(ours, theirs) -> float:
    """The fastest of our times over the fastest of theirs (nan without both)."""
    return min(ours) / min(theirs) if len(ours) and len(theirs) else float("nan")


def quartiles(values) -> tuple[float, float, float]:
    """First quartile, median and third quartile (nan without values)."""
    if not len(values):
        return (float("nan"),) * 3
    q1, q2, q3 = np.percentile(values, [25, 50, 75])
    return float(q1), float(q2), float(q3)
