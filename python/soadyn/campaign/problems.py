"""How a spec's problems are worded and gathered: all of them at once, each naming its item.

A check raises ValueError naming the item at fault (`[simulation]: dt must be ...`); a Problems
collector runs the checks of a spec one after another, keeps every message, and raises one
SpecError listing them all, so one round of edits fixes a spec. Values are shown short (a huge
list, a deep nesting or a 5000-digit integer never floods, nor breaks, a message), and an unknown
name comes with its closest valid names, never a model's whole list.
"""
from __future__ import annotations

import difflib
import math
import numbers
import reprlib

from .errors import SpecError

CLOSEST = 3          # at most this many suggestions for an unknown name
SHORT_LIST = 8       # a list of valid names this short is shown whole when nothing is close

_REPR = reprlib.Repr()
_REPR.maxlevel, _REPR.maxstring, _REPR.maxother, _REPR.maxlist, _REPR.maxdict = 3, 60, 60, 6, 6


def shown(value) -> str:
    """repr(value), cut short: what a message quotes of a value from a spec."""
    if isinstance(value, int) and not isinstance(value, bool) and value.bit_length() > 256:
        return f"an integer of {value.bit_length()} bits"
    try:
        return _REPR.repr(value)
    except (ValueError, RecursionError):  # e.g. a huge integer inside a list
        return f"a {type(value).__name__}"


def finite_number(value):
    """value as a float if it is a finite real number (not a bool, not an integer beyond a float's
    range), else None."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        return None
    try:
        x = float(value)
    except OverflowError:
        return None
    return x if math.isfinite(x) else None


def closest(name, names, what: str = "") -> str:
    """' (did you mean 'a' or 'b'?)' with the valid names closest to `name`; when none is close,
    every valid name if they are few (' (<what>: a, b, c)'), else how many there are. `what` names
    the valid names in the plural ('parameters')."""
    names = [str(n) for n in names]
    close = difflib.get_close_matches(name, names, n=CLOSEST) if isinstance(name, str) and len(name) <= 200 else []
    if close:
        quoted = [repr(n) for n in close]
        return f" (did you mean {', '.join(quoted[:-1]) + ' or ' if len(quoted) > 1 else ''}{quoted[-1]}?)"
    if len(names) <= SHORT_LIST:
        return f" ({what or 'known'}: {', '.join(names)})"
    return f" (none of the {len(names)} {what or 'known names'} is close)"


def spec_error(source: str, problem: str) -> SpecError:
    """The SpecError of a spec with one problem (naming its item), from `source`."""
    return SpecError(f"{source}: {problem}", problems=[problem])


class Problems:
    """The problems found in one spec so far."""

    def __init__(self, source: str):
        self.source = source
        self.messages: list[str] = []

    def add(self, message: str) -> None:
        self.messages.append(" ".join(str(message).split()))

    def check(self, fn, *args, default=None):
        """fn(*args), or `default` after recording the ValueError it raised (a SpecError's problems
        each on their own)."""
        try:
            return fn(*args)
        except SpecError as error:
            for message in error.problems:
                self.add(message)
        except ValueError as error:
            self.add(str(error))
        return default

    def raise_if_any(self) -> None:
        """One SpecError naming the source and listing every problem (numbered when several)."""
        if not self.messages:
            return
        if len(self.messages) == 1:
            text = self.messages[0]
        else:
            text = f"{len(self.messages)} problems: " + "; ".join(f"({k}) {m}" for k, m in
                                                                  enumerate(self.messages, 1))
        raise SpecError(f"{self.source}: {text}", problems=self.messages)
