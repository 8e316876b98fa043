"""Cost of soadyn.parameter_sensitivity (forward-mode automatic differentiation) per parameter
direction, against central differences of the dynamics (two dynamics calls per direction, plus the
set_parameter calls), on the benchmark robots and the four-bar loop scene.
Writes bench/results/sensitivity.md.

    python bench/bench_sensitivity.py
"""
from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE.parent / "tests"))

import soadyn  # noqa: E402
from bench_robots import write_report  # noqa: E402
from robots import robot  # noqa: E402

REPEATS = 5


def median_time(fn) -> float:
    times = []
    for _ in range(REPEATS):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return float(np.median(times))


def dynamics(m, q, v, u):
    return soadyn.constrained_dynamics(m, q, v, u) if m.nloops else soadyn.hybrid_dynamics(m, q, v, u)


def central_differences(m, names, q, v, u, h=1e-6) -> int:
    """Central differences along every coordinate of the masses and centres of mass in `names`
    (a direction of an inertia or a placement costs the same: two set_parameter and two dynamics
    calls). Returns the number of directions."""
    count = 0
    for name in names:
        if not name.endswith((".mass", ".com")):
            continue
        value = np.atleast_1d(np.array(m.get_parameter(name), dtype=float))
        for k in range(value.size):
            for sign in (1.0, -1.0):
                moved = value.copy()
                moved[k] += sign * h
                m.set_parameter(name, moved if value.size > 1 else float(moved[0]))
                dynamics(m, q, v, u)
            count += 1
        m.set_parameter(name, value if value.size > 1 else float(value[0]))
    return count


def cases():
    for name in ("ur5", "panda", "anymal_c", "talos"):
        path, floating = robot(name)
        m = soadyn.load_urdf(str(path), floating_base=floating)
        yield name, m, soadyn.random_configuration(m, 1)
    yield "four_bar (loops)", soadyn.scenes.four_bar(), soadyn.scenes.four_bar_state(0.7, 1.3)[0]


def main() -> int:
    lines = ["# Design sensitivity: automatic differentiation against central differences", "",
             "Per parameter direction (a mass is 1 direction, a com 3, an inertia 9, a placement 6, gravity 3).",
             "AD: soadyn.parameter_sensitivity for every parameter of the model (one dual-number dynamics",
             "call per direction, in C++). FD: central differences from Python, two dynamics calls per",
             "direction plus set_parameter. Median of 5 runs.", "",
             "| model | nv | parameters | directions | dynamics call (us) | AD per direction (us) | "
             "FD per direction (us) | AD / FD | AD / dynamics call |",
             "|---|---|---|---|---|---|---|---|---|"]
    for label, m, q in cases():
        rng = np.random.default_rng(2)
        v = rng.normal(size=m.nv) if not m.nloops else soadyn.scenes.four_bar_state(0.7, 1.3)[1]
        u = rng.normal(size=m.nv)
        names = m.parameter_names
        result = soadyn.parameter_sensitivity(m, q, v, u, names)
        n_dir = sum(int(np.prod(r[0].shape[1:])) for r in result.values())
        t_ad = median_time(lambda: soadyn.parameter_sensitivity(m, q, v, u, names)) / n_dir
        fd_dirs = central_differences(m, names, q, v, u)
        t_fd = median_time(lambda: central_differences(m, names, q, v, u)) / fd_dirs
        t_dyn = median_time(lambda: [dynamics(m, q, v, u) for _ in range(100)]) / 100
        lines.append(f"| {label} | {m.nv} | {len(names)} | {n_dir} | {t_dyn * 1e6:.1f} | {t_ad * 1e6:.1f} | "
                     f"{t_fd * 1e6:.1f} | {t_ad / t_fd:.2f} | {t_ad / t_dyn:.1f} |")
        print(lines[-1])
    write_report("sensitivity.md", lines)
    return 0


if __name__ == "__main__":
    sys.exit(main())
