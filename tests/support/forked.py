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

`run_forked_cases("fuzz.loop_cases", seeds, folder)` is run_forked(run_case, seed) of that module for
every seed, forked not from the test process but from a fresh interpreter that has imported only the
module: fork copies the parent's page tables, and a test process holding every oracle and many models
forks several times slower than a small one. Each case still runs alone in its own child.
"""
from __future__ import annotations

import importlib
import json
import os
import select
import signal
import subprocess
import sys
import time
from pathlib import Path

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


TESTS = Path(__file__).resolve().parents[1]  # on the server's sys.path, for support/ and fuzz/
SERVER = "from support.forked import serve; serve()"


def run_forked_cases(cases: str, seeds, folder: Path, timeout: float = 10.0) -> dict:
    """{seed: run_forked(<cases>.run_case, seed, timeout)} for every seed, forked from a fresh interpreter that
    imported the module `cases` (and ran its prepare(), if it has one) and works in `folder` (a temporary
    folder: scratch a case leaves, such as MuJoCo's log, goes there)."""
    seeds = list(seeds)
    environment = dict(os.environ, PYTHONPATH=os.pathsep.join(filter(None, [str(TESTS),
                                                                             os.environ.get("PYTHONPATH")])))
    server = subprocess.run([sys.executable, "-c", SERVER, cases, repr(timeout), *map(str, seeds)], cwd=folder,
                            env=environment, capture_output=True, text=True, timeout=60 + len(seeds) * timeout)
    outcomes = dict(json.loads(line) for line in server.stdout.splitlines())
    assert server.returncode == 0 and sorted(outcomes) == sorted(seeds), \
        f"the case server for {cases} stopped (exit {server.returncode}) after {len(outcomes)} of {len(seeds)} " \
        f"cases:\n{server.stderr[-3000:]}"
    return outcomes


def serve() -> None:
    """The case server of run_forked_cases: argv is (module, timeout, seed, ...); one JSON line [seed, outcome]
    per case on its standard output, which the cases' own printing (sent to standard error) cannot reach."""
    cases, timeout, *seeds = sys.argv[1:]
    report = os.fdopen(os.dup(sys.stdout.fileno()), "w")
    sys.stdout.flush()
    os.dup2(sys.stderr.fileno(), sys.stdout.fileno())
    np.random.default_rng(0)  # numpy imports its random module on first use: here, not in every child
    module = importlib.import_module(cases)
    getattr(module, "prepare", lambda: None)()
    for seed in map(int, seeds):
        report.write(json.dumps([seed, run_forked(module.run_case, seed, float(timeout))]) + "\n")
        report.flush()
