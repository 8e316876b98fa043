"""Every URDF of example-robot-data, fixed and floating, against Pinocchio.

Each file that loads under the default inertia="strict" is compared with
Pinocchio's own model of it (pin.buildModelFromUrdf, with
pin.JointModelFreeFlyer() for a floating base; DOFs matched by name): mass
matrix, inverse dynamics (RNEA) and forward dynamics (ABA) within 1e-9
relative, and every DOF's effort limit is its joint's <limit effort> as
xml.etree reads the file (none where 0 or absent). A DOF whose whole
subtree is massless has no inertia to accelerate: it is prescribed, and the
other DOFs' accelerations are compared with the partitioned solve of
Pinocchio's M and RNEA (Jain & Rodriguez's hybrid problem). The refused
files are listed with their reason; they load with inertia="accept"
(compared with Pinocchio, which keeps a file's values too) and with
inertia="repair" (warnings naming the links).
"""
import warnings
from xml.etree import ElementTree

import numpy as np
import pytest

import soadyn
from soadyn.check import relative_difference
from soadyn.oracles import PinocchioOracle
from soadyn.urdf import UrdfRepairWarning
from soadyn.urdf_reader import read_urdf
from support.robots import robot, robots_dir

TOLERANCE = 1e-9
FILES = sorted(str(p.relative_to(robots_dir())) for p in robots_dir().glob("**/*.urdf"))

# file: (reason under inertia="strict", loads with "accept" and "repair")
REFUSED = {
    "human_description/robots/human.urdf": ("a moving link has no <inertial>", True),
    "romeo_description/urdf/romeo_small.urdf": ("triangle inequality", True),
    "romeo_description/urdf/romeo_laas_small.urdf": ("triangle inequality|not positive semidefinite", True),
    "ur_description/urdf/ur3.urdf": ("the robot has no <link>", False),  # an empty <robot/>
}


def file_effort_limits(path) -> dict:
    """{joint name: <limit effort>} of the file's revolute, continuous and prismatic joints, read here with
    xml.etree; inf where <limit>, its effort or its value is missing or 0 (URDF: no limit known)."""
    efforts = {}
    for joint in ElementTree.parse(path).getroot().findall("joint"):
        if joint.get("type") in ("revolute", "continuous", "prismatic"):
            effort = float(joint.find("limit").get("effort", 0)) if joint.find("limit") is not None else 0.0
            efforts[joint.get("name")] = effort if effort > 0 else np.inf
    return efforts


def assert_effort_limits_from_file(model, path) -> None:
    efforts = file_effort_limits(path)
    assert set(efforts) <= set(model.dof_names)
    assert dict(zip(model.dof_names, model.effort_limits)) == {dof: efforts.get(dof, np.inf) for dof in model.dof_names}


def massless_subtree_dofs(model) -> np.ndarray:
    """Mask of the DOFs whose body and descendants have no mass at all."""
    subtree_mass = np.array(model.masses, dtype=float)
    for body in range(model.nbodies - 1, 0, -1):
        if model.parents[body] >= 0:
            subtree_mass[model.parents[body]] += subtree_mass[body]
    ends = list(model.v_index[1:]) + [model.nv]
    mask = np.zeros(model.nv, dtype=bool)
    for body in range(model.nbodies):
        mask[model.v_index[body]:ends[body]] = subtree_mass[body] == 0
    return mask


