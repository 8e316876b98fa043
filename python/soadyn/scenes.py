"""Built-in scenes (built in C++, examples/soadyn_scenes/scenes.cpp, so C++ programs share them).

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

Closed-loop scenes (trees closed by cut joints; their data, in C++
FourBarData, SliderCrankData and DeltaRobotData, are documented in
examples/soadyn_scenes/scenes.hpp):

``four_bar`` is the planar crank-rocker of Saha, Shah & Nandihal, "Evolution
of the DeNOC-based dynamic modelling for multibody systems", Mechanical
Sciences 4, 2013 (Fig. 16): crank 0.038 m (1.5 kg), coupler 0.1152 m (5 kg),
output link ("rocker") 0.1152 m (3 kg), ground 0.0895 m, uniform slender
rods, gravity along -y in the x-y plane. DOFs: "crank" (from the ground line
O1 O2), "coupler" (relative to the crank), "rocker" (from the ground line, at
O2); the loop "coupler_rocker" pins the coupler's tip to the rocker's tip.

``slider_crank`` is an offset slider-crank: crank 0.05 m (1 kg), connecting
rod 0.2 m (1.5 kg), slider (0.8 kg) on a line 0.02 m above the crank's pivot;
DOFs "crank", "connecting_rod" (relative), "slider" (x position); the loop
"wrist_pin" pins the rod's tip to the slider.

``delta_robot`` is a Delta parallel robot: three arms (0.3 m, 0.4 kg) hinged
on the base at radius 0.2 m, each carrying a parallelogram of two forearm
rods (0.7 m, 0.1 kg, 0.1 m apart) on universal joints, whose far ends are
ball joints ("point" loops) on a free travelling plate (0.5 kg, balls at
radius 0.05 m); gravity along -z: 21 DOFs, 6 loops, 3 degrees of freedom.

``stanford_arm`` is Scheinman's Stanford arm from Paul's (1981) parameters, built in Python from its
Denavit-Hartenberg table (soadyn.stanford_arm, which documents the data and the two readings of the
table it takes); ``stanford_arm_motion`` gives the cycloidal rest-to-rest motion of Saha, Shah &
Nandihal (Eqs. 34-35) as one MotionSource per DOF.

The ``*_state`` functions return a closed (q, v) by closed-form position and
velocity analysis.
"""
from __future__ import annotations

import numpy as np

from . import _soadyn as _core
from ._soadyn import FlexibleBody
from .model import Model
from .stanford_arm import stanford_arm, stanford_arm_motion  # noqa: F401 (scenes of this module)
from .viz.cassini_visuals import cassini_visuals

__all__ = ["cassini", "drive_cassini", "pendulum_chain", "cantilever_beam", "four_bar", "slider_crank", "delta_robot",
           "four_bar_state", "slider_crank_state", "delta_robot_state", "stanford_arm", "stanford_arm_motion",
           "SCENES", "LOOP_SCENE_STARTS", "TURNTABLE_RATE", "PLANAR_CUTS", "CASSINI_DRIVEN_DOFS"]

TURNTABLE_RATE = 3.0 * 2.0 * np.pi / 60.0
"""The cassini turntable's prescribed rate: 3 rpm, in rad/s (Jain & Rodriguez's application example)."""


def cassini() -> Model:
    """The default scene, with its visuals (soadyn.viz.cassini_visuals: the bus, antennas, probe, engine,
    wheels and slosh masses as primitives).

    A free-flying tree without gravity: the bus on a free joint (q starts with its position in m and its
    quaternion x y z w), hinges in rad, two flexible booms' modal DOFs; the turntable and the engine gimbal's
    two axes are prescribed. Bodies, masses (kg) and sizes (m) are tabled in the scenes guide."""
    m = Model()
    m._load_cassini()
    m.visuals = cassini_visuals()
    return m


CASSINI_DRIVEN_DOFS = ("turntable", "gimbal_pitch", "gimbal_yaw")
"""The DOFs drive_cassini prescribes."""


