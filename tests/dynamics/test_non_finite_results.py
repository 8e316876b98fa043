"""Inputs that are finite but overflow the arithmetic (v = 1e200, positions
of 1e308) make every public algorithm raise DynamicsError naming the DOF,
coordinate or body at fault: never a silent NaN or infinity."""
from __future__ import annotations

import numpy as np
import pytest

import soadyn


@pytest.fixture
def model():
    m = soadyn.Model()
    m.add_body("base", None, soadyn.Joint.free(), mass=2.0, inertia=[1.0, 1.2, 0.8])
    m.add_body("slider", "base", soadyn.Joint.prismatic([1, 0, 0]), mass=1.0, com=[0.1, 0, 0], inertia=[0.1] * 3)
    m.add_body("elbow", "slider", soadyn.Joint.revolute([0, 0, 1]), placement=[0.2, 0, 0], mass=1.0,
               com=[0.3, 0, 0], inertia=[0.01, 0.02, 0.02])
    return m


def huge_velocity(m):
    q = soadyn.neutral_configuration(m)
    v = np.zeros(m.nv)
    v[m.dof_names.index("elbow")] = 1e200
    return q, v


DOF_OR_BODY = r"'(base|base:\w+|slider|elbow)'"


@pytest.mark.parametrize("call", [
    lambda m, q, v: soadyn.inverse_dynamics(m, q, v, np.zeros(m.nv)),
    lambda m, q, v: soadyn.bias_forces(m, q, v),
    lambda m, q, v: soadyn.joint_wrenches(m, q, v, np.zeros(m.nv)),
    lambda m, q, v: soadyn.kinetic_energy(m, q, v),
    lambda m, q, v: soadyn.forward_dynamics(m, q, v, np.zeros(m.nv)),
    lambda m, q, v: soadyn.hybrid_dynamics(m, q, v, np.zeros(m.nv)),
    lambda m, q, v: soadyn.hybrid_dynamics(m, q, v, np.zeros(m.nv), joint_wrenches=True),
], ids=["inverse_dynamics", "bias_forces", "joint_wrenches", "kinetic_energy", "forward_dynamics",
        "hybrid_dynamics", "hybrid_dynamics_wrenches"])
def test_overflowing_velocity_raises_naming_the_item(model, call):
    q, v = huge_velocity(model)
    with pytest.raises(soadyn.DynamicsError, match=DOF_OR_BODY + r".* not finite|not finite.*" + DOF_OR_BODY):
        call(model, q, v)


def test_hybrid_with_prescribed_dofs_names_the_dof(model):
    q, v = huge_velocity(model)
    model.set_prescribed("slider")
    with pytest.raises(soadyn.DynamicsError, match=DOF_OR_BODY):
        soadyn.hybrid_dynamics(model, q, v, np.zeros(model.nv))


def test_momentum_far_away_names_the_body(model):
    """Momentum is linear in v (v = 1e200 does not overflow it); its moment
    about the world origin does, for a body 1e300 m out moving at 1e10 m/s."""
    q = soadyn.neutral_configuration(model)
    q[model.coordinate_names.index("slider")] = 1e300
    v = np.zeros(model.nv)
    v[model.dof_names.index("base:vy")] = 1e10
    with pytest.raises(soadyn.DynamicsError, match=r"momentum is not finite: body 'slider'"):
        soadyn.momentum(model, q, v)


def test_integrate_overflow_names_the_coordinate(model):
    q = soadyn.neutral_configuration(model)
    v = np.zeros(model.nv)
    v[model.dof_names.index("slider")] = 1e308
    with pytest.raises(soadyn.DynamicsError, match=r"integrate: the coordinate of 'slider' is not finite"):
        soadyn.integrate(model, q, v, 10.0)


def test_far_positions_name_the_body(model):
    q = soadyn.neutral_configuration(model)
    q[model.coordinate_names.index("slider")] = 1e308
    with pytest.raises(soadyn.DynamicsError, match=r"center_of_mass is not finite: body 'slider'"):
        soadyn.center_of_mass(model, q)
    with pytest.raises(soadyn.DynamicsError, match=r"potential_energy is not finite: body 'slider'"):
        soadyn.potential_energy(model, q)
    with pytest.raises(soadyn.DynamicsError, match=r"mass_matrix: the result for DOF '(base:\w+|slider|elbow)'"):
        soadyn.mass_matrix(model, q)


