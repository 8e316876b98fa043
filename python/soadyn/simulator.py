"""Simulator: fixed-step simulation with motion sources and run-time events."""
from __future__ import annotations

import math
import numbers
import os
import zipfile
from dataclasses import dataclass

import numpy as np

from ._soadyn import DynamicsError, MotionSource, _Simulator

__all__ = ["Simulator", "Trajectory", "MotionSource", "STEP_TOLERANCE"]

# run(duration) accepts a duration whose step count duration / dt is this
# close to a whole number (absorbs the rounding of decimal durations such as
# 0.3 / 0.1 = 2.9999999999999996) and refuses any other.
STEP_TOLERANCE = 1e-6
# run() records every step: a bound on one call's step count (its arrays).
MAX_RUN_STEPS = 10**9


def read_arrays(path, names) -> dict[str, np.ndarray]:
    """{name: float array} of `names` in .npz file `path`; ValueError naming the file and what is wrong."""
    if os.path.isfile(path) and not zipfile.is_zipfile(path):
        raise ValueError(f"trajectory file '{path}': not a .npz archive (what numpy.savez and Trajectory.save write)")
    try:
        with np.load(path, allow_pickle=False) as data:
            missing = [name for name in names if name not in data.files]
            if missing:
                raise KeyError(f"lacks {', '.join(missing)} (has {', '.join(data.files) or 'nothing'})")
            return {name: np.array(data[name], dtype=float) for name in names}
    except (OSError, EOFError, ValueError, KeyError, AttributeError, TypeError) as error:
        message = error.args[0] if isinstance(error, KeyError) else " ".join(str(error).split())
        raise ValueError(f"trajectory file '{path}': {message}") from None


@dataclass
class Trajectory:
    """Recorded states: t (N+1), q (N+1, nq), v (N+1, nv), and tau (N, nv), the
    generalized forces at the start of each step (drive torques on prescribed DOFs)."""

    t: np.ndarray
    q: np.ndarray
    v: np.ndarray
    tau: np.ndarray

    def save(self, path) -> None:
        """Write t, q, v and tau to a .npz file (what `soadyn view --trajectory` and Trajectory.load read)."""
        np.savez(path, t=self.t, q=self.q, v=self.v, tau=self.tau)

    @classmethod
    def load(cls, path) -> "Trajectory":
        """The Trajectory a save() wrote; ValueError naming the file and what it lacks."""
        names = ("t", "q", "v", "tau")
        arrays = read_arrays(path, names)
        return cls(*(arrays[name] for name in names))