class WorldWeldOracle:
    """Pinocchio for a floating robot whose URDF root is a 'world' link welded to the base at X.

    soadyn's free joint replaces the weld (base pose X T(q), velocity the
    base's body twist); Pinocchio's free flyer moves the 'world' link (pose
    T(q_pin) = X T(q) X^-1, velocity that link's body twist A v, with
    A = [[R, 0], [p^ R, R]] for X = (R, p)). A is constant, so accelerations
    map like velocities and generalized forces by A'.
    """

    def __init__(self, model, path, weld):
        self.pin, self.R, self.p = PinocchioOracle(model, path, True), weld.rotation, weld.translation
        self.A = np.eye(model.nv)
        self.A[:3, :3] = self.A[3:6, 3:6] = self.R
        self.A[3:6, :3] = np.cross(np.eye(3), self.p).T @ self.R  # rows: p x (R w)
        self.A_inv = np.linalg.inv(self.A)

    def q(self, q):
        import pinocchio as pin
        R_q = pin.Quaternion(*q[6:7], *q[3:6]).toRotationMatrix()  # (w, x, y, z)
        out = q.copy()
        out[:3] = self.R @ q[:3] + self.p - self.R @ R_q @ self.R.T @ self.p
        quat = pin.Quaternion(self.R @ R_q @ self.R.T)
        out[3:7] = [quat.x, quat.y, quat.z, quat.w]
        return out

    def mass_matrix(self, q):
        return self.A.T @ self.pin.mass_matrix(self.q(q)) @ self.A

    def inverse_dynamics(self, q, v, qdd):
        return self.A.T @ self.pin.inverse_dynamics(self.q(q), self.A @ v, self.A @ qdd)

    def forward_dynamics(self, q, v, tau):
        return self.A_inv @ self.pin.forward_dynamics(self.q(q), self.A @ v, self.A_inv.T @ tau)


def pinocchio(model, path, floating):
    robot = read_urdf(path)
    roots = set(robot.links) - {j.child for j in robot.joints}
    if floating and roots == {"world"}:
        (weld,) = [j for j in robot.joints if j.parent == "world"]
        return WorldWeldOracle(model, path, weld)
    return PinocchioOracle(model, path, floating)


def backward_error(M, h, tau, qdd) -> float:
    """Componentwise (Oettli-Prager) backward error of qdd as a solution of M qdd + h = tau:
    the smallest relative change of M, h and tau, entry by entry, that makes qdd exact."""
    return float(np.max(np.abs(M @ qdd + h - tau) / (np.abs(M) @ np.abs(qdd) + np.abs(h) + np.abs(tau))))


def compare_with_pinocchio(model, path, floating, states=2, seed=11) -> float:
    """The largest relative difference of M, RNEA and (hybrid) forward dynamics.

    Accelerations are compared with Pinocchio's where the mass matrix allows
    it (condition number up to 1e9; of the 256 states, the worst difference
    seen is 1.4e-10); at the one nearly singular state (floating icub at its
    first random configuration: cond 1.3e13, where Pinocchio's ABA and a
    dense LU solve of its own M differ by 2.4e-8, and soadyn differs from
    both by 1.6e-6) they are compared through the componentwise backward
    error in Pinocchio's equations of motion instead, with the same 1e-9
    (soadyn's is 5e-14 there).
    """
    oracle = pinocchio(model, path, floating)
    if model.nv == 0:  # every link welded to the ground
        assert oracle.model.nv == 0
        return 0.0
    massless = massless_subtree_dofs(model)
    model.set_prescribed(massless)
    r, p = ~massless, massless
    rng = np.random.default_rng(seed)
    worst = 0.0
    for k in range(states):
        q = soadyn.random_configuration(model, seed + k)
        v, tau, qdd = rng.normal(size=(3, model.nv))
        M = oracle.mass_matrix(q)
        worst = max(worst, relative_difference(soadyn.mass_matrix(model, q), M))
        worst = max(worst, relative_difference(soadyn.inverse_dynamics(model, q, v, qdd),
                                               oracle.inverse_dynamics(q, v, qdd)))
        if not r.any():
            continue
        h = oracle.inverse_dynamics(q, v, np.zeros(model.nv))
        ours, _ = soadyn.hybrid_dynamics(model, q, v, np.where(massless, qdd, tau))
        M_rr, rhs = M[np.ix_(r, r)], tau[r] - h[r] - M[np.ix_(r, p)] @ qdd[p]
        if np.linalg.cond(M_rr) <= 1e9:  # partitioned solve: M_rr qdd_r = tau_r - h_r - M_rp qdd_p
            expected = oracle.forward_dynamics(q, v, tau) if not p.any() else np.linalg.solve(M_rr, rhs)
            worst = max(worst, relative_difference(ours[r], expected[r] if not p.any() else expected))
        else:
            worst = max(worst, backward_error(M_rr, np.zeros(r.sum()), rhs, ours[r]))
    return worst


