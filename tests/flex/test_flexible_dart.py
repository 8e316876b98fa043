"""The cantilever's first bending frequency against DART (dartpy), which models the
same beam as a chain of 40 rigid links joined by revolute joints with torsional
springs of equivalent stiffness: DART's eigenfrequency from its mass matrix and
spring stiffnesses, and the period of DART's own time integration of the chain."""
import dartpy as dart
import numpy as np

import soadyn
from soadyn import scenes
from support.beams import BETA_L, euler_bernoulli_frequencies

LENGTH, EI, MU, LINKS = 2.0, 50.0, 1.5, 40
TIME_STEP = 1e-4


def dart_chain(links=LINKS):
    """A DART skeleton of `links` rigid links of length l = L / links along x, each hinged
    about z at its inboard end (the first to the world at the clamp, x = 0).

    Each link is a slender rod: mass mu l, centre of mass at l / 2, mu l^3 / 12 about the
    lateral axes (a tiny positive value about its axis). The spring of a hinge lumps the
    bending stiffness of the beam around it: a moment M bends a length s of beam through
    M s / EI, so the hinge between two links, standing for the half links on either side
    (s = l), gets k = EI / l, and the hinge at the clamp, standing for the first half link
    only (s = l / 2), gets k = 2 EI / l. With these the first frequency converges to the
    Euler-Bernoulli one at second order, about -0.46 / links^2 (-4.6e-3, -1.1e-3, -2.9e-4
    with 10, 20, 40 links); k = EI / l at the clamp too converges at first order only
    (-9.1 %, -4.8 %, -2.4 %)."""
    l = LENGTH / links
    mass = MU * l
    lateral = mass * l * l / 12
    skeleton = dart.dynamics.Skeleton("beam")
    parent, hinges, bodies = None, [], []
    for i in range(links):
        properties = dart.dynamics.RevoluteJointProperties()
        properties.mName = f"hinge_{i}"
        properties.mAxis = [0.0, 0.0, 1.0]
        to_hinge = dart.math.Isometry3()
        to_hinge.set_translation([0.0 if i == 0 else l, 0.0, 0.0])  # the parent link's outboard end
        properties.mT_ParentBodyToJoint = to_hinge
        hinge, body = skeleton.createRevoluteJointAndBodyNodePair(
            parent, properties, dart.dynamics.BodyNodeProperties(dart.dynamics.BodyNodeAspectProperties(f"link_{i}")))
        body.setInertia(dart.dynamics.Inertia(mass, [l / 2, 0.0, 0.0], np.diag([1e-6 * lateral, lateral, lateral])))
        hinge.setSpringStiffness(0, (2.0 if i == 0 else 1.0) * EI / l)
        hinge.setRestPosition(0, 0.0)
        hinge.setDampingCoefficient(0, 0.0)
        hinges.append(hinge)
        bodies.append(body)
        parent = body
    assert skeleton.getNumDofs() == links
    return skeleton, hinges, bodies


def dart_modes(skeleton, hinges):
    """Frequencies (rad/s, ascending) and mode shapes of K q = omega^2 M q, M from DART's mass
    matrix at q = 0 and K the diagonal of the hinges' spring stiffnesses (through the symmetric
    K^-1/2 M K^-1/2, whose eigenvalues are 1 / omega^2)."""
    skeleton.setPositions(np.zeros(len(hinges)))
    M = skeleton.getMassMatrix()
    scale = 1.0 / np.sqrt([h.getSpringStiffness(0) for h in hinges])
    inverse_squares, vectors = np.linalg.eigh(scale[:, None] * M * scale[None, :])
    order = np.argsort(inverse_squares)[::-1]
    return 1.0 / np.sqrt(inverse_squares[order]), scale[:, None] * vectors[:, order]


def tip_deflection(body, l):
    """y of the chain's free end, the point l along the last link's axis."""
    X = body.getWorldTransform()
    return (X.rotation() @ [l, 0.0, 0.0] + X.translation())[1]


def relative_difference(value, reference):
    return value / reference - 1.0


