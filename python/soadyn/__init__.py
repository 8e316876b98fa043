"""soadyn: O(N) hybrid (prescribed/regular) multibody dynamics.

Conventions: spatial vectors are [angular; linear]; quaternions are stored
(x, y, z, w); a free joint's v is the body-frame angular velocity followed by
the body-frame linear velocity of the body origin. Every function returns
fresh numpy arrays; the model's preallocated scratch is reused between calls.
"""
from ._soadyn import (
    QUATERNION_TOLERANCE,
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
from ._soadyn import (  # the equations of motion term by term
    christoffel_symbols,
    coriolis_matrix,
    external_forces_to_generalized,
    gravity_forces,
    mass_matrix_derivative,
)
from ._soadyn import dissipated_power, force_element_potential, force_elements  # springs and dampers
from .derivatives import dynamics_derivatives, inverse_dynamics_derivatives
from .loops import assemble, project_velocity
from .linearize import linearize
from .modes import Modes, modes, natural_frequencies, stiffness_matrix
from .statics import (StaticEquilibrium, equilibrium_sensitivities, loop_force_stiffness, objective_gradient,
                      static_equilibrium)
from .model import Model
from .parameters import ParameterError, parameter_sensitivity
from .simulator import MotionSource, Simulator, Trajectory
from .urdf import UrdfError, load_urdf
from .mjcf import MjcfError, MjcfIgnoredWarning, load_mjcf
from .visuals import Visual
from .model_file import ModelFileError, load_model, save_model
from .urdf_export import UrdfExportWarning, save_urdf
from . import batch, campaign, hil, scenes
from .viewer import Viewer  # viser is imported when a Viewer is made

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
__all__ += ["dynamics_derivatives", "inverse_dynamics_derivatives"]
__all__ += ["parameter_sensitivity", "ParameterError"]
__all__ += ["equilibrium_sensitivities", "objective_gradient"]
__all__ += ["Visual", "load_mjcf", "MjcfError", "MjcfIgnoredWarning"]
__all__ += ["save_model", "load_model", "ModelFileError"]
__all__ += ["save_urdf", "UrdfExportWarning"]
__all__ += ["Viewer"]
