"""The divergence guard (Simulator.divergence_guard, on in HIL runs): a step
whose energy grows beyond what the applied forces can supply stops the run
with status "diverging", naming the DOF, while the state is still finite;
nominal runs of the built-in scenes never trip it.
"""
import numpy as np
import pytest

import soadyn
from soadyn import hil, scenes


def chain_at_its_default_limits(guard: bool):
    """The pendulum-chain scene at 1 kHz (RK4), every DOF commanded at its default HIL limit 1000 * M_ii:
    RK4 loses finiteness at step 77."""
    sim = hil.scene_simulator("pendulum-chain", rate=1000.0)
    limits = 1000.0 * np.diag(soadyn.mass_matrix(sim._model, sim.q))
    for dof, limit in enumerate(limits):
        sim.set_input(dof, limit)
    sim.divergence_guard = guard
    return sim


def test_without_the_guard_a_command_at_the_limit_ends_non_finite():
    with pytest.raises(soadyn.DynamicsError, match="non-finite result"):
        chain_at_its_default_limits(guard=False).run(2.0)


def test_the_guard_stops_the_same_run_while_the_state_is_finite():
    sim = chain_at_its_default_limits(guard=True)
    with pytest.raises(soadyn.DynamicsError, match=r"diverging \(DOF 'link_\d'\).* at t = ") as error:
        sim.run(2.0)
    trajectory = error.value.trajectory
    assert np.all(np.isfinite(trajectory.q)) and np.all(np.isfinite(trajectory.v))
    assert np.all(np.isfinite(sim.q)) and np.all(np.isfinite(sim.v))  # the last good step is kept


def test_a_hil_run_reports_the_divergence_and_the_last_good_state():
    sim = chain_at_its_default_limits(guard=False)  # run_hil turns it on by default
    report = hil.run_hil(sim, rate=1000.0, duration=2.0, progress=False, realtime=False)
    assert report.status == "diverging" and report.failed_dof.startswith("link_")
    assert report.failed_step is not None and report.failed_step < 2000
    assert np.all(np.isfinite(report.final_state["q"])) and np.all(np.isfinite(report.final_state["v"]))
    assert report.final_state["t"] == pytest.approx(report.failed_step * 1e-3)


def test_a_velocity_limit_names_its_dof():
    m = scenes.pendulum_chain(2)
    sim = soadyn.Simulator(m, 1e-3)
    sim.set_input(1, 5.0)
    sim.velocity_limits = [np.inf, 2.0]
    sim.divergence_guard = True
    with pytest.raises(soadyn.DynamicsError, match=r"diverging \(DOF 'link_2'\)"):
        sim.run(5.0)
    assert np.abs(sim.v[1]) <= 2.0


@pytest.mark.parametrize("limits, message", [
    ([1.0], r"velocity_limits has shape \(1,\), expected \(2,\) \(nv\)"),
    ([1.0, -1.0], "velocity limit of DOF 1 must be > 0"),
    ([np.nan, 1.0], "velocity limit of DOF 0 must be > 0"),
])
def test_bad_velocity_limits_are_refused_by_name(limits, message):
    sim = soadyn.Simulator(scenes.pendulum_chain(2), 1e-3)
    with pytest.raises(ValueError, match=message):
        sim.velocity_limits = limits


@pytest.mark.parametrize("integrator", ["rk4", "euler"])
@pytest.mark.parametrize("name", sorted(scenes.SCENES))
def test_nominal_runs_of_the_built_in_scenes_never_trip_it(name, integrator):
    """Each scene's nominal start (cassini's wheels spinning and its drives on, the slosh pendulums, the
    loop scenes driven at their rate) for 3 s at 1 kHz with the guard on."""
    sim = hil.scene_simulator(name, rate=1000.0, integrator=integrator)
    sim.divergence_guard = True
    sim.run(3.0)  # a trip raises DynamicsError
