"""Events of a HIL run: lock or release a DOF or joint at a simulation time."""
from __future__ import annotations

import math
import re
from dataclasses import dataclass


@dataclass
class HilEvent:
    """A lock or release of a DOF (or of every DOF of a joint) at a simulation time in s, as `soadyn hil
    --event "lock scan_az at 2.5"` gives it (parse_event)."""

    kind: str  # 'lock' or 'release'
    target: str  # DOF or joint name
    time: float

    def __str__(self) -> str:
        return f"{self.kind} {self.target} at {self.time:g}"


_EVENT = re.compile(r"^\s*(lock|release)\s+(\S+)\s+at\s+(\S+)\s*$")


def parse_event(text: str) -> HilEvent:
    """'lock <dof-or-joint> at <seconds>' or 'release <dof-or-joint> at <seconds>'.

    Returns a HilEvent; ValueError quoting the text when it is not of that form or its time is not a finite
    number >= 0.
    """
    match = _EVENT.match(text)
    if not match:
        raise ValueError(f"bad event {text!r}: expected 'lock <dof-or-joint> at <seconds>' "
                         "or 'release <dof-or-joint> at <seconds>'")
    kind, target, when = match.groups()
    try:
        time = float(when)
    except ValueError:
        raise ValueError(f"bad event {text!r}: the time {when!r} is not a number") from None
    if not (math.isfinite(time) and time >= 0):
        raise ValueError(f"bad event {text!r}: the time must be finite and >= 0")
    return HilEvent(kind, target, time)
