"""Closed loops: soadyn.constrained_dynamics against Pinocchio's constraintDynamics, same run.

Models (each built identically in both libraries, the same cut in both: "point" is
Pinocchio's CONTACT_3D, "weld" its CONTACT_6D; loops closed at the timed configuration,
velocities on the loops' tangent space):
- four-bar: the crank-rocker of Saha, Shah & Nandihal 2013 (Fig. 16), cut at the
  coupler-rocker pin by a point loop (3 equations of rank 2: redundant);
- delta: a Delta-like parallel robot: three hip revolutes, three forearms on ball joints,
  a free-floating platform held by three point loops (9 equations, nv = 18);
- talos (example-robot-data, free-floating, nv = 38) with both hands welded to a fixed
  object (two 6-D weld loops to the world);
- a 30-body random tree with 0-8 point loops, and random trees of 10-160 bodies with 4
  point loops (the scaling tables).
Python-level per-call wall time (numpy in, numpy out) of soadyn.constrained_dynamics and
pin.constraintDynamics (initConstraintDynamics once, outside the timing), interleaved
repetition by repetition (measure.interleaved_per_call_us, 21 repetitions); ratios are medians
over repetitions of the ratio within a repetition. Pinocchio's proximal settings per model are
the cheapest that reproduce soadyn's accelerations (agreement reported): mu = 0 and one
iteration where the loop equations have full rank; where they are redundant, mu = 1e-9 and the
fewest iterations (up to 10) that reproduce soadyn's accelerations to 1e-9. The per-call
overhead of each binding is measured on a one-body model with one point loop.

With --before DIR --before-rev REV (an earlier build installed with pip install --target DIR),
hybrid_dynamics of the peer robots, C++ (timing.time_cpp, peer_bench's protocol) and Python
per call, this build against that one, each timed in a child process, the builds alternating
round by round; ratios are medians over rounds: what the loop layer costs models without loops.

Writes bench/results/loops.json. Usage: python bench/bench_loops.py [--quick] [--before DIR --before-rev REV]
"""
from __future__ import annotations

import argparse
import json
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

import fixtures
from fixtures import ROBOTS, load_robot, random_states

STATES = 16


def hybrid_child(calls: int, py_calls: int) -> None:
    """Child process: hybrid_dynamics timings of the robots with whichever soadyn is imported."""
    import soadyn
    from timing import time_cpp

    out = {}
    for name in ROBOTS:
        m = load_robot(name)
        q, v, u = random_states(m, 1)
        cpp = time_cpp(m, "hybrid", q, v, u, calls)
        reps = []
        for _ in range(7):
            start = time.perf_counter()
            for i in range(py_calls):
                soadyn.hybrid_dynamics(m, q[i % 64], v[i % 64], u[i % 64])
            reps.append((time.perf_counter() - start) / py_calls * 1e6)
        out[name] = {"cpp": cpp, "python": float(np.median(reps))}
    print(json.dumps(out))


if __name__ == "__main__" and len(sys.argv) > 1 and sys.argv[1] == "--hybrid-child":
    hybrid_child(int(sys.argv[2]), int(sys.argv[3]))
    sys.exit(0)

import os  # noqa: E402

import pinocchio as pin  # noqa: E402

import soadyn  # noqa: E402
from builds import add_before_arguments, alternate_builds, before_error, has_build  # noqa: E402
from measure import interleaved_per_call_us, median_ratio  # noqa: E402
from support.pinocchio_mapping import JointMatch, PinocchioMapping, free_joint_names  # noqa: E402  (tests/support)
from report import Table, write  # noqa: E402
from support.pinocchio_trees import BodySpec, Mapping, build_pinocchio, build_soadyn  # noqa: E402
from timing import time_cpp  # noqa: E402
from support.trees import random_inertia, random_rotation, random_unit  # noqa: E402

CONTACT = {"point": pin.ContactType.CONTACT_3D, "weld": pin.ContactType.CONTACT_6D}


# ---------------------------------------------------------------------------
# A model in both libraries, with its loops
# ---------------------------------------------------------------------------

@dataclass
class Loop:
    kind: str             # "point" or "weld"
    a: str                # soadyn body name of frame A
    b: str | None         # of frame B (None: the world)
    Ra: np.ndarray        # frame A in body a; frame B is placed to coincide with it at q
    pa: np.ndarray


