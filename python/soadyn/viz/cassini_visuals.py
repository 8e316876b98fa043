"""What the cassini scene looks like: primitives on its bodies and frames, sized after the scene's data.

The scene (`soadyn.scenes.cassini`, built in C++) places its hinges and
frames at round figures of the Cassini orbiter; these shapes follow them:
the propellant stack as a translucent cylinder (the slosh pendulums swing
inside it), the electronics bus above it, the 4 m high-gain antenna dish on
its frame at the top, the Huygens probe's heat shield on the side, the
turntable and the two-axis scan platform, the probe relay antenna, the
gimbaled main engine's nozzle below, and four reaction wheels, each with a
mark so that its spin shows. The magnetometer boom and the plasma-wave
antenna are flexible bodies: the viewer draws them as beams through their
deformed nodes. Sizes are picked to look right, not taken from flight data.
"""
from __future__ import annotations

import numpy as np

from .visuals import Visual, revolved_mesh, rotation_z_to

__all__ = ["cassini_visuals"]

GOLD_FOIL = (0.86, 0.66, 0.22, 0.45)
DARK = (0.22, 0.22, 0.25, 1.0)
WHITE = (0.94, 0.94, 0.90, 1.0)
METAL = (0.55, 0.56, 0.60, 1.0)
MARK = (0.85, 0.15, 0.12, 1.0)
PROPELLANT = (0.20, 0.45, 0.90, 0.85)
WHEELS = ("wheel_1", "wheel_2", "wheel_3", "wheel_4")
SLOSH_PENDULUMS = ("oxidizer_slosh", "fuel_slosh")
SLOSH_LENGTH = 0.35  # the pendulums' centre of mass below their pivots (the scene's data)


def _dish(name: str, frame: str, radius: float, focal_length: float, rgba, height: float = 0.0) -> Visual:
    r = np.linspace(0.0, radius, 10)
    vertices, faces = revolved_mesh(r, height + r**2 / (4.0 * focal_length), segments=40)
    return Visual(name, frame, "mesh", vertices=vertices, faces=faces, rgba=rgba)


def _bus() -> list[Visual]:
    shield_r = np.array([0.0, 0.45, 0.65, 0.65])
    shield, shield_faces = revolved_mesh(shield_r, np.array([0.30, 0.18, 0.0, -0.12]), segments=40)
    return [
        Visual("bus/propellant_stack", "bus", "cylinder", size=[0.65, 3.0], translation=[0, 0, 1.5], rgba=GOLD_FOIL),
        Visual("bus/electronics", "bus", "cylinder", size=[1.0, 0.8], translation=[0, 0, 3.4], rgba=DARK),
        Visual("bus/lower_equipment", "bus", "cylinder", size=[0.7, 0.3], translation=[0, 0, -0.15], rgba=DARK),
        _dish("high_gain_antenna/dish", "high_gain_antenna", 2.0, 1.5, WHITE),
        Visual("high_gain_antenna/feed", "high_gain_antenna", "cylinder", size=[0.08, 1.0],
               translation=[0, 0, 0.5], rgba=METAL),
        Visual("huygens_probe/heat_shield", "huygens_probe", "mesh", vertices=shield, faces=shield_faces,
               rotation=rotation_z_to([1.0, 0.0, 0.0]), rgba=(0.80, 0.45, 0.20, 1.0)),
    ]


def _instruments() -> list[Visual]:
    return [
        Visual("turntable/disc", "turntable", "cylinder", size=[0.3, 0.08], translation=[0, 0, 0.04], rgba=METAL),
        Visual("turntable/mark", "turntable", "box", size=[0.25, 0.05, 0.05], translation=[0.14, 0, 0.1], rgba=MARK),
        Visual("scan_az/column", "scan_az", "cylinder", size=[0.12, 0.6], translation=[0, 0, 0.3], rgba=METAL),
        Visual("scan_el/pallet", "scan_el", "box", size=[0.5, 0.4, 0.3], translation=[0, 0.2, 0.1],
               rgba=(0.15, 0.25, 0.55, 1.0)),
        Visual("scan_el/camera", "scan_el", "cylinder", size=[0.08, 0.35], rotation=rotation_z_to([0, 1, 0]),
               translation=[0.12, 0.45, 0.1], rgba=DARK),
        Visual("probe_relay_antenna/mast", "probe_relay_antenna", "cylinder", size=[0.02, 0.25],
               translation=[0, 0, 0.125], rgba=METAL),
        _dish("probe_relay_antenna/dish", "probe_relay_antenna", 0.25, 0.2, WHITE, height=0.25),
        Visual("gimbal_pitch/cross", "gimbal_pitch", "sphere", size=[0.1], rgba=METAL),
    ]


def _engine() -> list[Visual]:
    nozzle, faces = revolved_mesh([0.12, 0.15, 0.45], [0.0, -0.3, -1.0], segments=40)
    return [Visual("engine/nozzle", "engine", "mesh", vertices=nozzle, faces=faces, rgba=(0.35, 0.35, 0.38, 1.0))]


def _wheels_and_slosh() -> list[Visual]:
    out = []
    for wheel in WHEELS:  # the spin axis is the wheel frame's z axis (the hinge axis)
        out += [Visual(f"{wheel}/rotor", wheel, "cylinder", size=[0.18, 0.08], rgba=METAL),
                Visual(f"{wheel}/mark", wheel, "box", size=[0.15, 0.04, 0.09], translation=[0.08, 0, 0], rgba=MARK)]
    for pendulum in SLOSH_PENDULUMS:
        out += [Visual(f"{pendulum}/rod", pendulum, "cylinder", size=[0.015, SLOSH_LENGTH],
                       translation=[0, 0, -SLOSH_LENGTH / 2], rgba=METAL),
                Visual(f"{pendulum}/mass", pendulum, "sphere", size=[0.25], translation=[0, 0, -SLOSH_LENGTH],
                       rgba=PROPELLANT)]
    return out


def cassini_visuals() -> list[Visual]:
    """The cassini scene's visuals (see the module documentation)."""
    return _bus() + _instruments() + _engine() + _wheels_and_slosh()