def drive_cassini(sim) -> None:
    """Drive a cassini Simulator as in the paper: the turntable at 3 rpm and the
    engine gimbal under velocity control (0.5 deg/s sinusoidal rate commands, period 20 s).

    TypeError for an argument that is not a soadyn.Simulator; ValueError naming the DOF a simulator of
    another model lacks."""
    from .simulator import Simulator

    if not isinstance(sim, Simulator):
        raise TypeError(f"drive_cassini needs a soadyn.Simulator, got {type(sim).__name__}")
    dofs = sim._model.dof_names
    missing = [name for name in CASSINI_DRIVEN_DOFS if name not in dofs]
    if missing:
        raise ValueError(f"drive_cassini: the simulator's model has no DOF '{missing[0]}' (it drives a cassini model)")
    sim._drive_cassini()


def _positive(value, what: str, scene: str) -> float:
    """`value` as a float when it is a real number, finite and > 0; TypeError or ValueError naming it otherwise."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise TypeError(f"{scene}: {what} must be a real number, got {type(value).__name__} ({value!r})")
    if not np.isfinite(value) or value <= 0:
        raise ValueError(f"{scene}: {what} must be a finite number > 0, got {value!r}")
    return float(value)


def pendulum_chain(n: int = 10, length: float = 0.5, mass: float = 1.0) -> Model:
    """n identical uniform rods of `length` m and `mass` kg, each hinged to the previous one's tip about
    parallel x axes (the first to the world at the origin), hanging along -z under gravity 9.81 m/s^2.
    DOFs link_1 ... link_n (rad). TypeError or ValueError names an argument that is not a whole number of
    links >= 1 or a finite length and mass > 0."""
    if isinstance(n, (bool, np.bool_)) or not isinstance(n, (int, np.integer)):
        raise TypeError(f"pendulum_chain: n must be a whole number of links, got {type(n).__name__} ({n!r})")
    length, mass = _positive(length, "length", "pendulum_chain"), _positive(mass, "mass", "pendulum_chain")
    m = Model()
    m._load_pendulum_chain(int(n), length, mass)
    return m


def cantilever_beam(length: float, EI: float, mass_per_length: float, n_modes: int,
                    n_nodes: int = 60) -> Model:
    """One flexible beam 'beam' along x, clamped to the world at the origin, without gravity: `length` in m,
    `EI` (bending stiffness) in N m^2, `mass_per_length` in kg/m; ValueError names one that is not finite and
    positive, or a count below 1.

    n_modes clamped-free bending modes in each of the x-y and x-z planes
    (FlexibleBody.cantilever_beam: 2 n_modes modal DOFs, 'beam:mode1', ...),
    from n_nodes lumped segments; its tip is the frame 'beam:tip'.
    """
    m = Model()
    m.gravity = [0.0, 0.0, 0.0]
    m.add_flexible_body("beam", None, FlexibleBody.cantilever_beam(length, EI, mass_per_length, n_modes, n_nodes))
    return m


PLANAR_CUTS = ("revolute", "point")
"""The cut-joint kinds four_bar and slider_crank accept as `closure`."""


def _planar_cut(closure: str, scene: str) -> str:
    if closure not in PLANAR_CUTS:
        raise ValueError(f"{scene}: closure must be 'revolute' or 'point', got {closure!r}")
    return closure


def four_bar(closure: str = "revolute") -> Model:
    """The crank-rocker of Saha, Shah & Nandihal 2013 (Fig. 16), closed at the coupler-rocker pin by a
    "revolute" cut (5 equations of rank 2, the default) or a "point" cut (3 equations of rank 2)."""
    m = Model()
    m._load_four_bar(_planar_cut(closure, "four_bar"))
    return m


def slider_crank(closure: str = "revolute") -> Model:
    """The offset slider-crank, closed at the wrist pin by a "revolute" (default) or a "point" cut (ValueError
    for another `closure`); lengths, masses and DOFs in this module's docstring."""
    m = Model()
    m._load_slider_crank(_planar_cut(closure, "slider_crank"))
    return m


def delta_robot() -> Model:
    """The Delta parallel robot: arms "arm_1..3", forearm rods "rod_1a" ... "rod_3b", plate "plate"; lengths
    and masses in this module's docstring, gravity 9.81 m/s^2 along -z."""
    m = Model()
    m._load_delta_robot()
    return m


def _angle_and_rate(name: str, crank_angle, crank_rate) -> tuple[float, float]:
    try:
        return float(crank_angle), float(crank_rate)
    except (TypeError, ValueError):
        raise TypeError(f"{name}: crank_angle and crank_rate must be real numbers, "
                        f"got {crank_angle!r}, {crank_rate!r}") from None


