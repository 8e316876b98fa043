# Generated from the compiled module by pybind11-stubgen; do not edit. Regenerate: python tests/support/stub.py --write
"""
soadyn C++ core
"""
from __future__ import annotations
import collections.abc
import numpy
import numpy.typing
import typing
__all__: list[str] = ['DynamicsError', 'FlexibleBody', 'HilRunner', 'Joint', 'LoopError', 'ModelFileError', 'MotionSource', 'NonphysicalInertiaError', 'ParameterError', 'QUATERNION_TOLERANCE', 'bias_forces', 'center_of_mass', 'center_of_mass_jacobian', 'christoffel_symbols', 'constrained_dynamics', 'coriolis_matrix', 'dissipated_power', 'external_forces_to_generalized', 'force_element_potential', 'force_elements', 'forward_dynamics', 'forward_kinematics', 'frame_acceleration', 'frame_jacobian', 'frame_jacobian_time_variation', 'frame_pose', 'frame_velocity', 'gravity_forces', 'hybrid_dynamics', 'independent_coordinates', 'integrate', 'inverse_dynamics', 'joint_wrenches', 'kinetic_energy', 'loop_force_stiffness', 'loop_jacobian', 'loop_rank', 'loop_residual', 'mass_matrix', 'mass_matrix_derivative', 'momentum', 'neutral_configuration', 'potential_energy', 'random_configuration']
class FlexibleBody:
    """
    Modal flexible body: a rigid reference frame at the inboard hinge plus n_modes linear modes
    of a lumped model (nodes with point masses, rotary inertias and 6 x n_modes mode shapes,
    rows [rotation; translation]). Immutable; its modal integrals are computed once.
    """
    @staticmethod
    def cantilever_beam(length: typing.Any, EI: typing.Any, mass_per_length: typing.Any, n_modes: typing.Any, n_nodes: typing.Any = 60) -> FlexibleBody:
        """
        Uniform Euler-Bernoulli cantilever along x, clamped at the body origin: n_nodes lumped
        segments plus a massless 'tip' node; n_modes clamped-free bending modes per plane in the
        x-y and x-z planes, interleaved (2 * n_modes modes in all).
        """
    def __init__(self, positions: typing.Any, masses: typing.Any, rotary_inertias: typing.Any, mode_shapes: typing.Any, stiffness: typing.Any, damping: typing.Any = None, attachments: collections.abc.Mapping[str, typing.SupportsInt | typing.SupportsIndex] = {}) -> None:
        """
        positions (N, 3) undeformed node positions in the body frame; masses (N,); rotary_inertias
        (N, 3, 3) about each node; mode_shapes (N, 6, n_modes); stiffness and damping (n_modes,
        n_modes), symmetric positive semidefinite (damping None: zero); attachments {name: node}.
        Units: m, kg, kg m^2; mode shapes per unit modal coordinate (rad and m); stiffness in the modal
        coordinates' units (N m / rad^2 for a unit-rad mode), damping likewise per s. A wrong shape, a non-finite
        or negative mass, an asymmetric or indefinite matrix or an attachment to a missing node raises
        ValueError naming the node or the matrix.
        """
    def __repr__(self) -> str:
        ...
    def augmented_mass_matrix(self, eta: typing.Any) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"]:
        """
        M(eta), (6 + n_modes) square: T = 1/2 [V; eta_dot]' M [V; eta_dot], V = [omega; v_origin] body frame.
        """
    def natural_frequencies_clamped(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]:
        """
        Natural frequencies (rad/s, ascending) of the body clamped at its reference frame.
        """
    def node_load(self, j: typing.Any, eta: typing.Any, wrench: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[6, 1]"]) -> tuple[typing.Annotated[numpy.typing.NDArray[numpy.float64], "[6, 1]"], typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]]:
        """
        Generalized force of `wrench` = [torque; force] applied at node j (node frame) at eta: returns
        (body_wrench, modal_forces): the wrench about the body origin in the body frame (add it to
        f_ext[body]) and the modal forces (add them to the modal DOFs' entries of tau / u).
        """
    def node_pose(self, j: typing.Any, eta: typing.Any) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[4, 4]"]:
        """
        4x4 pose of node j in the body frame at eta.
        """
    def strain_energy(self, eta: typing.Any) -> float:
        """
        1/2 eta' K eta.
        """
    @property
    def attachments(self) -> dict[str, int]:
        """
        {name: node index} of the attachment nodes.
        """
    @property
    def damping(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"]:
        """
        (n_modes, n_modes) modal damping D.
        """
    @property
    def masses(self) -> numpy.typing.NDArray[numpy.float64]:
        """
        (N,) node masses, kg.
        """
    @property
    def modal_mass(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"]:
        """
        (n_modes, n_modes) modal mass: sum over nodes of the mode shapes' mass-weighted products.
        """
    @property
    def mode_shapes(self) -> numpy.typing.NDArray[numpy.float64]:
        """
        (N, 6, n_modes): rows [rotation; translation].
        """
    @property
    def n_modes(self) -> int:
        """
        Number of modes (modal DOFs).
        """
    @property
    def n_nodes(self) -> int:
        """
        Number of nodes N.
        """
    @property
    def nodes(self) -> numpy.typing.NDArray[numpy.float64]:
        """
        (N, 3) undeformed node positions, body frame.
        """
    @property
    def rotary_inertias(self) -> numpy.typing.NDArray[numpy.float64]:
        """
        (N, 3, 3) node rotary inertias, kg m^2.
        """
    @property
    def stiffness(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"]:
        """
        (n_modes, n_modes) modal stiffness K.
        """
class Joint:
    """
    A joint type; build one with the static constructors and give it to Model.add_body.
    
    Axes are 3-vectors in the joint frame, normalised when the body is added; a zero or non-finite axis is
    refused by Model.add_body with a ValueError naming the joint. Coordinates: rad for rotations, m for
    translations (a helical joint's pitch in m per rad). DOF names are the joint's name, or '<name>:<part>'
    for joints of several DOFs (':1', ':2' of a universal joint, ':angle', ':offset' of a cylindrical one).
    """
    @staticmethod
    def cylindrical(axis: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], name: str = '') -> Joint:
        """
        Rotation about and translation along `axis`: ':angle', ':offset'.
        """
    @staticmethod
    def fixed(name: str = '') -> Joint:
        """
        Weld: the body is merged into its parent and becomes a named frame.
        """
    @staticmethod
    def free(name: str = '') -> Joint:
        """
        Six DOF: q = (position, quaternion x y z w), v = body-frame (angular, linear velocity of the origin).
        """
    @staticmethod
    def helical(axis: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], pitch: typing.SupportsFloat | typing.SupportsIndex, name: str = '') -> Joint:
        """
        Screw about `axis`: `pitch` metres of travel per radian. One DOF.
        """
    @staticmethod
    def planar(name: str = '') -> Joint:
        """
        x-y translation and z rotation: q = (x, y, theta), v = body-frame (vx, vy, wz).
        """
    @staticmethod
    def prismatic(axis: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], name: str = '') -> Joint:
        """
        Translation along `axis`. One DOF.
        """
    @staticmethod
    def revolute(axis: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], name: str = '') -> Joint:
        """
        Rotation about `axis` (joint frame). One DOF.
        """
    @staticmethod
    def spherical(name: str = '') -> Joint:
        """
        Ball joint: q = quaternion (x, y, z, w), v = body-frame angular velocity.
        """
    @staticmethod
    def translation(name: str = '') -> Joint:
        """
        Cartesian translation along the joint frame's x, y, z: q = v = (x, y, z). DOFs ':x', ':y', ':z'.
        """
    @staticmethod
    def universal(axis1: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], axis2: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], name: str = '') -> Joint:
        """
        Rotation about axis1, then about axis2 of the rotated frame. DOFs '<name>:1', '<name>:2'.
        """
    def __repr__(self) -> str:
        ...
    @property
    def name(self) -> str:
        """
        Its name ('': the body's name).
        """
    @property
    def nq(self) -> int:
        """
        Its number of coordinates.
        """
    @property
    def nv(self) -> int:
        """
        Its number of DOFs.
        """
    @property
    def type(self) -> str:
        """
        The joint type's name ('revolute', 'free', ...).
        """