@dataclass
class Case:
    name: str
    m: soadyn.Model
    model: pin.Model
    data: pin.Data
    mapping: PinocchioMapping
    constraints: pin.StdVec_RigidConstraintModel
    constraint_datas: pin.StdVec_RigidConstraintData
    settings: pin.ProximalSettings
    states: tuple         # soadyn (q, v, u), STATES rows each
    pin_states: tuple     # the same in Pinocchio's coordinates
    rank: int
    agreement: float = float("nan")


def _homogeneous(R, p) -> np.ndarray:
    X = np.eye(4)
    X[:3, :3], X[:3, 3] = R, p
    return X


def close_loops(m, model, joint_of_body: dict, q, loops: list[Loop]):
    """Adds the loops to m and returns Pinocchio's constraint models, each loop closed at q."""
    poses = soadyn.forward_kinematics(m, q)[0]
    constraints = pin.StdVec_RigidConstraintModel()
    for k, loop in enumerate(loops):
        a = m.body_names.index(loop.a)
        A_world = poses[a] @ _homogeneous(loop.Ra, loop.pa)
        B = A_world if loop.b is None else np.linalg.solve(poses[m.body_names.index(loop.b)], A_world)
        m.add_loop(f"loop{k}", loop.a, loop.b, loop.kind, placement_a=(loop.Ra, loop.pa),
                   placement_b=(B[:3, :3], B[:3, 3]))
        jb = 0 if loop.b is None else model.getJointId(joint_of_body[loop.b])
        constraints.append(pin.RigidConstraintModel(CONTACT[loop.kind], model, model.getJointId(joint_of_body[loop.a]),
                                                    pin.SE3(loop.Ra, loop.pa), jb, pin.SE3(B[:3, :3], B[:3, 3]),
                                                    pin.ReferenceFrame.LOCAL))
    return constraints


def make_case(name, m, model, mapping, joint_of_body, q, loops, seed=0) -> Case:
    constraints = close_loops(m, model, joint_of_body, q, loops)
    datas = pin.StdVec_RigidConstraintData()
    for c in constraints:
        datas.append(c.createData())
    data = model.createData()
    pin.initConstraintDynamics(model, data, constraints, datas)
    rng = np.random.default_rng(seed)
    C = soadyn.loop_jacobian(m, q) if m.nloops else np.zeros((0, m.nv))
    rank = int(np.linalg.matrix_rank(C)) if m.nloops else 0
    P = np.eye(m.nv) - np.linalg.pinv(C) @ C if m.nloops else np.eye(m.nv)
    v = rng.uniform(-1, 1, (STATES, m.nv)) @ P.T
    u = rng.uniform(-1, 1, (STATES, m.nv))
    qs = np.tile(q, (STATES, 1))
    states = (qs, v, u)
    pin_states = (np.array([mapping.q(x) for x in qs]), v[:, mapping.perm], u[:, mapping.perm])
    case = Case(name, m, model, data, mapping, constraints, datas, pin.ProximalSettings(1e-12, 0.0, 1), states,
                pin_states, rank)
    if rank < C.shape[0]:  # redundant: the proximal iterations, as few as reproduce soadyn's accelerations
        for iterations in range(1, 11):
            case.settings = pin.ProximalSettings(1e-12, 1e-9, iterations)
            if agreement(case) <= 1e-9:
                break
    case.agreement = agreement(case)
    return case


def agreement(c: Case) -> float:
    """Largest relative difference of the accelerations of both libraries over the states."""
    worst = 0.0
    for i in range(STATES):
        qdd = soadyn.constrained_dynamics(c.m, *(x[i] for x in c.states))[0]
        ddq = pin.constraintDynamics(c.model, c.data, *(x[i] for x in c.pin_states), c.constraints,
                                     c.constraint_datas, c.settings)
        worst = max(worst, np.abs(qdd - c.mapping.back(ddq)).max() / max(1.0, np.abs(qdd).max()))
    return float(worst)


def spec_case(name, specs, gravity, q, loops, seed=0) -> Case:
    m = build_soadyn(specs)
    m.gravity = gravity
    model = build_pinocchio(specs, m.gravity)
    return make_case(name, m, model, Mapping(m, model, specs), {s.name: s.name for s in specs}, q, loops, seed)


# ---------------------------------------------------------------------------
# The models
# ---------------------------------------------------------------------------