def test_finite_results_are_unchanged(model):
    """The checks refuse only what overflows: ordinary states compute as before."""
    q = soadyn.random_configuration(model, 3)
    v = np.random.default_rng(3).uniform(-1, 1, model.nv)
    tau = soadyn.inverse_dynamics(model, q, v, np.ones(model.nv))
    np.testing.assert_allclose(soadyn.forward_dynamics(model, q, v, tau), np.ones(model.nv), rtol=1e-12)
    assert np.isfinite(soadyn.kinetic_energy(model, q, v))


def test_integer_mask_is_refused_as_ambiguous(model):
    mask = np.array([0, 1] * (model.nv // 2) + [0] * (model.nv % 2))
    with pytest.raises(ValueError, match="ambiguous"):
        model.set_prescribed(mask)
    assert not model.prescribed.any()
    model.set_prescribed(mask.astype(bool))
    assert list(model.prescribed) == list(mask.astype(bool))


def test_integer_indices_still_select_dofs(model):
    model.set_prescribed(np.array([6, 7]))
    assert np.flatnonzero(model.prescribed).tolist() == [6, 7]
    with pytest.raises(ValueError, match="DOF index 6 is given more than once"):
        model.set_prescribed(np.array([6, 6]))
    with pytest.raises(TypeError, match="flag must be True or False"):
        model.set_prescribed("elbow", "yes")


@pytest.mark.parametrize("flexible", [False, True], ids=["articulated-path", "mass-matrix-path"])
@pytest.mark.parametrize("prescribed", [False, True], ids=["regular", "slider-prescribed"])
def test_constrained_dynamics_overflow_names_the_item(model, flexible, prescribed):
    """A loop model with an overflowing velocity, on both paths of constrained_dynamics (a flexible beam,
    a tree of its own, moves the model off the rigid articulated-body path): a DynamicsError naming the
    DOF, body or loop at fault, never a silent NaN."""
    model.add_loop("pin", "elbow", None, "point", placement_a=(None, (0.3, 0.0, 0.0)))
    if flexible:
        model.add_flexible_body("beam", None, soadyn.FlexibleBody.cantilever_beam(1.0, 10.0, 1.0, 2),
                                soadyn.Joint.revolute((0, 1, 0)))
    if prescribed:
        model.set_prescribed("slider")
    q, v = huge_velocity(model)
    with pytest.raises(soadyn.DynamicsError, match=DOF_OR_BODY + r".* not finite|not finite.*" + DOF_OR_BODY +
                       r"|loop 'pin'"):
        soadyn.constrained_dynamics(model, q, v, np.zeros(model.nv))


def planar_chain(masses, placements):
    """Revolute joints about z, each body a point mass with equal principal moments."""
    m = soadyn.Model()
    parent = None
    for k, (mass, placement) in enumerate(zip(masses, placements)):
        name = f"link{k}"
        m.add_body(name, parent, soadyn.Joint.revolute([0, 0, 1]), placement=placement, mass=mass,
                   inertia=[mass] * 3)
        parent = name
    return m


def test_mass_matrix_overflow_of_a_rigid_chain_names_the_dof():
    """Each body's inertia is finite, but a 1e300 kg body 1e5 m from the first axis overflows M:
    the composite-rigid-body path (tree frames, no reach checks for a revolute chain) names a DOF."""
    m = planar_chain([1.0, 1e300], [[0, 0, 0], [1e5, 0, 0]])
    with pytest.raises(soadyn.DynamicsError, match=r"mass_matrix: the result for DOF 'link0' is not finite"):
        soadyn.mass_matrix(m, soadyn.neutral_configuration(m))


def test_mass_matrix_near_overflow_is_returned():
    """Entries near the largest double whose sum overflows: every entry is finite, so M is returned
    (the sum is only a probe), and equals the closed form of three coaxial point masses."""
    big = 2e307
    m = planar_chain([1.0, big, big], [[0, 0, 0], [1, 0, 0], [0, 0, 0]])
    M = soadyn.mass_matrix(m, soadyn.neutral_configuration(m))
    # link0: inertia 1, its centre on axis 0; link1 and link2: inertia `big` each, both centres on
    # axis 1, 1 m from axis 0. The probe sums 11 big > the largest double.
    expected = np.array([[1 + 4 * big, 2 * big, big],
                         [2 * big, 2 * big, big],
                         [big, big, big]])
    assert np.isinf(11 * big)
    np.testing.assert_allclose(M, expected, rtol=1e-15)