def test_first_frequency_agrees_with_a_dart_chain_of_40_links():
    model = scenes.cantilever_beam(LENGTH, EI, MU, 3)
    omega = soadyn.natural_frequencies(model, np.zeros(model.nq))
    euler_bernoulli = euler_bernoulli_frequencies(BETA_L[0], LENGTH, EI, MU)
    skeleton, hinges, _ = dart_chain()
    dart_omega, _ = dart_modes(skeleton, hinges)

    soadyn_vs_dart = relative_difference(omega[0], dart_omega[0])
    assert abs(soadyn_vs_dart) < 0.02, (
        f"soadyn {omega[0]:.6f} rad/s vs DART chain {dart_omega[0]:.6f} rad/s: {soadyn_vs_dart:.3e}")
    # soadyn's lumped 60-node beam lands near Euler-Bernoulli (the bound of
    # test_flexible_body); DART's chain at its discretisation error, -2.9e-4 for 40 links
    # (docstring of dart_chain), bounded here by 1e-3.
    soadyn_vs_closed_form = relative_difference(omega[0], euler_bernoulli)
    assert abs(soadyn_vs_closed_form) < 0.005, (
        f"soadyn {omega[0]:.6f} rad/s vs Euler-Bernoulli {euler_bernoulli:.6f} rad/s: {soadyn_vs_closed_form:.3e}")
    dart_vs_closed_form = relative_difference(dart_omega[0], euler_bernoulli)
    assert abs(dart_vs_closed_form) < 1e-3, (
        f"DART chain {dart_omega[0]:.6f} rad/s vs Euler-Bernoulli {euler_bernoulli:.6f} rad/s: "
        f"{dart_vs_closed_form:.3e}")


def test_dart_time_simulation_vibrates_at_its_eigenfrequency():
    """DART's own integration of the chain, released at rest from its first mode shape with a
    1 mm tip deflection, crosses zero at the tip every half period of the first
    eigenfrequency (so the comparison above rests on DART's dynamics, not only on its mass
    matrix).

    Tolerance 1e-4 on the period, far above what separates the two for a correct chain:
    DART's semi-implicit Euler step (springs evaluated at q + h dq) shifts the frequency by
    O((omega h)^2) ~ 3e-7 and damps it by omega h / 2 ~ 2.5e-4 per radian, which moves it by
    O(1e-7); 1 mm on a 2 m beam keeps the geometric nonlinearity near 1e-8 (5e-5 at 10 cm);
    zero crossings interpolated linearly between steps are exact to O(h^3). The chain's
    fastest mode (omega h ~ 1.6) stays stable under this step."""
    skeleton, hinges, bodies = dart_chain()
    omega, shapes = dart_modes(skeleton, hinges)
    l = LENGTH / LINKS
    world = dart.simulation.World()
    world.setGravity([0.0, 0.0, 0.0])
    world.setTimeStep(TIME_STEP)
    world.addSkeleton(skeleton)
    # For small angles link i turns by q_0 + ... + q_i, so the tip deflection is l sum_i sum_{j<=i} q_j.
    shape = 1e-3 * shapes[:, 0] / (l * np.cumsum(shapes[:, 0]).sum())
    skeleton.setPositions(shape)
    skeleton.setVelocities(np.zeros(len(hinges)))
    tip = bodies[-1]
    assert abs(tip_deflection(tip, l) / 1e-3 - 1) < 1e-3

    period = 2 * np.pi / omega[0]
    steps = int(2.2 * period / TIME_STEP)
    signal = np.empty(steps + 1)
    signal[0] = tip_deflection(tip, l)
    for k in range(steps):
        world.step()
        signal[k + 1] = tip_deflection(tip, l)
    t = np.arange(steps + 1) * TIME_STEP
    i = np.nonzero(np.sign(signal[:-1]) != np.sign(signal[1:]))[0]
    crossings = t[i] - signal[i] * TIME_STEP / (signal[i + 1] - signal[i])
    assert len(crossings) == 4, crossings  # T/4, 3T/4, 5T/4, 7T/4
    half_periods = np.diff(crossings)
    measured_period = 2 * np.polyfit(np.arange(len(crossings)), crossings, 1)[0]
    simulated_vs_eigen = relative_difference(measured_period, period)
    assert abs(simulated_vs_eigen) < 1e-4, (
        f"DART simulated period {measured_period:.7f} s vs eigenfrequency period {period:.7f} s: "
        f"{simulated_vs_eigen:.3e}")
    spread = np.ptp(half_periods) / (period / 2)
    assert spread < 1e-4, f"half periods {half_periods} differ by {spread:.3e} of a half period"
    first_quarter = relative_difference(crossings[0], period / 4)
    assert abs(first_quarter) < 1e-4, f"first zero crossing at {crossings[0]:.7f} s: {first_quarter:.3e} from T/4"
