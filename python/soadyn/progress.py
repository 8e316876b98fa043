"""Progress display for long runs: tqdm's bar when tqdm is installed (the
`progress` extra: pip install "soadyn[progress]"), otherwise a plain line on
stderr every few seconds. Library users and C++-only builds need neither."""
from __future__ import annotations

import sys
import time

PLAIN_INTERVAL = 5.0  # seconds between two lines of the plain display


class PlainProgress:
    """The part of tqdm's interface the runs use: n, update, set_postfix, close."""

    def __init__(self, total: int, unit: str, desc: str, disable: bool = False, stream=None):
        self.n = 0
        self.total = total
        self.unit = unit
        self.desc = desc
        self.disable = disable
        self.stream = sys.stderr if stream is None else stream
        self._postfix: dict = {}
        self._last_line = time.monotonic()

    def update(self, count: int = 1) -> None:
        self.n += count
        if time.monotonic() - self._last_line >= PLAIN_INTERVAL:
            self._print()

    def set_postfix(self, postfix: dict, refresh: bool = True) -> None:
        self._postfix = dict(postfix)

    def close(self) -> None:
        self._print()

    def _print(self) -> None:
        self._last_line = time.monotonic()
        if self.disable:
            return
        fields = "".join(f", {key}={value}" for key, value in self._postfix.items())
        print(f"{self.desc}: {self.n}/{self.total} {self.unit}s{fields}", file=self.stream, flush=True)


def progress_bar(total: int, unit: str, desc: str, disable: bool = False):
    """A tqdm bar if tqdm is installed, else a PlainProgress."""
    try:
        from tqdm import tqdm
    except ImportError:
        return PlainProgress(total, unit, desc, disable)
    return tqdm(total=total, unit=unit, disable=disable, dynamic_ncols=True, desc=desc)