class _Model:
    def __init__(self) -> None:
        ...
    def _add_body(self, name: str, parent: str, joint: Joint, R: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 3]"], p: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], mass: typing.SupportsFloat | typing.SupportsIndex, com: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], inertia: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 3]"], accept_nonphysical_inertia: bool = False) -> int:
        ...
    def _add_flexible_body(self, arg0: str, arg1: str, arg2: Joint, arg3: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 3]"], arg4: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], arg5: FlexibleBody) -> int:
        ...
    def _add_loop(self, arg0: str, arg1: str, arg2: str, arg3: str, arg4: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 3]"], arg5: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], arg6: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 3]"], arg7: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], arg8: typing.SupportsFloat | typing.SupportsIndex, arg9: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[m, 1]"] | None) -> int:
        ...
    def _copy_from(self, arg0: _Model) -> None:
        ...
    def _load_cassini(self) -> None:
        ...
    def _load_delta_robot(self) -> None:
        ...
    def _load_four_bar(self, arg0: str) -> None:
        ...
    def _load_json(self, text: str, source: str) -> None:
        """
        Replaces this model by the one model-file JSON `text` holds.
        """
    def _load_pendulum_chain(self, arg0: typing.SupportsInt | typing.SupportsIndex, arg1: typing.SupportsFloat | typing.SupportsIndex, arg2: typing.SupportsFloat | typing.SupportsIndex) -> None:
        ...
    def _load_slider_crank(self, arg0: str) -> None:
        ...
    def _require_regular_modal_dofs(self, arg0: collections.abc.Sequence[typing.SupportsInt | typing.SupportsIndex]) -> None:
        """
        Raises ValueError naming the first of `dofs` that is a modal coordinate (always regular).
        """
    def _set_armature(self, arg0: collections.abc.Sequence[typing.SupportsInt | typing.SupportsIndex], arg1: typing.SupportsFloat | typing.SupportsIndex) -> None:
        ...
    def _set_effort_limit(self, arg0: collections.abc.Sequence[typing.SupportsInt | typing.SupportsIndex], arg1: typing.SupportsFloat | typing.SupportsIndex) -> None:
        ...
    def _set_prescribed_indices(self, arg0: collections.abc.Sequence[typing.SupportsInt | typing.SupportsIndex], arg1: bool) -> None:
        ...
    def _set_prescribed_mask(self, arg0: collections.abc.Sequence[bool]) -> None:
        ...
    def _to_json(self) -> str:
        """
        The model as model-file JSON text (soadyn/model/model_file.hpp).
        """
    def body_index(self, arg0: str) -> int:
        """
        Index of the named body, or -1.
        """
    def dof_index(self, arg0: str) -> int:
        """
        Velocity index of the named DOF, or -1.
        """
    def flexible_body(self, name: str) -> FlexibleBody:
        """
        The FlexibleBody of the named body.
        """
    @property
    def _description(self) -> str:
        """
        The description (visuals, metadata) as JSON text: kept by model files, unused by the dynamics.
        """
    @_description.setter
    def _description(self, arg1: str) -> None:
        ...
    @property
    def appendage_in_root_frame(self) -> list[bool]:
        """
        Per body: whether it is a flexible appendage welded to its root, whose modal integrals the dynamics read formed once in the root's frame.
        """
    @property
    def armature(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]:
        """
        Float array (nv): each DOF's armature (rotor inertia on the DOF; zero by default).
        """
    @property
    def body_names(self) -> list[str]:
        """
        Body names in tree order (parent before child).
        """
    @property
    def constant_leaf_hinge(self) -> list[bool]:
        """
        Per body: whether it is a leaf turning about an axis of mass symmetry on a body welded to its root (a reaction wheel), whose hinge terms D, G and P+ the dynamics read formed once (when its DOF is regular and has no armature).
        """
    @property
    def constant_tree_inertia(self) -> list[bool]:
        """
        Per body: whether the dynamics read its inertia formed once (constant in its free root's frame: welded to the root, or turning about an axis of mass symmetry on it).
        """
    @property
    def coordinate_names(self) -> list[str]:
        """
        Coordinate names in q order (a quaternion's four entries named each).
        """
    @property
    def dof_names(self) -> list[str]:
        """
        DOF names in velocity order (entries of v, tau, u).
        """
    @property
    def effort_limits(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]:
        """
        Float array (nv): each DOF's effort limit (largest actuator force or torque; inf: none,
        the default). HIL runs take it as the DOF's command limit.
        """
    @property
    def frame_names(self) -> list[str]:
        """
        Names of the frames welded to bodies (fixed-joint links, flexible bodies' attachment nodes).
        """
    @property
    def gravity(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[3, 1]"]:
        """
        Gravity in the world frame (default (0, 0, -9.81)).
        """
    @gravity.setter
    def gravity(self, arg1: typing.Any) -> None:
        ...
    @property
    def joint_names(self) -> list[str]:
        """
        Each body's joint name, in body order.
        """
    @property
    def joint_types(self) -> list[str]:
        """
        Each body's joint type ('revolute', 'free', ...), in body order.
        """
    @property
    def leaf_terms_presummed(self) -> list[tuple[bool, bool]]:
        """
        Per body: (under the prescribed flags, with every DOF regular), whether it is a leaf whose constant P+ (or, prescribed, its constant P) its parent's articulated inertia starts with, summed once.
        """
    @property
    def loop_names(self) -> list[str]:
        """
        Names of the closed loops, in the order added.
        """
    @property
    def loop_solver(self) -> str:
        """
        How constrained_dynamics solves the loops of this model: 'articulated' (the articulated-body response to unit multipliers, O(N) in the bodies) or 'mass matrix' (M by CRBA, factored with the tree's sparsity: rigid trees where that factor is cheap for their number of loop equations, and models with flexible bodies). A call with a body beyond its tree-frame reach takes the mass matrix in body frames.
        """
    @property
    def masses(self) -> list[float]:
        """
        Each body's mass in kg, welded parts included.
        """
    @property
    def modal(self) -> numpy.typing.NDArray[numpy.bool]:
        """
        Bool array (nv): True where the DOF is a modal coordinate (always regular).
        """
    @property
    def n_modes(self) -> list[int]:
        """
        Modal coordinates per body (0 for a rigid body).
        """
    @property
    def nbodies(self) -> int:
        """
        Number of bodies (welded ones merged into their parents are frames).
        """
    @property
    def nloop_equations(self) -> int:
        """
        Number of loop-closure equations (the rows of loop_jacobian).
        """
    @property
    def nloops(self) -> int:
        """
        Number of closed loops.
        """
    @property
    def nq(self) -> int:
        """
        Number of coordinates (len q).
        """
    @property
    def nv(self) -> int:
        """
        Number of DOFs (len v).
        """
    @property
    def parents(self) -> list[int]:
        """
        Each body's parent body index (-1: the world).
        """
    @property
    def placement_axes(self) -> list[str]:
        """
        Per body: the shape of its placement's rotation as the sweeps apply it: 'identity', 'axis_permutation' (quarter turns: each axis onto a coordinate axis, up to sign) or 'general'. Entries within machine epsilon of the first two count as them.
        """
    @property
    def prescribed(self) -> numpy.typing.NDArray[numpy.bool]:
        """
        Bool array (nv): True where the DOF is prescribed.
        """
    @property
    def q_index(self) -> list[int]:
        """
        Each body's first coordinate's index in q.
        """
    @property
    def v_index(self) -> list[int]:
        """
        Each body's first DOF's index in v.
        """
class NonphysicalInertiaError(ValueError):
    """
    A body's mass properties are not those of a physical body (a ValueError): a negative mass, an inertia that is not positive semi-definite or breaks the triangle inequality, a spatial inertia that is not finite. The message names the body; Model.add_body(accept_nonphysical_inertia=True) opts out of the physical tests (never of the finite one).
    """
class LoopError(ValueError):
    """
    A closed loop is ill-formed or cannot be satisfied (a ValueError): an unknown frame or kind, a loop between frames of the same body, a configuration assemble() cannot close. The message names the loop.
    """
class ModelFileError(ValueError):
    """
    A model file cannot be read or written (a ValueError): invalid JSON, a newer version, a missing, mistyped, non-finite or unknown value, a file over the size or nesting limit. The message names the file and the JSON path of the item (/bodies/3/mass).
    """
class DynamicsError(ArithmeticError):
    """
    A dynamics call or a simulation step could not produce finite results (an ArithmeticError): a singular articulated-body inertia (its message names the body or DOF), a non-finite state or result, a motion source that failed or returned a non-finite value (the DOF named, chained to the cause), a loop that could not be closed, or dopri5's sub-step limit. Simulator.run attaches the steps done as `trajectory`.
    """
class MotionSource:
    """
    Position, velocity and acceleration of one DOF as functions of time.
    """
    @staticmethod
    def constant_acceleration(acceleration: typing.SupportsFloat | typing.SupportsIndex, v0: typing.SupportsFloat | typing.SupportsIndex = 0.0, q0: typing.SupportsFloat | typing.SupportsIndex = 0.0, t0: typing.SupportsFloat | typing.SupportsIndex = 0.0) -> MotionSource:
        """
        q(t) = q0 + v0 (t - t0) + acceleration (t - t0)^2 / 2 (rad or m, s); ValueError naming a non-finite
        argument.
        """
    @staticmethod
    def constant_velocity(velocity: typing.SupportsFloat | typing.SupportsIndex, q0: typing.SupportsFloat | typing.SupportsIndex = 0.0, t0: typing.SupportsFloat | typing.SupportsIndex = 0.0) -> MotionSource:
        """
        q(t) = q0 + velocity (t - t0) (rad or m, s); ValueError naming a non-finite argument.
        """
    @staticmethod
    def cycloidal(q0: typing.SupportsFloat | typing.SupportsIndex, q1: typing.SupportsFloat | typing.SupportsIndex, t0: typing.SupportsFloat | typing.SupportsIndex, duration: typing.SupportsFloat | typing.SupportsIndex) -> MotionSource:
        """
        Rest-to-rest cycloidal motion from q0 to q1 (Saha, Shah & Nandihal 2013, Eq. 34).
        """
    @staticmethod
    def function(fn: collections.abc.Callable) -> MotionSource:
        """
        fn(t) -> (q, v, a): a Python callable (not real-time), a function of time: a Simulator keeps its last finite result and reuses it when asked for the same time again. If it raises or returns a non-finite value, the step stops with DynamicsError naming the DOF (chained to the exception raised).
        """
    @staticmethod
    def polynomial(coefficients: collections.abc.Sequence[typing.SupportsFloat | typing.SupportsIndex], t0: typing.SupportsFloat | typing.SupportsIndex = 0.0) -> MotionSource:
        """
        q(t) = sum c_k (t - t0)^k, constant term first.
        """
    @staticmethod
    def spline(times: collections.abc.Sequence[typing.SupportsFloat | typing.SupportsIndex], values: collections.abc.Sequence[typing.SupportsFloat | typing.SupportsIndex]) -> MotionSource:
        """
        Natural cubic spline through the table (held outside it).
        """
    def sample(self, t: typing.SupportsFloat | typing.SupportsIndex) -> tuple[float, float, float]:
        """
        (q, v, a) at time t.
        """
class _SimulatorCore:
    pass
class _Simulator(_SimulatorCore):
    def __init__(self, model: _Model, dt: typing.Any, integrator: typing.Any = 'rk4', event_capacity: typing.Any = 64) -> None:
        ...
    def _drive_cassini(self) -> None:
        ...
    def _lock(self, arg0: typing.SupportsInt | typing.SupportsIndex) -> None:
        ...
    def _prescribe(self, arg0: typing.SupportsInt | typing.SupportsIndex, arg1: MotionSource) -> None:
        ...
    def _release(self, arg0: typing.SupportsInt | typing.SupportsIndex) -> None:
        ...
    def _run(self, steps: typing.SupportsInt | typing.SupportsIndex) -> tuple:
        ...
    def _schedule(self, arg0: typing.SupportsFloat | typing.SupportsIndex, arg1: str, arg2: typing.SupportsInt | typing.SupportsIndex) -> int:
        ...
    def _schedule_prescribe(self, arg0: typing.SupportsFloat | typing.SupportsIndex, arg1: typing.SupportsInt | typing.SupportsIndex, arg2: MotionSource) -> int:
        ...
    def _set_external_wrench(self, arg0: typing.SupportsInt | typing.SupportsIndex, arg1: typing.Any) -> None:
        ...
    def _set_input(self, arg0: typing.SupportsInt | typing.SupportsIndex, arg1: typing.SupportsFloat | typing.SupportsIndex) -> None:
        ...
    def _set_state(self, arg0: typing.Any, arg1: typing.Any, arg2: typing.SupportsFloat | typing.SupportsIndex) -> None:
        ...
    def step(self) -> None:
        """
        Advance one step; on failure raises DynamicsError and leaves the state as before the step.
        """
    @property
    def _dof_names(self) -> list[str]:
        ...
    @property
    def atol(self) -> float:
        """
        dopri5: absolute error tolerance of a sub-step, in the state's units (> 0; ValueError otherwise).
        """
    @atol.setter
    def atol(self, arg1: typing.SupportsFloat | typing.SupportsIndex) -> None:
        ...
    @property
    def divergence_guard(self) -> bool:
        """
        Whether a step that makes the state's energy grow beyond what the applied forces can supply (or a
        velocity pass its limit) stops with DynamicsError 'diverging' before the state is non-finite. Off by
        default; on in HIL runs. Turning it on takes the current state as the energy's reference.
        """
    @divergence_guard.setter
    def divergence_guard(self, arg1: typing.Any) -> None:
        ...
    @property
    def dt(self) -> float:
        """
        The step, in s.
        """
    @property
    def energy_lost(self) -> float:
        """
        Kinetic energy removed by lock impulses so far.
        """
    @property
    def event_capacity(self) -> int:
        """
        Most events that can be pending at once.
        """
    @property
    def external_wrenches(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"]:
        """
        Each body's external wrench, (nbodies, 6): [torque; force] in its frame about its origin.
        """
    @property
    def forces(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]:
        """
        Generalized forces at the start of the last step (drive torques on prescribed DOFs).
        """
    @property
    def inputs(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]:
        """
        The torques (N m) or forces (N) applied to the regular DOFs, (nv,).
        """
    @property
    def integrator(self) -> str:
        """
        'euler', 'rk4' or 'dopri5'.
        """
    @property
    def last_substeps(self) -> int:
        """
        dopri5: sub-step attempts of the last step.
        """
    @property
    def loop_drift(self) -> tuple[float, float]:
        """
        (position, velocity): the largest |Psi_i| and |(C v)_i| the integrator left at the end of the last step,
        before the closure projection.
        """
    @property
    def loop_max_iterations(self) -> int:
        """
        Gauss-Newton steps the closure projection may take after a step; beyond it the step fails.
        """
    @loop_max_iterations.setter
    def loop_max_iterations(self, arg1: typing.SupportsInt | typing.SupportsIndex) -> None:
        ...
    @property
    def loop_tolerance(self) -> float:
        """
        Largest loop-closure residual |Psi_i| the projection after each step leaves.
        """
    @loop_tolerance.setter
    def loop_tolerance(self, arg1: typing.SupportsFloat | typing.SupportsIndex) -> None:
        ...
    @property
    def max_loop_drift(self) -> tuple[float, float]:
        """
        (position, velocity): the largest loop_drift over all steps so far.
        """
    @property
    def max_substeps(self) -> int:
        """
        dopri5: sub-step attempts allowed in one step; beyond it the step fails (DynamicsError).
        """
    @max_substeps.setter
    def max_substeps(self, arg1: typing.SupportsInt | typing.SupportsIndex) -> None:
        ...
    @property
    def pending_events(self) -> int:
        """
        Scheduled events not yet applied.
        """
    @property
    def prescribed(self) -> numpy.typing.NDArray[numpy.bool]:
        """
        Bool array (nv,): True where the DOF is prescribed now (locks and prescribe events included).
        """
    @property
    def q(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]:
        """
        The coordinates now, (nq,), a fresh array.
        """
    @property
    def rtol(self) -> float:
        """
        dopri5: relative error tolerance of a sub-step (>= 0; ValueError otherwise).
        """
    @rtol.setter
    def rtol(self, arg1: typing.SupportsFloat | typing.SupportsIndex) -> None:
        ...
    @property
    def steps_taken(self) -> int:
        """
        Steps completed since construction (a failed step does not count).
        """
    @property
    def time(self) -> float:
        """
        Simulation time now, in s.
        """
    @property
    def v(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]:
        """
        The velocities now, (nv,), a fresh array.
        """
    @property
    def velocity_limits(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]:
        """
        Per-DOF |v| limits the divergence guard enforces (nv values; inf: none, the default).
        """
    @velocity_limits.setter
    def velocity_limits(self, arg1: typing.Any) -> None:
        ...
class _HilSummary:
    @property
    def as_fast_as_possible(self) -> bool:
        ...
    @property
    def command_out_of_range_dof(self) -> int:
        ...
    @property
    def command_policy(self) -> str:
        ...
    @property
    def commands_rejected(self) -> int:
        ...
    @property
    def commands_saturated(self) -> int:
        ...
    @property
    def compute_max_us(self) -> float:
        ...
    @property
    def compute_p50_us(self) -> float:
        ...
    @property
    def compute_p999_us(self) -> float:
        ...
    @property
    def compute_p99_us(self) -> float:
        ...
    @property
    def cpu_max_us(self) -> float:
        ...
    @property
    def cpu_p50_us(self) -> float:
        ...
    @property
    def cpu_p999_us(self) -> float:
        ...
    @property
    def cpu_p99_us(self) -> float:
        ...
    @property
    def deadline_misses(self) -> int:
        ...
    @property
    def dynamics_floor_evaluations(self) -> int:
        ...
    @property
    def dynamics_floor_max_us(self) -> float:
        ...
    @property
    def dynamics_floor_p50_us(self) -> float:
        ...
    @property
    def dynamics_floor_p999_us(self) -> float:
        ...
    @property
    def dynamics_floor_p99_us(self) -> float:
        ...
    @property
    def exception_step(self) -> int:
        ...
    @property
    def failed_dof(self) -> int:
        ...
    @property
    def failed_step(self) -> int:
        ...
    @property
    def floor_interleaved(self) -> bool:
        ...
    @property
    def floor_max_us(self) -> float:
        ...
    @property
    def floor_p50_us(self) -> float:
        ...
    @property
    def floor_p999_us(self) -> float:
        ...
    @property
    def floor_p99_us(self) -> float:
        ...
    @property
    def floor_periods(self) -> int:
        ...
    @property
    def floor_target_us(self) -> float:
        ...
    @property
    def involuntary_switches(self) -> int:
        ...
    @property
    def kernel_drops(self) -> int:
        ...
    @property
    def kernel_drops_counted(self) -> bool:
        ...
    @property
    def lateness_max_us(self) -> float:
        ...
    @property
    def lateness_p50_us(self) -> float:
        ...
    @property
    def lateness_p99_us(self) -> float:
        ...
    @property
    def max_packets_per_step(self) -> int:
        ...
    @property
    def misses_compute_overrun(self) -> int:
        ...
    @property
    def misses_late_wakeup(self) -> int:
        ...
    @property
    def misses_preempted(self) -> int:
        ...
    @property
    def packets_dropped(self) -> int:
        ...
    @property
    def packets_received(self) -> int:
        ...
    @property
    def packets_rejected_sender(self) -> int:
        ...
    @property
    def packets_sent(self) -> int:
        ...
    @property
    def packets_stale(self) -> int:
        ...
    @property
    def preempted_steps(self) -> int:
        ...
    @property
    def preemption_margin_us(self) -> float:
        ...
    @property
    def realtime(self) -> dict:
        ...
    @property
    def requested_steps(self) -> int:
        ...
    @property
    def saturated_per_dof(self) -> list[int]:
        ...
    @property
    def send_failures(self) -> int:
        ...
    @property
    def status(self) -> str:
        ...
    @property
    def steps(self) -> int:
        ...
    @property
    def steps_left_pending(self) -> int:
        ...
    @property
    def stopped(self) -> bool:
        ...
    @property
    def wall_seconds(self) -> float:
        ...
    @property
    def warm_up(self) -> bool:
        ...
class HilRunner:
    """
    Fixed-rate loop over a Simulator with optional UDP I/O (see soadyn.hil.run_hil).
    """
    def __init__(self, sim: _Simulator, rate_hz: typing.SupportsFloat | typing.SupportsIndex, steps: typing.SupportsInt | typing.SupportsIndex, udp_port: typing.SupportsInt | typing.SupportsIndex | None = None, udp_destination_port: typing.SupportsInt | typing.SupportsIndex = 0, as_fast_as_possible: bool = False, record_every: typing.SupportsInt | typing.SupportsIndex = 0, spin_us: typing.SupportsFloat | typing.SupportsIndex = 0.0, fifo_priority: typing.SupportsInt | typing.SupportsIndex = 0, cpu: typing.SupportsInt | typing.SupportsIndex = -1, lock_memory: bool = False, command_limits: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[m, 1]"] | None = None, command_policy: str = 'clamp', udp_command_port: typing.SupportsInt | typing.SupportsIndex = -1, max_packets_per_step: typing.SupportsInt | typing.SupportsIndex = 16, floor_periods: typing.SupportsInt | typing.SupportsIndex = 0, floor: str = 'interleaved', preemption_margin_us: typing.SupportsFloat | typing.SupportsIndex = 10.0, warm_up: bool = True) -> None:
        ...
    def latest_state(self) -> typing.Any:
        """
        (step, t, q, v) the loop published last, read without disturbing it (thread-safe; any time during or after run()), or None before the first run.
        """
    def release_peer(self) -> None:
        """
        Forget the latched command sender: the next valid command's sender becomes the peer (thread-safe).
        """
    def request_stop(self) -> None:
        """
        Ask a running loop to stop (thread-safe).
        """
    def run(self) -> None:
        """
        Run the loop (GIL released); the outcome is in summary(). An exception raised by a Python motion source ends the run: run() raises the DynamicsError naming its DOF, caused by that exception, as Simulator.step does; summary() still holds the run.
        """
    def summary(self) -> _HilSummary:
        """
        The run's counts and timing percentiles (what soadyn.hil.HilReport is made from); RuntimeError while
        run() is running.
        """
    def trajectory(self) -> tuple[numpy.typing.NDArray[numpy.float64], numpy.typing.NDArray[numpy.float64], numpy.typing.NDArray[numpy.float64]]:
        """
        Recorded (t, q, v): the start and every record_every steps.
        """
    @property
    def command_limits(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]:
        """
        Per-DOF limits of the command values (default a * M_ii at the start; inf: none).
        """
    @command_limits.setter
    def command_limits(self, arg1: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[m, 1]"]) -> None:
        ...
    @property
    def commands_rejected(self) -> int:
        """
        Commands refused for a value beyond its limit so far (policy 'reject').
        """
    @property
    def commands_saturated(self) -> int:
        """
        Command values clamped to their limit so far (policy 'clamp').
        """
    @property
    def compute_ns(self) -> numpy.typing.NDArray[numpy.int64]:
        """
        Per-step compute times in ns (steps_done,); RuntimeError while run() is running.
        """
    @property
    def cpu_ns(self) -> numpy.typing.NDArray[numpy.int64]:
        """
        Per-step CPU time of the loop's thread in ns (steps_done,); RuntimeError while run() is running.
        """
    @property
    def deadline_misses(self) -> int:
        """
        Steps that ended after their period's deadline so far.
        """
    @property
    def dynamics_floor_ns(self) -> numpy.typing.NDArray[numpy.int64]:
        """
        Per-period times of the dynamics floor (evaluations of the dynamics at the present state, about the steps' median length), in the same periods as floor_ns.
        """
    @property
    def floor_ns(self) -> numpy.typing.NDArray[numpy.int64]:
        """
        Per-period times of the machine's floor (register arithmetic of the steps' median length).
        """
    @property
    def involuntary_switches(self) -> numpy.typing.NDArray[numpy.int32]:
        """
        Per-step involuntary context switches of the loop's thread (steps_done,); RuntimeError while run() is running.
        """
    @property
    def lateness_ns(self) -> numpy.typing.NDArray[numpy.int64]:
        """
        Per-step lateness of the wake-up past its deadline in ns (steps_done,); RuntimeError while run() is
        running.
        """
    @property
    def misses_ours(self) -> int:
        """
        Deadline misses so far whose step's own CPU time exceeded the period (the others are the machine's).
        """
    @property
    def packets_received(self) -> int:
        """
        Valid commands received so far (0 without UDP).
        """
    @property
    def steps_done(self) -> int:
        """
        Steps completed so far (thread-safe during run()).
        """
    @property
    def udp_port(self) -> typing.Any:
        """
        The bound UDP port (an ephemeral one when 0 was asked), or None without UDP.
        """
class ParameterError(ValueError):
    """
    A model parameter's name or value is refused (a ValueError): an unknown name (the closest names are suggested), a value of the wrong shape, or one that would make the model non-physical. The message names the parameter.
    """
def _add_joint_spring(arg0: _Model, arg1: str, arg2: typing.SupportsInt | typing.SupportsIndex, arg3: typing.SupportsFloat | typing.SupportsIndex, arg4: typing.SupportsFloat | typing.SupportsIndex, arg5: typing.SupportsFloat | typing.SupportsIndex) -> int:
    ...
def _add_point_spring(arg0: _Model, arg1: str, arg2: str, arg3: str, arg4: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], arg5: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], arg6: typing.SupportsFloat | typing.SupportsIndex, arg7: typing.SupportsFloat | typing.SupportsIndex, arg8: typing.SupportsFloat | typing.SupportsIndex | None, arg9: collections.abc.Sequence[typing.SupportsFloat | typing.SupportsIndex], arg10: collections.abc.Sequence[typing.SupportsFloat | typing.SupportsIndex]) -> int:
    ...
def _appendage_kernel() -> str:
    """
    The kernel of flexible appendages' update on this processor (sweeps/appendage_update.hpp): 'AVX2 FMA' or 'baseline'; results agree bit for bit only between processes that use the same one.
    """
def _assemble(model: _Model, q: typing.Any, free: collections.abc.Sequence[bool], tolerance: typing.Any, max_iterations: typing.Any) -> numpy.typing.NDArray[numpy.float64]:
    ...
def _batch_dynamics_derivatives(model: _Model, Q: typing.Any, V: typing.Any, U: typing.Any, f_ext: typing.Any, n: typing.SupportsInt | typing.SupportsIndex, threads: typing.SupportsInt | typing.SupportsIndex, lanes: typing.SupportsInt | typing.SupportsIndex) -> tuple[numpy.typing.NDArray[numpy.float64], numpy.typing.NDArray[numpy.float64], numpy.typing.NDArray[numpy.float64], numpy.typing.NDArray[numpy.float64], numpy.typing.NDArray[numpy.float64], numpy.typing.NDArray[numpy.float64]]:
    """
    Dynamics derivatives of n rows (soadyn.batch.dynamics_derivatives).
    """
def _batch_forward_dynamics(model: _Model, Q: typing.Any, V: typing.Any, TAU: typing.Any, f_ext: typing.Any, n: typing.SupportsInt | typing.SupportsIndex, threads: typing.SupportsInt | typing.SupportsIndex, lanes: typing.SupportsInt | typing.SupportsIndex) -> numpy.typing.NDArray[numpy.float64]:
    """
    Forward dynamics of n rows (soadyn.batch.forward_dynamics).
    """
def _batch_hybrid_dynamics(model: _Model, Q: typing.Any, V: typing.Any, U: typing.Any, f_ext: typing.Any, n: typing.SupportsInt | typing.SupportsIndex, threads: typing.SupportsInt | typing.SupportsIndex, lanes: typing.SupportsInt | typing.SupportsIndex) -> tuple[numpy.typing.NDArray[numpy.float64], numpy.typing.NDArray[numpy.float64]]:
    """
    Hybrid dynamics of n rows (soadyn.batch.hybrid_dynamics).
    """
def _batch_inverse_dynamics(model: _Model, Q: typing.Any, V: typing.Any, QDD: typing.Any, f_ext: typing.Any, n: typing.SupportsInt | typing.SupportsIndex, threads: typing.SupportsInt | typing.SupportsIndex, lanes: typing.SupportsInt | typing.SupportsIndex) -> numpy.typing.NDArray[numpy.float64]:
    """
    Inverse dynamics of n rows (soadyn.batch.inverse_dynamics).
    """
def _batch_mass_matrix(model: _Model, Q: typing.Any, n: typing.SupportsInt | typing.SupportsIndex, threads: typing.SupportsInt | typing.SupportsIndex, lanes: typing.SupportsInt | typing.SupportsIndex) -> numpy.typing.NDArray[numpy.float64]:
    """
    Mass matrices of n rows (soadyn.batch.mass_matrix).
    """
def _batch_packet_minimum_rows() -> int:
    """
    The fewest rows a batched call runs in packets (soadyn.batch.packet_minimum_rows).
    """
def _batch_rollout(model: _Model, x0s: typing.Any, runs: typing.SupportsInt | typing.SupportsIndex, controls: typing.Any, controls_per_run: bool, dt: typing.SupportsFloat | typing.SupportsIndex, steps: typing.SupportsInt | typing.SupportsIndex, integrator: str, record_every: typing.SupportsInt | typing.SupportsIndex, parameters: collections.abc.Sequence[typing.SupportsInt | typing.SupportsIndex], parameter_values: typing.Any, sources: collections.abc.Sequence[tuple[typing.SupportsInt | typing.SupportsIndex, MotionSource]], events: collections.abc.Sequence[tuple[str, typing.SupportsInt | typing.SupportsIndex]], event_times: typing.Any, threads: typing.SupportsInt | typing.SupportsIndex, lanes: typing.SupportsInt | typing.SupportsIndex) -> tuple[numpy.typing.NDArray[numpy.float64], numpy.typing.NDArray[numpy.float64], list[int], list[str], int]:
    """
    Parallel rollouts (soadyn.batch.rollout): (q, v, failed_step, messages).
    """
def _batch_widest_lanes() -> int:
    """
    States per pass of the batched calls' packet path on this processor (soadyn.batch.widest_lanes).
    """
def _delta_robot_state(position: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], velocity: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"]) -> tuple[typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"], typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]]:
    ...
