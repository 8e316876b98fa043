"""Hostile cases for the analysis layer, each drawn from one integer seed.

A case builds a small model (a random tree of fuzz.api_cases, a pendulum
chain, a flexible cantilever on a hinge or the four-bar), now and then with
joint springs of hostile constants and with some or every DOF prescribed, and
makes one call with hostile arguments: modes, natural_frequencies,
stiffness_matrix, linearize (hostile dt and integrator names),
dynamics_derivatives, inverse_dynamics_derivatives, parameter_sensitivity,
static_equilibrium (few iterations), objective_gradient (at the equilibrium
of a pendulum chain), force_element_potential, dissipated_power,
FlexibleBody.node_pose and augmented_mass_matrix (hostile modal coordinates
and node indices), or Model.add_body with an inertia no body has (a negative
principal moment, principal moments that break the triangle inequality), now
and then with its centre of mass 1e9 m or more from the body frame, where
m |c|^2 in the inertia about the frame dwarfs the defect: those must be
refused.

The property (support.forked.judged): finite results or a documented error
with a message naming what is at fault; never a crash, a hang, a silent NaN
or a complex or string array read as numbers.
"""
from __future__ import annotations

import numpy as np

import soadyn
from fuzz.api_cases import EXPECTED_ERRORS, hostile_float, hostile_vector, random_model
from fuzz.loop_cases import hostile_configuration, hostile_count, hostile_hold, hostile_wrenches, huge
from support.forked import judged

CALLS = ("modes", "natural_frequencies", "stiffness_matrix", "linearize", "dynamics_derivatives",
         "inverse_dynamics_derivatives", "parameter_sensitivity", "static_equilibrium", "objective_gradient",
         "force_element_potential", "dissipated_power", "node_pose", "augmented_mass_matrix", "add_body")
INTEGRATORS = ("rk4", "euler", "dopri5", "leapfrog", "", 3, None)
# A node index out of range is an IndexError, Python's convention for a sequence.
NODE_ERRORS = EXPECTED_ERRORS + (IndexError,)


def maybe_hostile(rng: np.random.Generator, ordinary: float, probability: float = 0.2) -> float:
    return hostile_float(rng) if rng.uniform() < probability else ordinary


def beam(rng: np.random.Generator) -> soadyn.FlexibleBody:
    """A small cantilever (2 to 8 nodes, 1 or 2 modes per plane), its constants now and then hostile."""
    return soadyn.FlexibleBody.cantilever_beam(
        maybe_hostile(rng, float(rng.uniform(0.5, 2.0)), 0.1), maybe_hostile(rng, float(rng.uniform(1.0, 50.0)), 0.1),
        maybe_hostile(rng, float(rng.uniform(0.5, 2.0)), 0.1), int(rng.integers(1, 3)), int(rng.integers(2, 9)))


def with_springs(rng: np.random.Generator, m: soadyn.Model) -> soadyn.Model:
    """Zero to three joint springs on random DOFs, their constants now and then hostile. Refusals (a DOF no
    spring fits, a negative or non-finite constant) must be documented errors and leave the model as it was."""
    for k in range(int(rng.integers(0, 4))):
        if not m.nv:
            break
        try:
            m.add_joint_spring(f"spring{k}", int(rng.integers(m.nv)), maybe_hostile(rng, float(rng.uniform(0, 50))),
                               maybe_hostile(rng, float(rng.uniform(0, 2))), maybe_hostile(rng, float(rng.normal())))
        except EXPECTED_ERRORS:
            pass
    return m