def _body(name, parent, kind, axis=(0, 0, 1), translation=(0, 0, 0), rotation=None, mass=1.0, com=(0, 0, 0),
          inertia=(1e-3, 1e-3, 1e-3)) -> BodySpec:
    axis = np.asarray(axis, dtype=float)
    inertia = np.asarray(inertia, dtype=float)
    return BodySpec(name=name, parent=parent, kind=kind, axis=axis / np.linalg.norm(axis),
                    axis2=np.array([1.0, 0.0, 0.0]), pitch=0.0,
                    rotation=np.eye(3) if rotation is None else rotation, translation=np.asarray(translation, float),
                    mass=mass, com=np.asarray(com, float), inertia=np.diag(inertia) if inertia.ndim == 1 else inertia)


def rod(length, mass, along=0):
    """Uniform slender rod along body axis `along`: centre of mass and inertia about it (a tiny axial moment)."""
    com = np.zeros(3)
    com[along] = length / 2
    moments = np.full(3, mass * length**2 / 12)
    moments[along] = 1e-6 * mass * length**2
    return dict(mass=mass, com=com, inertia=moments)


def four_bar_case() -> Case:
    from support.four_bar import COUPLER, CRANK, GROUND, MASSES, ROCKER, assembled

    specs = [_body("crank", -1, "revolute", **rod(CRANK, MASSES[0])),
             _body("coupler", 0, "revolute", translation=(CRANK, 0, 0), **rod(COUPLER, MASSES[1])),
             _body("rocker", -1, "revolute", translation=(GROUND, 0, 0), **rod(ROCKER, MASSES[2]))]
    q = assembled(1.0)
    # The pin between coupler and rocker: frame A at the coupler's tip, B (on the rocker) placed onto it.
    return spec_case("four-bar (point cut)", specs, (0.0, -9.81, 0.0), q,
                     [Loop("point", "coupler", "rocker", np.eye(3), np.array([COUPLER, 0, 0]))])


def delta_case() -> Case:
    """Three arms (hip revolute about the base circle's tangent, forearm on a ball joint at the
    elbow) and a free platform held by a point loop at each forearm's tip; assembled by the
    Delta's inverse kinematics with the platform at (0, 0, -0.35)."""
    base, plate, upper, fore = 0.20, 0.05, 0.20, 0.45
    platform = np.array([0.0, 0.0, -0.35])
    specs, q_parts = [], []
    tips = []
    for i in range(3):
        phi = 2 * np.pi * i / 3
        radial, tangent = np.array([np.cos(phi), np.sin(phi), 0.0]), np.array([-np.sin(phi), np.cos(phi), 0.0])
        hip = base * radial
        target = platform + plate * radial

        def gap(theta):
            elbow = hip + upper * (np.cos(theta) * radial - np.sin(theta) * np.array([0, 0, 1.0]))
            return np.linalg.norm(target - elbow) - fore

        # The first sign change of the gap from the arm pointing up to pointing down, refined by bisection.
        thetas = np.linspace(-0.5 * np.pi, 0.5 * np.pi, 721)
        k = int(np.argmax(np.sign([gap(t) for t in thetas[:-1]]) != np.sign([gap(t) for t in thetas[1:]])))
        a, b = thetas[k], thetas[k + 1]
        for _ in range(80):
            mid = 0.5 * (a + b)
            a, b = (mid, b) if np.sign(gap(mid)) == np.sign(gap(a)) else (a, mid)
        theta = 0.5 * (a + b)
        R_hip = soadyn_rotation(tangent, theta)
        elbow = hip + R_hip @ (upper * radial)
        w = R_hip.T @ ((target - elbow) / fore)  # forearm direction in the hip (= elbow joint) frame
        down = np.array([0.0, 0.0, -1.0])
        R_ball = rotation_between(down, w)
        specs.append(_body(f"hip{i}", -1, "revolute", axis=tangent, translation=hip,
                           **rod_along(upper, 0.3, radial)))
        specs.append(_body(f"forearm{i}", 2 * i, "spherical", translation=upper * radial,
                           **rod_along(fore, 0.1, down)))
        q_parts += [[theta], quaternion_xyzw(R_ball)]
        tips.append(Loop("point", f"forearm{i}", "platform", np.eye(3), fore * down))
    specs.append(_body("platform", -1, "free", mass=0.5, inertia=(1e-3, 1e-3, 2e-3)))
    q = np.concatenate(q_parts + [platform, [0, 0, 0, 1.0]])
    return spec_case("delta (3 point loops)", specs, (0.0, 0.0, -9.81), q, tips)


