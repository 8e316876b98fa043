"""The offset slider-crank driven at a constant rate: the crank's drive torque and the wrist pin's force.

The crank is prescribed (its acceleration given: zero, for a constant rate); the connecting rod and the
slider are regular with no drive. At each crank angle of one revolution the closed state comes from the
closed-form position and velocity analysis (scenes.slider_crank_state), and `constrained_dynamics` gives
the crank's torque and the force the slider's wrist pin carries (the cut joint's reaction). Over a
revolution the mechanism comes back to where it started, so the crank's work (the integral of torque
times rate) is zero up to the quadrature error: printed with the torque's and the pin force's extremes;
plotted (--plot) against the crank angle.

    python examples/python/slider_crank.py [--rate 6.283] [--samples 721] [--plot slider_crank.png]
"""
from __future__ import annotations

import argparse

import numpy as np

import soadyn
from plotting import two_panels


def revolution(rate: float, samples: int) -> dict:
    """Crank angle (rad), drive torque (N m) and wrist-pin force (N) over one revolution at `rate` rad/s."""
    m = soadyn.scenes.slider_crank()
    m.set_prescribed("crank")
    crank = m.dof_index("crank")
    angles = np.linspace(0.0, 2.0 * np.pi, samples)
    torque, pin_force = np.empty(samples), np.empty(samples)
    for k, angle in enumerate(angles):
        q, v = soadyn.scenes.slider_crank_state(angle, rate)
        u = np.zeros(m.nv)  # the crank's acceleration (zero: a constant rate); no drive on the others
        _, tau, loop_wrenches = soadyn.constrained_dynamics(m, q, v, u)
        torque[k] = tau[crank]
        pin_force[k] = np.linalg.norm(loop_wrenches[0][3:])  # the wrench's linear part
    work = float(np.sum((torque[1:] + torque[:-1]) / 2 * np.diff(angles)))  # rate dt = d(angle)
    return {"angles": angles, "torque": torque, "pin_force": pin_force, "work": work}


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rate", type=float, default=2.0 * np.pi, help="crank rate, rad/s (default 2 pi)")
    parser.add_argument("--samples", type=int, default=721, help="crank angles over the revolution (default 721)")
    parser.add_argument("--plot", help="write the torque and the pin force against the crank angle to this PNG")
    args = parser.parse_args(argv)
    result = revolution(args.rate, args.samples)
    print(f"crank at {args.rate:g} rad/s, {args.samples} angles over one revolution")
    print(f"drive torque {result['torque'].min():+.4f} .. {result['torque'].max():+.4f} N m; "
          f"work over the revolution {result['work']:+.2e} J")
    print(f"wrist pin force {result['pin_force'].min():.4f} .. {result['pin_force'].max():.4f} N")
    if args.plot:
        two_panels(np.degrees(result["angles"]), result["torque"], result["pin_force"],
                   ("crank angle (deg)", "crank torque (N m)", "wrist pin force (N)"),
                   "slider-crank at a constant crank rate", args.plot)
    return result


if __name__ == "__main__":
    main()
