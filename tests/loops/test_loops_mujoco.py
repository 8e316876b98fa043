"""Constrained dynamics of random trees closed by 1-4 loops of every kind
against MuJoCo: the same tree built as MJCF, MuJoCo's mass matrix
(mj_mulM), bias forces (qfrc_bias), site Jacobians (mj_jacSite, mj_jac) and
their time derivatives (mj_jacDot), assembled here into the KKT system of
the cut joints,
    M qdd + h = tau + C' lambda,   C qdd = kappa,
with prescribed DOFs substituted, and solved by least squares (minimum-norm
multipliers when loop equations are redundant). Nothing of soadyn enters
the reference: the constraint directions W of each kind are written below
from the sites' frames, after the conventions of soadyn/model/loop.hpp.

Trees: the spatial random trees of support/pinocchio_trees.random_specs
(helical joints, which MuJoCo lacks, become cylindrical ones about the same
axis), and planar random linkages (planar root, hinges normal to the plane,
slides in it), where revolute, point, weld and prismatic cuts are redundant.

The tree's MJCF and the map of soadyn's coordinates to MuJoCo's are
support/mujoco_trees.py's.
"""
from __future__ import annotations

import dataclasses
import functools

import mujoco
import numpy as np
import pytest

import soadyn
from support.error_log import ErrorLog, report_fixture
from support.mujoco_models import full_mass_matrix
from support.mujoco_trees import mjcf, mujoco_state, rot_z
from support.pinocchio_trees import BodySpec, build_soadyn, random_specs
from support.trees import random_inertia, random_rotation, random_unit

RTOL = 1e-9
KINDS = ("point", "revolute", "prismatic", "weld", "distance")
GRAVITY = np.array([0.7, -2.1, -9.81])  # not along an axis: every mapping of it is exercised

LOG = ErrorLog("MuJoCo", RTOL)
check = LOG.check


report_errors = report_fixture(LOG)


# ---------------------------------------------------------------------------
# Trees
# ---------------------------------------------------------------------------

def spatial_specs(seed: int, floating: bool) -> list[BodySpec]:
    """support/pinocchio_trees.py's random tree, helical joints made cylindrical."""
    return [dataclasses.replace(s, kind="cylindrical") if s.kind == "helical" else s
            for s in random_specs(seed, floating)]


SHALLOW_KINDS = ("revolute", "prismatic", "universal", "cylindrical", "planar", "spherical", "translation")


def shallow_specs(seed: int) -> list[BodySpec]:
    """A small shallow spatial tree (3-6 bodies, none deeper than a child of a world-hinged body):
    constrained_dynamics solves its loops through the mass matrix (Model.loop_solver)."""
    rng = np.random.default_rng(700 + seed)
    specs: list[BodySpec] = []
    for i in range(int(rng.integers(3, 7))):
        # Off the world, or off the previous body when that one hangs off the world (depth-first order).
        parent = i - 1 if i > 0 and specs[i - 1].parent < 0 and rng.uniform() < 0.6 else -1
        axis = random_unit(rng)
        axis2 = np.cross(axis, random_unit(rng))
        specs.append(BodySpec(
            name=f"b{i}", parent=parent, kind=str(rng.choice(SHALLOW_KINDS)), axis=axis,
            axis2=axis2 / np.linalg.norm(axis2), pitch=0.0, rotation=random_rotation(rng),
            translation=rng.uniform(-0.5, 0.5, size=3), mass=float(rng.uniform(0.5, 3.0)),
            com=rng.uniform(-0.3, 0.3, size=3), inertia=random_inertia(rng) * rng.uniform(0.5, 2.0)))
    return specs


def planar_specs(seed: int) -> list[BodySpec]:
    """A random planar linkage in the world x-y plane: a planar root, then hinges about z and
    slides along in-plane axes, each body off the previous one or one of its ancestors."""
    rng = np.random.default_rng(500 + seed)
    nbodies = int(rng.integers(5, 9))
    specs: list[BodySpec] = []
    for i in range(nbodies):
        parent = i - 1
        while parent > 0 and rng.uniform() < 0.4:
            parent = specs[parent].parent
        kind = "planar" if i == 0 else ("prismatic" if rng.uniform() < 0.25 else "revolute")
        axis = np.array([0.0, 0.0, 1.0]) if kind == "revolute" else rot_z(rng.uniform(0, 2 * np.pi))[:, 0]
        specs.append(BodySpec(
            name=f"b{i}", parent=parent, kind=kind, axis=axis, axis2=np.array([1.0, 0.0, 0.0]), pitch=0.0,
            rotation=rot_z(rng.uniform(0, 2 * np.pi)), translation=np.r_[rng.uniform(-0.5, 0.5, size=2), 0.0],
            mass=float(rng.uniform(0.5, 3.0)), com=rng.uniform(-0.3, 0.3, size=3),
            inertia=random_inertia(rng) * rng.uniform(0.5, 2.0)))
    return specs