def soadyn_rotation(axis, angle) -> np.ndarray:
    k = np.asarray(axis) / np.linalg.norm(axis)
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(angle) * K + (1 - np.cos(angle)) * K @ K


def rotation_between(a, b) -> np.ndarray:
    """The smallest rotation taking unit vector a onto unit vector b."""
    axis = np.cross(a, b)
    s, c = np.linalg.norm(axis), float(a @ b)
    return np.eye(3) if s < 1e-15 else soadyn_rotation(axis / s, np.arctan2(s, c))


def quaternion_xyzw(R) -> np.ndarray:
    w = 0.5 * np.sqrt(max(0.0, 1 + np.trace(R)))
    x = np.copysign(0.5 * np.sqrt(max(0.0, 1 + R[0, 0] - R[1, 1] - R[2, 2])), R[2, 1] - R[1, 2])
    y = np.copysign(0.5 * np.sqrt(max(0.0, 1 - R[0, 0] + R[1, 1] - R[2, 2])), R[0, 2] - R[2, 0])
    z = np.copysign(0.5 * np.sqrt(max(0.0, 1 - R[0, 0] - R[1, 1] + R[2, 2])), R[1, 0] - R[0, 1])
    return np.array([x, y, z, w])


def rod_along(length, mass, direction):
    """A uniform rod from the body origin along `direction` (unit): centre of mass and inertia."""
    d = np.asarray(direction, dtype=float)
    inertia = mass * length**2 / 12 * (np.eye(3) - np.outer(d, d)) + 1e-6 * mass * length**2 * np.outer(d, d)
    return dict(mass=mass, com=0.5 * length * d, inertia=inertia)


def talos_case() -> Case:
    m = fixtures.load_robot("talos")
    model = fixtures.pinocchio_robot("talos")
    joints = []
    for jid in range(1, model.njoints):
        name = model.names[jid]
        q_names, v_names = free_joint_names(name) if name == "root_joint" else ((name,), (name,))
        joints.append(JointMatch(jid, q_names, v_names))
    mapping = PinocchioMapping(m, model, joints)
    joint_of_body = dict(zip(m.body_names, m.joint_names))
    q = soadyn.random_configuration(m, 3)
    hand = np.array([0.0, 0.0, -0.1])  # a point in the palm, below the last wrist joint
    loops = [Loop("weld", "arm_left_7_link", None, np.eye(3), hand),
             Loop("weld", "arm_right_7_link", None, np.eye(3), hand)]
    return make_case("talos (2 weld loops)", m, model, mapping, joint_of_body, q, loops)


SCALING_KINDS = ("revolute", "prismatic", "spherical", "universal")


def random_tree_specs(nbodies: int, seed: int) -> list[BodySpec]:
    """A fixed-base random tree in depth-first order (each body off the previous one or one of its
    ancestors), revolute, prismatic, spherical and universal joints, random placements and inertias."""
    rng = np.random.default_rng(seed)
    specs: list[BodySpec] = []
    for i in range(nbodies):
        parent = i - 1
        while parent >= 0 and rng.uniform() < 0.3:
            parent = specs[parent].parent
        a1 = random_unit(rng)
        a2 = np.cross(a1, random_unit(rng))
        specs.append(BodySpec(name=f"b{i}", parent=parent, kind=str(rng.choice(SCALING_KINDS)), axis=a1,
                              axis2=a2 / np.linalg.norm(a2), pitch=0.0, rotation=random_rotation(rng),
                              translation=rng.uniform(-0.3, 0.3, size=3), mass=float(rng.uniform(0.5, 2.0)),
                              com=rng.uniform(-0.1, 0.1, size=3), inertia=random_inertia(rng)))
    return specs


def random_point_loops(nbodies: int, nloops: int, seed: int) -> list[Loop]:
    rng = np.random.default_rng(seed + 1)
    loops = []
    for _ in range(nloops):
        a, b = rng.choice(np.arange(-1, nbodies), size=2, replace=False)
        if a < 0:
            a, b = b, a
        loops.append(Loop("point", f"b{a}", None if b < 0 else f"b{b}", np.eye(3), rng.uniform(-0.2, 0.2, size=3)))
    return loops


