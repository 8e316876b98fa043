"""Built-in scenes (built in C++, cpp/src/scenes.cpp, so C++ programs share them).

``cassini`` follows the application example of the prescribed-motion paper
(Jain & Rodriguez): a free-flying spacecraft bus with a turntable driven at
3 rpm, a two-axis scan platform, a probe relay antenna, a two-axis main-engine
gimbal, four reaction wheels and fuel-slosh pendulums, in free fall. Masses
and sizes are round figures of the Cassini orbiter's published class (about
2.5 t dry bus, an 11 m magnetometer boom, a 4 m high-gain antenna, the 320 kg
Huygens probe); they are plausible, not flight data. Prescribed DOFs: the
turntable and the engine gimbal.

``pendulum_chain`` is n identical rods swinging about parallel x axes.

``cantilever_beam`` is one uniform Euler-Bernoulli beam clamped to the world.
"""
from __future__ import annotations

import numpy as np

from ._soadyn import FlexibleBody
from .model import Model

TURNTABLE_RATE = 3.0 * 2.0 * np.pi / 60.0  # 3 rpm in rad/s


def cassini() -> Model:
    """The default scene."""
    m = Model()
    m._load_cassini()
    return m


def drive_cassini(sim) -> None:
    """Drive a cassini Simulator as in the paper: the turntable at 3 rpm and the
    engine gimbal under velocity control (0.5 deg/s sinusoidal rate commands, period 20 s)."""
    sim._drive_cassini()


def pendulum_chain(n: int = 10, length: float = 0.5, mass: float = 1.0) -> Model:
    """n identical links swinging about parallel x axes, hanging along -z."""
    m = Model()
    m._load_pendulum_chain(int(n), float(length), float(mass))
    return m


def cantilever_beam(length: float, EI: float, mass_per_length: float, n_modes: int,
                    n_nodes: int = 60) -> Model:
    """One flexible beam 'beam' along x, clamped to the world at the origin, without gravity.

    n_modes clamped-free bending modes in each of the x-y and x-z planes
    (FlexibleBody.cantilever_beam: 2 n_modes modal DOFs, 'beam:mode1', ...),
    from n_nodes lumped segments; its tip is the frame 'beam:tip'.
    """
    m = Model()
    m.gravity = [0.0, 0.0, 0.0]
    m.add_flexible_body("beam", None, FlexibleBody.cantilever_beam(length, EI, mass_per_length, n_modes, n_nodes))
    return m


SCENES = {"cassini": cassini, "pendulum-chain": pendulum_chain}