# ---------------------------------------------------------------------------
# Loops: frames, residuals and constraint directions from MuJoCo's sites
# ---------------------------------------------------------------------------

@dataclasses.dataclass
class LoopSpec:
    name: str
    kind: str
    a: int                # body index of frame A
    b: int                # body index of frame B, -1: the world
    Ra: np.ndarray        # frame A in body a
    pa: np.ndarray
    Rb: np.ndarray        # frame B in body b (or the world)
    pb: np.ndarray
    length: float | None  # distance loops


def _homogeneous(R, p) -> np.ndarray:
    X = np.eye(4)
    X[:3, :3], X[:3, 3] = R, p
    return X


def draw_loop(rng, kind: str, name: str, a: int, b: int, poses, planar: bool) -> LoopSpec:
    """A loop of `kind` between bodies a and b, closed at the configuration of `poses` (soadyn's
    body poses, used only to place frame B where frame A's kind lets it be). In a planar linkage
    frame A's z axis is the plane normal (prismatic: in the plane, else the cut could not slide)."""
    if planar:
        Ra = rot_z(rng.uniform(0, 2 * np.pi))
        if kind == "prismatic":
            Ra = Ra @ np.array([[1.0, 0, 0], [0, 0, -1.0], [0, 1.0, 0]])
        pa = np.r_[rng.uniform(-0.3, 0.3, size=2), 0.0]
    else:
        Ra, pa = random_rotation(rng), rng.uniform(-0.3, 0.3, size=3)
    A = poses[a] @ _homogeneous(Ra, pa)
    offset, length = np.eye(4), None
    if kind == "point":        # any relative orientation
        offset[:3, :3] = rot_z(rng.uniform(0, 2 * np.pi)) if planar else random_rotation(rng)
    elif kind == "revolute":   # any rotation about the common z axis
        offset[:3, :3] = rot_z(rng.uniform(0, 2 * np.pi))
    elif kind == "prismatic":  # B's origin anywhere on the common z axis
        offset[2, 3] = rng.uniform(-0.3, 0.3)
    elif kind == "distance":   # B's origin at a distance, in the plane for a planar linkage
        d = rng.normal(size=3)
        if planar:
            d[2] = 0.0
        offset[:3, 3] = rng.uniform(0.2, 0.5) * d / np.linalg.norm(d)
        length = float(np.linalg.norm(offset[:3, 3]))
    B_world = A @ offset
    B = B_world if b < 0 else np.linalg.solve(poses[b], B_world)
    return LoopSpec(name, kind, a, b, Ra, pa, B[:3, :3], B[:3, 3], length)


def _small_rotation_vector(R: np.ndarray) -> np.ndarray:
    """Rotation vector of a rotation close to the identity (first order is enough for a residual)."""
    return 0.5 * np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]])


def loop_residual(kind, RA, pA, RB, pB, length) -> np.ndarray:
    d = pA - pB
    return {
        "point": lambda: d,
        "revolute": lambda: np.r_[d, RA[:, 0] @ np.cross(RB[:, 2], RA[:, 2]), RA[:, 1] @ np.cross(RB[:, 2], RA[:, 2])],
        "prismatic": lambda: np.r_[_small_rotation_vector(RA @ RB.T), RB[:, 0] @ d, RB[:, 1] @ d],
        "weld": lambda: np.r_[_small_rotation_vector(RA @ RB.T), d],
        "distance": lambda: np.array([np.linalg.norm(d) - length]),
    }[kind]()


def directions(kind, RA, pA, RB, pB) -> np.ndarray:
    """W (6 x k): each column maps the relative spatial velocity [w_A - w_B; v_A - v_B(P)] (world
    axes) to one equation's rate, and the multipliers to B's wrench on A about A's origin."""
    e = np.eye(3)
    Z = np.zeros((3, 3))
    return {
        "point": lambda: np.vstack([Z, e]),
        "revolute": lambda: np.block([[Z, RA[:, :2]], [e, np.zeros((3, 2))]]),
        "prismatic": lambda: np.block([[e, np.zeros((3, 2))], [Z, RB[:, :2]]]),
        "weld": lambda: np.eye(6),
        "distance": lambda: np.r_[np.zeros(3), (pA - pB) / np.linalg.norm(pA - pB)][:, None],
    }[kind]()


