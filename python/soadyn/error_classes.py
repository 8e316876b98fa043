"""Docstrings of the exception classes the compiled module registers (soadyn._soadyn).

pybind11 creates them with their base class's docstring; these say what each means and what its
message names. Set once, when soadyn is imported.
"""
from . import _soadyn

DOCSTRINGS = {
    "DynamicsError": (
        "A dynamics call or a simulation step could not produce finite results (an ArithmeticError): a singular "
        "articulated-body inertia (its message names the body or DOF), a non-finite state or result, a motion "
        "source that failed or returned a non-finite value (the DOF named, chained to the cause), a loop that "
        "could not be closed, or dopri5's sub-step limit. Simulator.run attaches the steps done as `trajectory`."),
    "NonphysicalInertiaError": (
        "A body's mass properties are not those of a physical body (a ValueError): a negative mass, an inertia "
        "that is not positive semi-definite or breaks the triangle inequality, a spatial inertia that is not "
        "finite. The message names the body; Model.add_body(accept_nonphysical_inertia=True) opts out of the "
        "physical tests (never of the finite one)."),
    "LoopError": (
        "A closed loop is ill-formed or cannot be satisfied (a ValueError): an unknown frame or kind, a loop "
        "between frames of the same body, a configuration assemble() cannot close. The message names the loop."),
    "ModelFileError": (
        "A model file cannot be read or written (a ValueError): invalid JSON, a newer version, a missing, "
        "mistyped, non-finite or unknown value, a file over the size or nesting limit. The message names the file "
        "and the JSON path of the item (/bodies/3/mass)."),
    "ParameterError": (
        "A model parameter's name or value is refused (a ValueError): an unknown name (the closest names are "
        "suggested), a value of the wrong shape, or one that would make the model non-physical. The message "
        "names the parameter."),
}

for _name, _text in DOCSTRINGS.items():
    getattr(_soadyn, _name).__doc__ = _text
