"""An actuator lock-up fault on cassini: the scan platform's azimuth hinge seizes in the middle of a slew.

The scene flies free (no gravity) with its turntable driven at 3 rpm and its engine gimbal under velocity
commands (scenes.drive_cassini). A constant 2 N m slews the scan platform in azimuth; at the lock time
the hinge locks (a prescribed DOF held at zero rate from then on), the impulse that stops the platform
takes kinetic energy (Simulator.energy_lost) and hands its angular momentum to the whole spacecraft: the
bus's angular rate jumps. Printed: the platform's rate before and after, the energy taken, the bus's rate
change; plotted (--plot): the platform's rate and the bus's angular rate against time.

    python examples/python/cassini_lockup.py [--duration 10] [--lock-time 4] [--plot lockup.png]
"""
from __future__ import annotations

import argparse

import numpy as np

from plotting import two_panels
from soadyn import Simulator, scenes

SLEW_TORQUE = 2.0  # N m on the scan platform's azimuth hinge


def fly(duration: float, lock_time: float):
    """(the Simulator after the run, its trajectory) of cassini slewing its scan platform until it locks."""
    m = scenes.cassini()
    sim = Simulator(m, dt=1e-3, integrator="rk4")
    scenes.drive_cassini(sim)
    sim.set_input("scan_az", SLEW_TORQUE)
    sim.schedule(lock_time, "lock", "scan_az")
    return sim, sim.run(duration)


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=10.0, help="simulated seconds (default 10)")
    parser.add_argument("--lock-time", type=float, default=4.0, help="when the hinge locks, s (default 4)")
    parser.add_argument("--plot", help="write the rates against time to this PNG")
    args = parser.parse_args(argv)
    sim, run = fly(args.duration, args.lock_time)
    m = sim._model
    scan = m.dof_index("scan_az")
    bus_rate = np.linalg.norm(run.v[:, 0:3], axis=1)  # the free bus's angular velocity, body frame, rad/s
    before, after = np.searchsorted(run.t, args.lock_time) - 1, np.searchsorted(run.t, args.lock_time) + 1
    result = {"scan_rate_before": float(run.v[before, scan]), "scan_rate_after": float(run.v[after, scan]),
              "energy_lost": float(sim.energy_lost), "bus_rate_change": float(bus_rate[after] - bus_rate[before])}
    print(f"scan platform azimuth rate: {result['scan_rate_before']:.6f} rad/s before the lock at "
          f"{args.lock_time:g} s, {result['scan_rate_after']:.6f} rad/s after")
    print(f"kinetic energy taken by the lock: {result['energy_lost']:.6f} J")
    print(f"bus angular rate: {1e3 * bus_rate[before]:.4f} -> {1e3 * bus_rate[after]:.4f} mrad/s")
    if args.plot:
        two_panels(run.t, run.v[:, scan], 1e3 * bus_rate, ("time (s)", "scan azimuth rate (rad/s)", "bus rate (mrad/s)"),
                   "cassini: the scan platform's azimuth hinge locks mid-slew", args.plot, marks=[args.lock_time])
    return result


if __name__ == "__main__":
    main()
