"""Output paths checked before any work: every command checks the files and directories it will
write (a report, a plot, a campaign's results) before it simulates anything, so a bad path costs
an error line, not a finished run.

The check does what the write will do, then undoes it: a missing file is created and removed, an
existing one opened for appending (unchanged), a missing directory created and removed (its
first missing level), an existing one given a temporary file (a hidden `.tmp`, the kind a
campaign's results directory cleans up). So whatever the cause (a missing or read-only
directory, a file where a directory belongs, /proc, a name too long), the answer is the
system's own.
"""
from __future__ import annotations

import os
import tempfile
from pathlib import Path
from typing import Optional

__all__ = ["output_problem"]


def output_problem(path, directory: bool = False) -> Optional[str]:
    """Why `path` cannot be written, or None: a file written there (created or replaced), or with
    `directory`, a directory created there with its parents (or an existing one written in)."""
    try:
        path = Path(path)
        return _directory_problem(path) if directory else _file_problem(path)
    except ValueError as error:  # a NUL byte in the path
        return str(error)
    except OSError as error:  # a directory on the way that cannot be searched
        return f"cannot be reached ({error.strerror or error})"


def _file_problem(path: Path) -> Optional[str]:
    if path.is_dir():
        return "is a directory"
    parent = path.parent
    if not parent.exists():
        return f"the directory {parent} does not exist"
    if not parent.is_dir():
        return f"{parent} is not a directory"
    try:
        if not path.exists():
            os.close(os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666))
            os.unlink(path)
        elif path.is_file():
            open(path, "ab").close()  # appends nothing: the file is unchanged
        elif not os.access(path, os.W_OK):  # a device or a pipe: opening it could block
            return "is not writable"
    except OSError as error:
        return f"cannot be written ({error.strerror or error})"
    return None


def _directory_problem(path: Path) -> Optional[str]:
    if path.exists():
        if not path.is_dir():
            return "is a file, not a directory"
        try:
            descriptor, probe = tempfile.mkstemp(dir=path, prefix=".soadyn-probe-", suffix=".tmp")
            os.close(descriptor)
            os.unlink(probe)
        except OSError as error:
            return f"cannot be written in ({error.strerror or error})"
        return None
    first_missing = path
    while not first_missing.parent.exists() and first_missing.parent != first_missing:
        first_missing = first_missing.parent
    if not first_missing.parent.is_dir():
        return f"{first_missing.parent} is not a directory"
    try:
        first_missing.mkdir()
        first_missing.rmdir()
    except OSError as error:
        return f"cannot be created ({error.strerror or error})"
    return None