def directions_rate_times(kind, RA, pA, RB, pB, wA, wB, rel) -> np.ndarray:
    """d/dt(W)' rel for the relative velocity rel = [w_A - w_B; v_A - v_B(P)] (world axes)."""
    if kind == "revolute":      # d/dt x_A = w_A x x_A
        return np.r_[np.zeros(3), [np.cross(wA, RA[:, j]) @ rel[:3] for j in (0, 1)]]
    if kind == "prismatic":     # d/dt x_B = w_B x x_B
        return np.r_[np.zeros(3), [np.cross(wB, RB[:, j]) @ rel[3:] for j in (0, 1)]]
    if kind == "distance":      # d/dt n = (I - n n') dp / |p_A - p_B|
        d = pA - pB
        n = d / np.linalg.norm(d)
        dp = rel[3:]
        return np.array([(dp - n * (n @ dp)) @ dp / np.linalg.norm(d)])
    return np.zeros(6 if kind == "weld" else 3)


# ---------------------------------------------------------------------------
# MuJoCo's quantities and the reference solve
# ---------------------------------------------------------------------------

@dataclasses.dataclass
class Equations:
    M: np.ndarray        # soadyn coordinates
    h: np.ndarray
    C: np.ndarray
    kappa: np.ndarray
    residual: np.ndarray
    W: list              # per loop, at the current configuration


def _point_jacobians(model, data, body: str | None, point: np.ndarray):
    """6 x nv Jacobian [angular; linear] of the named body's material point at `point` (world), and
    its time derivative; zero for the world (None)."""
    if body is None:
        return np.zeros((6, model.nv)), np.zeros((6, model.nv))
    jp, jr, djp, djr = (np.zeros((3, model.nv)) for _ in range(4))
    bid = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, body)
    mujoco.mj_jac(model, data, jp, jr, point, bid)
    mujoco.mj_jacDot(model, data, djp, djr, point, bid)
    return np.vstack([jr, jp]), np.vstack([djr, djp])


def mujoco_equations(m, model, specs, loops, q, v) -> Equations:
    data = mujoco.MjData(model)
    st = mujoco_state(m, model, specs, q, v)
    data.qpos[:] = st.qpos
    data.qvel[:] = st.T @ v
    mujoco.mj_forward(model, data)
    Mm = full_mass_matrix(model, data)
    T, Tdv = st.T, st.T_dot_v
    M = T.T @ Mm @ T
    h = T.T @ (data.qfrc_bias + Mm @ Tdv)
    rows_C, rows_kappa, residual, Ws = [], [], [], []
    for loop in loops:
        sa = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SITE, f"{loop.name}:A")
        sb = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SITE, f"{loop.name}:B")
        RA, pA = data.site_xmat[sa].reshape(3, 3).copy(), data.site_xpos[sa].copy()
        RB, pB = data.site_xmat[sb].reshape(3, 3).copy(), data.site_xpos[sb].copy()
        P = pA if loop.kind == "prismatic" else pB  # body B's point whose velocity enters
        JA, dJA = _point_jacobians(model, data, specs[loop.a].name, pA)
        JB, dJB = _point_jacobians(model, data, None if loop.b < 0 else specs[loop.b].name, P)
        qvel = data.qvel
        vel_A, vel_B = JA @ qvel, JB @ qvel
        rel = vel_A - vel_B
        # Accelerations at qdd = 0 (qacc_mujoco = Tdot v): Jdot v_mujoco + J Tdot v.
        acc0 = (dJA @ qvel + JA @ Tdv) - (dJB @ qvel + JB @ Tdv)
        if loop.kind == "prismatic":  # P slides on B: d/dt v_B(P) gains w_B x (v_A - v_B(P))
            acc0[3:] -= np.cross(vel_B[:3], rel[3:])
        W = directions(loop.kind, RA, pA, RB, pB)
        rows_C.append(W.T @ (JA - JB) @ T)
        rows_kappa.append(-(directions_rate_times(loop.kind, RA, pA, RB, pB, vel_A[:3], vel_B[:3], rel)
                            + W.T @ acc0))
        residual.append(loop_residual(loop.kind, RA, pA, RB, pB, loop.length))
        Ws.append(W)
    return Equations(M, h, np.vstack(rows_C), np.concatenate(rows_kappa), np.concatenate(residual), Ws)