def _dual_dynamics_derivatives(model: _Model, q: typing.Any, v: typing.Any, u: typing.Any, f_ext: typing.Any = None, spanning_tree: bool = False) -> tuple:
    ...
def _equilibrium_sensitivities(model: _Model, q: typing.Any, multipliers: typing.Any, free: collections.abc.Sequence[bool], params: collections.abc.Sequence[str]) -> dict:
    """
    {name: (dq/dp, dnu/dp, dH/dp of the held DOFs)} at a static equilibrium, direct method.
    """
def _four_bar_state(crank_angle: typing.SupportsFloat | typing.SupportsIndex, crank_rate: typing.SupportsFloat | typing.SupportsIndex) -> tuple[typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"], typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]]:
    ...
def _get_parameter(model: _Model, name: str) -> typing.Any:
    ...
def _joint_angle_kernel() -> str:
    """
    The kernel of the joint angles' sines and cosines on this processor (sweeps/joint_angles.hpp): results agree bit for bit only between processes that use the same one.
    """
def _linearize(model: _Model, q: typing.Any, v: typing.Any, u: typing.Any, dt: typing.Any, integrator: typing.Any, f_ext: typing.Any = None) -> tuple[numpy.typing.NDArray[numpy.float64], numpy.typing.NDArray[numpy.float64]]:
    ...
def _loop_equation_names(model: _Model) -> list[str]:
    """
    'loop[i]' for each loop-closure equation, in the rows' order.
    """
def _mass_matrix_kernel() -> str:
    """
    The kernel of rigid models' mass matrix on this processor (algorithms/crba.hpp): 'AVX2 FMA' or 'baseline'; results agree bit for bit only between processes that use the same one.
    """
def _modes(model: _Model, q: typing.Any) -> tuple:
    ...
def _modes_of(model: _Model, mass_matrix: typing.Any, stiffness: typing.Any, damping: typing.Any) -> tuple:
    ...
def _objective_gradient(model: _Model, q: typing.Any, multipliers: typing.Any, free: collections.abc.Sequence[bool], params: collections.abc.Sequence[str], dphi_dq: typing.Any, dphi_dnu: typing.Any = None) -> dict:
    """
    {name: dphi/dp} of a scalar objective at a static equilibrium, adjoint method.
    """
def _parameter_names(model: _Model) -> list[str]:
    ...
def _parameter_sensitivity(model: _Model, q: typing.Any, v: typing.Any, u: typing.Any, params: collections.abc.Sequence[str], spanning_tree: bool = False) -> dict:
    ...
def _probe_array_fields(arg0: typing.Any) -> typing.Any:
    ...
def _probe_model_handles(arg0: typing.Any) -> tuple[int, int]:
    ...
def _project_velocity(model: _Model, q: typing.Any, v: typing.Any, free: collections.abc.Sequence[bool]) -> numpy.typing.NDArray[numpy.float64]:
    ...
def _set_parameter(model: _Model, name: str, value: typing.Any) -> None:
    ...
def _slider_crank_state(crank_angle: typing.SupportsFloat | typing.SupportsIndex, crank_rate: typing.SupportsFloat | typing.SupportsIndex) -> tuple[typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"], typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]]:
    ...
def _static_equilibrium(model: _Model, q0: typing.Any, free: collections.abc.Sequence[bool], tol: typing.Any, max_iterations: typing.Any) -> tuple[numpy.typing.NDArray[numpy.float64], numpy.typing.NDArray[numpy.float64], numpy.typing.NDArray[numpy.float64], numpy.typing.NDArray[numpy.float64], int, float, bool]:
    """
    (q, nu, G - C' nu, stiffness eigenvalues, iterations, residual norm, stable) of the static equilibrium
    nearest q0 with the DOFs whose `free` entry is False held (soadyn.static_equilibrium wraps it).
    """
def _tree_dynamics_derivatives(model: _Model, q: typing.Any, v: typing.Any, u: typing.Any, f_ext: typing.Any = None) -> tuple:
    ...
def _tree_inverse_dynamics_derivatives(model: _Model, q: typing.Any, v: typing.Any, qdd: typing.Any, f_ext: typing.Any = None) -> tuple:
    ...
def bias_forces(model: _Model, q: typing.Any, v: typing.Any) -> numpy.typing.NDArray[numpy.float64]:
    """
    h(q, v), (nv,): Coriolis, centrifugal and gravity generalized forces (N, N m).
    
    q: (nq,) coordinates (m, rad; a quaternion as x y z w), v: (nv,) velocities (m/s, rad/s; body-frame for spherical, planar and free joints), accelerations (nv,) likewise per s; generalized forces (nv,) in N for translations and N m for rotations; f_ext: None or (nbodies, 6) body-frame wrenches [torque N m; force N] about each body origin. Units are SI throughout.
    
    Raises TypeError for an argument that is not an array of real numbers; ValueError naming the argument and the coordinate or DOF for a wrong shape, a NaN or infinite entry or a quaternion off unit norm (soadyn.QUATERNION_TOLERANCE); DynamicsError naming the body or DOF when the result is not finite (a singular articulated inertia, an input too large for floating point).
    """
def center_of_mass(model: _Model, q: typing.Any) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[3, 1]"]:
    """
    Centre of mass (3,) of the whole tree in the world frame, in m.
    
    q: (nq,) coordinates (m, rad; a quaternion as x y z w), v: (nv,) velocities (m/s, rad/s; body-frame for spherical, planar and free joints), accelerations (nv,) likewise per s; generalized forces (nv,) in N for translations and N m for rotations; f_ext: None or (nbodies, 6) body-frame wrenches [torque N m; force N] about each body origin. Units are SI throughout.
    
    Raises TypeError for an argument that is not an array of real numbers; ValueError naming the argument and the coordinate or DOF for a wrong shape, a NaN or infinite entry or a quaternion off unit norm (soadyn.QUATERNION_TOLERANCE); DynamicsError naming the body or DOF when the result is not finite (a singular articulated inertia, an input too large for floating point).
    """
def center_of_mass_jacobian(model: _Model, q: typing.Any) -> numpy.typing.NDArray[numpy.float64]:
    """
    Jacobian (3 x nv) of the centre of mass in the world frame: J v is its velocity (m/s).
    
    q: (nq,) coordinates (m, rad; a quaternion as x y z w), v: (nv,) velocities (m/s, rad/s; body-frame for spherical, planar and free joints), accelerations (nv,) likewise per s; generalized forces (nv,) in N for translations and N m for rotations; f_ext: None or (nbodies, 6) body-frame wrenches [torque N m; force N] about each body origin. Units are SI throughout.
    
    Raises TypeError for an argument that is not an array of real numbers; ValueError naming the argument and the coordinate or DOF for a wrong shape, a NaN or infinite entry or a quaternion off unit norm (soadyn.QUATERNION_TOLERANCE); DynamicsError naming the body or DOF when the result is not finite (a singular articulated inertia, an input too large for floating point).
    """
def christoffel_symbols(model: _Model, q: typing.Any) -> numpy.typing.NDArray[numpy.float64]:
    """
    Gamma, (nv, nv, nv), with C(q, v)[i, j] = sum_k Gamma[i, j, k] v[k]. For DOFs whose coordinates
    integrate their velocities, Gamma[i, j, k] = 1/2 (dM[i,j]/dq_k + dM[i,k]/dq_j - dM[j,k]/dq_i) (symmetric in
    j, k); for spherical, planar and free joints (body-frame velocities) the derivatives are along
    q (+) eps e_k and Gamma adds the Lie-bracket terms of that moving frame (the analysis guide, "Equations
    term by term"). Rigid bodies only (ValueError naming a flexible body).
    
    q: (nq,) coordinates (m, rad; a quaternion as x y z w), v: (nv,) velocities (m/s, rad/s; body-frame for spherical, planar and free joints), accelerations (nv,) likewise per s; generalized forces (nv,) in N for translations and N m for rotations; f_ext: None or (nbodies, 6) body-frame wrenches [torque N m; force N] about each body origin. Units are SI throughout.
    
    Raises TypeError for an argument that is not an array of real numbers; ValueError naming the argument and the coordinate or DOF for a wrong shape, a NaN or infinite entry or a quaternion off unit norm (soadyn.QUATERNION_TOLERANCE); DynamicsError naming the body or DOF when the result is not finite (a singular articulated inertia, an input too large for floating point).
    """
def constrained_dynamics(model, q, v, u, f_ext = None, joint_wrenches = False):
    """
    Hybrid dynamics with the model's closed loops: u as in hybrid_dynamics. Returns fresh arrays (qdd, tau,
    loop_wrenches): every DOF's acceleration and generalized force, and per loop (nloops, 6) the wrench
    [torque; force] that frame_b's side exerts on frame_a's side, world-aligned axes, about frame_a's origin;
    with joint_wrenches=True also the (nbodies, 6) joint wrenches of the tree loaded by f_ext and the loop
    forces (as joint_wrenches). Redundant loop equations give minimum-norm multipliers. With more prescribed
    DOFs than the mechanism's mobility (redundant actuation) tau holds the minimum-norm actuator forces: the
    smallest ||tau_p|| over every set of loop forces consistent with the motion. Closure accelerations that
    cannot be met (inconsistent prescribed accelerations, a driven mechanism at a dead centre) raise
    DynamicsError naming the loop. Equals hybrid_dynamics without loops.
    
    q: (nq,) coordinates (m, rad; a quaternion as x y z w), v: (nv,) velocities (m/s, rad/s; body-frame for spherical, planar and free joints), accelerations (nv,) likewise per s; generalized forces (nv,) in N for translations and N m for rotations; f_ext: None or (nbodies, 6) body-frame wrenches [torque N m; force N] about each body origin. Units are SI throughout.
    
    Raises TypeError for an argument that is not an array of real numbers; ValueError naming the argument and the coordinate or DOF for a wrong shape, a NaN or infinite entry or a quaternion off unit norm (soadyn.QUATERNION_TOLERANCE); DynamicsError naming the body or DOF when the result is not finite (a singular articulated inertia, an input too large for floating point).
    """
def coriolis_matrix(model: _Model, q: typing.Any, v: typing.Any) -> numpy.typing.NDArray[numpy.float64]:
    """
    C(q, v), (nv, nv): C v = h(q, v) - g(q) and dM/dt - 2 C is skew-symmetric (Echeandia & Wensing 2021);
    C(q, v) = sum_k christoffel_symbols(m, q)[:, :, k] v[k]. Rigid bodies only (ValueError naming a
    flexible body).
    
    q: (nq,) coordinates (m, rad; a quaternion as x y z w), v: (nv,) velocities (m/s, rad/s; body-frame for spherical, planar and free joints), accelerations (nv,) likewise per s; generalized forces (nv,) in N for translations and N m for rotations; f_ext: None or (nbodies, 6) body-frame wrenches [torque N m; force N] about each body origin. Units are SI throughout.
    
    Raises TypeError for an argument that is not an array of real numbers; ValueError naming the argument and the coordinate or DOF for a wrong shape, a NaN or infinite entry or a quaternion off unit norm (soadyn.QUATERNION_TOLERANCE); DynamicsError naming the body or DOF when the result is not finite (a singular articulated inertia, an input too large for floating point).
    """
def dissipated_power(model: _Model, q: typing.Any, v: typing.Any) -> float:
    """
    Power the dampers dissipate at (q, v), >= 0: the rate at which kinetic plus potential energy falls when no actuator or external force acts; in W.
    
    q: (nq,) coordinates (m, rad; a quaternion as x y z w), v: (nv,) velocities (m/s, rad/s; body-frame for spherical, planar and free joints), accelerations (nv,) likewise per s; generalized forces (nv,) in N for translations and N m for rotations; f_ext: None or (nbodies, 6) body-frame wrenches [torque N m; force N] about each body origin. Units are SI throughout.
    
    Raises TypeError for an argument that is not an array of real numbers; ValueError naming the argument and the coordinate or DOF for a wrong shape, a NaN or infinite entry or a quaternion off unit norm (soadyn.QUATERNION_TOLERANCE); DynamicsError naming the body or DOF when the result is not finite (a singular articulated inertia, an input too large for floating point).
    """
def external_forces_to_generalized(model: _Model, q: typing.Any, f_ext: typing.Any) -> numpy.typing.NDArray[numpy.float64]:
    """
    J(q)' f_ext, (nv,): the generalized forces of (nbodies, 6) body-frame wrenches [torque; force] about each
    body origin (the f_ext of forward_dynamics: M qdd + h = tau + J' f_ext); f_ext of another shape raises
    ValueError naming it.
    
    q: (nq,) coordinates (m, rad; a quaternion as x y z w), v: (nv,) velocities (m/s, rad/s; body-frame for spherical, planar and free joints), accelerations (nv,) likewise per s; generalized forces (nv,) in N for translations and N m for rotations; f_ext: None or (nbodies, 6) body-frame wrenches [torque N m; force N] about each body origin. Units are SI throughout.
    
    Raises TypeError for an argument that is not an array of real numbers; ValueError naming the argument and the coordinate or DOF for a wrong shape, a NaN or infinite entry or a quaternion off unit norm (soadyn.QUATERNION_TOLERANCE); DynamicsError naming the body or DOF when the result is not finite (a singular articulated inertia, an input too large for floating point).
    """
def force_element_potential(model: _Model, q: typing.Any) -> float:
    """
    Potential energy of the springs alone, in J (also included in potential_energy).
    
    q: (nq,) coordinates (m, rad; a quaternion as x y z w), v: (nv,) velocities (m/s, rad/s; body-frame for spherical, planar and free joints), accelerations (nv,) likewise per s; generalized forces (nv,) in N for translations and N m for rotations; f_ext: None or (nbodies, 6) body-frame wrenches [torque N m; force N] about each body origin. Units are SI throughout.
    
    Raises TypeError for an argument that is not an array of real numbers; ValueError naming the argument and the coordinate or DOF for a wrong shape, a NaN or infinite entry or a quaternion off unit norm (soadyn.QUATERNION_TOLERANCE); DynamicsError naming the body or DOF when the result is not finite (a singular articulated inertia, an input too large for floating point).
    """
def force_elements(model: _Model) -> list:
    """
    The model's force elements as a list of dicts (joint springs first, then point springs): name, kind, the
    DOF or the two frames and points, stiffness (N/m or N m/rad), damping (N s/m or N m s/rad), rest value.
    """
def forward_dynamics(model, q, v, tau, f_ext = None):
    """
    Accelerations qdd = M^-1 (tau - h + J' f_ext) by the articulated-body algorithm (every DOF regular,
    whatever the model's flags). f_ext: (nbodies, 6) body-frame wrenches [torque; force] about each body
    origin. Returns a fresh (nv,) array.
    
    q: (nq,) coordinates (m, rad; a quaternion as x y z w), v: (nv,) velocities (m/s, rad/s; body-frame for spherical, planar and free joints), accelerations (nv,) likewise per s; generalized forces (nv,) in N for translations and N m for rotations; f_ext: None or (nbodies, 6) body-frame wrenches [torque N m; force N] about each body origin. Units are SI throughout.
    
    Raises TypeError for an argument that is not an array of real numbers; ValueError naming the argument and the coordinate or DOF for a wrong shape, a NaN or infinite entry or a quaternion off unit norm (soadyn.QUATERNION_TOLERANCE); DynamicsError naming the body or DOF when the result is not finite (a singular articulated inertia, an input too large for floating point).
    """
def forward_kinematics(model: _Model, q: typing.Any, v: typing.Any = None) -> typing.Any:
    """
    (poses, velocities): (nbodies, 4, 4) homogeneous body poses in the world and, with v, (nbodies, 6)
    body-frame spatial velocities [angular rad/s; linear m/s of the body origin].
    
    q: (nq,) coordinates (m, rad; a quaternion as x y z w), v: (nv,) velocities (m/s, rad/s; body-frame for spherical, planar and free joints), accelerations (nv,) likewise per s; generalized forces (nv,) in N for translations and N m for rotations; f_ext: None or (nbodies, 6) body-frame wrenches [torque N m; force N] about each body origin. Units are SI throughout.
    
    Raises TypeError for an argument that is not an array of real numbers; ValueError naming the argument and the coordinate or DOF for a wrong shape, a NaN or infinite entry or a quaternion off unit norm (soadyn.QUATERNION_TOLERANCE); DynamicsError naming the body or DOF when the result is not finite (a singular articulated inertia, an input too large for floating point).
    """
def frame_acceleration(model: _Model, q: typing.Any, v: typing.Any, qdd: typing.Any, frame: typing.Any, reference: typing.Any = 'local', classical: typing.Any = False) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]:
    """
    Spatial acceleration [angular; linear] of the frame, velocity products included, gravity
    not. classical=True: linear rows w x v + (spatial linear), the classical acceleration.
    reference: 'world' (world axes, about the world origin), 'local' (frame axes, about the frame origin) or
    'local_world_aligned' (world axes, about the frame origin). frame: a body name, a frame name (welded links
    included) or a body index; an unknown frame or reference raises ValueError naming it. Angular parts in
    rad/s (rad/s^2), linear parts in m/s (m/s^2).
    
    q: (nq,) coordinates (m, rad; a quaternion as x y z w), v: (nv,) velocities (m/s, rad/s; body-frame for spherical, planar and free joints), accelerations (nv,) likewise per s; generalized forces (nv,) in N for translations and N m for rotations; f_ext: None or (nbodies, 6) body-frame wrenches [torque N m; force N] about each body origin. Units are SI throughout.
    
    Raises TypeError for an argument that is not an array of real numbers; ValueError naming the argument and the coordinate or DOF for a wrong shape, a NaN or infinite entry or a quaternion off unit norm (soadyn.QUATERNION_TOLERANCE); DynamicsError naming the body or DOF when the result is not finite (a singular articulated inertia, an input too large for floating point).
    """
def frame_jacobian(model: _Model, q: typing.Any, frame: typing.Any, reference: typing.Any = 'local') -> numpy.typing.NDArray[numpy.float64]:
    """
    Frame Jacobian (6 x nv, rows [angular; linear]): J v is frame_velocity.
    reference: 'world' (world axes, about the world origin), 'local' (frame axes, about the frame origin) or
    'local_world_aligned' (world axes, about the frame origin). frame: a body name, a frame name (welded links
    included) or a body index; an unknown frame or reference raises ValueError naming it. Angular parts in
    rad/s (rad/s^2), linear parts in m/s (m/s^2).
    
    q: (nq,) coordinates (m, rad; a quaternion as x y z w), v: (nv,) velocities (m/s, rad/s; body-frame for spherical, planar and free joints), accelerations (nv,) likewise per s; generalized forces (nv,) in N for translations and N m for rotations; f_ext: None or (nbodies, 6) body-frame wrenches [torque N m; force N] about each body origin. Units are SI throughout.
    
    Raises TypeError for an argument that is not an array of real numbers; ValueError naming the argument and the coordinate or DOF for a wrong shape, a NaN or infinite entry or a quaternion off unit norm (soadyn.QUATERNION_TOLERANCE); DynamicsError naming the body or DOF when the result is not finite (a singular articulated inertia, an input too large for floating point).
    """
def frame_jacobian_time_variation(model: _Model, q: typing.Any, v: typing.Any, frame: typing.Any, reference: typing.Any = 'local') -> numpy.typing.NDArray[numpy.float64]:
    """
    dJ/dt (6 x nv) of frame_jacobian along v: J qdd + dJ/dt v is frame_acceleration (world,
    local), or its classical form (local_world_aligned).
    reference: 'world' (world axes, about the world origin), 'local' (frame axes, about the frame origin) or
    'local_world_aligned' (world axes, about the frame origin). frame: a body name, a frame name (welded links
    included) or a body index; an unknown frame or reference raises ValueError naming it. Angular parts in
    rad/s (rad/s^2), linear parts in m/s (m/s^2).
    
    q: (nq,) coordinates (m, rad; a quaternion as x y z w), v: (nv,) velocities (m/s, rad/s; body-frame for spherical, planar and free joints), accelerations (nv,) likewise per s; generalized forces (nv,) in N for translations and N m for rotations; f_ext: None or (nbodies, 6) body-frame wrenches [torque N m; force N] about each body origin. Units are SI throughout.
    
    Raises TypeError for an argument that is not an array of real numbers; ValueError naming the argument and the coordinate or DOF for a wrong shape, a NaN or infinite entry or a quaternion off unit norm (soadyn.QUATERNION_TOLERANCE); DynamicsError naming the body or DOF when the result is not finite (a singular articulated inertia, an input too large for floating point).
    """
def frame_pose(model: _Model, q: typing.Any, frame: typing.Any) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[4, 4]"]:
    """
    4x4 homogeneous pose of the frame in the world at q (rotation, translation in m). frame: a body name, a
    frame name (welded links included) or a body index; an unknown frame raises ValueError naming it.
    
    q: (nq,) coordinates (m, rad; a quaternion as x y z w), v: (nv,) velocities (m/s, rad/s; body-frame for spherical, planar and free joints), accelerations (nv,) likewise per s; generalized forces (nv,) in N for translations and N m for rotations; f_ext: None or (nbodies, 6) body-frame wrenches [torque N m; force N] about each body origin. Units are SI throughout.
    
    Raises TypeError for an argument that is not an array of real numbers; ValueError naming the argument and the coordinate or DOF for a wrong shape, a NaN or infinite entry or a quaternion off unit norm (soadyn.QUATERNION_TOLERANCE); DynamicsError naming the body or DOF when the result is not finite (a singular articulated inertia, an input too large for floating point).
    """
def frame_velocity(model: _Model, q: typing.Any, v: typing.Any, frame: typing.Any, reference: typing.Any = 'local') -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]:
    """
    Spatial velocity [angular; linear] of the frame.
    reference: 'world' (world axes, about the world origin), 'local' (frame axes, about the frame origin) or
    'local_world_aligned' (world axes, about the frame origin). frame: a body name, a frame name (welded links
    included) or a body index; an unknown frame or reference raises ValueError naming it. Angular parts in
    rad/s (rad/s^2), linear parts in m/s (m/s^2).
    
    q: (nq,) coordinates (m, rad; a quaternion as x y z w), v: (nv,) velocities (m/s, rad/s; body-frame for spherical, planar and free joints), accelerations (nv,) likewise per s; generalized forces (nv,) in N for translations and N m for rotations; f_ext: None or (nbodies, 6) body-frame wrenches [torque N m; force N] about each body origin. Units are SI throughout.
    
    Raises TypeError for an argument that is not an array of real numbers; ValueError naming the argument and the coordinate or DOF for a wrong shape, a NaN or infinite entry or a quaternion off unit norm (soadyn.QUATERNION_TOLERANCE); DynamicsError naming the body or DOF when the result is not finite (a singular articulated inertia, an input too large for floating point).
    """