def random_tree_case(nbodies: int, nloops: int, seed: int = 7) -> Case:
    specs = random_tree_specs(nbodies, seed)
    m = build_soadyn(specs)
    q = soadyn.random_configuration(m, seed)
    return spec_case(f"random tree {nbodies} bodies, {nloops} point loop{'' if nloops == 1 else 's'}", specs, (0.0, 0.0, -9.81), q,
                     random_point_loops(nbodies, nloops, seed))


def overhead_case() -> Case:
    """One free body whose corner is held by a point loop to the world (3 equations of full rank, so
    Pinocchio needs one iteration): the bindings' per-call floor."""
    specs = [_body("block", -1, "free", mass=1.0, inertia=(1e-2, 2e-2, 3e-2))]
    return spec_case("1 free body, 1 point loop", specs, (0.0, 0.0, -9.81), np.array([0, 0, 0, 0, 0, 0, 1.0]),
                     [Loop("point", "block", None, np.eye(3), np.array([0.1, 0.05, 0.02]))])


# ---------------------------------------------------------------------------
# Timing
# ---------------------------------------------------------------------------

def time_case(c: Case, calls: int, repetitions: int = 21) -> dict:
    s = interleaved_per_call_us({
        "soadyn": (lambda q, v, u: soadyn.constrained_dynamics(c.m, q, v, u), c.states),
        "pinocchio": (lambda q, v, u: pin.constraintDynamics(c.model, c.data, q, v, u, c.constraints,
                                                             c.constraint_datas, c.settings), c.pin_states),
    }, calls, repetitions)
    cpp = time_cpp(c.m, "constrained", *c.states, calls=max(50, calls), repetitions=7)
    return {"soadyn": float(np.median(s["soadyn"])), "pinocchio": float(np.median(s["pinocchio"])),
            "ratio": median_ratio(s["soadyn"], s["pinocchio"]), "cpp": cpp}


def parts_of_soadyn(c: Case, calls: int) -> dict:
    """Python per-call time of the tree algorithm constrained_dynamics runs first on a rigid model (the
    hybrid sweeps, whose articulated-body factors the loop response reuses), interleaved with the whole
    call: the share of the loop-specific work."""
    s = interleaved_per_call_us({
        "constrained_dynamics": (lambda q, v, u: soadyn.constrained_dynamics(c.m, q, v, u), c.states),
        "hybrid_dynamics (no loops)": (lambda q, v, u: soadyn.hybrid_dynamics(c.m, q, v, u), c.states),
    }, calls)
    return {k: float(np.median(x)) for k, x in s.items()}


# ---------------------------------------------------------------------------
# Report
# ---------------------------------------------------------------------------

def case_table(title: str) -> Table:
    table = Table(title, ["model", "nv", "loop equations", "rank", "soadyn loop solver",
                          "soadyn.constrained_dynamics (us)", "pin.constraintDynamics (us)", "soadyn / Pinocchio",
                          "soadyn C++ (us)", "Pinocchio settings", "qdd agreement"], headline=["soadyn / Pinocchio"])
    table.formats = {"soadyn.constrained_dynamics (us)": ".2f", "pin.constraintDynamics (us)": ".2f",
                     "soadyn / Pinocchio": ".2f", "soadyn C++ (us)": ".2f", "qdd agreement": ".0e"}
    return table


