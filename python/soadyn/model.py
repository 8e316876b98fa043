"""Model: the multibody tree, with Python argument handling on top of the C++ core."""
from __future__ import annotations

import copy
import numbers
from typing import Iterable, Union

import numpy as np

from . import _soadyn
from ._soadyn import FlexibleBody, Joint, LoopError, NonphysicalInertiaError, _Model, _add_joint_spring, _add_point_spring
from .viz.visuals import Visual

__all__ = ["Model", "Joint", "NonphysicalInertiaError"]

Placement = Union[None, tuple, np.ndarray]


def _real_array(x, what: str, body: str, owner: str = "body") -> np.ndarray:
    """`x` as a float array; TypeError naming the argument and the body unless it holds real numbers.

    numpy would read a string ('1.5') as a number and drop a complex number's
    imaginary part: both are refused, as are booleans and None.
    """
    if isinstance(x, (str, bytes)):
        raise TypeError(f"{owner} '{body}': {what} must be real numbers, got {type(x).__name__}")
    try:
        a = np.asarray(x)
    except (TypeError, ValueError) as exc:  # ragged nesting
        raise TypeError(f"{owner} '{body}': {what} must be real numbers, got {type(x).__name__}") from exc
    if a.dtype.kind not in "iuf":
        raise TypeError(f"{owner} '{body}': {what} must be real numbers, got {a.dtype} "
                        f"({type(x).__name__})")
    return a.astype(float)


def _real_scalar(x, what: str, body: str, owner: str = "body") -> float:
    if isinstance(x, (bool, np.bool_)) or not isinstance(x, (numbers.Real, np.ndarray)):
        raise TypeError(f"{owner} '{body}': {what} must be a real number, got {type(x).__name__}")
    a = _real_array(x, what, body, owner)
    if a.shape != ():
        raise TypeError(f"{owner} '{body}': {what} must be a real number, got an array of shape {a.shape}")
    return float(a)


def _placement(placement: Placement, body: str, owner: str = "body"):
    """(R, p), a 4x4 homogeneous matrix, a translation p, or None (identity)."""
    if placement is None:
        return np.eye(3), np.zeros(3)
    if isinstance(placement, tuple) and len(placement) == 2:
        R, p = placement
        R = np.eye(3) if R is None else _real_array(R, "placement rotation", body, owner)
        p = np.zeros(3) if p is None else _real_array(p, "placement translation", body, owner)
    else:
        T = _real_array(placement, "placement", body, owner)
        if T.shape == (4, 4):
            R, p = T[:3, :3], T[:3, 3]
        elif T.shape == (3,):
            R, p = np.eye(3), T
        else:
            raise ValueError(f"{owner} '{body}': placement must be (R, p), a 4x4 matrix or a translation, "
                             f"got shape {T.shape}")
    if R.shape != (3, 3) or p.shape != (3,):
        raise ValueError(f"{owner} '{body}': placement rotation must be 3x3 and translation length 3")
    return R, p


def _inertia(inertia, body: str) -> np.ndarray:
    """A 3x3 matrix or the 3 principal moments (diagonal)."""
    I = _real_array(inertia, "inertia", body)
    if I.shape == (3,):
        return np.diag(I)
    if I.shape != (3, 3):
        raise ValueError(f"body '{body}': inertia must be 3x3 or 3 principal moments, got shape {I.shape}")
    return I


def _vector3(x, what: str, body: str) -> np.ndarray:
    a = _real_array(x, what, body)
    if a.shape != (3,):
        raise ValueError(f"body '{body}': {what} must have 3 components, got shape {a.shape}")
    return a


def _refuse_ambiguous_indices(indices: np.ndarray, nv: int) -> None:
    """Integer DOF indices for set_prescribed: refuse repeats, and nv zeros and
    ones, which may as well be a mask written with integers."""
    if indices.size == nv and np.isin(indices, (0, 1)).all():
        raise ValueError(f"set_prescribed: an integer array of {nv} zeros and ones is ambiguous (a mask or DOF "
                         "indices?): pass a bool mask (np.asarray(mask, dtype=bool)) or DOF names")
    values, counts = np.unique(indices, return_counts=True)
    if (counts > 1).any():
        raise ValueError(f"set_prescribed: DOF index {int(values[counts > 1][0])} is given more than once")