def random_analysis_model(rng: np.random.Generator) -> soadyn.Model:
    r = rng.uniform()
    if r < 0.4:
        m = random_model(rng)
    elif r < 0.65:
        m = soadyn.scenes.pendulum_chain(int(rng.integers(1, 4)))
    elif r < 0.85:
        m = soadyn.Model()
        m.add_flexible_body("beam", None, beam(rng), soadyn.Joint.revolute(rng.normal(size=3)))
        if rng.uniform() < 0.5:
            m.add_body("tip", "beam:tip", soadyn.Joint.revolute((0.0, 0.0, 1.0)), mass=float(rng.uniform(0.1, 2)),
                       com=(0.1, 0.0, 0.0), inertia=(0.01, 0.02, 0.02))
    else:
        m = soadyn.scenes.four_bar()
    with_springs(rng, m)
    if m.nv and rng.uniform() < 0.4:  # modal DOFs stay regular: prescribe the others only
        mask = (rng.uniform(size=m.nv) < 0.5) if rng.uniform() < 0.6 else np.ones(m.nv, dtype=bool)
        m.set_prescribed(mask & ~np.asarray(m.modal, dtype=bool))
    return m


def hostile_state(rng: np.random.Generator, m: soadyn.Model):
    q = hostile_configuration(rng, m, soadyn.random_configuration(m, int(rng.integers(1 << 30))))
    return q, huge(rng, hostile_vector(rng, m.nv), 0.1), huge(rng, hostile_vector(rng, m.nv), 0.1)


def modes_result(m: soadyn.Model, q) -> tuple:
    """The numbers of soadyn.modes; a damping ratio is NaN by definition for a rigid-body mode (w = 0)."""
    result = soadyn.modes(m, q)
    moving = result.angular_frequencies != 0
    return (result.angular_frequencies, result.frequencies_hz, result.damping_ratios[moving],
            result.eigenvalues.real, result.eigenvalues.imag, result.shapes)


def equilibrium_result(e: soadyn.StaticEquilibrium) -> tuple:
    return (e.q, e.loop_wrenches, e.joint_wrenches, e.multipliers, e.stiffness_eigenvalues, e.residual_norm,
            np.array(list(e.holding_forces.values()), dtype=float))


def hostile_parameters(rng: np.random.Generator, m: soadyn.Model) -> list:
    names = list(m.parameter_names)
    chosen = [names[k] for k in np.flatnonzero(rng.uniform(size=len(names)) < 0.2)]
    if rng.uniform() < 0.1:
        chosen.append(["no_such_body.mass", "gravity.x", 3, None][rng.integers(4)])
    return chosen


def flattened(sensitivities: dict) -> tuple:
    return tuple(np.asarray(d, dtype=float) for value in sensitivities.values()
                 for d in (value if isinstance(value, tuple) else (value,)))


def objective_gradient(rng: np.random.Generator):
    """objective_gradient at the static equilibrium of a pendulum chain (springs now and then)."""
    m = with_springs(rng, soadyn.scenes.pendulum_chain(int(rng.integers(1, 3))))
    q0 = rng.normal(scale=0.2, size=m.nq)
    e = soadyn.static_equilibrium(m, q0, hostile_hold(rng, m), max_iterations=int(rng.integers(1, 30)))
    dphi_dq = huge(rng, hostile_vector(rng, m.nv), 0.1)
    return flattened(soadyn.objective_gradient(m, e, hostile_parameters(rng, m), dphi_dq)), {"dphi_dq": dphi_dq}


def node_call(rng: np.random.Generator, name: str):
    body = beam(rng)
    eta = hostile_vector(rng, body.n_modes)
    if isinstance(eta, np.ndarray) and eta.dtype.kind == "f" and rng.uniform() < 0.3:
        with np.errstate(over="ignore"):
            eta = eta * float(rng.choice([1e3, 1e150, 1e200]))  # deformations far beyond the beam's length
    if name == "augmented_mass_matrix":
        return body.augmented_mass_matrix(eta), {"eta": eta}
    j = int(rng.integers(body.n_nodes)) if rng.uniform() < 0.8 else \
        [-1, body.n_nodes, body.n_nodes + 1, 2 ** 40, 1.5, None][rng.integers(6)]
    return body.node_pose(j, eta), {"eta": eta}


