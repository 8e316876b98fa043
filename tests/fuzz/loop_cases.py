"""Hostile cases for closed loops, each drawn from one integer seed.

A case takes a mechanism with closed loops (the four-bar, the slider-crank,
the Delta robot, or a small random tree of fuzz.api_cases closed by one or two
loops of every kind: point, revolute, prismatic, weld, distance) in a closed
state or near one, spoils the state (huge finite coordinates such as 1e200,
NaN, infinities, wrong shapes, dtypes and types), the prescribed flags, the
held DOFs, the tolerance and the iteration limit, and makes one loop call:
loop_residual, loop_jacobian, loop_rank, constrained_dynamics, assemble,
project_velocity, independent_coordinates or loop_force_stiffness.

The property (support.forked.judged): finite results of the documented shape
or a documented error (ValueError and its LoopError, TypeError, DynamicsError)
with a message; never a crash, a hang, a silent NaN or a complex or string
array read as numbers. Besides: assemble's configuration closes every loop
within the tolerance it was given, and independent_coordinates names DOFs of
the model.
"""
from __future__ import annotations

import numpy as np

import soadyn
from fuzz.api_cases import hostile_float, hostile_vector, random_model
from support.forked import judged

LOOP_KINDS = ("point", "revolute", "prismatic", "weld", "distance")
CALLS = ("loop_residual", "loop_jacobian", "loop_rank", "constrained_dynamics", "assemble", "project_velocity",
         "independent_coordinates", "loop_force_stiffness")


def closed_scene(rng: np.random.Generator):
    """(model, q, v) of a loop scene in a closed state."""
    scenes = soadyn.scenes
    which = int(rng.integers(3))
    if which == 0:
        return scenes.four_bar(str(rng.choice(scenes.PLANAR_CUTS))), *scenes.four_bar_state(
            float(rng.uniform(-np.pi, np.pi)), float(rng.normal()))
    if which == 1:
        return scenes.slider_crank(str(rng.choice(scenes.PLANAR_CUTS))), *scenes.slider_crank_state(
            float(rng.uniform(-np.pi, np.pi)), float(rng.normal()))
    position = np.array([0.0, 0.0, -0.6]) + rng.uniform(-0.05, 0.05, 3)
    return scenes.delta_robot(), *scenes.delta_robot_state(position, rng.normal(scale=0.1, size=3))


def random_loop(rng: np.random.Generator, m: soadyn.Model, name: str) -> None:
    """One loop of a random kind between a body and another body or the world, its placements and length
    now and then hostile (the refusals are part of the case)."""
    bodies = list(m.body_names)
    a = bodies[rng.integers(len(bodies))] if bodies else "b0"  # no body: the library names the missing frame
    others = [b for b in bodies if b != a]
    b = others[rng.integers(len(others))] if others and rng.uniform() < 0.6 else None
    placements = [(None, rng.uniform(-0.5, 0.5, 3)) for _ in range(2)]
    if rng.uniform() < 0.1:
        placements[rng.integers(2)][1][rng.integers(3)] = hostile_float(rng)
    kind = LOOP_KINDS[rng.integers(len(LOOP_KINDS))] if rng.uniform() < 0.97 else "hinge"
    length = None
    if kind == "distance" and rng.uniform() < 0.5:
        length = float(rng.uniform(0.1, 1.0)) if rng.uniform() < 0.7 else hostile_float(rng)
    m.add_loop(name, a, b, kind, placement_a=placements[0], placement_b=placements[1], length=length)


def closed_tree(rng: np.random.Generator):
    """(model, q, v): a random tree of api_cases closed by one or two random loops, at a random configuration
    (closed or not: assembling it is one of the calls)."""
    m = random_model(rng)
    for k in range(int(rng.integers(1, 3))):
        random_loop(rng, m, f"loop{k}")
    return m, soadyn.random_configuration(m, int(rng.integers(1 << 30))), rng.normal(size=m.nv)


def hostile_configuration(rng: np.random.Generator, m: soadyn.Model, q: np.ndarray):
    """q moved a little along the joints, or spoiled: one coordinate huge but finite, NaN or infinite;
    another dtype (complex, strings, objects, booleans), length, number of axes or type."""
    r = rng.uniform()
    if r < 0.5:
        return soadyn.integrate(m, q, rng.normal(scale=10.0 ** rng.integers(-6, 0), size=m.nv), 1.0)
    if r < 0.75 and m.nq:
        q = np.array(q, dtype=float)
        q[rng.integers(m.nq)] = float(rng.choice([1e200, -1e200, 1e15, np.nan, np.inf])) \
            if rng.uniform() < 0.7 else hostile_float(rng)
        return q
    if r < 0.88:
        return [lambda: q + 1e-3j, lambda: q.astype(str), lambda: [*q[:-1], None], lambda: q != 0,
                lambda: q[:-1], lambda: np.append(q, 0.0), lambda: q[None], lambda: q.tolist()][rng.integers(8)]()
    return q


