"""Shared by the viewer's tests: Viewers on free ports closed after the test, and a replayed four-bar."""
from __future__ import annotations

import pytest

import soadyn
from soadyn.simulator import Simulator
from soadyn.viewer import Viewer


@pytest.fixture
def quiet_viewer():
    """make(m, **kwargs): a Viewer of m on a free port, closed after the test."""
    viewers = []

    def make(m, **kwargs):
        v = Viewer(m, port=0, **kwargs)
        viewers.append(v)
        return v
    yield make
    for v in viewers:
        v.close()


def four_bar_run(duration: float, crank_rate: float = 0.0):
    """(model, trajectory) of the four-bar closed at crank angle 0.5 rad, turning at crank_rate, simulated
    for `duration` seconds (RK4, 1 ms)."""
    m = soadyn.scenes.four_bar()
    q, v = soadyn.scenes.four_bar_state(0.5, crank_rate)
    sim = Simulator(m, dt=1e-3)
    sim.set_state(q, v)
    return m, sim.run(duration)