@pytest.mark.parametrize("floating", [False, True], ids=["fixed", "floating"])
@pytest.mark.parametrize("relative", FILES)
def test_example_robot_data_against_pinocchio(relative, floating):
    path = robots_dir() / relative
    if relative in REFUSED:
        reason, loadable = REFUSED[relative]
        with pytest.raises(soadyn.UrdfError, match=reason) as error:
            soadyn.load_urdf(path, floating_base=floating)
        assert str(path) in str(error.value)
        if not loadable:
            return
        with pytest.warns(UrdfRepairWarning, match="link '"):
            soadyn.load_urdf(path, floating_base=floating, inertia="repair")
        model = soadyn.load_urdf(path, floating_base=floating, inertia="accept")
    else:
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            model = soadyn.load_urdf(path, floating_base=floating)
    assert_effort_limits_from_file(model, path)
    assert compare_with_pinocchio(model, path, floating) <= TOLERANCE


@pytest.mark.parametrize("name, some", [("ur5", {"shoulder_pan_joint": 150.0, "wrist_3_joint": 28.0}),
                                        ("panda", {"panda_joint1": 87.0, "panda_joint7": 12.0,
                                                   "panda_finger_joint2": 100.0})])
def test_arm_effort_limits_are_the_files(name, some):
    """Every moving joint of these arms has a <limit effort>: every DOF has a finite effort limit, the file's
    (the makers' ratings, in N m and N)."""
    path, floating = robot(name)
    model = soadyn.load_urdf(path, floating_base=floating)
    assert_effort_limits_from_file(model, path)
    limits = dict(zip(model.dof_names, model.effort_limits))
    assert np.all(np.isfinite(model.effort_limits)) and {dof: limits[dof] for dof in some} == some


def test_backward_error_sees_a_wrong_model():
    """The backward-error comparison is not vacuous: a 1 % heavier link is far above the tolerance."""
    path = robots_dir() / "icub_description/robots/icub.urdf"
    model = soadyn.load_urdf(path, floating_base=True)
    oracle = PinocchioOracle(model, path, True)
    q = soadyn.random_configuration(model, 11)
    v, tau = np.random.default_rng(0).normal(size=(2, model.nv))
    h = oracle.inverse_dynamics(q, v, np.zeros(model.nv))
    qdd = soadyn.forward_dynamics(model, q, v, tau)
    assert np.linalg.cond(oracle.mass_matrix(q)) > 1e12  # the nearly singular state
    assert backward_error(oracle.mass_matrix(q), h, tau, qdd) < TOLERANCE
    oracle.model.inertias[5].mass *= 1.01  # the left knee's link
    oracle.data = oracle.model.createData()
    assert backward_error(oracle.mass_matrix(q), oracle.inverse_dynamics(q, v, 0 * v), tau, qdd) > 1e-4


def test_example_robot_data_count():
    """The URDF guide's count (docs/guides/urdf.md): 69 files, each fixed and floating; 130 loads, 8 refusals (4 files)."""
    loaded, refused = 0, []
    for relative in FILES:
        for floating in (False, True):
            try:
                soadyn.load_urdf(robots_dir() / relative, floating_base=floating)
                loaded += 1
            except soadyn.UrdfError:
                refused.append(relative)
    assert len(FILES) == 69
    assert (loaded, len(refused)) == (130, 8)
    assert sorted(set(refused)) == sorted(REFUSED)
