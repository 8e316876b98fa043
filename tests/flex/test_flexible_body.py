"""Modal flexible body (soadyn/flex): the cantilever beam against Euler-Bernoulli
closed forms, the augmented mass matrix against an independent node-by-node
assembly of the lumped kinetic energy, and input validation."""
import numpy as np
import pytest

import soadyn
from soadyn import FlexibleBody
from support.beams import BETA_L, euler_bernoulli_frequencies
from support.flexible_trees import rodrigues, skew

BEAM = dict(length=2.0, EI=50.0, mass_per_length=1.5)


def distinct_clamped_frequencies(body):
    """The beam's modes come in equal pairs (x-y and x-z planes, interleaved)."""
    return body.natural_frequencies_clamped()[::2]


def assembled_mass_matrix(body, eta):
    """sum_j m_j G_j' G_j + Jr_j' J_j Jr_j, node by node: G_j maps [omega; v; eta_dot] to the
    velocity of the deformed node point p_j = r_j + Phi_t,j eta (v + omega x p_j + Phi_t,j eta_dot),
    Jr_j to the node's angular velocity omega + Phi_r,j eta_dot."""
    n = body.n_modes
    M = np.zeros((6 + n, 6 + n))
    for r, m, J, phi in zip(body.nodes, body.masses, body.rotary_inertias, body.mode_shapes):
        p = r + phi[3:] @ eta
        G = np.hstack([-skew(p), np.eye(3), phi[3:]])
        Jr = np.hstack([np.eye(3), np.zeros((3, 3)), phi[:3]])
        M += m * G.T @ G + Jr.T @ J @ Jr
    return M


def kinetic_energy_of_nodes(body, eta, omega, v, eta_dot):
    """T of Eq. (1) of modal_integrals.hpp from node velocities built with cross products."""
    T = 0.0
    for r, m, J, phi in zip(body.nodes, body.masses, body.rotary_inertias, body.mode_shapes):
        p = r + phi[3:] @ eta
        node_velocity = v + np.cross(omega, p) + phi[3:] @ eta_dot
        node_spin = omega + phi[:3] @ eta_dot
        T += 0.5 * m * node_velocity @ node_velocity + 0.5 * node_spin @ J @ node_spin
    return T


def random_point_cloud_inertia(rng, points=5):
    """Rotary inertia of a random cloud of point masses about its origin: physical by construction."""
    J = np.zeros((3, 3))
    for d, m in zip(rng.normal(scale=0.2, size=(points, 3)), rng.uniform(0.1, 1.0, points)):
        J += m * (d @ d * np.eye(3) - np.outer(d, d))
    return J


def exactly_symmetric(a):
    """The body stores the symmetric part of K and C; give it one it keeps bit for bit."""
    return np.triu(a) + np.triu(a, 1).T


def random_body_arrays(rng, n_nodes=7, n_modes=4):
    """Arbitrary lumped data (not a beam): one massless node, one node without rotary inertia."""
    positions = rng.normal(size=(n_nodes, 3))
    masses = rng.uniform(0.2, 2.0, n_nodes)
    masses[1] = 0.0
    inertias = np.array([random_point_cloud_inertia(rng) for _ in range(n_nodes)])
    inertias[2] = 0.0
    mode_shapes = rng.normal(size=(n_nodes, 6, n_modes))
    a = rng.normal(size=(n_modes, n_modes))
    b = rng.normal(size=(n_modes, n_modes))
    return dict(positions=positions, masses=masses, rotary_inertias=inertias, mode_shapes=mode_shapes,
                stiffness=exactly_symmetric(a @ a.T), damping=exactly_symmetric(0.01 * b @ b.T),
                attachments={"port": 3})


def random_body(seed):
    return FlexibleBody(**random_body_arrays(np.random.default_rng(seed)))


def beam(n_modes=4, n_nodes=60):
    return FlexibleBody.cantilever_beam(**BEAM, n_modes=n_modes, n_nodes=n_nodes)


def relative_error(a, b):
    return np.max(np.abs(a - b)) / np.max(np.abs(b))


# --- cantilever beam against Euler-Bernoulli -------------------------------------------------

