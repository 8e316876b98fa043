"""Running fuzz cases: the property a hostile call keeps (`judged`), and one
case in a forked child (`run_forked`), so that a crash or a hang of the case
is an outcome rather than the end of the run.

`judged(call)` runs call() -> (name, result, arguments) and returns "ok" when
the result is finite and no argument was an array of something other than
real numbers, or the name of the documented error (fuzz.api_cases.
EXPECTED_ERRORS) the call raised with a message of its own; it raises
AssertionError otherwise (a silent NaN or infinity, a complex or string array
taken as numbers, an error without a message or with one of Python's or
pybind11's that names no argument, such as "'float' object is not iterable").

`run_forked(run_case, seed)` forks; the child runs `run_case(seed)` (which
returns "ok" or the name of the documented error it met, and raises
AssertionError when a call returned NaN or infinity without raising) and
leaves through os._exit with a code, its message sent up a pipe. The parent
returns one of:

    "ok", "expected", "non-finite: <message>", "unexpected: <type>: <message>",
    "crash: signal <N>", "hang" (still running after `timeout` seconds: killed)
"""
from __future__ import annotations

import os
import select
import signal
import sys
import time

import numpy as np

from fuzz.api_cases import EXPECTED_ERRORS, check_finite

OK, EXPECTED, NON_FINITE, UNEXPECTED = 0, 1, 3, 4
# Messages of Python's conversions and of pybind11's argument matching: an argument got past the API's own checks.
UNNAMED_ERRORS = ("incompatible function arguments", "object is not iterable", "int() argument must be",
                  "cannot convert float NaN to integer", "could not convert string to float",
                  "only 0-dimensional arrays can be converted", "unsupported operand type", "not supported between")
MESSAGE_BYTES = 4000  # below PIPE_BUF: the child's one write never blocks


def not_real(x) -> str | None:
    """The dtype of x when x is an array (or nested sequence) of something other than real numbers:
    complex, strings, bytes, objects or booleans, which the single calls refuse with a TypeError."""
    try:
        dtype = np.asarray(x).dtype
    except (TypeError, ValueError):  # ragged nested sequences
        return "ragged"
    return None if dtype.kind in "fiu" else str(dtype)


def judged(call, expected: tuple = EXPECTED_ERRORS) -> str:
    """'ok' or the name of the documented error (one of `expected`) call() raised (see the module docstring)."""
    try:
        name, result, arguments = call()
    except expected as e:
        if not str(e) or any(text in str(e) for text in UNNAMED_ERRORS):
            raise AssertionError(f"{type(e).__name__} without a message naming the argument: {e!r:.300}") from e
        return type(e).__name__
    check_finite(result, name)
    for argument, x in arguments.items():
        dtype = None if x is None else not_real(x)
        if dtype:
            raise AssertionError(f"{name} took {argument} of dtype {dtype} as numbers without raising")
    return "ok"


def _child(run_case, seed: int, pipe: int) -> None:
    code, message = UNEXPECTED, ""
    try:
        code = OK if run_case(seed) == "ok" else EXPECTED
    except AssertionError as e:
        code, message = NON_FINITE, str(e)
    except BaseException as e:  # noqa: BLE001 - reporting it is the point
        message = f"{type(e).__name__}: {e}"
    finally:
        os.write(pipe, message.encode(errors="replace")[:MESSAGE_BYTES])
        os._exit(code)


def run_forked(run_case, seed: int, timeout: float = 10.0) -> str:
    """The outcome of run_case(seed) run in a forked child (see the module docstring)."""
    sys.stdout.flush()
    sys.stderr.flush()
    read_end, write_end = os.pipe()
    pid = os.fork()
    if pid == 0:
        os.close(read_end)
        _child(run_case, seed, write_end)
    os.close(write_end)
    try:
        message, deadline = b"", time.monotonic() + timeout
        while True:  # until the child's end of the pipe closes (it exited) or the deadline
            remaining = deadline - time.monotonic()
            if remaining <= 0 or not select.select([read_end], [], [], remaining)[0]:
                os.kill(pid, signal.SIGKILL)
                os.waitpid(pid, 0)
                return "hang"
            chunk = os.read(read_end, MESSAGE_BYTES)
            if not chunk:
                break
            message += chunk
    finally:
        os.close(read_end)
    _, status = os.waitpid(pid, 0)
    if os.WIFSIGNALED(status):
        return f"crash: signal {os.WTERMSIG(status)}"
    text = message.decode(errors="replace")
    code = os.WEXITSTATUS(status)
    return {OK: "ok", EXPECTED: "expected", NON_FINITE: f"non-finite: {text}",
            UNEXPECTED: f"unexpected: {text}"}.get(code, f"unexpected: exit code {code}")
