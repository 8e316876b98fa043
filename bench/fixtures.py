"""The models and states the benchmarks share: the example-robot-data robots,
the built-in scenes, and seeded random states.

The published numbers depend on these draws, so each function keeps the seed
and the order of draws its benchmarks use; a benchmark that draws differently
says so through the arguments (the seed, a generator shared by several
models, the count). Builders shared with the test suite (seeded random trees,
Pinocchio twins of soadyn models) are found in tests/support/ through the path set here and nowhere
else.
"""
from __future__ import annotations

import json
import sys
import tempfile
from pathlib import Path

import numpy as np

import soadyn

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO / "tests"))

ROBOTS = ("ur5", "panda", "solo12", "talos")  # the robots of Pinocchio's peer_bench, in its order
STATES = 64  # states per timing loop, cycled through (peer_bench's count)

# The robots' URDF files: example-robot-data, located as the tests locate it.
from support.robots import ROBOTS as URDFS  # noqa: E402  name: (path below robots/, floating base)
from support.robots import robot, robots_dir  # noqa: E402,F401  (URDF path, floating base) of a robot


def load_robot(name: str) -> soadyn.Model:
    path, floating = robot(name)
    return soadyn.load_urdf(path, floating_base=floating)


def pinocchio_robot(name: str):
    """The same robot as a Pinocchio model (a free-flyer root where soadyn's is floating)."""
    import pinocchio as pin

    path, floating = robot(name)
    return pin.buildModelFromUrdf(str(path), pin.JointModelFreeFlyer()) if floating else pin.buildModelFromUrdf(str(path))


def dart_oracle(name: str, model: soadyn.Model):
    """DART's skeleton of the same robot with its DOFs matched to `model`'s by name (soadyn.check.oracles)."""
    from soadyn.check.oracles import DartOracle

    path, floating = robot(name)
    return DartOracle(model, str(path), floating)


# ---------------------------------------------------------------------------
# States
# ---------------------------------------------------------------------------

def generator(rng) -> np.random.Generator:
    """A seed or a generator, as a generator (a generator passed on keeps its stream across models)."""
    return rng if isinstance(rng, np.random.Generator) else np.random.default_rng(rng)


def random_states(model, rng=1, count: int = STATES):
    """(q, v, u), `count` rows each: each configuration from a seed drawn from `rng`, then v and then u uniform
    in [-1, 1]. The states of the peer comparisons (seed 1 per model)."""
    rng = generator(rng)
    q = np.array([soadyn.random_configuration(model, int(rng.integers(1 << 31))) for _ in range(count)])
    return q, rng.uniform(-1, 1, (count, model.nv)), rng.uniform(-1, 1, (count, model.nv))


def numbered_states(model, rng, count: int = STATES):
    """(q, v, u), `count` rows each: configuration k from seed k, then v and then u uniform in [-1, 1] from
    `rng` (which the caller may go on drawing from)."""
    rng = generator(rng)
    q = np.array([soadyn.random_configuration(model, k) for k in range(count)])
    return q, rng.uniform(-1, 1, (count, model.nv)), rng.uniform(-1, 1, (count, model.nv))


def one_state(model, rng, normal: bool = False):
    """(q, v, u) of one state: the configuration of seed 1, then v and then u from `rng`, uniform in [-1, 1] or
    standard normal."""
    rng = generator(rng)
    q = soadyn.random_configuration(model, 1)
    if normal:
        return q, rng.normal(size=model.nv), rng.normal(size=model.nv)
    return q, rng.uniform(-1, 1, model.nv), rng.uniform(-1, 1, model.nv)


def joint_mask(model, rng, fraction: float) -> np.ndarray:
    """Prescribed flags by whole joints, each joint prescribed with probability `fraction` (DART cannot mix
    modes within a joint)."""
    rng = generator(rng)
    mask = np.zeros(model.nv, dtype=bool)
    for joint in model.joint_names:
        dofs = model._dof_indices(joint)
        if rng.uniform() < fraction:
            mask[dofs] = True
    return mask


def dof_mask(nv: int, rng, fraction: float = 0.5) -> np.ndarray:
    """Prescribed flags DOF by DOF, each prescribed with probability `fraction`."""
    return generator(rng).uniform(size=nv) < fraction


# ---------------------------------------------------------------------------
# Scenes
# ---------------------------------------------------------------------------

CASSINI_BOOMS = ("magnetometer_boom", "plasma_wave_antenna")
CASSINI_WHEELS = ("wheel_1", "wheel_2", "wheel_3", "wheel_4")
CASSINI_SLOSH = ("oxidizer_slosh", "fuel_slosh")
CASSINI_PARTS = {  # label: the bodies left out
    "all 15 bodies": (),
    "without the two flexible booms": CASSINI_BOOMS,
    "without the four wheels": CASSINI_WHEELS,
    "without the two slosh pendulums": CASSINI_SLOSH,
    "the bus and its six other bodies (none of the above)": CASSINI_BOOMS + CASSINI_WHEELS + CASSINI_SLOSH,
}


def cassini() -> soadyn.Model:
    """The built-in cassini scene: 15 bodies, two flexible booms of four modes each, nv 28."""
    return soadyn.scenes.cassini()


def cassini_without(names) -> soadyn.Model:
    """The cassini model without the bodies `names`: its saved model file with those bodies left out."""
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "cassini.json"
        soadyn.save_model(cassini(), path)
        spec = json.loads(path.read_text())
        spec["bodies"] = [body for body in spec["bodies"] if body["name"] not in names]
        path.write_text(json.dumps(spec))
        return soadyn.load_model(path)


def cassini_simulator(rate: float = 1000.0):
    """The cassini simulator as `soadyn hil` runs it: RK4 at 1/rate, turntable and gimbal driven."""
    from soadyn.hil import scene_simulator

    return scene_simulator("cassini", rate)


def four_bar():
    """(model, q, v): the four-bar loop scene at crank angle 0.7 rad, crank rate 1.3 rad/s."""
    q, v = soadyn.scenes.four_bar_state(0.7, 1.3)[:2]
    return soadyn.scenes.four_bar(), q, v


def pendulum_chain(n: int) -> soadyn.Model:
    return soadyn.scenes.pendulum_chain(n)


def revolute_tree(n: int) -> soadyn.Model:
    """A random tree of `n` bodies on revolute joints about random axes, fixed base (tests/support/trees.py, seed 7)."""
    from support.trees import random_tree

    return random_tree(7, n, kinds=("revolute",), floating=False)[0]


def one_revolute_body() -> soadyn.Model:
    m = soadyn.Model()
    m.add_body("wheel", None, soadyn.Joint.revolute([0, 0, 1]), mass=2.0, inertia=[2.5, 2.5, 4.0])
    return m


def free_base_arm() -> soadyn.Model:
    """A free base carrying six revolute links about z and y in turn; links 1 and 3 prescribed."""
    m = soadyn.Model()
    m.add_body("base", None, soadyn.Joint.free(), mass=3.0, inertia=[0.3, 0.4, 0.5], com=[0.1, 0, 0])
    parent = "base"
    for k in range(6):
        m.add_body(f"link{k}", parent, soadyn.Joint.revolute([0, 1, 0] if k % 2 else [0, 0, 1]),
                   placement=[0, 0, 0.3], mass=1.0, inertia=[0.02, 0.02, 0.01], com=[0, 0, 0.15])
        parent = f"link{k}"
    m.set_prescribed(["link1", "link3"])
    return m
