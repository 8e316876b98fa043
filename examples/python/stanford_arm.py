"""The Stanford arm (Paul's parameters): the drive forces of a rest-to-rest motion, and a free fall.

Inverse dynamics (as Fig. 5 of Saha, Shah & Nandihal 2013): every DOF is prescribed to follow the
cycloidal rest-to-rest profile of their Eq. 34 over T = 10 s (scenes.stanford_arm_motion), and the
hybrid algorithm, with nothing left regular, returns the five joint torques and the boom's force.
Forward dynamics (as their Fig. 6): from the same start, with no drive, the arm falls under gravity.
Printed: each DOF's peak drive force and its value at rest at the start (gravity alone), the free fall's
end state and its energy drift; plotted (--plot): the forces against time, and the joint motions of the
fall. The scene's data and the test against Pinocchio's RNEA and ABA: soadyn.stanford_arm,
tests/dynamics/test_stanford_arm.py.

    python examples/python/stanford_arm.py [--duration 10] [--fall 0.5] [--plot stanford_arm.png]
"""
from __future__ import annotations

import argparse

import numpy as np

from plotting import stacked_panels
from soadyn import Simulator, kinetic_energy, potential_energy, scenes
from soadyn.stanford_arm import MOTION_END, MOTION_START

DT = 1e-3  # s


def drive(duration: float):
    """The trajectory of the arm prescribed along the cycloid from MOTION_START to MOTION_END in `duration` s."""
    m = scenes.stanford_arm()
    m.set_prescribed([True] * m.nv)
    sim = Simulator(m, dt=DT, integrator="rk4")
    sim.set_state(MOTION_START, np.zeros(m.nv))
    for dof, source in enumerate(scenes.stanford_arm_motion(duration, MOTION_START, MOTION_END)):
        sim.prescribe(dof, source)
    return m, sim.run(duration)


def fall(duration: float):
    """The trajectory of the undriven arm falling from MOTION_START at rest for `duration` s."""
    m = scenes.stanford_arm()
    sim = Simulator(m, dt=DT, integrator="rk4")
    sim.set_state(MOTION_START, np.zeros(m.nv))
    return m, sim.run(duration)


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=10.0, help="the motion's duration T, s (default 10)")
    parser.add_argument("--fall", type=float, default=0.5, help="the free fall's duration, s (default 0.5)")
    parser.add_argument("--plot", help="write the drive forces and the free fall's joint motions to this PNG")
    args = parser.parse_args(argv)
    m, driven = drive(args.duration)
    names = m.dof_names
    print(f"cycloidal rest-to-rest motion over {args.duration:g} s, every DOF prescribed")
    print("drive forces in N m (the boom's in N):")
    print(f"{'DOF':<8} {'at rest, t = 0':>15} {'peak |force|':>13}")
    for k, name in enumerate(names):
        print(f"{name:<8} {driven.tau[0, k]:>+15.4f} {np.max(np.abs(driven.tau[:, k])):>13.4f}")
    m_fall, falling = fall(args.fall)
    energy = [kinetic_energy(m_fall, q, v) + potential_energy(m_fall, q) for q, v in zip(falling.q, falling.v)]
    print(f"free fall from the same start, {args.fall:g} s; q at the end (rad, the boom in m):")
    print("  " + ", ".join(f"{name} {value:+.4f}" for name, value in zip(names, falling.q[-1])))
    print(f"energy drift over the fall: {max(energy) - min(energy):.2e} J (RK4, dt = {DT:g} s)")
    if args.plot:
        revolute = [k for k, name in enumerate(names) if name != "boom"]
        stacked_panels([
            (driven.t[:-1], driven.tau[:, revolute], "torque (N m)", [names[k] for k in revolute]),
            (driven.t[:-1], driven.tau[:, names.index("boom")], "boom force (N)", None),
            (falling.t, np.degrees(falling.q[:, revolute]), "free fall (deg)", [names[k] for k in revolute]),
        ], "time (s)", "Stanford arm: drive forces of the cycloidal motion, then a free fall", args.plot)
    return {"driven": driven, "falling": falling, "energy": np.array(energy)}


if __name__ == "__main__":
    main()
