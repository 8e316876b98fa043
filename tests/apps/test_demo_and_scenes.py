"""The README's main job (`soadyn demo`) and the built-in scenes."""
import shutil
import subprocess

import numpy as np
import pytest

import soadyn
from soadyn import scenes
from soadyn.cli import main
from soadyn.demo import run_demo
from support.robots import robot, robots_dir


def test_demo_cli_prints_report(capsys, tmp_path):
    plot = tmp_path / "booms.png"
    assert main(["demo", "--duration", "0.2", "--boom-duration", "3", "--plot", str(plot)]) == 0
    out = capsys.readouterr().out
    assert "scene cassini: 15 bodies" in out and "steps              200" in out
    assert "magnetometer_boom" in out and "peak tip deflection" in out
    assert plot.stat().st_size > 10_000


def test_cassini_booms_ring_at_their_linearised_frequencies_after_a_gimbal_step():
    """At rest until the gimbal step; then each boom's tip rings at a natural frequency of
    the linearised spacecraft (drives held), found independently by natural_frequencies."""
    from soadyn.boom_vibration import gimbal_step_response

    model = scenes.cassini()
    assert [n for n, k in zip(model.body_names, model.n_modes) if k] == ["magnetometer_boom", "plasma_wave_antenna"]
    r = gimbal_step_response(model, duration=24.0)  # resolves the 0.56 and 0.64 Hz modes
    before = r.t < r.t_step
    for name, d in r.deflection.items():
        assert np.abs(d[before]).max() == 0.0
        assert r.peak[name] > 1e-5
        nearest = r.linearised_hz[np.argmin(np.abs(r.linearised_hz - r.dominant_hz[name]))]
        assert abs(r.dominant_hz[name] / nearest - 1) < 0.03, (name, r.dominant_hz[name], nearest)
    with pytest.raises(ValueError, match="leaves less than 1 s of ringing"):
        gimbal_step_response(model, duration=1.5)


def test_console_script_is_installed():
    exe = shutil.which("soadyn")
    assert exe, "the soadyn console script is not on PATH"
    result = subprocess.run([exe, "demo", "--duration", "0.05"], capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    assert "hybrid_dynamics" in result.stdout


def test_demo_switch_keeps_velocity_and_momentum_converges_with_step():
    """Internal drives conserve momentum: the integrator's drift shrinks in proportion to dt."""
    drift = []
    for dt in (2e-3, 1e-3):
        r = run_demo(scenes.cassini(), duration=0.4, dt=dt)
        assert np.isfinite(r.scan_az_rate_at_switch) and r.scan_az_rate_at_switch > 0
        drift.append(np.abs(r.momentum_end - r.momentum_start).max())
    assert drift[1] == pytest.approx(drift[0] / 2, rel=0.2)


def test_cassini_scene_prescribes_turntable_and_gimbal():
    m = scenes.cassini()
    prescribed = {n for n, p in zip(m.dof_names, m.prescribed) if p}
    assert prescribed == {"turntable", "gimbal_pitch", "gimbal_yaw"}
    assert m.joint_types[0] == "free" and list(m.gravity) == [0, 0, 0]


def test_pendulum_chain_small_oscillation_period():
    """One link: small-angle frequency sqrt(m g d / I_pivot) of a rod pendulum."""
    m = scenes.pendulum_chain(1, length=0.8, mass=2.0)
    theta = 1e-6
    qdd = soadyn.forward_dynamics(m, [theta], [0.0], [0.0])[0]
    I_pivot = 2.0 * 0.8**2 / 12 + 2.0 * 0.4**2
    assert -qdd / theta == pytest.approx(2.0 * 9.81 * 0.4 / I_pivot, rel=1e-9)
    with pytest.raises(ValueError, match="at least one link"):
        scenes.pendulum_chain(0)


@pytest.mark.parametrize("arguments, error, message", [
    ((2.5,), TypeError, r"n must be a whole number of links, got float \(2.5\)"),
    (("3",), TypeError, "n must be a whole number of links, got str"),
    ((True,), TypeError, "n must be a whole number of links, got bool"),
    ((2, -0.5), ValueError, "length must be a finite number > 0, got -0.5"),
    ((2, float("nan")), ValueError, "length must be a finite number > 0, got nan"),
    ((2, 0.5, 0.0), ValueError, "mass must be a finite number > 0, got 0.0"),
    ((2, 0.5, "1"), TypeError, "mass must be a real number, got str"),
])
def test_pendulum_chain_names_a_bad_argument(arguments, error, message):
    with pytest.raises(error, match=f"pendulum_chain: {message}"):
        scenes.pendulum_chain(*arguments)


def test_drive_cassini_refuses_what_is_not_a_cassini_simulator():
    with pytest.raises(ValueError, match="drive_cassini: the simulator's model has no DOF 'turntable'"):
        scenes.drive_cassini(soadyn.Simulator(scenes.pendulum_chain(2), dt=0.01))
    with pytest.raises(TypeError, match="drive_cassini needs a soadyn.Simulator, got Model"):
        scenes.drive_cassini(scenes.cassini())


def test_a_misspelt_scene_names_the_closest_ones():
    with pytest.raises(AttributeError, match=r"no scene 'casini'; did you mean cassini"):
        scenes.casini()
    with pytest.raises(AttributeError, match=r"no scene 'four_bars'; did you mean four_bar\b"):
        scenes.four_bars()
    with pytest.raises(AttributeError, match=r"no scene 'zzz'; the scenes: cantilever_beam, cassini, "):
        scenes.zzz()
    assert not hasattr(scenes, "stanford_army") and hasattr(scenes, "cassini")


def test_soadyn_robots_lists_the_scenes_and_every_example_robot_with_its_path(capsys):
    assert main(["robots"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[0] == "built-in scenes (soadyn view NAME): cassini, four-bar, slider-crank, delta-robot, stanford-arm"
    assert lines[1].endswith(f"URDF files in {robots_dir()} (soadyn view NAME, or its path where two share a name)")
    listed = [line.split(maxsplit=1) for line in lines[2:]]
    assert sorted(path for _, path in listed) == sorted(str(p) for p in robots_dir().glob("**/*.urdf"))
    assert ["ur5_robot", str(robot("ur5")[0])] in listed


def test_an_example_robot_loads_by_its_listed_name_and_a_wrong_one_is_answered():
    from soadyn.io.example_robots import example_robot
    from soadyn.viewer import load_any

    assert example_robot("ur5_robot") == robot("ur5")[0]
    assert load_any("talos_reduced").nbodies == soadyn.load_urdf(robot("talos")[0]).nbodies
    with pytest.raises(ValueError, match=r"no example robot 'ur5'; did you mean ur5_gripper, ur5_joint_limited_robot, "
                                         r"ur5_robot\?"):
        load_any("ur5")
    with pytest.raises(ValueError, match=r"example robot 'anymal' names 2 files; give the path of one: .*anymal_b"):
        load_any("anymal")


def test_soadyn_robots_says_how_to_install_the_example_robots(capsys, monkeypatch):
    import soadyn.apps.cli as cli

    monkeypatch.setattr(cli, "example_robot_files", lambda: [])
    assert cli.main(["robots"]) == 0
    assert capsys.readouterr().out.splitlines()[-1] == (
        "example-robot-data is not installed here: pip install example-robot-data")
