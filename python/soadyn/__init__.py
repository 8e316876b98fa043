"""soadyn: O(N) hybrid (prescribed/regular) multibody dynamics.

Conventions: spatial vectors are [angular; linear]; quaternions are stored
(x, y, z, w); a free joint's v is the body-frame angular velocity followed by
the body-frame linear velocity of the body origin. Every function returns
fresh numpy arrays; the model's preallocated scratch is reused between calls.
"""
import sys as _sys
from importlib import import_module as _import_module
from importlib.util import spec_from_loader as _spec_from_loader

from . import error_classes  # noqa: F401 (the exception classes' docstrings)
from ._soadyn import (
    DynamicsError,
    FlexibleBody,
    Joint,
    LoopError,
    NonphysicalInertiaError,
    bias_forces,
    center_of_mass,
    center_of_mass_jacobian,
    constrained_dynamics,
    forward_dynamics,
    forward_kinematics,
    frame_acceleration,
    frame_jacobian,
    frame_jacobian_time_variation,
    frame_pose,
    frame_velocity,
    hybrid_dynamics,
    independent_coordinates,
    integrate,
    inverse_dynamics,
    joint_wrenches,
    kinetic_energy,
    loop_jacobian,
    loop_rank,
    loop_residual,
    mass_matrix,
    momentum,
    neutral_configuration,
    potential_energy,
    random_configuration,
)
from ._soadyn import ParameterError, loop_force_stiffness
from . import _soadyn as _core

QUATERNION_TOLERANCE: float = _core.QUATERNION_TOLERANCE
"""How far from 1 (1e-6) the norm of a quaternion in q may be: within it, the quaternion is used normalised;
further, the call is refused with a ValueError naming the joint, never silently normalised."""
from ._soadyn import (  # the equations of motion term by term
    christoffel_symbols,
    coriolis_matrix,
    external_forces_to_generalized,
    gravity_forces,
    mass_matrix_derivative,
)
from ._soadyn import dissipated_power, force_element_potential, force_elements  # springs and dampers
from .analysis.derivatives import dynamics_derivatives, inverse_dynamics_derivatives
from .analysis.linearize import linearize
from .analysis.modes import Modes, modes, natural_frequencies, stiffness_matrix
from .analysis.parameters import parameter_sensitivity
from .analysis.statics import StaticEquilibrium, equilibrium_sensitivities, objective_gradient, static_equilibrium
from .io.mjcf import MjcfError, MjcfIgnoredWarning, load_mjcf
from .io.model_file import ModelFileError, load_model, save_model
from .io.urdf import UrdfError, load_urdf
from .io.urdf_export import UrdfExportWarning, save_urdf
from .fmu import FmuError, export_fmu
from .loops import assemble, project_velocity
from .model import Model
from .simulator import MotionSource, Simulator, Trajectory
from .viz.visuals import Visual
from .viz.viewer import Viewer  # viser is imported when a Viewer is made
from . import batch, campaign, hil, scenes

from ._version import __version__  # written by the build from pyproject.toml

__all__ = [
    "Model", "Joint", "DynamicsError", "NonphysicalInertiaError", "QUATERNION_TOLERANCE", "load_urdf", "UrdfError",
    "Simulator", "Trajectory", "MotionSource",
    "FlexibleBody", "natural_frequencies", "stiffness_matrix",
    "forward_dynamics", "inverse_dynamics", "hybrid_dynamics", "mass_matrix", "bias_forces",
    "joint_wrenches", "kinetic_energy", "potential_energy", "momentum", "center_of_mass",
    "forward_kinematics", "integrate", "neutral_configuration", "random_configuration",
    "scenes", "hil", "batch", "campaign",
    "LoopError", "constrained_dynamics", "loop_residual", "loop_jacobian", "loop_rank",
    "assemble", "project_velocity", "independent_coordinates",
    "frame_pose", "frame_velocity", "frame_acceleration", "frame_jacobian", "frame_jacobian_time_variation",
    "center_of_mass_jacobian",
]
__all__ += ["gravity_forces", "external_forces_to_generalized", "coriolis_matrix", "mass_matrix_derivative",
            "christoffel_symbols"]
__all__ += ["static_equilibrium", "StaticEquilibrium", "loop_force_stiffness"]
__all__ += ["dynamics_derivatives", "inverse_dynamics_derivatives", "linearize", "modes", "Modes"]
__all__ += ["force_elements", "force_element_potential", "dissipated_power"]
__all__ += ["parameter_sensitivity", "ParameterError"]
__all__ += ["equilibrium_sensitivities", "objective_gradient"]
__all__ += ["Visual", "load_mjcf", "MjcfError", "MjcfIgnoredWarning"]
__all__ += ["save_model", "load_model", "ModelFileError"]
__all__ += ["save_urdf", "UrdfExportWarning"]
__all__ += ["export_fmu", "FmuError"]
__all__ += ["Viewer"]

# The package was flat before it had subpackages: its old module paths keep working, as the very modules at
# their new homes (`import soadyn.urdf`, `from soadyn.urdf import ...`, `soadyn.urdf`; monkeypatching either
# name patches both). A module imported above is bound under its old path at once (so `import soadyn.modes`
# never rebinds the function soadyn.modes), the others when first imported, by _MovedModuleFinder.
_MOVED_MODULES = {f"soadyn.{old}": f"soadyn.{new}" for old, new in {
    "urdf": "io.urdf", "urdf_reader": "io.urdf_reader", "urdf_inertia": "io.urdf_inertia",
    "urdf_visuals": "io.urdf_visuals", "urdf_export": "io.urdf_export", "mjcf": "io.mjcf",
    "model_file": "io.model_file", "text_files": "io.text_files",
    "derivatives": "analysis.derivatives", "linearize": "analysis.linearize", "modes": "analysis.modes",
    "statics": "analysis.statics", "equilibrium_sensitivity": "analysis.equilibrium_sensitivity",
    "parameters": "analysis.parameters",
    "oracles": "check.oracles", "mujoco_oracle": "check.mujoco_oracle", "pinocchio_mjcf": "check.pinocchio_mjcf",
    "viewer": "viz.viewer", "visuals": "viz.visuals",
    "cli": "apps.cli", "demo": "apps.demo", "four_bar_demo": "apps.four_bar_demo",
    "boom_vibration": "apps.boom_vibration",
}.items()}


class _MovedModuleFinder:
    """Import hook (sys.meta_path) for the old module paths: the module at the new home, not a copy."""

    def find_spec(self, name, path=None, target=None):
        return _spec_from_loader(name, self) if name in _MOVED_MODULES else None

    def create_module(self, spec):
        return None  # a placeholder, which exec_module replaces in sys.modules

    def exec_module(self, module):
        _sys.modules[module.__name__] = _import_module(_MOVED_MODULES[module.__name__])

    def get_code(self, name):
        """`python -m <old path>` runs the module at its new home as __main__."""
        return compile(f"import runpy; runpy.run_module({_MOVED_MODULES[name]!r}, run_name='__main__', "
                       "alter_sys=True)", f"<{name}: moved to {_MOVED_MODULES[name]}>", "exec")


def __getattr__(name: str):
    """soadyn.<old module name> (soadyn.urdf, soadyn.oracles, soadyn.cli, ...): the module at its new home."""
    if f"soadyn.{name}" in _MOVED_MODULES:
        return _import_module(f"soadyn.{name}")
    raise AttributeError(f"module 'soadyn' has no attribute {name!r}")


_sys.modules.update({old: _sys.modules[new] for old, new in _MOVED_MODULES.items() if new in _sys.modules})
_sys.meta_path.append(_MovedModuleFinder())