def null_space(A: np.ndarray, scale: float) -> np.ndarray:
    """Orthonormal basis (columns) of the null space of A, by SVD: singular values below 1e-9 * scale count
    as zero (scale: that of the matrix A is cut from, so a block of rounding noise counts as zero)."""
    _, sv, Vh = np.linalg.svd(A)
    rank = int((sv > 1e-9 * scale).sum())
    return Vh[rank:].T


def reference_solution(eq: Equations, prescribed: np.ndarray, u: np.ndarray):
    """qdd, tau and the multipliers of M qdd + h = tau + C' lambda, C qdd = kappa, with qdd given on
    prescribed DOFs and tau on regular ones.

    qdd and the minimum-norm multipliers lambda0: the bordered system [M_rr -C_r'; C_r 0] solved by least
    squares (qdd_r is unique; the minimum-norm solution has the minimum-norm multipliers). Any lambda0 + N z,
    N a basis of null(C_r'), gives the same motion; when C_p' N != 0 (more prescribed DOFs than the mechanism
    needs: redundant actuation) they give different tau_p, and tau_p is the minimum-norm actuator force
    (z: least squares of C_p' N z = tau_p(lambda0)). Returns qdd, tau, lambda and whether the actuation is
    redundant."""
    r, p = ~prescribed, prescribed
    nr, k = int(r.sum()), eq.C.shape[0]
    K = np.block([[eq.M[np.ix_(r, r)], -eq.C[:, r].T], [eq.C[:, r], np.zeros((k, k))]])
    rhs = np.r_[u[r] - eq.h[r] - eq.M[np.ix_(r, p)] @ u[p], eq.kappa - eq.C[:, p] @ u[p]]
    x = np.linalg.lstsq(K, rhs, rcond=1e-11)[0]
    qdd = u.copy()
    qdd[r] = x[:nr]
    lam = x[nr:]
    N = null_space(eq.C[:, r].T, max(1.0, np.linalg.norm(eq.C, 2)))
    B = eq.C[:, p].T @ N
    redundant_actuation = B.size > 0 and np.abs(B).max() > 1e-9 * max(1.0, np.linalg.norm(eq.C, 2))
    if redundant_actuation:
        tau0 = eq.M @ qdd + eq.h - eq.C.T @ lam
        lam = lam + N @ np.linalg.lstsq(B, tau0[p], rcond=1e-11)[0]
    tau = eq.M @ qdd + eq.h - eq.C.T @ lam
    tau[r] = u[r]
    return qdd, tau, lam, redundant_actuation


# ---------------------------------------------------------------------------
# Cases
# ---------------------------------------------------------------------------

@functools.lru_cache(maxsize=None)
def _tree(tree: str, seed: int):
    if tree == "planar":
        return planar_specs(seed)
    if tree == "shallow":
        return shallow_specs(seed)
    return spatial_specs(seed, tree == "floating")


def build_case(tree: str, seed: int, nloops: int):
    specs = _tree(tree, seed)
    m = build_soadyn(specs)
    m.gravity = GRAVITY
    rng = np.random.default_rng(1000 * seed + 10 * nloops + len(tree))
    q = soadyn.random_configuration(m, seed)
    poses = soadyn.forward_kinematics(m, q)[0]
    loops = []
    for k in range(nloops):
        a, b = rng.choice(np.arange(-1, m.nbodies), size=2, replace=False)
        if a < 0:
            a, b = b, a
        kind = KINDS[(seed + k) % len(KINDS)]
        loop = draw_loop(rng, kind, f"loop{k}", int(a), int(b), poses, tree == "planar")
        loops.append(loop)
        m.add_loop(loop.name, m.body_names[loop.a], None if loop.b < 0 else m.body_names[loop.b], kind,
                   placement_a=(loop.Ra, loop.pa), placement_b=(loop.Rb, loop.pb), length=loop.length)
    sites = [(f"{l.name}:A", l.a, l.Ra, l.pa) for l in loops] + [(f"{l.name}:B", l.b, l.Rb, l.pb) for l in loops]
    model = mujoco.MjModel.from_xml_string(mjcf(specs, sites, GRAVITY))
    return m, model, specs, loops, q, rng


TREES = ("floating", "fixed", "planar", "shallow")
CASES = [(tree, seed, nloops) for tree in TREES for seed in range(12) for nloops in (1, 2, 3, 4)]
IDS = [f"{t}-seed{s}-{n}loops" for t, s, n in CASES]