def four_bar_state(crank_angle: float, crank_rate: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """(q, v) of four_bar closed at `crank_angle` (rad from the ground line) turning at `crank_rate`.

    Position: the coupler-rocker pin Q is where the circles of radius coupler_length about the crank's
    tip P and rocker_length about the rocker's pivot O2 meet, on the left of P -> O2 (above the ground
    line: the assembly of the paper's figure). Velocity: the time derivative of the closure
    a e(t1) + b e(phi2) - c e(t3) = O2 (Saha, Shah & Nandihal 2013, Eqs. 51-52), solved for the coupler's
    absolute rate phi2' and the rocker's rate t3'. The coupler's relative angle is in (-pi, pi].
    Computed in C++ (soadyn::four_bar_state); ValueError for a non-finite argument.
    """
    return _core._four_bar_state(*_angle_and_rate("four_bar_state", crank_angle, crank_rate))


def slider_crank_state(crank_angle: float, crank_rate: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """(q, v) of slider_crank closed at `crank_angle` turning at `crank_rate`, the slider on the
    far side of the crank (x > crank's tip). With P the crank's tip and phi the rod's absolute angle:
    sin phi = (offset - P_y) / rod_length, x = P_x + rod_length cos phi; differentiated,
    phi' = -r w cos(t) / (l cos phi) and x' = -r w sin(t) - l phi' sin(phi).
    Computed in C++ (soadyn::slider_crank_state)."""
    return _core._slider_crank_state(*_angle_and_rate("slider_crank_state", crank_angle, crank_rate))


def delta_robot_state(position, velocity=(0.0, 0.0, 0.0)) -> tuple[np.ndarray, np.ndarray]:
    """(q, v) of delta_robot with the plate's centre at `position` (m, base frame; e.g. (0, 0, -0.6)),
    level, translating at `velocity` (m/s). Closed-form inverse kinematics of each arm: in its hinge
    frame (radial u, tangent w, up z) the elbow is E = B + L_a (cos t, 0, -sin t) and the parallelogram's
    mid-line r = P - E has length L_f, so a cos t - c sin t = K (a, c: the u and z parts of P - B,
    K = (|P - B|^2 + L_a^2 - L_f^2) / (2 L_a)) and t = atan2(-c, a) - acos(K / hypot(a, c)) (elbow out);
    the rods' universal joints follow from r's direction in the arm's frame, the rates from the
    derivatives of these relations. Computed in C++ (soadyn::delta_robot_state); ValueError for a
    position out of reach, naming the arm."""
    position, velocity = np.asarray(position, dtype=float), np.asarray(velocity, dtype=float)
    if position.shape != (3,) or velocity.shape != (3,):
        raise ValueError("delta_robot_state: position and velocity need 3 components")
    return _core._delta_robot_state(position, velocity)


SCENES = {"cassini": cassini, "pendulum-chain": pendulum_chain, "stanford-arm": stanford_arm}
"""{name: builder} of the scenes the command line runs by name (`soadyn hil --scene NAME`, campaigns), the loop
scenes included."""

# The loop scenes and the closed state, at rest, a run of them starts from
# (`soadyn hil --scene four-bar`): a simulator cannot start from the neutral
# configuration, which does not close their loops.
LOOP_SCENE_STARTS = {
    "four-bar": (four_bar, lambda: four_bar_state(0.7)),
    "slider-crank": (slider_crank, lambda: slider_crank_state(0.5)),
    "delta-robot": (delta_robot, lambda: delta_robot_state((0.0, 0.0, -0.6))),
}
"""{name: (builder, closed-state function)} of the loop scenes: a run of one starts from the closed state at
rest the function returns (a simulator cannot start from the neutral configuration, which leaves the loops
open)."""
SCENES.update({name: build for name, (build, _) in LOOP_SCENE_STARTS.items()})


def __getattr__(name: str):
    """scenes.<a name that is not a scene>: AttributeError naming the closest scenes (PEP 562)."""
    import difflib

    known = sorted(n for n, v in globals().items() if callable(v) and not n.startswith("_")
                   and getattr(v, "__module__", None) in (__name__, stanford_arm.__module__))
    close = difflib.get_close_matches(name, known, n=3, cutoff=0.5)
    hint = f"; did you mean {', '.join(close)}?" if close else f"; the scenes: {', '.join(known)}"
    raise AttributeError(f"soadyn.scenes has no scene {name!r}{hint}")