def test_first_three_clamped_frequencies_match_euler_bernoulli():
    body = beam(n_modes=4, n_nodes=200)
    assert body.n_modes == 8 and body.n_nodes == 201
    # The values of the brief, to 7 digits.
    reference = euler_bernoulli_frequencies(np.array([1.875104, 4.694091, 7.854757]), **BEAM)
    frequencies = distinct_clamped_frequencies(body)[:3]
    np.testing.assert_allclose(frequencies, reference, rtol=5e-3)
    # Pairs: the x-y and x-z planes have the same frequencies.
    pairs = body.natural_frequencies_clamped().reshape(-1, 2)
    np.testing.assert_allclose(pairs[:, 0], pairs[:, 1], rtol=1e-12)


def test_clamped_frequencies_converge_at_second_order_in_the_node_spacing():
    """Lumping the mass at segment centres is a midpoint rule: error ~ h^2, so halving h quarters it."""
    reference = euler_bernoulli_frequencies(BETA_L[:3], **BEAM)
    errors = np.array([np.abs(distinct_clamped_frequencies(beam(4, n))[:3] / reference - 1.0)
                       for n in (20, 40, 80, 160)])
    ratios = errors[:-1] / errors[1:]
    assert np.all(ratios > 3.9) and np.all(ratios < 4.05), ratios
    assert np.all(errors[-1] < 1e-4), errors[-1]


def test_beam_modal_stiffness_is_the_continuous_bending_stiffness():
    """integral EI phi_i''^2 = EI beta_i^4 L for the unscaled clamped-free modes, and the modes are
    orthogonal: the quadrature reproduces both to rounding level."""
    body = beam(n_modes=4)
    expected = np.repeat(BEAM["EI"] * BETA_L ** 4 / BEAM["length"] ** 3, 2)
    K = body.stiffness
    np.testing.assert_allclose(np.diag(K), expected, rtol=1e-12)
    assert np.max(np.abs(K - np.diag(np.diag(K)))) < 1e-12 * np.max(expected)
    np.testing.assert_array_equal(body.damping, 0.0)


def test_beam_mode_shapes_are_the_analytic_clamped_free_modes():
    body = beam(n_modes=3, n_nodes=40)
    L = BEAM["length"]
    x = body.nodes[:, 0]
    assert np.allclose(body.nodes[:, 1:], 0.0) and x[-1] == L and body.attachments == {"tip": 40}
    for i, bl in enumerate(BETA_L[:3]):
        b = bl / L
        s = (np.cosh(bl) + np.cos(bl)) / (np.sinh(bl) + np.sin(bl))
        shape = np.cosh(b * x) - np.cos(b * x) - s * (np.sinh(b * x) - np.sin(b * x))
        slope = b * (np.sinh(b * x) + np.sin(b * x) - s * (np.cosh(b * x) - np.cos(b * x)))
        xy, xz = body.mode_shapes[:, :, 2 * i], body.mode_shapes[:, :, 2 * i + 1]
        # x-y plane: deflection along y, rotation about z equal to the slope.
        np.testing.assert_allclose(xy[:, 4], shape, rtol=0, atol=1e-10)
        np.testing.assert_allclose(xy[:, 2], slope, rtol=0, atol=1e-10 * b)
        # x-z plane: deflection along z, rotation about y equal to minus the slope.
        np.testing.assert_allclose(xz[:, 5], shape, rtol=0, atol=1e-10)
        np.testing.assert_allclose(xz[:, 1], -slope, rtol=0, atol=1e-10 * b)
        assert np.count_nonzero(xy[:, [0, 1, 3, 5]]) == 0 and np.count_nonzero(xz[:, [0, 2, 3, 4]]) == 0
        assert abs(abs(shape[-1]) - 2.0) < 1e-9  # |phi_i(L)| = 2


def test_beam_lumped_masses_and_rigid_inertia():
    """mu h per segment, massless tip, and about the root exactly the rod's mu L^3 / 3 (the
    segments' h^2/12 rotary terms complete the midpoint sum of x^2)."""
    n_nodes = 50
    body = beam(n_modes=2, n_nodes=n_nodes)
    L, mu = BEAM["length"], BEAM["mass_per_length"]
    h = L / n_nodes
    np.testing.assert_allclose(body.masses[:-1], mu * h, rtol=1e-15)
    assert body.masses[-1] == 0.0 and np.all(body.rotary_inertias[-1] == 0.0)
    M = body.augmented_mass_matrix(np.zeros(body.n_modes))
    rod = mu * L
    rigid = np.zeros((6, 6))
    rigid[1, 1] = rigid[2, 2] = rod * L ** 2 / 3
    rigid[3:, 3:] = rod * np.eye(3)
    rigid[:3, 3:] = rod * skew([L / 2, 0, 0])
    rigid[3:, :3] = rigid[:3, 3:].T
    np.testing.assert_allclose(M[:6, :6], rigid, rtol=0, atol=1e-13 * rod * L ** 2)