def parameter_name(name) -> str:
    """`name` if it is a str (a parameter name); TypeError naming it otherwise."""
    if not isinstance(name, str):
        raise TypeError(f"parameter name must be a str, got {type(name).__name__} ({name!r})")
    return name


def _body_name(name) -> str:
    if not isinstance(name, str):
        raise TypeError(f"body name must be a str, got {type(name).__name__} ({name!r})")
    return name


class Model(_Model):
    """A rigid multibody tree.

    Bodies are stored in the order they are added (parent before child). The
    model owns preallocated scratch (Data) reused by every dynamics call;
    calls on one model from several threads are serialised, so give each
    thread its own ``model.copy()`` to run in parallel.
    """

    def add_body(self, name: str, parent, joint: Joint, placement: Placement = None, mass: float = 0.0,
                 com=(0.0, 0.0, 0.0), inertia=(0.0, 0.0, 0.0), *, accept_nonphysical_inertia: bool = False) -> int:
        """Add a body and return its index (-1 for a fixed joint, whose body is merged into the parent).

        parent: None or -1 for the world, or a body (or frame) name or index.
        placement: the joint frame in the parent's frame, as (R, p), a 4x4 matrix or a translation.
        mass, com (body frame), inertia about the centre of mass in the body frame (3x3 or principal moments).
        The spatial inertia (mass, mass * com, inertia about the frame origin) must be finite, and the
        body (with what is welded to it) physical: NonphysicalInertiaError otherwise, unless
        accept_nonphysical_inertia=True opts out of the physical tests (never of the finite one).
        An argument of the wrong type (a string mass, a complex com) raises TypeError naming it.
        """
        name = _body_name(name)
        if not isinstance(joint, Joint):
            raise TypeError(f"body '{name}': joint must be a soadyn.Joint, got {type(joint).__name__}")
        if not isinstance(accept_nonphysical_inertia, (bool, np.bool_)):
            raise TypeError(f"body '{name}': accept_nonphysical_inertia must be a bool, "
                            f"got {type(accept_nonphysical_inertia).__name__}")
        parent_name = self._parent_name(parent, name)
        R, p = _placement(placement, name)
        return self._add_body(name, parent_name, joint, R, p, _real_scalar(mass, "mass", name),
                              _vector3(com, "com", name), _inertia(inertia, name), bool(accept_nonphysical_inertia))

    def add_flexible_body(self, name: str, parent, body: FlexibleBody, joint: Joint | None = None,
                          placement: Placement = None) -> int:
        """Add a flexible body (modal deformation) and return its index.

        Its reference frame is the joint frame; its mass and deformation come
        from `body` (a FlexibleBody). joint None clamps it to the parent (a
        fixed joint; it stays a body with modal DOFs only). Its modal
        coordinates are DOFs named '<name>:mode<k>', k = 1..n_modes, after the
        joint's DOFs; they are always regular. Each attachment node becomes a
        frame '<name>:<attachment>' that add_body accepts as a parent.
        """
        name = _body_name(name)
        if not isinstance(body, FlexibleBody):
            raise TypeError(f"body '{name}': body must be a soadyn.FlexibleBody, got {type(body).__name__}")
        joint = Joint.fixed() if joint is None else joint
        if not isinstance(joint, Joint):
            raise TypeError(f"body '{name}': joint must be a soadyn.Joint, got {type(joint).__name__}")
        R, p = _placement(placement, name)
        return self._add_flexible_body(name, self._parent_name(parent, name), joint, R, p, body)

    def add_loop(self, name: str, frame_a, frame_b, kind: str, placement_a: Placement = None,
                 placement_b: Placement = None, length: float | None = None, q=None) -> int:
        """Add a closed loop (a cut joint) and return its index.

        frame_a: a body or frame name (or body index); frame_b: a body or frame name, or None for the world.
        kind: "point" (3 equations: the frames' origins coincide), "revolute" (5: origins coincide and z axes
        stay aligned), "prismatic" (5: equal orientations, frame_a's origin on frame_b's z axis), "weld" (6),
        "distance" (1: a massless rod of `length` between the origins; without length, the rod has the current
        length: the distance between the two frames at configuration `q`, or at the model's neutral
        configuration (soadyn.neutral_configuration) when q is None).
        placement_a/placement_b: the loop frames in frame_a's/frame_b's frame, as (R, p), a 4x4 matrix or a
        translation. Loops on flexible bodies are refused. Raises LoopError naming the loop at fault.
        """
        if not isinstance(name, str):
            raise TypeError(f"loop name must be a str, got {type(name).__name__} ({name!r})")
        if not isinstance(kind, str):
            raise TypeError(f"loop '{name}': kind must be a str, got {type(kind).__name__}")
        Ra, pa = _placement(placement_a, name, "loop")
        Rb, pb = _placement(placement_b, name, "loop")
        a_name = self._parent_name(frame_a, name) if frame_a is not None else ""
        b_name = self._parent_name(frame_b, name)
        if q is not None and (kind != "distance" or length is not None):
            raise LoopError(f"loop '{name}': q= gives the length of a distance loop without length=")
        if length is None:
            length = 0.0  # C++: a distance loop of length 0 measures it (at q, or at the neutral configuration)
        else:
            length = float(_real_array(length, "length", name, "loop"))
            if kind == "distance" and not length > 0:
                raise LoopError(f"loop '{name}': a distance loop needs a finite, positive length")
        if q is not None:
            _soadyn.forward_kinematics(self, q)  # checks q: shape, finite, unit quaternions (named errors)
            q = np.ascontiguousarray(q, dtype=float)
        return self._add_loop(name, a_name, b_name, kind, Ra, pa, Rb, pb, length, q)

    def add_joint_spring(self, name: str, dof, stiffness: float, damping: float = 0.0, rest: float = 0.0) -> int:
        """Add a spring-damper on one DOF and return its index among the joint springs.

        Generalized force on the DOF: -stiffness (q - rest) - damping v, q the DOF's coordinate. `dof` is a DOF
        name (or the name of a one-DOF joint) or a velocity index. DOFs whose coordinate is not a scalar with
        q' = v (planar, spherical and free joints) and modal DOFs are refused. The spring acts in every dynamics
        call, in the Simulator, and its potential 1/2 stiffness (q - rest)^2 is part of potential_energy.
        Raises ValueError naming the element (duplicate name, unknown DOF, negative or non-finite constants).
        """
        if not isinstance(name, str):
            raise TypeError(f"force element name must be a str, got {type(name).__name__} ({name!r})")
        try:
            dofs = self._dof_indices(dof)
        except (TypeError, ValueError) as exc:
            raise ValueError(f"force element '{name}': {exc}") from exc
        if len(dofs) != 1:
            raise ValueError(f"force element '{name}': '{dof}' selects {len(dofs)} DOFs; name one DOF")
        k, c, r = (_real_scalar(x, what, name, "force element") for x, what in
                   ((stiffness, "stiffness"), (damping, "damping"), (rest, "rest")))
        return _add_joint_spring(self, name, dofs[0], k, c, r)

    def add_point_spring(self, name: str, frame_a, frame_b, stiffness: float, damping: float = 0.0,
                         rest_length: float | None = None, placement_a=None, placement_b=None,
                         force_law=None) -> int:
        """Add a spring-damper along the line between two points and return its index among the point springs.

        Point A is placement_a (a translation, or any placement soadyn accepts: only its translation matters)
        in the frame of body or frame `frame_a`; point B likewise in `frame_b` (None or "world": the world).
        Tension T = stiffness (L - rest_length) + F(L) + damping dL/dt, L the distance between the points;
        A is pulled towards B by T and B towards A (equal and opposite forces). rest_length None: the length at
        the neutral configuration. force_law: optional table (lengths, forces) of the tension F against length,
        interpolated by the monotone piecewise-cubic Hermite spline (Fritsch-Carlson; the interpolant of
        scipy.interpolate.PchipInterpolator, no overshoot, so jounce stops stay monotone) and continued
        linearly with the end slopes outside the table. Potential: 1/2 stiffness (L - rest_length)^2 plus the
        integral of F from the table's first length. Point springs on flexible bodies are refused.
        Raises ValueError naming the element at fault.
        """
        if not isinstance(name, str):
            raise TypeError(f"force element name must be a str, got {type(name).__name__} ({name!r})")
        a_name = "" if frame_a == "world" else self._parent_name(frame_a, name)
        b_name = "" if frame_b == "world" else self._parent_name(frame_b, name)
        _, pa = _placement(placement_a, name, "force element")
        _, pb = _placement(placement_b, name, "force element")
        k = _real_scalar(stiffness, "stiffness", name, "force element")
        c = _real_scalar(damping, "damping", name, "force element")
        rest = None if rest_length is None else _real_scalar(rest_length, "rest_length", name, "force element")
        lengths: list = []
        forces: list = []
        if force_law is not None:
            try:
                lengths, forces = force_law
            except (TypeError, ValueError) as exc:
                raise ValueError(f"force element '{name}': force_law must be a pair (lengths, forces)") from exc
            lengths = _real_array(lengths, "force_law lengths", name, "force element")
            forces = _real_array(forces, "force_law forces", name, "force element")
            if lengths.ndim != 1 or forces.ndim != 1:
                raise ValueError(f"force element '{name}': force_law lengths and forces must be 1-D")
            lengths, forces = list(lengths), list(forces)
        return _add_point_spring(self, name, a_name, b_name, pa, pb, k, c, rest, lengths, forces)

    def _parent_name(self, parent, name: str) -> str:
        if parent is None:
            return ""
        if isinstance(parent, (bool, np.bool_)):
            raise TypeError(f"body '{name}': parent must be None, a name or an index, got bool")
        if isinstance(parent, (int, np.integer)):
            if parent == -1:
                return ""
            if 0 <= parent < self.nbodies:
                return self.body_names[parent]
            raise ValueError(f"body '{name}': parent index {parent} does not exist "
                             f"(the model has {self.nbodies} bodies)")
        if isinstance(parent, str):
            if parent == "":
                raise ValueError(f"body '{name}': parent name is empty (use None for the world)")
            return parent
        raise TypeError(f"body '{name}': parent must be None, a name or an index, got {type(parent).__name__}")

    def _dof_indices(self, selection) -> list[int]:
        """DOF indices of a name, index, or iterable of them. A joint name selects all its DOFs."""
        if isinstance(selection, (str, int, np.integer)):
            items = [selection]
        else:
            try:
                items = list(selection)
            except TypeError:
                raise TypeError(f"DOF selector {selection!r} is neither a name, an index nor a list of them") from None
        names = self.dof_names
        out: list[int] = []
        for item in items:
            if isinstance(item, (int, np.integer)) and not isinstance(item, bool):
                if not 0 <= item < self.nv:
                    raise ValueError(f"DOF index {item} is out of range (nv = {self.nv})")
                out.append(int(item))
                continue
            if not isinstance(item, str):
                raise TypeError(f"DOF selector {item!r} is neither a name nor an index")
            k = self.dof_index(item)
            if k >= 0:
                out.append(k)
                continue
            prefix = item + ":"
            modal = self.modal
            joint_dofs = [i for i, n in enumerate(names) if n.startswith(prefix) and not modal[i]]
            if not joint_dofs:
                raise ValueError(f"unknown DOF or joint '{item}'")
            out.extend(joint_dofs)
        return out

    def set_prescribed(self, mask_or_names, flag: bool = True) -> None:
        """Mark DOFs prescribed (flag=True) or regular (flag=False).

        A boolean array of length nv sets every DOF at once: prescribed where
        it equals ``flag``. Names (a DOF, or a joint for all its DOFs),
        indices, or lists of them change only those DOFs. Changing flags
        allocates nothing and needs no re-initialisation.
        """
        if not isinstance(flag, (bool, np.bool_)):
            raise TypeError(f"set_prescribed: flag must be True or False, got {flag!r}")
        arr = np.asarray(mask_or_names) if not isinstance(mask_or_names, str) else None
        if arr is not None and arr.dtype == bool:
            if arr.shape != (self.nv,):
                raise ValueError(f"prescribed mask has shape {arr.shape}, expected ({self.nv},)")
            self._set_prescribed_mask([bool(x) == bool(flag) for x in arr])
            return
        if arr is not None and arr.dtype.kind in "iu" and arr.ndim == 1:
            _refuse_ambiguous_indices(arr, self.nv)
        self._set_prescribed_indices(self._dof_indices(mask_or_names), bool(flag))

    def set_armature(self, dof, value: float) -> None:
        """Give DOFs an armature: a rotor inertia on the DOF itself (MuJoCo's ``armature``).

        ``dof`` is a DOF name, a joint name (all its DOFs), an index, or a list of them. The mass
        matrix carries the armature on its diagonal (tau_k = ... + armature_k qdd_k) in every
        dynamics call, and kinetic energy gains armature_k v_k^2 / 2. Finite and non-negative;
        modal coordinates have none. A refused value changes nothing.
        """
        value = _real_scalar(value, "armature", str(dof), "DOF")
        self._set_armature(self._dof_indices(dof), value)

    def set_effort_limit(self, dof, value: float) -> None:
        """Give DOFs an effort limit: the largest force or torque their actuator applies.

        ``dof`` as in set_armature. Positive; ``inf`` removes the limit. Loaders set it from URDF
        ``<limit effort>`` and MJCF ``forcerange`` (or ``ctrlrange`` times ``gear``); model files keep
        it; HIL runs take it as the DOF's command limit (soadyn.hil). A refused value changes nothing.
        """
        value = _real_scalar(value, "effort limit", str(dof), "DOF")
        self._set_effort_limit(self._dof_indices(dof), value)

    def set_regular(self, names) -> None:
        """Mark the named DOFs regular (torque given)."""
        self.set_prescribed(names, False)

    @property
    def parameter_names(self) -> list:
        """Names of the model's parameters: per rigid body <body>.mass (float), .com (3,), .inertia (3, 3; about
        the centre of mass, body frame), per body (flexible ones included) .placement (4, 4: the joint frame in the
        parent body's frame), each force element's constants (<element>.stiffness, .damping, ...), and gravity
        (3,). A body carries what is welded to it by fixed joints; a welded part has no parameters of its own."""
        return _soadyn._parameter_names(self)

    def get_parameter(self, name: str):
        """The value of a named parameter: a float or a numpy array (shapes as in parameter_names)."""
        return _soadyn._get_parameter(self, parameter_name(name))

    def set_parameter(self, name: str, value) -> None:
        """Change a named parameter in place (no structural change; in C++ no allocation). A placement also
        takes (R, p). ParameterError (a ValueError) names an unknown parameter, a wrong shape or a non-finite
        or out-of-range value; NonphysicalInertiaError an impossible mass distribution. A refused value changes
        nothing."""
        name = parameter_name(name)
        if name.endswith(".placement") and isinstance(value, tuple):
            R, p = _placement(value, name[: -len(".placement")])
            value = np.eye(4)
            value[:3, :3], value[:3, 3] = R, p
        _soadyn._set_parameter(self, name, value)

    @property
    def visuals(self) -> list:
        """How the model is drawn: a list of soadyn.Visual (description data the dynamics never use)."""
        visuals = self.__dict__.get("_visuals")
        if visuals is None:
            visuals = self.__dict__["_visuals"] = []
        return visuals

    @visuals.setter
    def visuals(self, visuals) -> None:
        visuals = list(visuals)
        for v in visuals:
            if not isinstance(v, Visual):
                raise TypeError(f"visuals must be soadyn.Visual objects, got {type(v).__name__}")
        self.__dict__["_visuals"] = visuals

    def copy(self) -> "Model":
        """An independent copy (same parameters, flags and visuals, its own scratch)."""
        other = Model()
        other._copy_from(self)
        other.visuals = [copy.deepcopy(v) for v in self.visuals]
        return other

    def __copy__(self) -> "Model":
        return self.copy()

    def __deepcopy__(self, memo) -> "Model":
        return self.copy()

    def __repr__(self) -> str:
        return f"<soadyn.Model nbodies={self.nbodies} nq={self.nq} nv={self.nv}>"