def add_case(table: Table, c: Case, t: dict) -> None:
    equations = sum(3 if l.type == pin.ContactType.CONTACT_3D else 6 for l in c.constraints)
    solver = c.m.loop_solver if c.m.nloops else "(no loops)"
    settings = f"mu {c.settings.mu:g}, {c.settings.max_iter} iter."
    table.add(c.name, c.m.nv, equations, c.rank, solver, t["soadyn"], t["pinocchio"], t["ratio"], t["cpp"],
              settings, c.agreement)
    print(c.name, t, f"agreement {c.agreement:.1e}", flush=True)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer calls (a smoke run, noisier)")
    add_before_arguments(parser, required=False, without="; without it, no comparison of builds")
    args = parser.parse_args()
    if before_error(args):
        print(before_error(args), file=sys.stderr)
        return 2
    calls, rounds, cpp_calls, hybrid_py_calls = (300, 2, 2000, 300) if args.quick else (1000, 6, 20000, 2000)

    load_before = os.getloadavg()[0]
    overhead = time_case(overhead_case(), calls)
    print("overhead", overhead, flush=True)
    per_call = case_table("Per call")
    main_cases = [four_bar_case(), delta_case(), talos_case()]
    for c in main_cases:
        add_case(per_call, c, time_case(c, calls))
    talos_parts = parts_of_soadyn(main_cases[2], calls)
    print("talos parts", talos_parts, flush=True)
    by_loops = case_table("Loops on one tree (30 bodies: revolute, prismatic, spherical and universal joints, fixed "
                          "base; point loops between random bodies or to the world)")
    by_loops.summary = False
    for n in (0, 1, 2, 4, 6, 8):
        c = random_tree_case(30, n)
        add_case(by_loops, c, time_case(c, calls))
    by_size = case_table("Tree size, 4 point loops")
    for n in (10, 20, 40, 80, 160):
        c = random_tree_case(n, 4)
        add_case(by_size, c, time_case(c, max(50, calls * 20 // n)))

    overhead_table = Table("Binding overhead: one free body, one point loop to the world (Python per call, us)",
                           ["call", "soadyn", "Pinocchio", "soadyn / Pinocchio"],
                           {"soadyn": ".2f", "Pinocchio": ".2f", "soadyn / Pinocchio": ".2f"}, summary=False)
    overhead_table.add("constrained dynamics", overhead["soadyn"], overhead["pinocchio"], overhead["ratio"])
    parts = Table("Where soadyn's time goes on talos with two welds (Python per call, us)", ["call", "us"],
                  {"us": ".2f"}, summary=False)
    for label, t in talos_parts.items():
        parts.add(label, t)
    tables = [per_call, overhead_table, parts, by_loops, by_size]

    if has_build(args.before):
        hybrid = alternate_builds(Path(__file__), ["--hybrid-child", str(cpp_calls), str(hybrid_py_calls)], args.before,
                                  rounds, "hybrid")
        builds = Table(f"Models without loops: hybrid_dynamics per call (us), this build against {args.before_rev}",
                       ["robot", "C++ before", "C++ after", "C++ after / before", "Python before", "Python after",
                        "Python after / before"], headline=["C++ after / before", "Python after / before"])
        builds.formats = {c: ".2f" for c in builds.columns[1:]}
        for name in ROBOTS:
            med = {k: {x: float(np.median([r[name][x] for r in hybrid[k]])) for x in ("cpp", "python")} for k in hybrid}
            builds.add(name, med["before"]["cpp"], med["after"]["cpp"],
                       median_ratio([a[name]["cpp"] for a in hybrid["after"]], [b[name]["cpp"] for b in hybrid["before"]]),
                       med["before"]["python"], med["after"]["python"],
                       median_ratio([a[name]["python"] for a in hybrid["after"]],
                                    [b[name]["python"] for b in hybrid["before"]]))
        tables.append(builds)
    for table in tables:
        table.print()
    settings = {
        "calls": calls, "repetitions": 21, "states": STATES, "pin": pin.__version__,
        "load_average": [round(load_before, 1), round(os.getloadavg()[0], 1)],
        "before": {"commit": args.before_rev, "rounds": rounds, "cpp_calls": cpp_calls,
                   "python_calls": hybrid_py_calls} if has_build(args.before) else None,
    }
    notes = [
        "Python per call: median of 21 repetitions cycling through 16 states (one closed configuration, "
        "velocities on the loops' tangent space, random inputs), the two libraries interleaved repetition by "
        "repetition; ratio = median over repetitions of the ratio within one.",
        "Pinocchio: initConstraintDynamics once, then constraintDynamics per call with the settings shown (the "
        "cheapest that reproduce soadyn's accelerations; qdd agreement: the largest relative difference over the "
        "states). soadyn C++: time_cpp(m, 'constrained', ...) over the same states (median of 7 repetitions).",
        "soadyn's loop solver (Model.loop_solver, chosen per model): 'mass matrix' where the tree factor's work "
        "is at most 300 per loop equation, 'articulated' otherwise.",
        "Binding overhead: soadyn returns three fresh arrays (qdd, tau, loop wrenches); Pinocchio returns ddq "
        "and keeps the multipliers in its data.",
        "Without loops constrained_dynamics is hybrid_dynamics: the 0-loop row of the loop-count table.",
    ]
    write("loops", "Closed loops: soadyn.constrained_dynamics against Pinocchio's constraintDynamics", tables,
          settings, notes)
    return 0


if __name__ == "__main__":
    sys.exit(main())
