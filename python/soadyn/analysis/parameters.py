"""The design sensitivity of the dynamics with respect to named model parameters.

The parameters themselves (names, shapes, get and set) are the model's: ``Model.parameter_names``,
``Model.get_parameter``, ``Model.set_parameter`` (soadyn/model.py).
"""
from __future__ import annotations

from .. import _soadyn
from ..model import parameter_name

__all__ = ["parameter_sensitivity", "ParameterError"]

ParameterError = _soadyn.ParameterError


def parameter_sensitivity(model, q, v, u, params) -> dict:
    """Derivatives of the dynamics with respect to named parameters, by forward-mode automatic differentiation.

    Returns ``{name: (dqdd_dp, dtau_dp)}`` for a tree (the outputs of ``hybrid_dynamics`` under the
    model's prescribed flags, u as there), or ``{name: (dqdd_dp, dtau_dp, dwrench_dp)}`` for a model with
    closed loops (the outputs of ``constrained_dynamics``; dwrench_dp has shape (nloops, 6, ...)).
    Each derivative has the output's shape followed by the parameter's direction axes:
    mass: none; com, gravity: (3,); inertia: (3, 3), entry [a, b] the derivative along the symmetric
    change (E_ab + E_ba)/2 (so d = sum_ab dI[a, b] * deriv[..., a, b] for a symmetric dI);
    placement: (6,), (dtheta, dp) moving (R, p) to (R expm([dtheta]x), p + dp): dtheta in the joint frame,
    dp in the parent body's frame. Flexible bodies included (their placements are their parameters).

    ParameterError names an unknown parameter (with the closest names). Raises TypeError or ValueError naming an
    argument of the wrong type or shape or a non-finite entry, and DynamicsError naming the body or DOF when the
    dynamics fail, as the state calls do (soadyn.forward_dynamics).
    """
    return _soadyn._parameter_sensitivity(model, q, v, u, parameter_name_list(params))


def parameter_name_list(params) -> list:
    """A parameter name or an iterable of them, as a list of str; TypeError naming what is not a name."""
    if isinstance(params, str):
        return [params]
    try:
        items = list(params)
    except TypeError:
        raise TypeError(f"params must be a parameter name or a list of them, got {type(params).__name__}") from None
    return [parameter_name(p) for p in items]