# --- augmented mass matrix against an independent assembly ----------------------------------

@pytest.mark.parametrize("make_body", [lambda: random_body(1), lambda: random_body(2), lambda: beam(3, 30)],
                         ids=["random-1", "random-2", "beam"])
def test_augmented_mass_matrix_equals_node_by_node_assembly(make_body):
    body = make_body()
    rng = np.random.default_rng(7)
    for scale in (0.0, 0.05, 0.5, 3.0):  # exact for any eta: the energy is quadratic in eta
        eta = scale * rng.normal(size=body.n_modes)
        M = body.augmented_mass_matrix(eta)
        expected = assembled_mass_matrix(body, eta)
        assert M.shape == (6 + body.n_modes, 6 + body.n_modes)
        assert relative_error(M, expected) < 1e-12, relative_error(M, expected)


def test_augmented_mass_matrix_gives_the_kinetic_energy_of_the_nodes():
    body = random_body(3)
    rng = np.random.default_rng(11)
    for _ in range(5):
        eta, eta_dot = rng.normal(size=body.n_modes), rng.normal(size=body.n_modes)
        omega, v = rng.normal(size=3), rng.normal(size=3)
        x = np.concatenate([omega, v, eta_dot])
        T = kinetic_energy_of_nodes(body, eta, omega, v, eta_dot)
        assert abs(0.5 * x @ body.augmented_mass_matrix(eta) @ x - T) < 1e-12 * T


def test_augmented_mass_matrix_is_symmetric_positive_definite():
    rng = np.random.default_rng(5)
    for seed in range(4):
        body = random_body(seed)
        for _ in range(3):
            M = body.augmented_mass_matrix(rng.normal(size=body.n_modes))
            assert np.array_equal(M, M.T)
            assert np.linalg.eigvalsh(M)[0] > 1e-6 * np.linalg.eigvalsh(M)[-1]
            np.linalg.cholesky(M)


def test_modal_mass_is_the_constant_modal_block():
    body = random_body(4)
    eta = np.random.default_rng(0).normal(size=body.n_modes)
    n = body.n_modes
    np.testing.assert_array_equal(body.augmented_mass_matrix(eta)[6:, 6:], body.modal_mass)
    assert relative_error(body.modal_mass, assembled_mass_matrix(body, eta)[6:, 6:]) < 1e-13
    assert body.modal_mass.shape == (n, n)


def test_clamped_frequencies_solve_the_generalized_eigenproblem():
    body = random_body(6)
    L = np.linalg.cholesky(body.modal_mass)
    Linv = np.linalg.inv(L)
    expected = np.sqrt(np.clip(np.linalg.eigvalsh(Linv @ body.stiffness @ Linv.T), 0, None))
    np.testing.assert_allclose(body.natural_frequencies_clamped(), expected, rtol=1e-10)


# --- strain energy and node poses -------------------------------------------------------------

def test_strain_energy():
    body = random_body(8)
    eta = np.random.default_rng(2).normal(size=body.n_modes)
    assert body.strain_energy(eta) == pytest.approx(0.5 * eta @ body.stiffness @ eta, rel=1e-14)
    # Beam: 1/2 EI integral phi_i''^2 = 1/2 EI beta_i^4 L for eta = e_i (x-y plane, mode 2).
    b = beam(n_modes=3)
    e = np.zeros(b.n_modes)
    e[2] = 0.1
    expected = 0.5 * 0.1 ** 2 * BEAM["EI"] * BETA_L[1] ** 4 / BEAM["length"] ** 3
    assert b.strain_energy(e) == pytest.approx(expected, rel=1e-12)


def test_node_pose_at_zero_is_the_undeformed_node():
    body = random_body(9)
    for j in range(body.n_nodes):
        X = body.node_pose(j, np.zeros(body.n_modes))
        np.testing.assert_array_equal(X[:3, :3], np.eye(3))
        np.testing.assert_array_equal(X[:3, 3], body.nodes[j])
        np.testing.assert_array_equal(X[3], [0, 0, 0, 1])