def hostile_hold(rng: np.random.Generator, m: soadyn.Model):
    """None, some DOFs by name or index, every DOF, or a selector the model does not have."""
    names = list(m.dof_names)
    r = rng.uniform()
    if r < 0.4 or not names:
        return None
    if r < 0.7:
        return [names[k] for k in np.flatnonzero(rng.uniform(size=len(names)) < 0.3)]
    if r < 0.8:
        return names
    if r < 0.85:
        return list(range(len(names)))
    return [["no_such_dof"], [len(names)], [-1], rng.uniform(size=len(names)) < 0.5, [None], 1.5][rng.integers(6)]


def hostile_count(rng: np.random.Generator):
    """Mostly a few iterations; now and then none, a negative, fractional or NaN count, or a huge one (which
    must end all the same when the loops cannot close)."""
    r = rng.uniform()
    if r < 0.8:
        return int(rng.choice([0, 1, 2, 3, 5, 10, 30]))
    if r < 0.95:
        return [-1, -(2 ** 40), 2.5, np.nan, "5", None][rng.integers(6)]
    return 10 ** 9


def assembled(m: soadyn.Model, q, hold, tolerance, max_iterations) -> np.ndarray:
    """soadyn.assemble, and its promise: every loop residual within the tolerance at the result."""
    closed = soadyn.assemble(m, q, hold, tolerance, max_iterations)
    residual = np.abs(soadyn.loop_residual(m, closed)).max(initial=0.0)
    if not residual <= tolerance:
        raise AssertionError(f"assemble returned a configuration with loop residual {residual:.3g} > tolerance "
                             f"{tolerance!r}")
    return closed


def named_dofs(m: soadyn.Model, q) -> tuple:
    names = soadyn.independent_coordinates(m, q)
    unknown = [name for name in names if name not in m.dof_names]
    if unknown:
        raise AssertionError(f"independent_coordinates named DOFs the model does not have: {unknown}")
    return ()


def hostile_wrenches(rng: np.random.Generator, m: soadyn.Model):
    """None, or (nbodies, 6) body wrenches spoiled as fuzz.api_cases.hostile_vector spoils vectors."""
    if rng.uniform() < 0.7:
        return None
    f_ext = hostile_vector(rng, 6 * m.nbodies)
    return f_ext.reshape(-1, 6) if isinstance(f_ext, np.ndarray) and f_ext.size % 6 == 0 else f_ext


def huge(rng: np.random.Generator, x, probability: float):
    """x times 1e200 now and then (a float array only): finite inputs whose products overflow."""
    if rng.uniform() < probability and isinstance(x, np.ndarray) and x.dtype.kind == "f":
        with np.errstate(over="ignore"):
            return x * 1e200
    return x


def call(rng: np.random.Generator):
    """One loop call with hostile arguments: (name, result, array arguments)."""
    m, q, v = closed_scene(rng) if rng.uniform() < 0.6 else closed_tree(rng)
    q = hostile_configuration(rng, m, q)
    if rng.uniform() < 0.3:
        v = hostile_vector(rng, m.nv)
    v = huge(rng, v, 0.1)
    if rng.uniform() < 0.3 and m.nv:
        mask = rng.uniform(size=m.nv) < (0.5 if rng.uniform() < 0.7 else 1.0)
        m.set_prescribed(mask)
    name = CALLS[rng.integers(len(CALLS))]
    arrays = {"q": q}
    if name == "loop_residual":
        with_v = rng.uniform() < 0.5
        arrays["v"] = v if with_v else None
        return name, soadyn.loop_residual(m, q, v) if with_v else soadyn.loop_residual(m, q), arrays
    if name in ("loop_jacobian", "loop_rank"):
        return name, getattr(soadyn, name)(m, q), arrays
    if name == "independent_coordinates":
        return name, named_dofs(m, q), arrays
    if name == "constrained_dynamics":
        u, f_ext = hostile_vector(rng, m.nv), hostile_wrenches(rng, m)
        arrays.update(v=v, u=u, f_ext=f_ext)
        return name, soadyn.constrained_dynamics(m, q, v, u, f_ext, joint_wrenches=bool(rng.uniform() < 0.5)), arrays
    if name == "assemble":
        tolerance = 1e-10 if rng.uniform() < 0.5 else hostile_float(rng)
        return name, assembled(m, q, hostile_hold(rng, m), tolerance, hostile_count(rng)), arrays
    if name == "project_velocity":
        arrays["v"] = v
        return name, soadyn.project_velocity(m, q, v, hostile_hold(rng, m)), arrays
    nu = huge(rng, hostile_vector(rng, m.nloop_equations), 0.2)
    arrays["nu"] = nu
    return name, soadyn.loop_force_stiffness(m, q, nu), arrays


def run_case(seed: int) -> str:
    """Runs case `seed`; returns 'ok' or the name of the documented error raised.
    Raises AssertionError or an unexpected exception when the property fails."""
    rng = np.random.default_rng(seed)
    return judged(lambda: call(rng))
