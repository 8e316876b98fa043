"""A spacecraft deploys a solar wing of two hinged panels, latches it, and the wing rings.

The bus flies free (no gravity, no external force). Its wing is folded like an accordion. The inner
panel's hinge, on the bus, turns from -90 to 0 deg; the outer panel's hinge from 180 to 0 deg. Each hinge
has a torsion spring, loaded by the fold, that would snap the wing open. A rate controller on each hinge
(a prescribed DOF) lets it open at a constant rate instead: it starts from rest, so its first instant
is an impulse, and its torque brakes the spring. When the wing is flat the hinges latch: the controllers
let go (the DOFs are released, regular), the springs hold the wing at 0 deg, and the rate the hinges
still had makes the wing ring against the bus. The hinge torques push the bus, which turns and shifts;
the total momentum stays zero throughout.

Printed: the controllers' torque peaks, the bus's attitude change, the drift of the momentum, and the wing's
ringing frequencies. The frequencies are measured from the run (the spectrum's peaks) and computed from
the model linearised at the latched pose (analysis.natural_frequencies). Plotted (--plot): the hinge
angles, the ringing after the latch, and the bus's angular rate.

    python examples/python/solar_panel_deployment.py [--deploy 30] [--ring 60] [--plot deployment.png]
"""
from __future__ import annotations

import argparse

import numpy as np

from plotting import stacked_panels
from soadyn import Joint, Model, MotionSource, Simulator, momentum, natural_frequencies, neutral_configuration

BUS_MASS, BUS_SIDE = 1200.0, 2.0  # kg, m (a cube)
PANEL_MASS, PANEL_LENGTH, PANEL_WIDTH = 25.0, 2.0, 1.5  # kg, m along the wing, m along the hinge
HINGE_STIFFNESS, HINGE_DAMPING = 300.0, 1.0  # N m/rad, N m s/rad, each hinge's spring (rest at 0)
HINGES = ("inner_panel", "outer_panel")  # the hinges' DOFs, named after the panels they carry
FOLDED = np.array([-np.pi / 2, np.pi])  # rad; 0 is the flat, deployed wing
DT = 1e-3  # s


def spacecraft() -> Model:
    """The bus (free joint) and its wing on the +y face; thin panels along +y, hinged about x; a spring
    on each hinge with its rest at 0 deg."""
    m = Model()
    m.gravity = [0.0, 0.0, 0.0]
    m.add_body("bus", None, Joint.free(), None, BUS_MASS, (0.0, 0.0, 0.0), BUS_MASS * BUS_SIDE**2 / 6 * np.ones(3))
    panel_inertia = PANEL_MASS / 12 * np.array([PANEL_LENGTH**2, PANEL_WIDTH**2, PANEL_LENGTH**2 + PANEL_WIDTH**2])
    for name, parent, hinge_at in (("inner_panel", "bus", BUS_SIDE / 2), ("outer_panel", "inner_panel", PANEL_LENGTH)):
        m.add_body(name, parent, Joint.revolute([1.0, 0.0, 0.0]), (0.0, hinge_at, 0.0), PANEL_MASS,
                   (0.0, PANEL_LENGTH / 2, 0.0), panel_inertia)
        m.add_joint_spring(f"{name}_spring", name, HINGE_STIFFNESS, HINGE_DAMPING)
    return m


def deploy_and_ring(deploy: float, ring: float):
    """(model, trajectory) of the wing opened from FOLDED to flat over `deploy` s, then latched for `ring` s."""
    m = spacecraft()
    m.set_prescribed(list(HINGES))
    sim = Simulator(m, dt=DT, integrator="rk4")
    q = neutral_configuration(m)
    q[[m.coordinate_names.index(h) for h in HINGES]] = FOLDED
    sim.set_state(q, np.zeros(m.nv))
    for hinge, folded in zip(HINGES, FOLDED):
        sim.prescribe(hinge, MotionSource.constant_velocity(-folded / deploy, folded))
        sim.schedule(deploy, "release", hinge)
    return m, sim.run(deploy + ring)


def ringing_frequencies(t: np.ndarray, angle: np.ndarray, count: int) -> np.ndarray:
    """The `count` strongest peaks (Hz, ascending) of the angle's spectrum (zero-padded 16 times)."""
    samples = len(angle)
    spectrum = np.abs(np.fft.rfft((angle - angle.mean()) * np.hanning(samples), n=16 * samples))
    frequencies = np.fft.rfftfreq(16 * samples, d=t[1] - t[0])
    peaks = [k for k in range(1, len(spectrum) - 1) if spectrum[k - 1] < spectrum[k] >= spectrum[k + 1]]
    return np.sort(frequencies[sorted(peaks, key=lambda k: -spectrum[k])[:count]])


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--deploy", type=float, default=30.0, help="the deployment's duration, s (default 30)")
    parser.add_argument("--ring", type=float, default=60.0, help="simulated time after the latch, s (default 60)")
    parser.add_argument("--plot", help="write the hinge angles and the bus's rate to this PNG")
    args = parser.parse_args(argv)
    m, run = deploy_and_ring(args.deploy, args.ring)
    hinge_v = [m.dof_index(h) for h in HINGES]
    hinge_q = [m.coordinate_names.index(h) for h in HINGES]
    deploying = run.t[:-1] < args.deploy
    print(f"deployment over {args.deploy:g} s at constant rates; latched at {args.deploy:g} s, "
          f"then {args.ring:g} s free")
    for hinge, k in zip(HINGES, hinge_v):
        print(f"{hinge} rate controller: peak |torque| {np.max(np.abs(run.tau[deploying, k])):.3f} N m")
    bus_w = run.q[-1, 3:7]  # quaternion x y z w
    print(f"bus attitude change at the end: {np.degrees(2 * np.arccos(min(1.0, abs(bus_w[3])))):.3f} deg")
    h = np.array([momentum(m, q, v) for q, v in zip(run.q[::100], run.v[::100])])
    print(f"momentum drift over the run: angular {np.max(np.abs(h[:, :3])):.1e} N m s, "
          f"linear {np.max(np.abs(h[:, 3:])):.1e} N s")
    latched = m.copy()
    latched.set_prescribed([False] * latched.nv)
    modes = natural_frequencies(latched, run.q[-1])
    linear_hz = np.sort(modes[modes > 0]) / (2 * np.pi)
    ringing = run.t >= args.deploy
    measured_hz = ringing_frequencies(run.t[ringing], run.q[ringing, hinge_q[0]], len(linear_hz))
    print("wing frequencies, linearised model: " + ", ".join(f"{f:.4f}" for f in linear_hz) + " Hz")
    print("wing frequencies, the run's spectrum: " + ", ".join(f"{f:.4f}" for f in measured_hz)
          + f" Hz (resolution {1 / args.ring:.3f} Hz before padding)")
    if args.plot:
        stacked_panels([
            (run.t, np.degrees(run.q[:, hinge_q]), "hinge angle (deg)", list(HINGES)),
            (run.t[ringing], np.degrees(run.q[ringing][:, hinge_q]), "after the latch (deg)", list(HINGES)),
            (run.t, np.degrees(run.v[:, :3]), "bus rate (deg/s)", ["x", "y", "z"]),
        ], "time (s)", "Solar wing deployment, latch and ringing", args.plot, marks=(args.deploy,))
    return {"run": run, "linear_hz": linear_hz, "measured_hz": measured_hz, "momentum": h}


if __name__ == "__main__":
    main()