def test_node_pose_moves_and_rotates_with_the_modes():
    body = random_body(10)
    rng = np.random.default_rng(3)
    for j in range(body.n_nodes):
        eta = 0.3 * rng.normal(size=body.n_modes)
        X = body.node_pose(j, eta)
        phi = body.mode_shapes[j]
        np.testing.assert_allclose(X[:3, 3], body.nodes[j] + phi[3:] @ eta, rtol=0, atol=1e-14)
        np.testing.assert_allclose(X[:3, :3], rodrigues(phi[:3] @ eta), rtol=0, atol=1e-14)


def test_beam_tip_pose_follows_the_tip_deflection_and_slope():
    body = beam(n_modes=2)
    tip = body.attachments["tip"]
    eta = np.zeros(body.n_modes)
    eta[1] = 0.01  # first x-z bending mode
    X = body.node_pose(tip, eta)
    deflection = body.mode_shapes[tip, 5, 1] * 0.01
    slope = -body.mode_shapes[tip, 1, 1] * 0.01
    np.testing.assert_allclose(X[:3, 3], [BEAM["length"], 0, deflection], rtol=1e-15)
    # The tip's x axis turns along the slope of the deflected beam: (cos a, 0, sin a), tan a = dw/dx.
    np.testing.assert_allclose(X[:3, 0], [np.cos(slope), 0, np.sin(slope)], rtol=0, atol=1e-15)


# --- properties and round trip ----------------------------------------------------------------

def test_constructor_round_trips_the_arrays():
    arrays = random_body_arrays(np.random.default_rng(12))
    body = FlexibleBody(**arrays)
    np.testing.assert_array_equal(body.nodes, arrays["positions"])
    np.testing.assert_array_equal(body.masses, arrays["masses"])
    np.testing.assert_array_equal(body.rotary_inertias, arrays["rotary_inertias"])
    np.testing.assert_array_equal(body.mode_shapes, arrays["mode_shapes"])
    np.testing.assert_array_equal(body.stiffness, arrays["stiffness"])
    np.testing.assert_array_equal(body.damping, arrays["damping"])
    assert body.attachments == {"port": 3}
    assert soadyn.FlexibleBody is FlexibleBody
    without_damping = {k: v for k, v in arrays.items() if k not in ("damping", "attachments")}
    np.testing.assert_array_equal(FlexibleBody(**without_damping).damping, 0.0)


# --- bad input --------------------------------------------------------------------------------

def modified(change, seed=13):
    arrays = random_body_arrays(np.random.default_rng(seed))
    change(arrays)
    return arrays


def set_item(key, index, value):
    def change(arrays):
        arrays[key][index] = value
    return change


def asymmetric_inertia(arrays):
    arrays["rotary_inertias"][1][0, 1] += 0.5


def non_symmetric_stiffness(arrays):
    arrays["stiffness"][0, 1] += 1.0


def indefinite_stiffness(arrays):
    arrays["stiffness"] = np.diag([1.0, -2.0, 3.0, 4.0])


def indefinite_damping(arrays):
    arrays["damping"] = -np.eye(4)


def massless_mode(arrays):
    arrays["mode_shapes"][:, :, 1] = 0.0


def dependent_modes(arrays):
    arrays["mode_shapes"][:, :, 3] = arrays["mode_shapes"][:, :, 0] + arrays["mode_shapes"][:, :, 2]


def no_mass(arrays):
    arrays["masses"][:] = 0.0
    arrays["rotary_inertias"][:] = 0.0