def gravity_forces(model: _Model, q: typing.Any) -> numpy.typing.NDArray[numpy.float64]:
    """
    g(q), (nv,): the generalized gravity forces, h(q, 0) (bias_forces at rest). On a model with flexible
    bodies, gravity only (their elastic forces are not part of it). In N and N m by the DOFs' kinds.
    
    q: (nq,) coordinates (m, rad; a quaternion as x y z w), v: (nv,) velocities (m/s, rad/s; body-frame for spherical, planar and free joints), accelerations (nv,) likewise per s; generalized forces (nv,) in N for translations and N m for rotations; f_ext: None or (nbodies, 6) body-frame wrenches [torque N m; force N] about each body origin. Units are SI throughout.
    
    Raises TypeError for an argument that is not an array of real numbers; ValueError naming the argument and the coordinate or DOF for a wrong shape, a NaN or infinite entry or a quaternion off unit norm (soadyn.QUATERNION_TOLERANCE); DynamicsError naming the body or DOF when the result is not finite (a singular articulated inertia, an input too large for floating point).
    """
def hybrid_dynamics(model, q, v, u, f_ext = None, joint_wrenches = False):
    """
    Hybrid dynamics (Jain & Rodriguez 1993, Eqs. 14, 28, 29): u holds the torque of each regular DOF and the acceleration of
    each prescribed DOF (model.prescribed). Returns fresh arrays (qdd, tau) with every DOF's acceleration
    and generalized force, each (nv,), plus the (nbodies, 6) joint wrenches when joint_wrenches=True.
    
    q: (nq,) coordinates (m, rad; a quaternion as x y z w), v: (nv,) velocities (m/s, rad/s; body-frame for spherical, planar and free joints), accelerations (nv,) likewise per s; generalized forces (nv,) in N for translations and N m for rotations; f_ext: None or (nbodies, 6) body-frame wrenches [torque N m; force N] about each body origin. Units are SI throughout.
    
    Raises TypeError for an argument that is not an array of real numbers; ValueError naming the argument and the coordinate or DOF for a wrong shape, a NaN or infinite entry or a quaternion off unit norm (soadyn.QUATERNION_TOLERANCE); DynamicsError naming the body or DOF when the result is not finite (a singular articulated inertia, an input too large for floating point).
    """
