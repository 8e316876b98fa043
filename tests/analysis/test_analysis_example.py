"""The analysis guide's worked example (examples/python/analysis_worked_example.py) runs and its
numbers hold: the four-bar's equilibrium equals the closed-form reference of
support/equilibria.py, the adjoint gradient equals the direct sensitivities, the LQR
loop is stable, and the modes agree with natural_frequencies."""
from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np
import pytest

import soadyn
from support.equilibria import reference_equilibrium, reference_sensitivities

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "python" / "analysis_worked_example.py"


def load_example():
    spec = importlib.util.spec_from_file_location("analysis_worked_example", EXAMPLE)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_worked_example(tmp_path):
    plot = tmp_path / "modes.png"
    out = load_example().main(["--plot", str(plot)])
    assert plot.stat().st_size > 0
    eq, m = out["four_bar"]["equilibrium"], out["four_bar"]["model"]
    crank = m.dof_names.index("crank")
    theta = reference_equilibrium()
    assert eq.q[crank] == pytest.approx(theta, abs=1e-9)
    reference = reference_sensitivities(theta)
    for name, gradient in out["four_bar"]["adjoint"].items():
        assert gradient == pytest.approx(eq.sensitivities[name]["q"][crank], rel=1e-9)
        assert gradient == pytest.approx(reference[name], rel=1e-6)
    assert (out["lqr"]["closed_loop"].real < 0).all()
    assert (np.linalg.eigvals(out["lqr"]["A"]).real > 0).any()  # upright is unstable without control
    arm = load_example().two_link_arm()
    np.testing.assert_allclose(out["modes"].angular_frequencies,
                               soadyn.natural_frequencies(arm, np.array([np.pi, 0.0])), rtol=1e-12)
