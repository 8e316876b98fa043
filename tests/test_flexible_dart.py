"""The cantilever's first bending frequency against DART (dartpy), which models the
same beam as a chain of 40 rigid links joined by revolute joints with torsional
springs of equivalent stiffness."""
import dartpy
import numpy as np

import soadyn
from soadyn import scenes
from test_flexible_body import BETA_L, euler_bernoulli_frequencies

LENGTH, EI, MU, LINKS = 2.0, 50.0, 1.5, 40


def chain_urdf(links, length, mass_per_length):
    """Rigid links of length l = L / links along x, hinged about z at their inboard ends.
    Each link is a slender rod (mass mu l, centre at l/2, mu l^3 / 12 about the lateral axes)."""
    l = length / links
    m = mass_per_length * l
    lateral = m * l * l / 12
    parts = ['<robot name="beam">', '<link name="world"/>']
    for i in range(1, links + 1):
        parts.append(f'<link name="link_{i}"><inertial><origin xyz="{l / 2} 0 0"/><mass value="{m}"/>'
                     f'<inertia ixx="1e-9" iyy="{lateral}" izz="{lateral}" ixy="0" ixz="0" iyz="0"/>'
                     '</inertial></link>')
        parent = "world" if i == 1 else f"link_{i - 1}"
        parts.append(f'<joint name="hinge_{i}" type="continuous"><parent link="{parent}"/>'
                     f'<child link="link_{i}"/><origin xyz="{0.0 if i == 1 else l} 0 0"/><axis xyz="0 0 1"/></joint>')
    parts.append("</robot>")
    return "\n".join(parts)


def dart_chain(links=LINKS):
    """The DART skeleton with its torsional springs. A hinge between two links stands for
    the bending stiffness of one link length, k = EI / l (rotation jump = moment * l / EI);
    the hinge at the clamp stands for half a link, k = 2 EI / l. With these the chain's
    frequencies converge to the beam's at second order in 1 / links."""
    loader = dartpy.utils.DartLoader()
    skeleton = loader.parseSkeletonString(chain_urdf(links, LENGTH, MU), dartpy.common.Uri("file:///beam.urdf"))
    l = LENGTH / links
    hinges = [skeleton.getJoint(j) for j in range(skeleton.getNumJoints()) if skeleton.getJoint(j).getNumDofs()]
    assert len(hinges) == links
    for k, hinge in enumerate(hinges):
        hinge.setSpringStiffness(0, (2.0 if k == 0 else 1.0) * EI / l)
        hinge.setRestPosition(0, 0.0)
    return skeleton, hinges


def dart_modes(skeleton, hinges):
    """Frequencies (rad/s) and mode shapes from DART's mass matrix and spring stiffnesses."""
    skeleton.setPositions(np.zeros(len(hinges)))
    M = skeleton.getMassMatrix()
    K = np.diag([h.getSpringStiffness(0) for h in hinges])
    lam, vectors = np.linalg.eig(np.linalg.solve(M, K))
    order = np.argsort(lam.real)
    return np.sqrt(lam.real[order]), vectors.real[:, order]


def test_first_frequency_agrees_with_a_dart_chain_of_40_links():
    model = scenes.cantilever_beam(LENGTH, EI, MU, 3)
    omega = soadyn.natural_frequencies(model, np.zeros(model.nq))
    euler_bernoulli = euler_bernoulli_frequencies(BETA_L[0], LENGTH, EI, MU)
    skeleton, hinges = dart_chain()
    dart_omega, _ = dart_modes(skeleton, hinges)
    assert abs(omega[0] / dart_omega[0] - 1) < 0.02, (omega[0], dart_omega[0])
    # Both also land where they should: soadyn's lumped beam and DART's chain near Euler-Bernoulli.
    assert abs(omega[0] / euler_bernoulli - 1) < 0.005
    assert abs(dart_omega[0] / euler_bernoulli - 1) < 0.005


def test_dart_time_simulation_vibrates_at_its_eigenfrequency():
    """DART's own integration of the chain, released from its first mode shape, oscillates
    with the period of the first eigenfrequency (so the comparison above rests on DART's
    dynamics, not only on its mass matrix)."""
    skeleton, hinges = dart_chain()
    omega, shapes = dart_modes(skeleton, hinges)
    world = dartpy.simulation.World()
    world.setGravity([0.0, 0.0, 0.0])
    world.setTimeStep(1e-4)
    world.addSkeleton(skeleton)
    shape = shapes[:, 0] / np.abs(shapes[:, 0]).max()
    skeleton.setPositions(1e-3 * shape)
    skeleton.setVelocities(np.zeros(len(hinges)))
    period = 2 * np.pi / omega[0]
    steps = int(2.2 * period / 1e-4)
    signal = np.empty(steps)
    for k in range(steps):
        world.step()
        signal[k] = skeleton.getPositions() @ shape
    t = (np.arange(steps) + 1) * 1e-4
    down = t[1:][np.diff(np.sign(signal)) < 0]  # released at +max: down at T/4, up at 3T/4, down at 5T/4
    up = t[1:][np.diff(np.sign(signal)) > 0]
    assert len(down) >= 2 and len(up) >= 1
    measured_period = down[1] - down[0]
    assert abs(measured_period / period - 1) < 0.01, (measured_period, period)
    assert abs((up[0] - down[0]) / (period / 2) - 1) < 0.01
