"""The solar-wing example (examples/python/solar_panel_deployment.py) against physics it must obey.

Nothing outside the spacecraft acts on it, so its momentum stays at its initial zero through the
controllers' starting impulse, the deployment and the release (a closed-form law, not a comparison
with soadyn). The wing is flat and at the controllers' rate when they let go, the run's two ringing
frequencies equal those of the model linearised at the latched pose, and the bus turned while the
wing opened (the hinge torques are internal but not balanced about its centre)."""
from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np

FOLDER = Path(__file__).resolve().parents[2] / "examples" / "python"


def load_example(monkeypatch):
    monkeypatch.syspath_prepend(str(FOLDER))  # the example imports its plotting helper
    spec = importlib.util.spec_from_file_location("solar_panel_deployment", FOLDER / "solar_panel_deployment.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_deployment_conserves_momentum_and_rings_at_the_linearised_frequencies(monkeypatch, tmp_path):
    example = load_example(monkeypatch)
    plot = tmp_path / "wing.png"
    out = example.main(["--deploy", "20", "--ring", "60", "--plot", str(plot)])
    assert plot.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    run = out["run"]
    assert np.max(np.abs(out["momentum"])) < 1e-9
    m = example.spacecraft()
    hinge_q = [m.coordinate_names.index(h) for h in example.HINGES]
    hinge_v = [m.dof_index(h) for h in example.HINGES]
    release = int(round(20.0 / example.DT))
    np.testing.assert_allclose(run.q[release, hinge_q], 0.0, atol=1e-9)
    np.testing.assert_allclose(run.v[release - 1, hinge_v], -example.FOLDED / 20.0, rtol=1e-12)
    assert len(out["linear_hz"]) == 2
    np.testing.assert_allclose(out["measured_hz"], out["linear_hz"], rtol=0.01)
    quaternion_w = run.q[release, 6]
    assert np.degrees(2 * np.arccos(abs(quaternion_w))) > 1.0
