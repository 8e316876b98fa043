"""Named model parameters and the design sensitivity of the dynamics.

Parameters (``Model.parameter_names``): per rigid body ``<body>.mass`` (float), ``<body>.com`` (3,),
``<body>.inertia`` (3, 3; about the centre of mass, body frame), per body (flexible ones included)
``<body>.placement`` (4, 4 homogeneous matrix of the joint frame in the parent body's frame; ``set_parameter``
also takes ``(R, p)``), and ``gravity`` (3,). A body carries what is welded to it by fixed joints; a welded
part has no parameters of its own. ``set_parameter`` changes no structure and, in C++, allocates nothing.
"""
from __future__ import annotations

import numpy as np

from . import _soadyn
from .model import _placement

__all__ = ["parameter_sensitivity", "ParameterError"]

ParameterError = _soadyn.ParameterError


def parameter_names(model) -> list:
    return _soadyn._parameter_names(model)


def get_parameter(model, name: str):
    return _soadyn._get_parameter(model, _name(name))


def set_parameter(model, name: str, value) -> None:
    name = _name(name)
    if name.endswith(".placement") and isinstance(value, tuple):
        R, p = _placement(value, name[: -len(".placement")])
        value = np.eye(4)
        value[:3, :3], value[:3, 3] = R, p
    _soadyn._set_parameter(model, name, value)


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
    return [_name(p) for p in items]


def _name(name) -> str:
    if not isinstance(name, str):
        raise TypeError(f"parameter name must be a str, got {type(name).__name__} ({name!r})")
    return name