@pytest.mark.parametrize("change, message", [
    (set_item("positions", (3, 1), np.nan), r"node 3 position entry 1 is NaN"),
    (set_item("positions", (0, 2), np.inf), r"node 0 position entry 2 is infinite"),
    (set_item("masses", 2, -1.0), r"node 2 has negative mass -1"),
    (set_item("masses", 4, np.nan), r"node 4 mass is not finite"),
    (asymmetric_inertia, r"node 1 rotary inertia is not symmetric"),
    (set_item("rotary_inertias", 4, np.diag([1.0, 1.0, 5.0])), r"node 4 rotary inertia violates the triangle"),
    (set_item("rotary_inertias", 5, np.diag([1.0, -0.5, 1.0])), r"node 5 rotary inertia has a negative principal"),
    (set_item("mode_shapes", (6, 4, 2), np.nan), r"node 6 mode shape of mode 2 is not finite in row 4"),
    (non_symmetric_stiffness, r"stiffness matrix K is not symmetric"),
    (indefinite_stiffness, r"stiffness matrix K is not positive semidefinite"),
    (set_item("damping", (1, 1), np.nan), r"damping matrix C entry \(1, 1\) is NaN"),
    (indefinite_damping, r"damping matrix C is not positive semidefinite"),
    (massless_mode, r"mode 1 has no modal mass"),
    (dependent_modes, r"modal mass matrix is singular"),
    (no_mass, r"no node has mass"),
    (set_item("attachments", "tip", 9), r"attachment 'tip' refers to node 9, but the body has 7 nodes"),
    (set_item("attachments", "root", -1), r"attachment 'root' refers to node -1"),
])
def test_invalid_body_data_is_refused_naming_the_item(change, message):
    with pytest.raises(ValueError, match=message):
        FlexibleBody(**modified(change))


@pytest.mark.parametrize("key, value, message", [
    ("positions", np.zeros((7, 2)), r"positions has shape \(7, 2\), expected \(N, 3\)"),
    ("masses", np.ones(6), r"masses has shape \(6,\), expected \(7,\)"),
    ("rotary_inertias", np.zeros((7, 3)), r"rotary_inertias has shape \(7, 3\), expected \(7, 3, 3\)"),
    ("mode_shapes", np.zeros((7, 3, 4)), r"mode_shapes has shape \(7, 3, 4\), expected \(7, 6, n_modes\)"),
    ("stiffness", np.eye(3), r"stiffness has shape \(3, 3\), expected \(4, 4\)"),
    ("damping", np.eye(5), r"damping has shape \(5, 5\), expected \(4, 4\)"),
])
def test_wrong_array_shapes_are_refused_naming_the_argument(key, value, message):
    with pytest.raises(ValueError, match=message):
        FlexibleBody(**modified(lambda arrays: arrays.__setitem__(key, value)))


def test_non_numeric_arrays_are_refused():
    with pytest.raises(TypeError, match="masses must be an array of real numbers"):
        FlexibleBody(**modified(lambda arrays: arrays.__setitem__("masses", ["a"] * 7)))


def test_bad_eta_and_node_index_are_refused():
    body = random_body(14)
    with pytest.raises(ValueError, match=r"eta has shape \(3,\), expected \(4,\)"):
        body.augmented_mass_matrix(np.zeros(3))
    with pytest.raises(ValueError, match=r"eta\[2\] \('mode 2'\) is NaN"):
        body.strain_energy(np.array([0.0, 0.0, np.nan, 0.0]))
    with pytest.raises(IndexError, match="node 7 is out of range: the body has 7 nodes"):
        body.node_pose(7, np.zeros(4))
    with pytest.raises(IndexError, match="node -1 is out of range"):
        body.node_pose(-1, np.zeros(4))


@pytest.mark.parametrize("kwargs, message", [
    (dict(length=0.0), "length must be positive"),
    (dict(length=-1.0), "length must be positive"),
    (dict(EI=np.nan), r"EI \(bending stiffness\) must be positive and finite"),
    (dict(mass_per_length=np.inf), "mass per length must be positive and finite"),
    (dict(n_modes=0), "n_modes must be >= 1"),
    (dict(n_nodes=0), "n_nodes must be >= 1"),
])
def test_invalid_beam_parameters_are_refused(kwargs, message):
    arguments = dict(BEAM, n_modes=2, n_nodes=10)
    arguments.update(kwargs)
    with pytest.raises(ValueError, match=message):
        FlexibleBody.cantilever_beam(**arguments)


def test_long_double_arrays_are_rounded_to_double():
    reference = FlexibleBody(**modified(lambda arrays: None))
    body = FlexibleBody(**modified(lambda arrays: arrays.update(
        {key: np.asarray(value, dtype=np.longdouble) for key, value in arrays.items() if key != "attachments"})))
    for name in ("nodes", "masses", "rotary_inertias", "mode_shapes", "stiffness", "damping", "modal_mass"):
        np.testing.assert_array_equal(getattr(body, name), getattr(reference, name))