class Simulator(_Simulator):
    """Steps a copy of `model` by `dt` with 'euler' (semi-implicit), 'rk4' or 'dopri5' (adaptive, sub-stepping).

    DOFs the model marks prescribed start locked (zero velocity). DOFs are
    given by name or index; a joint name selects all of its DOFs for
    lock/release.

    Thread-safe: calls from several threads run one after another (each
    holds the simulator's lock; run() holds it for the whole run).
    """

    def __init__(self, model, dt: float, integrator: str = "rk4", event_capacity: int = 64):
        # The simulator steps its own copy: names are resolved, and energies
        # measured, on that copy, whatever later happens to `model`.
        own = model.copy() if hasattr(model, "copy") else model
        super().__init__(own, dt, integrator, event_capacity)
        self._model = own

    def _dofs(self, dof) -> list[int]:
        return self._model._dof_indices(dof)

    def _one_dof(self, dof) -> int:
        dofs = self._dofs(dof)
        if len(dofs) != 1:
            raise ValueError(f"{dof!r} names {len(dofs)} DOFs; give one DOF")
        return dofs[0]

    def set_state(self, q, v, t: float = 0.0) -> None:
        """Set the state: q (nq,), v (nv,) and the time t in s. Raises TypeError or ValueError naming the
        argument and the coordinate or DOF for a wrong type or shape, a non-finite entry or a quaternion off
        unit norm; the state is unchanged then."""
        self._set_state(q, v, t)

    def set_input(self, dof, torque: float) -> None:
        """Torque (or force) applied to a regular DOF from now on."""
        self._set_input(self._one_dof(dof), torque)

    def set_external_wrench(self, body, wrench) -> None:
        """External wrench on a body from now on, held until changed: (6,) [torque; force] in the body's frame
        about its origin (N m, N), as f_ext of forward_dynamics. `body`: a body name or index; ValueError
        names an unknown body or a wrong, non-finite wrench entry."""
        index = self._model.body_index(body) if isinstance(body, str) else body
        if isinstance(index, bool) or not isinstance(index, numbers.Integral) or not 0 <= index < self._model.nbodies:
            raise ValueError(f"body {body!r} is not a body of the model (names: {', '.join(self._model.body_names)})")
        self._set_external_wrench(int(index), wrench)

    def prescribe(self, dof, source: MotionSource) -> None:
        """Drive the DOF by `source` from now on (positions continuous; a velocity jump is an impulse)."""
        self._prescribe(self._one_dof(dof), source)

    def _drivable(self, dof) -> list[int]:
        dofs = self._dofs(dof)
        self._model._require_regular_modal_dofs(dofs)  # all checked before any changes
        return dofs

    def lock(self, dof) -> None:
        """Stop the DOF(s) now with the impulse that brings them to rest (see energy_lost)."""
        for k in self._drivable(dof):
            self._lock(k)

    def release(self, dof) -> None:
        """Make the DOF(s) regular again from now on (after a lock or a prescription), keeping their velocity.
        `dof`: a DOF or joint name or a velocity index; ValueError names an unknown one or a modal DOF."""
        for k in self._drivable(dof):
            self._release(k)

    def schedule(self, t: float, kind: str, dof, source: MotionSource | None = None) -> None:
        """Schedule 'lock', 'release' or 'prescribe' (with `source`) at time t."""
        if kind == "prescribe":
            if source is None:
                raise ValueError("a 'prescribe' event needs a source")
            self._schedule_prescribe(t, self._one_dof(dof), source)
            return
        for k in self._dofs(dof):
            self._schedule(t, kind, k)

    def steps_in(self, duration: float) -> int:
        """The number of steps of dt in `duration` seconds; refuses a duration
        that is not a whole number of steps (within STEP_TOLERANCE of a step)."""
        if isinstance(duration, bool) or not isinstance(duration, numbers.Real):
            raise TypeError(f"duration must be a real number of seconds, got {type(duration).__name__}")
        d = float(duration)
        if not math.isfinite(d) or d < 0:
            raise ValueError(f"duration must be a finite number of seconds >= 0, got {duration!r}")
        exact = d / self.dt  # inf when dt is tiny (5e-324): refused below, never rounded
        if not exact <= MAX_RUN_STEPS + 0.5:
            raise ValueError(f"duration {d!r} s is {exact:.3g} steps of dt = {self.dt!r} s: run() records every "
                             f"step, at most {MAX_RUN_STEPS} per call; run in pieces or give a larger dt")
        steps = round(exact)
        if abs(exact - steps) > STEP_TOLERANCE:
            raise ValueError(f"duration {d!r} s is {exact:.9g} steps of dt = {self.dt!r} s, not a whole number: "
                             f"give a multiple of dt (within {STEP_TOLERANCE:g} of a step), e.g. "
                             f"{math.floor(exact) * self.dt!r} or {math.ceil(exact) * self.dt!r}")
        return steps

    def run(self, duration: float) -> Trajectory:
        """Run for `duration` seconds (a whole number of steps) in C++ with the GIL released; returns the trajectory.

        A failure (singular articulated inertia, non-finite state, a motion
        source failing, dopri5's sub-step limit) stops the run and raises
        DynamicsError; the exception's `trajectory` holds the steps done and
        the simulator is left after the last step done.
        """
        t, q, v, tau, done, error = self._run(self.steps_in(duration))
        trajectory = Trajectory(t[:done + 1], q[:done + 1], v[:done + 1], tau[:done])
        if error is not None:
            error.trajectory = trajectory
            raise error
        return trajectory
