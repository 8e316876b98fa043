"""Design sensitivities of a static equilibrium ("Joint Coordinate Method, Part 1", Sects. 6-7).

At an equilibrium (q*, nu*) the residual R(q, nu; p) = [G_f(q; p) - C_f(q)' nu; Psi(q)] vanishes
(statics.py: G the static force, inverse dynamics at rest; f the free DOFs; C the loop Jacobian,
Psi the closure). Differentiating R(q*(p), nu*(p); p) = 0 gives the direct method
    J [dq_f/dp; dnu/dp] = -[dG_f/dp; 0],   J = [[K_ff, -C_f'], [C_f, 0]],
K = dG/dq - d(C' nu)/dq (inverse_dynamics_derivatives and loop_force_stiffness, analytic), dG/dp
by forward-mode automatic differentiation of inverse dynamics at rest (parameter_sensitivity on
the spanning tree with every DOF prescribed). J is singular when the loop equations are redundant
(a planar four-bar's 3-D cut joint); the minimum-norm solution is taken (nu itself is the
minimum-norm one), so dq/dp is exact and dnu/dp is the derivative of the minimum-norm multipliers
within the equations' range. The adjoint method gives the gradient of a scalar objective
phi(q, nu) with one solve, J' lambda = [dphi/dq_f; dphi/dnu], dphi/dp = -lambda' [dG_f/dp; 0]:
one solve whatever the number of parameters. Holding forces H = G_h - C_h' nu of held DOFs h:
dH/dp = dG_h/dp + K_hf dq_f/dp - C_h' dnu/dp.

Parameters whose change moves the loops' closure (a body's placement on a loop model) are refused:
the closure's own dependence on them is not differentiated here.

Computed in C++ (soadyn/analysis/equilibrium_sensitivity.hpp: EquilibriumSensitivity::direct and
::objective_gradient); this module names the results.
"""
from __future__ import annotations

import numpy as np

from .. import _soadyn
from .parameters import parameter_name_list

__all__ = ["equilibrium_sensitivities", "objective_gradient"]


def _free(model, equilibrium) -> list:
    free = np.ones(model.nv, dtype=bool)
    free[list(equilibrium.held)] = False
    return [bool(f) for f in free]




def equilibrium_sensitivities(model, equilibrium, params) -> dict:
    """{name: {"q": dq*/dp (nv tangent, *dirs; zero on held DOFs), "multipliers": dnu/dp,
    "holding_forces": {held DOF name: dH/dp}}} by the direct method (module docstring).

    equilibrium: a StaticEquilibrium of static_equilibrium on this model; params: a parameter name or names
    (Model.parameter_names; *dirs are the parameter's direction axes, as in parameter_sensitivity).
    ParameterError names an unknown parameter; ValueError one whose change moves a loop's closure (a body's
    placement on a loop model).
    """
    raw = _soadyn._equilibrium_sensitivities(model, equilibrium.q, equilibrium.multipliers,
                                             _free(model, equilibrium), parameter_name_list(params))
    held = [model.dof_names[k] for k in equilibrium.held]
    return {name: {"q": dq, "multipliers": dnu, "holding_forces": dict(zip(held, dheld))}
            for name, (dq, dnu, dheld) in raw.items()}


def objective_gradient(model, equilibrium, params, dphi_dq, dphi_dnu=None) -> dict:
    """{name: dphi/dp (*dirs)} of a scalar objective phi(q*, nu*) at the equilibrium, by the adjoint
    method (one solve for every parameter). dphi_dq: (nv,) gradient with respect to q in the tangent
    space (held DOFs' entries are ignored: they do not move); dphi_dnu: (nloop_equations,) or None.

    equilibrium: a StaticEquilibrium of static_equilibrium on this model; params: a parameter name or names
    (Model.parameter_names; *dirs are the parameter's direction axes, as in parameter_sensitivity).
    ParameterError names an unknown parameter; ValueError one whose change moves a loop's closure (a body's
    placement on a loop model). A dphi_dq or dphi_dnu of another shape raises ValueError
    naming it.
    """
    return _soadyn._objective_gradient(model, equilibrium.q, equilibrium.multipliers, _free(model, equilibrium),
                                       parameter_name_list(params), dphi_dq, dphi_dnu)