@pytest.mark.parametrize("tree,seed,nloops", CASES, ids=IDS)
@pytest.mark.parametrize("prescribed_fraction", [0.0, 0.3], ids=["regular", "mixed"])
def test_constrained_dynamics_matches_mujoco(tree, seed, nloops, prescribed_fraction):
    m, model, specs, loops, q, rng = build_case(tree, seed, nloops)
    v0 = rng.normal(size=m.nv)
    eq = mujoco_equations(m, model, specs, loops, q, np.zeros(m.nv))
    assert np.abs(eq.residual).max() < 1e-12, "the loops are closed in MuJoCo's kinematics too"
    # A velocity on the loops' tangent space, from MuJoCo's C.
    v = v0 - np.linalg.pinv(eq.C, rcond=1e-11) @ (eq.C @ v0)
    eq = mujoco_equations(m, model, specs, loops, q, v)
    check("mass matrix (tree)", soadyn.mass_matrix(m, q), eq.M)
    check("bias forces (tree)", soadyn.bias_forces(m, q, v), eq.h)
    check("loop_jacobian", soadyn.loop_jacobian(m, q), eq.C)

    prescribed = rng.uniform(size=m.nv) < prescribed_fraction
    m.set_prescribed(prescribed)
    # Prescribed accelerations taken from an acceleration the loops allow: the equations stay consistent.
    C_pinv = np.linalg.pinv(eq.C, rcond=1e-11)
    admissible = C_pinv @ eq.kappa + (np.eye(m.nv) - C_pinv @ eq.C) @ rng.normal(size=m.nv)
    u = np.where(prescribed, admissible, rng.normal(size=m.nv))
    qdd_ref, tau_ref, lam, redundant_actuation = reference_solution(eq, prescribed, u)
    assert np.abs(eq.C @ qdd_ref - eq.kappa).max() < 1e-9 * max(1.0, np.abs(eq.kappa).max())
    rows = np.cumsum([0] + [W.shape[1] for W in eq.W])
    wrench_ref = np.array([W @ lam[row:row + W.shape[1]] for W, row in zip(eq.W, rows)])

    qdd, tau, wrenches = soadyn.constrained_dynamics(m, q, v, u)
    full_rank = np.linalg.matrix_rank(eq.C, tol=1e-9) == eq.C.shape[0]
    label = ("full rank" if full_rank else "redundant") + (", redundant actuation" if redundant_actuation else "")
    check(f"qdd ({label})", qdd, qdd_ref)
    check(f"tau ({label})", tau, tau_ref)
    # Each wrench lies in the span of its loop's directions W (orthonormal columns): lambda = W' wrench.
    lam_soadyn = np.concatenate([W.T @ w for W, w in zip(eq.W, wrenches)])
    check(f"wrench in the span of W ({label})", wrenches,
          np.array([W @ lam_soadyn[row:row + W.shape[1]] for W, row in zip(eq.W, rows)]))
    if redundant_actuation and not full_rank:
        # The multipliers' part in null(C') is not determined by the motion and the actuator forces
        # (soadyn reports one consistent choice): only the generalized loop force C' lambda is.
        check(f"generalized loop force C' lambda ({label})", eq.C.T @ lam_soadyn, eq.C.T @ lam)
    else:
        check(f"loop wrenches ({label})", wrenches, wrench_ref)


def test_cases_cover_every_kind_redundancy_and_mode():
    """The case list is what the module claims: every kind in every tree family, planar cuts
    redundant, spatial ones of full rank in some cases, prescribed DOFs in loops; both of
    constrained_dynamics' solvers (Model.loop_solver) run every kind: the shallow trees through the
    mass matrix, the floating ones by the articulated-body response (the others as their sparsity
    and loop count decide)."""
    seen, ranks, solved = set(), {"redundant": 0, "full rank": 0}, set()
    for tree, seed, nloops in CASES:
        m, model, specs, loops, q, _ = build_case(tree, seed, nloops)
        seen |= {(tree, l.kind) for l in loops}
        solved |= {(m.loop_solver, l.kind) for l in loops}
        if tree in ("shallow", "floating"):
            assert m.loop_solver == ("mass matrix" if tree == "shallow" else "articulated"), (tree, seed)
        C = mujoco_equations(m, model, specs, loops, q, np.zeros(m.nv)).C
        ranks["redundant" if np.linalg.matrix_rank(C, tol=1e-9) < C.shape[0] else "full rank"] += 1
    assert seen == {(t, k) for t in TREES for k in KINDS}
    assert solved == {(solver, k) for solver in ("articulated", "mass matrix") for k in KINDS}
    print(f"\ncases: {ranks}")
    assert ranks["redundant"] >= 10 and ranks["full rank"] >= 10, ranks
