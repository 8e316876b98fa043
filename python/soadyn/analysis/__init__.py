"""Analysis on top of the dynamics: derivatives, linearization, modes, statics and sensitivities.

Public as soadyn.<name> (soadyn.dynamics_derivatives, soadyn.linearize, soadyn.modes,
soadyn.static_equilibrium, soadyn.parameter_sensitivity, ...).
"""
