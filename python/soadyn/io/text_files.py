"""Writing the text files soadyn produces (model files, URDF exports), with errors that name the path."""
from __future__ import annotations

import os


def write_text(path, text: str, error: type, what: str) -> None:
    """Write `text` to `path`; an OSError becomes `error` naming the path and `what` was being written."""
    try:
        with open(os.fspath(path), "w", encoding="utf-8") as f:
            f.write(text)
    except OSError as exc:
        raise error(f"{os.fspath(path)}: cannot write the {what}: {exc.strerror or exc}") from exc