def independent_coordinates(model: _Model, q: typing.Any) -> list[str]:
    """
    Names of the independent DOFs at q by coordinate partitioning: the DOFs whose columns of the loop
    constraint Jacobian C(q) carry the largest pivots of a fully pivoted LU factorisation are dependent,
    the others (nv - rank C of them, in DOF order) independent.
    
    q: (nq,) coordinates (m, rad; a quaternion as x y z w), v: (nv,) velocities (m/s, rad/s; body-frame for spherical, planar and free joints), accelerations (nv,) likewise per s; generalized forces (nv,) in N for translations and N m for rotations; f_ext: None or (nbodies, 6) body-frame wrenches [torque N m; force N] about each body origin. Units are SI throughout.
    
    Raises TypeError for an argument that is not an array of real numbers; ValueError naming the argument and the coordinate or DOF for a wrong shape, a NaN or infinite entry or a quaternion off unit norm (soadyn.QUATERNION_TOLERANCE); DynamicsError naming the body or DOF when the result is not finite (a singular articulated inertia, an input too large for floating point).
    """
def integrate(model: _Model, q: typing.Any, v: typing.Any, dt: typing.Any) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]:
    """
    q (+) v dt, (nq,): each joint on its manifold (quaternions by the exponential map; free joints on
    SE(3)); dt in s.
    
    q: (nq,) coordinates (m, rad; a quaternion as x y z w), v: (nv,) velocities (m/s, rad/s; body-frame for spherical, planar and free joints), accelerations (nv,) likewise per s; generalized forces (nv,) in N for translations and N m for rotations; f_ext: None or (nbodies, 6) body-frame wrenches [torque N m; force N] about each body origin. Units are SI throughout.
    
    Raises TypeError for an argument that is not an array of real numbers; ValueError naming the argument and the coordinate or DOF for a wrong shape, a NaN or infinite entry or a quaternion off unit norm (soadyn.QUATERNION_TOLERANCE); DynamicsError naming the body or DOF when the result is not finite (a singular articulated inertia, an input too large for floating point).
    """
