"""Built-in scenes.

``cassini`` follows the application example of the prescribed-motion paper
(Jain & Rodriguez): a free-flying spacecraft bus with a turntable driven at
3 rpm, a two-axis scan platform, a probe relay antenna, a two-axis main-engine
gimbal, four reaction wheels and fuel-slosh pendulums. Masses and sizes are
round figures of the Cassini orbiter's published class (about 2.5 t dry bus,
an 11 m magnetometer boom, a 4 m high-gain antenna, the 320 kg Huygens
probe); they are plausible, not flight data.
"""
from __future__ import annotations

import numpy as np

from ._soadyn import Joint
from .model import Model

TURNTABLE_RATE = 3.0 * 2.0 * np.pi / 60.0  # 3 rpm in rad/s


def _rod(mass: float, length: float, axis: int = 2) -> np.ndarray:
    """Principal inertia of a thin rod along `axis`, about its centre."""
    moments = np.full(3, mass * length**2 / 12.0)
    moments[axis] = 1e-3 * mass
    return moments


def _cylinder(mass: float, radius: float, height: float, axis: int = 2) -> np.ndarray:
    transverse = mass * (3 * radius**2 + height**2) / 12.0
    moments = np.full(3, transverse)
    moments[axis] = 0.5 * mass * radius**2
    return moments


def cassini() -> Model:
    """The default scene, in free fall; prescribed DOFs: the turntable and the engine gimbal."""
    m = Model()
    m.gravity = [0.0, 0.0, 0.0]  # in orbit: free fall
    m.add_body("bus", None, Joint.free(), mass=2500.0, com=[0, 0, 1.5], inertia=_cylinder(2500.0, 1.0, 4.0))
    m.add_body("high_gain_antenna", "bus", Joint.fixed(), placement=[0, 0, 4.0], mass=105.0,
               inertia=[105.0, 105.0, 210.0])
    m.add_body("huygens_probe", "bus", Joint.fixed(), placement=[1.3, 0, 1.0], mass=320.0,
               inertia=_cylinder(320.0, 1.35, 0.6, axis=0))
    m.add_body("magnetometer_boom", "bus", Joint.fixed(), placement=(None, [0, 1.0, 3.5]), mass=30.0,
               com=[0, 5.5, 0], inertia=_rod(30.0, 11.0, axis=1))
    m.add_body("turntable", "bus", Joint.revolute([0, 0, 1]), placement=[0, -1.2, 0.5], mass=80.0,
               com=[0, 0, 0.2], inertia=_cylinder(80.0, 0.6, 0.3))
    m.add_body("scan_az", "bus", Joint.revolute([0, 0, 1]), placement=[-1.2, 0, 2.5], mass=40.0,
               com=[0, 0, 0.3], inertia=_cylinder(40.0, 0.3, 0.6))
    m.add_body("scan_el", "scan_az", Joint.revolute([1, 0, 0]), placement=[0, 0, 0.6], mass=60.0,
               com=[0, 0.2, 0.1], inertia=[3.0, 2.0, 2.5])
    m.add_body("probe_relay_antenna", "bus", Joint.revolute([0, 1, 0]), placement=[0.8, 0.8, 3.0], mass=5.0,
               com=[0, 0, 0.25], inertia=_cylinder(5.0, 0.25, 0.05))
    m.add_body("gimbal_pitch", "bus", Joint.revolute([1, 0, 0]), placement=[0, 0, -0.5], mass=4.0,
               inertia=[0.05, 0.05, 0.05])
    m.add_body("engine", "gimbal_pitch", Joint.revolute([0, 1, 0], name="gimbal_yaw"), mass=15.0,
               com=[0, 0, -0.5], inertia=_cylinder(15.0, 0.3, 1.0))
    wheel_axes = [[1, 0, 0], [0, 1, 0], [0, 0, 1], np.ones(3) / np.sqrt(3.0)]
    for k, axis in enumerate(wheel_axes):
        R = _frame_with_z(np.asarray(axis, dtype=float))
        m.add_body(f"wheel_{k + 1}", "bus", Joint.revolute([0, 0, 1]), placement=(R, [0.5 * (k - 1.5), -0.5, 1.0]),
                   mass=12.0, inertia=_cylinder(12.0, 0.17, 0.08))
    for name, z in (("oxidizer_slosh", 2.2), ("fuel_slosh", 0.9)):
        m.add_body(name, "bus", Joint.universal([1, 0, 0], [0, 1, 0]), placement=[0, 0, z], mass=400.0,
                   com=[0, 0, -0.35], inertia=np.full(3, 1.0))
    m.set_prescribed(["turntable", "gimbal_pitch", "gimbal_yaw"])
    return m


def _frame_with_z(axis: np.ndarray) -> np.ndarray:
    """A rotation whose z column is the unit `axis`."""
    z = axis / np.linalg.norm(axis)
    helper = np.array([1.0, 0, 0]) if abs(z[0]) < 0.9 else np.array([0, 1.0, 0])
    x = np.cross(helper, z)
    x /= np.linalg.norm(x)
    return np.column_stack([x, np.cross(z, x), z])


def pendulum_chain(n: int = 10, length: float = 0.5, mass: float = 1.0) -> Model:
    """n identical links swinging about parallel x axes, hanging along -z."""
    if n < 1:
        raise ValueError(f"pendulum_chain needs at least one link, got {n}")
    m = Model()
    inertia = _rod(mass, length)
    for i in range(n):
        m.add_body(f"link_{i + 1}", i - 1, Joint.revolute([1, 0, 0]), placement=[0, 0, -length if i else 0.0],
                   mass=mass, com=[0, 0, -length / 2], inertia=inertia)
    return m


SCENES = {"cassini": cassini, "pendulum-chain": pendulum_chain}
