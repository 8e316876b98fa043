"""Oracle comparisons that keep the largest relative error per quantity, printed at the
end of a test module (run pytest with -s to see the table)."""
from __future__ import annotations

import numpy as np
import pytest


def rel_error(a, b) -> float:
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    assert a.shape == b.shape
    return float(np.max(np.abs(a - b)) / max(1.0, float(np.max(np.abs(b)))))


class ErrorLog:
    def __init__(self, title: str, rtol: float):
        self.title, self.rtol, self.worst = title, rtol, {}

    def check(self, quantity: str, value, expected) -> None:
        err = rel_error(value, expected)
        self.worst[quantity] = max(self.worst.get(quantity, 0.0), err)
        assert err <= self.rtol, f"{quantity}: relative error {err:.3e} > {self.rtol:g}"

    def report(self) -> None:
        print(f"\nlargest relative error vs {self.title}:")
        for quantity, err in sorted(self.worst.items()):
            print(f"  {quantity:28s} {err:.3e}")


def report_fixture(log: ErrorLog):
    """A module-scoped autouse fixture printing `log`'s table after the module's tests:
    `report_errors = report_fixture(LOG)` at module level."""
    @pytest.fixture(scope="module", autouse=True)
    def report_errors():
        yield
        log.report()
    return report_errors