def inverse_dynamics(model, q, v, qdd, f_ext = None):
    """
    Generalized forces tau = M qdd + h - J' f_ext (recursive Newton-Euler). Returns a fresh (nv,) array.
    
    q: (nq,) coordinates (m, rad; a quaternion as x y z w), v: (nv,) velocities (m/s, rad/s; body-frame for spherical, planar and free joints), accelerations (nv,) likewise per s; generalized forces (nv,) in N for translations and N m for rotations; f_ext: None or (nbodies, 6) body-frame wrenches [torque N m; force N] about each body origin. Units are SI throughout.
    
    Raises TypeError for an argument that is not an array of real numbers; ValueError naming the argument and the coordinate or DOF for a wrong shape, a NaN or infinite entry or a quaternion off unit norm (soadyn.QUATERNION_TOLERANCE); DynamicsError naming the body or DOF when the result is not finite (a singular articulated inertia, an input too large for floating point).
    """
def joint_wrenches(model: _Model, q: typing.Any, v: typing.Any, qdd: typing.Any, f_ext: typing.Any = None, loop_wrenches: typing.Any = None) -> numpy.typing.NDArray[numpy.float64]:
    """
    Joint reaction wrenches (nbodies, 6): the spatial force [torque; force] the parent exerts on each body
    through its hinge, in the body frame about the body origin, at the given accelerations. On a model with
    closed loops the tree is also loaded by the loop forces, so loop_wrenches (nloops, 6) is required: the
    wrenches constrained_dynamics returns (each acts on frame_a's body about frame_a's origin, its opposite
    on frame_b's body with the force at frame_b's origin, frame_a's for a prismatic loop).
    
    q: (nq,) coordinates (m, rad; a quaternion as x y z w), v: (nv,) velocities (m/s, rad/s; body-frame for spherical, planar and free joints), accelerations (nv,) likewise per s; generalized forces (nv,) in N for translations and N m for rotations; f_ext: None or (nbodies, 6) body-frame wrenches [torque N m; force N] about each body origin. Units are SI throughout.
    
    Raises TypeError for an argument that is not an array of real numbers; ValueError naming the argument and the coordinate or DOF for a wrong shape, a NaN or infinite entry or a quaternion off unit norm (soadyn.QUATERNION_TOLERANCE); DynamicsError naming the body or DOF when the result is not finite (a singular articulated inertia, an input too large for floating point).
    """
