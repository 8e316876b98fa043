"""Cost of soadyn.parameter_sensitivity (forward-mode automatic differentiation) per parameter
direction, against central differences of the dynamics (two dynamics calls per direction, plus the
set_parameter calls), on four robots and the four-bar loop scene. Median of 5 runs.

Writes bench/results/sensitivity.json. Usage: python bench/bench_sensitivity.py
"""
from __future__ import annotations

import sys

import numpy as np

import soadyn
from fixtures import four_bar, load_robot, one_state
from measure import run_seconds
from report import Table, write

REPEATS = 5


def median_time(fn) -> float:
    return float(np.median(run_seconds(fn, REPEATS)))


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
    """(label, model, q, v, u): the robots at the configuration of seed 1 with standard normal v and u (seed 2);
    the four-bar at its closed state with a standard normal u (seed 2)."""
    for name in ("ur5", "panda", "anymal_c", "talos"):
        m = load_robot(name)
        yield (name, m, *one_state(m, 2, normal=True))
    m, q, v = four_bar()
    yield "four_bar (loops)", m, q, v, np.random.default_rng(2).normal(size=m.nv)


def main() -> int:
    table = Table("Per parameter direction: automatic differentiation (AD) against central differences (FD)", [
        "model", "nv", "parameters", "directions", "dynamics call (us)", "AD per direction (us)",
        "FD per direction (us)", "AD / FD", "AD / dynamics call"], headline=["AD / FD", "AD / dynamics call"])
    table.formats = {"dynamics call (us)": ".1f", "AD per direction (us)": ".1f", "FD per direction (us)": ".1f",
                     "AD / FD": ".2f", "AD / dynamics call": ".1f"}
    for label, m, q, v, u in cases():
        names = m.parameter_names
        result = soadyn.parameter_sensitivity(m, q, v, u, names)
        n_dir = sum(int(np.prod(r[0].shape[1:])) for r in result.values())
        t_ad = median_time(lambda: soadyn.parameter_sensitivity(m, q, v, u, names)) / n_dir
        fd_dirs = central_differences(m, names, q, v, u)
        t_fd = median_time(lambda: central_differences(m, names, q, v, u)) / fd_dirs
        t_dyn = median_time(lambda: [dynamics(m, q, v, u) for _ in range(100)]) / 100
        print(table.add(label, m.nv, len(names), n_dir, t_dyn * 1e6, t_ad * 1e6, t_fd * 1e6, t_ad / t_fd,
                        t_ad / t_dyn), flush=True)
    table.print()
    notes = ["Directions: a mass is 1, a centre of mass 3, an inertia 9, a placement 6, gravity 3.",
             "AD: soadyn.parameter_sensitivity for every parameter of the model (one dual-number dynamics call per "
             "direction, in C++). FD: central differences from Python, two dynamics calls per direction plus "
             "set_parameter. Median of 5 runs."]
    write("sensitivity", "Design sensitivity: automatic differentiation against central differences", [table],
          {"repeats": REPEATS}, notes)
    return 0


if __name__ == "__main__":
    sys.exit(main())
