"""The Stanford arm (Scheinman's six-axis arm: five revolute joints and a prismatic boom) from Paul's
parameters, and the rest-to-rest motion Saha, Shah & Nandihal drive it along.

Kinematics and mass properties: R. P. Paul, "Robot Manipulators: Mathematics, Programming, and
Control", MIT Press 1981, Tables 6.5 and 6.6, as tabulated in standard Denavit-Hartenberg form by
P. Corke's Robotics Toolbox (its Stanford model), with the 0.263 m hand offset d6 of the arm's DH
table. Two decisions of ours, both forced by the tabulation:

- Paul gives centres of mass in centimetres. The tabulation converted links 1 and 4 to metres but not
  links 2, 3, 5 and 6, whose entries (1.054, 6.447, 0.566 and 1.554) would put a centre of mass up to
  6.4 m from its joint on an arm whose boom reaches 1.27 m. We read those four as centimetres.
- Link 5's principal moments (0.003, 0.0004, 0) kg m^2 break the triangle inequality (no real body has
  Ixx > Iyy + Izz). We keep the table's values and build the model with accept_nonphysical_inertia=True:
  the mass matrix stays positive definite (the other links and link 6 carry every joint's inertia).

Paul's reflected motor inertias (Jm) are left out: `Model.set_armature` adds them.

The motion is the cycloidal rest-to-rest profile of Saha, Shah & Nandihal, "Evolution of the
DeNOC-based dynamic modelling for multibody systems", Mechanical Sciences 4, 2013, Eqs. 34 and 35,
q(t) = q(0) + (q(T) - q(0)) / T (t - T / (2 pi) sin(2 pi t / T)) over T = 10 s, gravity along -z of the
base. The paper takes its numbers from Saha (1999) and does not reproduce them; the end points here are
ours: from (0, pi/2, 0.5 m, 0, pi/4, 0), the boom level and half out, to (pi/2, pi/4, 0.9 m, pi/2,
pi/2, pi/2), inside the boom's travel (0.3048 to 1.27 m).
"""
from __future__ import annotations

import numpy as np

from ._soadyn import MotionSource
from .io.denavit_hartenberg import DHLink, dh_model
from .model import Model

__all__ = ["stanford_arm", "stanford_arm_motion", "STANFORD_ARM_LINKS", "MOTION_DURATION", "MOTION_START", "MOTION_END"]

CM = 0.01  # m

STANFORD_ARM_LINKS = (  # the DH rows: a, d in m, alpha, theta in rad, mass in kg, com in m, inertia in kg m^2
    DHLink("joint_1", "revolute", d=0.412, alpha=-np.pi / 2, mass=9.29,
           com=(0.0, 0.0175, -0.1105), inertia=(0.276, 0.255, 0.071)),
    DHLink("joint_2", "revolute", d=0.154, alpha=np.pi / 2, mass=5.01,
           com=(0.0, -1.054 * CM, 0.0), inertia=(0.108, 0.018, 0.100)),
    DHLink("boom", "prismatic", theta=-np.pi / 2, a=0.0203, mass=4.25,
           com=(0.0, 0.0, -6.447 * CM), inertia=(2.51, 2.51, 0.006)),
    DHLink("wrist_1", "revolute", alpha=-np.pi / 2, mass=1.08,
           com=(0.0, 0.092, -0.054), inertia=(0.002, 0.001, 0.001)),
    DHLink("wrist_2", "revolute", alpha=np.pi / 2, mass=0.630,
           com=(0.0, 0.566 * CM, 0.003 * CM), inertia=(0.003, 0.0004, 0.0)),
    DHLink("wrist_3", "revolute", d=0.263, mass=0.51,
           com=(0.0, 0.0, 1.554 * CM), inertia=(0.013, 0.013, 0.0003)),
)
"""The arm's six standard DH rows with Paul's mass properties (the readings of the module's docstring)."""

MOTION_DURATION = 10.0
"""T of Saha, Shah & Nandihal's Eqs. 34-35, in s."""
MOTION_START = np.array([0.0, np.pi / 2, 0.5, 0.0, np.pi / 4, 0.0])
"""q at the motion's start (rad; m for the boom, third): the boom level and half out."""
MOTION_END = np.array([np.pi / 2, np.pi / 4, 0.9, np.pi / 2, np.pi / 2, np.pi / 2])
"""q at the motion's end, t = MOTION_DURATION (rad; m for the boom)."""


def stanford_arm() -> Model:
    """The Stanford arm on a fixed base: DOFs joint_1, joint_2, boom (prismatic, m), wrist_1..3; the
    hand's frame `tool`; gravity 9.81 m/s^2 along -z of the base. q = 0 is Paul's zero configuration
    with the boom at d3 = 0 (its travel is 0.3048 to 1.27 m)."""
    return dh_model(STANFORD_ARM_LINKS, accept_nonphysical_inertia=True)


def stanford_arm_motion(duration: float = MOTION_DURATION, start=MOTION_START, end=MOTION_END) -> list[MotionSource]:
    """One cycloidal rest-to-rest MotionSource per DOF (Saha, Shah & Nandihal 2013, Eqs. 34-35), from
    `start` at t = 0 to `end` at t = duration (s), in the DOF order of stanford_arm()."""
    start, end = np.asarray(start, dtype=float), np.asarray(end, dtype=float)
    if start.shape != (6,) or end.shape != (6,):
        raise ValueError("stanford_arm_motion: start and end need 6 values (joint_1, joint_2, boom, wrist_1..3)")
    return [MotionSource.cycloidal(a, b, 0.0, duration) for a, b in zip(start, end)]