def kinetic_energy(model: _Model, q: typing.Any, v: typing.Any) -> float:
    """
    Kinetic energy 1/2 v' M v, in J.
    
    q: (nq,) coordinates (m, rad; a quaternion as x y z w), v: (nv,) velocities (m/s, rad/s; body-frame for spherical, planar and free joints), accelerations (nv,) likewise per s; generalized forces (nv,) in N for translations and N m for rotations; f_ext: None or (nbodies, 6) body-frame wrenches [torque N m; force N] about each body origin. Units are SI throughout.
    
    Raises TypeError for an argument that is not an array of real numbers; ValueError naming the argument and the coordinate or DOF for a wrong shape, a NaN or infinite entry or a quaternion off unit norm (soadyn.QUATERNION_TOLERANCE); DynamicsError naming the body or DOF when the result is not finite (a singular articulated inertia, an input too large for floating point).
    """
def loop_force_stiffness(model: _Model, q: typing.Any, nu: typing.Any) -> numpy.typing.NDArray[numpy.float64]:
    """
    d(C(q)' nu)/dq at fixed multipliers nu (nv, nv), tangent-space columns (column k: d/de at
    integrate(q, e e_k)): the stiffness of the cut-joint reactions C' nu, analytic. nu: (nloop_equations,)
    loop-force multipliers (N, N m), as constrained_dynamics solves them; another shape raises ValueError.
    
    q: (nq,) coordinates (m, rad; a quaternion as x y z w), v: (nv,) velocities (m/s, rad/s; body-frame for spherical, planar and free joints), accelerations (nv,) likewise per s; generalized forces (nv,) in N for translations and N m for rotations; f_ext: None or (nbodies, 6) body-frame wrenches [torque N m; force N] about each body origin. Units are SI throughout.
    
    Raises TypeError for an argument that is not an array of real numbers; ValueError naming the argument and the coordinate or DOF for a wrong shape, a NaN or infinite entry or a quaternion off unit norm (soadyn.QUATERNION_TOLERANCE); DynamicsError naming the body or DOF when the result is not finite (a singular articulated inertia, an input too large for floating point).
    """