def nonphysical_body(rng: np.random.Generator):
    """add_body with an inertia no rigid body has; returning is a failure of the property."""
    m = random_model(rng) if rng.uniform() < 0.5 else soadyn.Model()
    mass, com = float(rng.uniform(0.1, 3.0)), rng.uniform(-0.3, 0.3, 3)
    moments = rng.uniform(0.05, 0.2, 3)
    which = ["negative moment", "triangle inequality"][rng.integers(2)]
    if which == "negative moment":
        moments[rng.integers(3)] = -float(rng.uniform(1e-3, 1.0))
    else:
        k = int(rng.integers(3))
        moments[k] = moments.sum() - moments[k] + float(rng.uniform(1e-3, 1.0))
    if rng.uniform() < 0.5:  # far from the frame: m |c|^2 dwarfs the defect, which is refused all the same
        direction = rng.normal(size=3)
        com = direction / np.linalg.norm(direction) * 10.0 ** rng.uniform(9, 12)
        which += " and a far centre of mass"
    inertia = moments
    if rng.uniform() < 0.5:  # the same moments about turned axes, as a 3x3 matrix
        R = np.linalg.qr(rng.normal(size=(3, 3)))[0]
        inertia = R @ np.diag(moments) @ R.T
    m.add_body("odd", None, soadyn.Joint.revolute(rng.normal(size=3)), mass=mass, com=com, inertia=inertia)
    raise AssertionError(f"add_body accepted a body with a {which}: mass {mass:.3g} kg, |com| "
                         f"{np.linalg.norm(com):.3g} m, principal moments {np.round(moments, 4).tolist()} kg m^2")


def call(rng: np.random.Generator, name: str):
    """Call `name` with hostile arguments: (name, result, array arguments)."""
    if name == "objective_gradient":
        return (name, *objective_gradient(rng))
    if name in ("node_pose", "augmented_mass_matrix"):
        return (name, *node_call(rng, name))
    if name == "add_body":
        nonphysical_body(rng)
    m = random_analysis_model(rng)
    q, v, u = hostile_state(rng, m)
    if name == "modes":
        return name, modes_result(m, q), {"q": q}
    if name in ("natural_frequencies", "stiffness_matrix", "force_element_potential"):
        return name, getattr(soadyn, name)(m, q), {"q": q}
    if name == "dissipated_power":
        return name, soadyn.dissipated_power(m, q, v), {"q": q, "v": v}
    if name == "static_equilibrium":
        tol = 1e-10 if rng.uniform() < 0.7 else hostile_float(rng)
        return name, equilibrium_result(soadyn.static_equilibrium(m, q, hostile_hold(rng, m), tol,
                                                                  hostile_count(rng))), {"q0": q}
    if name == "parameter_sensitivity":
        return name, flattened(soadyn.parameter_sensitivity(m, q, v, u, hostile_parameters(rng, m))), \
            {"q": q, "v": v, "u": u}
    f_ext = hostile_wrenches(rng, m)
    arrays = {"q": q, "v": v, "u": u, "f_ext": f_ext}
    if name == "dynamics_derivatives":
        return name, soadyn.dynamics_derivatives(m, q, v, u, f_ext), arrays
    if name == "inverse_dynamics_derivatives":
        return name, soadyn.inverse_dynamics_derivatives(m, q, v, u, f_ext), arrays
    dt = None if rng.uniform() < 0.3 else [1e-3, hostile_float(rng), "0.001", 1e-3 + 1j][rng.integers(4)]
    integrator = "rk4" if rng.uniform() < 0.5 else INTEGRATORS[rng.integers(len(INTEGRATORS))]
    return name, soadyn.linearize(m, q, v, u, dt, integrator, f_ext), arrays | {"dt": dt}


def run_case(seed: int) -> str:
    """Runs case `seed`; returns 'ok' or the name of the documented error raised.
    Raises AssertionError or an unexpected exception when the property fails."""
    rng = np.random.default_rng(seed)
    name = CALLS[rng.integers(len(CALLS))]
    return judged(lambda: call(rng, name), NODE_ERRORS if name == "node_pose" else EXPECTED_ERRORS)