def loop_jacobian(model: _Model, q: typing.Any) -> numpy.typing.NDArray[numpy.float64]:
    """
    Loop constraint Jacobian C(q), (nloop_equations, nv): C v is the cut joints' relative velocity.
    
    q: (nq,) coordinates (m, rad; a quaternion as x y z w), v: (nv,) velocities (m/s, rad/s; body-frame for spherical, planar and free joints), accelerations (nv,) likewise per s; generalized forces (nv,) in N for translations and N m for rotations; f_ext: None or (nbodies, 6) body-frame wrenches [torque N m; force N] about each body origin. Units are SI throughout.
    
    Raises TypeError for an argument that is not an array of real numbers; ValueError naming the argument and the coordinate or DOF for a wrong shape, a NaN or infinite entry or a quaternion off unit norm (soadyn.QUATERNION_TOLERANCE); DynamicsError naming the body or DOF when the result is not finite (a singular articulated inertia, an input too large for floating point).
    """
def loop_rank(model: _Model, q: typing.Any) -> int:
    """
    Rank of the loop constraint Jacobian C(q) (column-pivoted QR; pivots below 1e3 machine epsilons times
    the largest count as zero).
    
    q: (nq,) coordinates (m, rad; a quaternion as x y z w), v: (nv,) velocities (m/s, rad/s; body-frame for spherical, planar and free joints), accelerations (nv,) likewise per s; generalized forces (nv,) in N for translations and N m for rotations; f_ext: None or (nbodies, 6) body-frame wrenches [torque N m; force N] about each body origin. Units are SI throughout.
    
    Raises TypeError for an argument that is not an array of real numbers; ValueError naming the argument and the coordinate or DOF for a wrong shape, a NaN or infinite entry or a quaternion off unit norm (soadyn.QUATERNION_TOLERANCE); DynamicsError naming the body or DOF when the result is not finite (a singular articulated inertia, an input too large for floating point).
    """
def loop_residual(model: _Model, q: typing.Any, v: typing.Any = None) -> typing.Any:
    """
    Loop-closure residual Psi(q) (nloop_equations,), and with v the tuple (Psi(q), C(q) v): per loop, the
    cut joint's constrained relative displacements (m, rad) and velocities (m/s, rad/s).
    
    q: (nq,) coordinates (m, rad; a quaternion as x y z w), v: (nv,) velocities (m/s, rad/s; body-frame for spherical, planar and free joints), accelerations (nv,) likewise per s; generalized forces (nv,) in N for translations and N m for rotations; f_ext: None or (nbodies, 6) body-frame wrenches [torque N m; force N] about each body origin. Units are SI throughout.
    
    Raises TypeError for an argument that is not an array of real numbers; ValueError naming the argument and the coordinate or DOF for a wrong shape, a NaN or infinite entry or a quaternion off unit norm (soadyn.QUATERNION_TOLERANCE); DynamicsError naming the body or DOF when the result is not finite (a singular articulated inertia, an input too large for floating point).
    """
def mass_matrix(model: _Model, q: typing.Any) -> numpy.typing.NDArray[numpy.float64]:
    """
    Joint-space mass matrix M(q), (nv, nv) (composite-rigid-body algorithm), in kg,
    kg m and kg m^2 by the DOFs' kinds.
    
    q: (nq,) coordinates (m, rad; a quaternion as x y z w), v: (nv,) velocities (m/s, rad/s; body-frame for spherical, planar and free joints), accelerations (nv,) likewise per s; generalized forces (nv,) in N for translations and N m for rotations; f_ext: None or (nbodies, 6) body-frame wrenches [torque N m; force N] about each body origin. Units are SI throughout.
    
    Raises TypeError for an argument that is not an array of real numbers; ValueError naming the argument and the coordinate or DOF for a wrong shape, a NaN or infinite entry or a quaternion off unit norm (soadyn.QUATERNION_TOLERANCE); DynamicsError naming the body or DOF when the result is not finite (a singular articulated inertia, an input too large for floating point).
    """
def mass_matrix_derivative(model: _Model, q: typing.Any, v: typing.Any) -> numpy.typing.NDArray[numpy.float64]:
    """
    dM/dt = C + C', (nv, nv): the rate of the mass matrix along the velocity v. Rigid bodies only (ValueError
    naming a flexible body).
    
    q: (nq,) coordinates (m, rad; a quaternion as x y z w), v: (nv,) velocities (m/s, rad/s; body-frame for spherical, planar and free joints), accelerations (nv,) likewise per s; generalized forces (nv,) in N for translations and N m for rotations; f_ext: None or (nbodies, 6) body-frame wrenches [torque N m; force N] about each body origin. Units are SI throughout.
    
    Raises TypeError for an argument that is not an array of real numbers; ValueError naming the argument and the coordinate or DOF for a wrong shape, a NaN or infinite entry or a quaternion off unit norm (soadyn.QUATERNION_TOLERANCE); DynamicsError naming the body or DOF when the result is not finite (a singular articulated inertia, an input too large for floating point).
    """
def momentum(model: _Model, q: typing.Any, v: typing.Any) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]:
    """
    Spatial momentum (6,) [angular about the world origin, N m s; linear, N s] in world axes.
    
    q: (nq,) coordinates (m, rad; a quaternion as x y z w), v: (nv,) velocities (m/s, rad/s; body-frame for spherical, planar and free joints), accelerations (nv,) likewise per s; generalized forces (nv,) in N for translations and N m for rotations; f_ext: None or (nbodies, 6) body-frame wrenches [torque N m; force N] about each body origin. Units are SI throughout.
    
    Raises TypeError for an argument that is not an array of real numbers; ValueError naming the argument and the coordinate or DOF for a wrong shape, a NaN or infinite entry or a quaternion off unit norm (soadyn.QUATERNION_TOLERANCE); DynamicsError naming the body or DOF when the result is not finite (a singular articulated inertia, an input too large for floating point).
    """
def neutral_configuration(model: _Model) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]:
    """
    The neutral configuration (nq,): zero coordinates with identity quaternions.
    """
def potential_energy(model: _Model, q: typing.Any) -> float:
    """
    Potential energy in J: gravity's, -sum m g.c (zero at the world
    origin), plus the flexible bodies' strain energy and the springs' (force_element_potential).
    
    q: (nq,) coordinates (m, rad; a quaternion as x y z w), v: (nv,) velocities (m/s, rad/s; body-frame for spherical, planar and free joints), accelerations (nv,) likewise per s; generalized forces (nv,) in N for translations and N m for rotations; f_ext: None or (nbodies, 6) body-frame wrenches [torque N m; force N] about each body origin. Units are SI throughout.
    
    Raises TypeError for an argument that is not an array of real numbers; ValueError naming the argument and the coordinate or DOF for a wrong shape, a NaN or infinite entry or a quaternion off unit norm (soadyn.QUATERNION_TOLERANCE); DynamicsError naming the body or DOF when the result is not finite (a singular articulated inertia, an input too large for floating point).
    """
def random_configuration(model: _Model, seed: typing.Any = 0) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]:
    """
    A random configuration (nq,) from the integer seed: angles in [-pi, pi] rad, offsets in [-1, 1] m,
    uniform unit quaternions.
    """
QUATERNION_TOLERANCE: float = 1e-06
_pybind11_version: str = '3.1.0'
