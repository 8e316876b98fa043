"""Campaign specs are checked completely before any run (one error lists every problem, each naming
its item, unknown names with their closest valid ones), a run is a pure
function of (spec, run id) drawn from SeedSequence(seed).spawn(runs)[i], and the metrics measure
what they say. No Dask here: tests/campaign/test_campaign_runs.py runs campaigns."""
import math
from pathlib import Path

import numpy as np
import pytest

import soadyn
from soadyn import cli, hil
from soadyn.campaign import EXAMPLES, SpecError, load_spec, run_one
from soadyn.campaign.metrics import METRICS, _rotation_angle
from soadyn.campaign.simulate import draw, generator


def spec_dict(**changes):
    """A small valid cassini spec with `changes` merged in (None removes a key)."""
    spec = {"name": "unit", "seed": 3, "runs": 5, "model": {"scene": "cassini"},
            "simulation": {"duration": 0.05, "dt": 0.001, "integrator": "rk4"},
            "dispersions": [{"parameter": "bus.mass", "distribution": "normal", "scale": 0.05}],
            "outputs": {"metrics": ["energy_lost"]}}
    for key, value in changes.items():
        if value is None:
            spec.pop(key)
        else:
            spec[key] = value
    return spec


def dispersion(**entry):
    return spec_dict(dispersions=[entry])


@pytest.mark.parametrize("spec, fragment", [
    (dispersion(parameter="bus.mas", distribution="normal", std=1.0),
     "dispersions[0] (parameter 'bus.mas'): unknown parameter 'bus.mas' (did you mean 'bus.mass'"),
    (dispersion(parameter="bus.mass", distribution="normal", std=-1.0),
     "dispersions[0] (parameter 'bus.mass'): std must be >= 0, got -1"),
    (dispersion(parameter="bus.mass", distribution="normal", scale=-0.1),
     "dispersions[0] (parameter 'bus.mass'): scale must be >= 0, got -0.1"),
    (spec_dict(model={"scene": "voyager"}), "[model]: unknown scene 'voyager' (scenes: cassini,"),
    (spec_dict(outputs={"metrics": ["peak_boom_tip"]}), "[outputs] metrics[0]: unknown metric 'peak_boom_tip'"),
    (spec_dict(runs=0), "runs must be an integer in 1..100000000, got 0"),
    (spec_dict(runs=2.5), "runs must be an integer in 1..100000000, got 2.5"),
    (spec_dict(seed=-1), "seed must be an integer >= 0, got -1"),
    (spec_dict(seed=None), "seed is required"),
    (spec_dict(colour="red"), "the spec: unknown key 'colour'"),
    (spec_dict(simulation={"duration": 0.05, "dt": 0.001, "integrator": "rk5"}),
     "[simulation]: integrator must be one of euler, rk4, dopri5, got 'rk5'"),
    (spec_dict(simulation={"duration": 0.0505, "dt": 0.001}), "[simulation] duration and dt: duration 0.0505 s is"),
    (spec_dict(simulation={"duration": 0.05, "dt": 0.001, "rate": 1000}), "give dt (s) or rate (steps per s)"),
    (spec_dict(simulation={"duration": 0.05, "dt": 0.001, "events": ["lock nothing at 0.1"]}),
     "[simulation] events[0]: unknown DOF or joint 'nothing'"),
    (dispersion(parameter="bus.com", distribution="normal", std=0.01),
     "bus.com has shape (3,): give one element, e.g. bus.com[0]"),
    (dispersion(parameter="bus.com[3]", distribution="normal", std=0.01), "got index [3]"),
    (dispersion(parameter="bus.placement[0,0]", distribution="normal", std=0.01),
     "only a placement's translation can be dispersed"),
    (dispersion(parameter="bus.mass", distribution="gamma", std=1.0), "distribution must be one of normal"),
    (dispersion(parameter="bus.mass", distribution="uniform", low=3.0, high=2.0), "low 3 is above high 2"),
    (dispersion(parameter="bus.mass", distribution="lognormal", sigma=-0.5), "sigma must be >= 0, got -0.5"),
    (dispersion(parameter="bus.mass", distribution="normal", std=float("nan")), "std must be finite"),
    (dispersion(parameter="bus.mass", distribution="normal", std=1.0, scale=0.1), "std or scale"),
    (dispersion(parameter="bus.mass", distribution="normal", std=1.0, median=3.0),
     "median is not a parameter of a normal distribution (it takes mean, std, scale)"),
    (dispersion(initial="q:nowhere", distribution="normal", std=0.1), "unknown coordinate 'nowhere'"),
    (dispersion(initial="w:scan_az", distribution="normal", std=0.1), "expected 'q:<coordinate>' or 'v:<DOF>'"),
    (dispersion(event="lock scan_zz", distribution="uniform", low=0.1, high=0.2),
     "unknown DOF or joint 'scan_zz' (did you mean 'scan_az'"),
    (dispersion(event="stop scan_az", distribution="uniform", low=0.1, high=0.2), "expected 'lock <DOF or joint>'"),
    (dispersion(event="lock scan_az", distribution="normal", std=0.1),
     "give mean (what is dispersed has no nominal value in the model)"),
    (dispersion(event="lock magnetometer_boom:mode1", distribution="uniform", low=0.1, high=0.2),
     "modal DOFs are always regular"),
    (dispersion(source="input:turntable", distribution="normal", mean=0.0, std=1.0),
     "'turntable' is prescribed; an input acts on a regular DOF"),
    (dispersion(source="velocity:bus:wx", distribution="normal", mean=0.0, std=1.0), "has no coordinate of its own"),
    (dispersion(parameter="bus.mass", initial="q:scan_az", distribution="normal", std=1.0),
     "give exactly one of parameter, initial, event, source"),
    (dispersion(parameter="bus.mass", distribution="normal", std=1.0, sdt=2.0), "unknown key 'sdt'"),
    (spec_dict(dispersions=[{"parameter": "bus.mass", "distribution": "normal", "std": 1.0}] * 2),
     "dispersions[1] (parameter 'bus.mass'): disperses what dispersions[0] already does"),
    (spec_dict(dispersions=[{"parameter": "bus.mass", "name": "status", "distribution": "normal", "std": 1.0}]),
     "column 'status' is reserved"),
    (spec_dict(outputs={"metrics": [], "trajectory_every": 0}), "[outputs]: nothing to keep"),
    (spec_dict(outputs={"metrics": ["energy_lost"], "trajectory_every": -1}), "trajectory_every must be an integer"),
    (spec_dict(outputs={"metrics": ["max_abs_q:nowhere"]}), "no coordinate 'nowhere' in the model"),
    (spec_dict(model={"scene": "pendulum-chain"}, dispersions=[],
               outputs={"metrics": ["peak_boom_tip_deflection"]}), "no body 'magnetometer_boom' in the model"),
    (spec_dict(model={"file": "missing.json"}), "[model]: cannot read the model file"),
    (spec_dict(model={"scene": "cassini", "file": "m.json"}), "give scene (a built-in scene) or file"),
    (spec_dict(initial={"q": {"scan_azz": 0.1}}), "[initial] q: unknown coordinate 'scan_azz'"),
    (spec_dict(initial={"v": {"scan_az": 2**2000}}), "[initial] v.scan_az: must be a finite number, got an integer "
                                                     "of 2001 bits"),
    (dispersion(parameter="bus.mass", distribution="normal", std=2**2000), "std must be finite, got an integer"),
    (dispersion(parameter="bus.mass", distribution="normal", scale=1e308), "scale 1e+308 times the nominal value"),
    (dispersion(parameter="bus.mass", distribution="uniform", low=-1e308, high=1e308), "high - low overflows"),
    (dispersion(parameter="bus.com[99999999999]", distribution="normal", std=1.0), "expected a parameter name"),
    (spec_dict(model={"file": "/dev/zero"}), "[model]: cannot read the model file '/dev/zero': not a regular file"),
])
def test_bad_specs_are_refused_naming_the_item(spec, fragment, tmp_path):
    with pytest.raises(SpecError) as error:
        load_spec(spec, base_dir=tmp_path)
    message = str(error.value)
    assert fragment in message
    assert message.startswith("<dict>: ") and "\n" not in message


def test_unknown_names_suggest_the_closest_few_never_the_whole_list():
    cases = [(dispersion(parameter="bus.weight", distribution="normal", std=1.0),
              "unknown parameter 'bus.weight' (none of the 55 parameters is close)"),
             (dispersion(parameter="bus.mas", distribution="normal", std=1.0), "(did you mean 'bus.mass'"),
             (spec_dict(initial={"v": {"scan": 0.1}}), "unknown DOF 'scan' (did you mean 'scan_el' or 'scan_az'?)"),
             (spec_dict(outputs={"metrics": ["peak_boom_tip"]}), "(did you mean 'peak_boom_tip_deflection'?)")]
    for spec, fragment in cases:
        with pytest.raises(SpecError) as error:
            load_spec(spec)
        message = str(error.value)
        assert fragment in message
        assert "fuel_slosh" not in message and "gravity" not in message and "wheel_1" not in message
        assert message.count("'") <= 2 * 5  # the name, the item, at most three suggestions


def test_every_problem_of_a_spec_is_reported_at_once():
    spec = {"seed": -1, "runs": 0, "colour": "red", "model": {"scene": "cassini"},
            "simulation": {"duration": 0.05, "dt": 5e-324, "integrator": "rk5", "events": ["lock nothing at 0.1"]},
            "initial": {"q": {"scan_azz": 0.1}},
            "dispersions": [{"parameter": "bus.mas", "distribution": "normal", "std": -1.0, "sdt": 1.0},
                            {"event": "lock scan_az", "distribution": "gamma"}],
            "outputs": {"metrics": ["peak_boom_tip"], "trajectory_every": -1}}
    with pytest.raises(SpecError) as error:
        load_spec(spec)
    expected = ["the spec: unknown key 'colour'", "seed must be an integer >= 0, got -1",
                "runs must be an integer in 1..100000000, got 0", "[simulation]: integrator must be one of",
                "[simulation] duration and dt: duration 0.05 s is inf steps of dt = 5e-324 s",
                "[simulation] events[0]: unknown DOF or joint 'nothing'",
                "[initial] q: unknown coordinate 'scan_azz'", "[outputs]: trajectory_every must be an integer",
                "dispersions[0] (parameter 'bus.mas'): unknown key 'sdt' (did you mean 'std'?)",
                "dispersions[0] (parameter 'bus.mas'): unknown parameter 'bus.mas'",
                "dispersions[0] (parameter 'bus.mas'): std must be >= 0, got -1",
                "dispersions[1] (event 'lock scan_az'): distribution must be one of normal, uniform, lognormal",
                "[outputs] metrics[0]: unknown metric 'peak_boom_tip'"]
    problems = error.value.problems
    assert len(problems) == len(expected)
    for fragment in expected:
        assert sum(p.startswith(fragment) for p in problems) == 1, fragment
    message = str(error.value)
    assert message.startswith(f"<dict>: {len(expected)} problems: (1) ") and "\n" not in message
    assert all(f"({k}) {p}" in message for k, p in enumerate(problems, 1))


def test_a_tiny_or_huge_step_is_a_spec_error_naming_duration_and_dt(tmp_path, capsys):
    for simulation, fragment in [({"duration": 1.0, "dt": 5e-324}, "duration 1.0 s is inf steps of dt = 5e-324 s"),
                                 ({"duration": 1.0, "rate": 5e-324}, "[simulation]: rate 5e-324 gives a step of inf"),
                                 ({"duration": 1.0, "rate": 1e308}, "duration 1.0 s is 1e+308 steps"),
                                 ({"duration": 1.0, "dt": 1e308}, "duration 1.0 s is shorter than one step")]:
        with pytest.raises(SpecError) as error:
            load_spec(spec_dict(simulation=simulation))
        assert fragment in str(error.value)
    path = tmp_path / "tiny_step.toml"
    path.write_text(EXAMPLES["cassini-example"].read_text().replace("dt = 0.001", "dt = 5e-324"))
    with pytest.raises(SystemExit) as exit_info:
        cli.main(["campaign", str(path), "--out", str(tmp_path / "out")])
    assert exit_info.value.code == 2
    err = capsys.readouterr().err
    assert "Traceback" not in err and err.count("error:") == 1  # the usage, then one error line
    assert err.strip().splitlines()[-1].startswith(f"soadyn campaign: error: argument SPEC: {path}: [simulation] "
                                                   f"duration and dt: duration 1.0 s is inf steps of dt = 5e-324 s")


def test_malformed_toml_and_missing_file_name_the_file(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text("seed = 1\nruns = [\n[model]\n")
    with pytest.raises(SpecError, match=r"bad.toml: not valid TOML: .*line"):
        load_spec(bad)
    with pytest.raises(SpecError, match=r"nope.toml: cannot read the spec: .*built-in examples: cassini-example"):
        load_spec(tmp_path / "nope.toml")


@pytest.mark.parametrize("argv, fragment", [
    (["campaign", "<SPEC>", "--out", "<OUT>"], "argument SPEC: <SPEC>: [model]: unknown scene 'voyager'"),
    (["campaign", "<SPEC>"], "argument --out: required"),
    (["campaign", "<SPEC>", "--out", "<OUT>", "--workers", "0"], "argument --workers: must be >= 1, got 0"),
    (["campaign", "<SPEC>", "--out", "<OUT>", "--runs", "-3"], "argument --runs: must be >= 1, got -3"),
    (["campaign", "<SPEC>", "--out", "<OUT>", "--workers", "2", "--scheduler", "tcp://127.0.0.1:1"],
     "argument --workers: sizes the local cluster"),
    (["campaign", "<SPEC>", "--out", "<OUT>", "--workers", "two"], "argument --workers: invalid int value: 'two'"),
    (["campaign", "<SPEC>", "EXTRA", "--out", "<OUT>"], "unrecognized arguments: EXTRA"),
    (["campaign", "replay", "<OUT>"], "replay takes DIR RUN_ID, got 1 argument"),
    (["campaign", "replay", "<OUT>", "x"], "argument RUN_ID: an integer is required, got 'x'"),
    (["campaign", "replay", "<OUT>", "1", "--runs", "3"], "argument --runs: not an option of `campaign replay`"),
    (["campaign", "replay", "<OUT>", "0"], "argument DIR: <OUT> is not a campaign results directory"),
    (["campaign", "report", "<OUT>"], "argument DIR: <OUT> is not a campaign results directory"),
    (["campaign", "report"], "report takes DIR, got 0 arguments"),
    (["campaign", "<SPEC>", "--out", "<OUT>", "--plots", "P"], "argument --plots: an option of `campaign report` only"),
    (["campaign"], "the following arguments are required: SPEC.toml|replay|report"),
])
def test_bad_campaign_command_lines_get_one_line_and_run_nothing(argv, fragment, tmp_path, capsys):
    spec = tmp_path / "spec.toml"
    spec.write_text('seed = 1\nruns = 4\n[model]\nscene = "voyager"\n[simulation]\nduration = 0.1\ndt = 0.001\n'
                    '[outputs]\nmetrics = ["energy_lost"]\n')
    out = tmp_path / "out"
    argv = [str(spec) if a == "<SPEC>" else str(out) if a == "<OUT>" else a for a in argv]
    with pytest.raises(SystemExit) as exit_info:
        cli.main(argv)
    assert exit_info.value.code == 2
    err = capsys.readouterr().err
    assert "Traceback" not in err
    line = err.strip().splitlines()[-1]
    assert line.startswith("soadyn campaign: error: ")
    assert fragment.replace("<SPEC>", str(spec)).replace("<OUT>", str(out)) in line
    assert not out.exists()  # nothing ran, nothing was written


@pytest.mark.parametrize("content, fragment", [
    (b"seed = 1\xff\xfe\n", "cannot read the spec: 'utf-8' codec can't decode byte 0xff"),
    (b"seed = " + b"[" * 3000 + b"]" * 3000, "not valid TOML: arrays or tables nested more than the 256 levels"),
    (b"".join(b"a%d." % k for k in range(300)) + b"b = 1", "not valid TOML: arrays or tables nested more than the 256"),
    (b"seed = " + b"9" * 5000, "not valid TOML: Exceeds the limit (4300 digits)"),
    (None, "cannot read the spec: not a regular file"),  # /dev/zero: a read that never ends
])
def test_hostile_spec_files_are_spec_errors(content, fragment, tmp_path):
    path = tmp_path / "hostile.toml"
    if content is None:
        path = Path("/dev/zero")
    else:
        path.write_bytes(content)
    with pytest.raises(SpecError) as error:
        load_spec(path)
    assert str(error.value).startswith(f"{path}: {fragment}")
    assert error.value.problems == (str(error.value)[len(f"{path}: "):],)


def test_the_example_is_package_data_and_reads_by_name():
    path = EXAMPLES["cassini-example"]
    assert path.is_file() and path.parent.parent == Path(soadyn.__file__).parent / "campaign"
    spec = load_spec("cassini-example")
    assert (spec.name, spec.runs, spec.scene, spec.duration, spec.dt, spec.integrator) == \
        ("cassini-example", 1000, "cassini", 1.0, 0.001, "rk4")
    assert "scan_az_lock_time" in spec.dispersion_columns and "bus.mass" in spec.dispersion_columns
    assert load_spec("cassini-example", runs=7).runs == 7
    with pytest.raises(SpecError, match=r"runs \(override\) must be an integer"):
        load_spec("cassini-example", runs=0)


def test_run_i_draws_from_child_i_of_seed_sequence_spawn():
    spec = load_spec(spec_dict(dispersions=[
        {"parameter": "bus.mass", "distribution": "normal", "scale": 0.05},
        {"event": "lock scan_az", "distribution": "uniform", "low": 0.01, "high": 0.04},
        {"parameter": "fuel_slosh.mass", "distribution": "lognormal", "sigma": 0.1}]))
    children = np.random.SeedSequence(spec.seed).spawn(spec.runs)
    for i, child in enumerate(children):
        rng = np.random.default_rng(child)
        expected = [rng.normal(2925.0, 0.05 * 2925.0), rng.uniform(0.01, 0.04), rng.lognormal(math.log(400.0), 0.1)]
        assert draw(spec, i) == expected
        assert generator(spec.seed, i).bit_generator.state == np.random.default_rng(child).bit_generator.state


def test_a_run_is_a_pure_function_of_spec_and_run_id():
    spec = load_spec(spec_dict(dispersions=[
        {"parameter": "bus.mass", "distribution": "normal", "scale": 0.05},
        {"parameter": "oxidizer_slosh.com[2]", "distribution": "normal", "scale": 0.1},
        {"initial": "v:scan_az", "distribution": "uniform", "low": 0.05, "high": 0.1},
        {"event": "lock scan_az", "distribution": "uniform", "low": 0.01, "high": 0.04},
        {"source": "input:wheel_1", "distribution": "normal", "mean": 0.0, "std": 0.5}],
        outputs={"metrics": ["peak_boom_tip_deflection", "final_attitude_error", "max_hinge_torque",
                             "energy_lost", "final_energy"], "trajectory_every": 5}))
    first = [run_one(spec, i) for i in range(3)]
    again = [run_one(spec, i) for i in (2, 0, 1)]
    for a, b in zip(first, [again[1], again[2], again[0]]):
        assert a.row == b.row
        assert all(np.array_equal(a.trajectory[k], b.trajectory[k]) for k in ("t", "q", "v"))
    assert first[0].row != first[1].row
    assert all(r.row["status"] == "ok" and r.row["energy_lost"] > 0 for r in first)  # the lock stops a slew
    assert first[0].trajectory["q"].shape == (11, 29)  # 50 steps, every 5th


def test_the_nominal_run_is_the_run_soadyn_hil_flies():
    spec = load_spec(spec_dict(dispersions=[], simulation={"duration": 0.2, "dt": 0.001},
                               outputs={"metrics": [], "trajectory_every": 1}))
    outcome = run_one(spec, 0)
    reference = hil.scene_simulator("cassini", 1000.0).run(0.2)
    assert np.array_equal(outcome.trajectory["q"], reference.q)
    assert np.array_equal(outcome.trajectory["v"], reference.v)


def test_parameter_dispersions_reach_the_model():
    spec = load_spec(spec_dict(dispersions=[
        {"parameter": "bus.inertia[0,2]", "distribution": "uniform", "low": 100.0, "high": 101.0},
        {"parameter": "fuel_slosh.placement[2,3]", "distribution": "uniform", "low": 0.5, "high": 0.6}],
        outputs={"metrics": ["energy_lost"]}))
    from soadyn.campaign.simulate import prepare

    values = draw(spec, 0)
    model = prepare(spec, values)._model
    inertia = model.get_parameter("bus.inertia")
    assert inertia[0, 2] == inertia[2, 0] == values[0]
    assert model.get_parameter("fuel_slosh.placement")[2, 3] == values[1]


def test_failed_runs_carry_status_and_message():
    spec = load_spec({"seed": 1, "runs": 3, "model": {"scene": "pendulum-chain"},
                      "simulation": {"duration": 0.05, "dt": 0.001},
                      "dispersions": [{"initial": "v:link_1", "distribution": "uniform", "low": 1e150, "high": 1e151}],
                      "outputs": {"metrics": ["final_energy", "max_abs_q:link_3"]}})
    row = run_one(spec, 0).row
    assert row["status"] == "failed" and row["final_energy"] is None and row["max_abs_q:link_3"] is None
    assert row["message"].startswith("DynamicsError: simulation stopped: non-finite result (DOF 'link_1')")
    assert 1e150 <= row["v:link_1"] <= 1e151
    spec = load_spec(dispersion(parameter="bus.mass", distribution="uniform", low=-2.0, high=-1.0))
    row = run_one(spec, 0).row
    assert row["status"] == "failed"
    assert row["message"].startswith("ParameterError: parameter 'bus.mass': mass -1.")
    assert row["message"].endswith("is negative")


def test_peak_tip_deflection_is_the_largest_node_pose_displacement():
    spec = load_spec(spec_dict(dispersions=[], simulation={"duration": 0.3, "dt": 0.001},
                               initial={"v": {"scan_az": 0.3}}))
    from soadyn.campaign.simulate import prepare

    sim = prepare(spec, [])
    trajectory = sim.run(0.3)
    model = sim._model
    b = model.body_names.index("magnetometer_boom")
    boom = model.flexible_body("magnetometer_boom")
    tip = boom.attachments["tip"]
    end = model.q_index[b + 1]
    rest = boom.node_pose(tip, np.zeros(4))[:3, 3]
    brute = max(np.linalg.norm(boom.node_pose(tip, eta)[:3, 3] - rest) for eta in trajectory.q[:, end - 4:end])
    value = METRICS["peak_boom_tip_deflection"].compute(model, trajectory, sim, None)
    assert value == brute and value > 0


def test_attitude_error_is_the_rotation_angle():
    half = 0.3 / 2
    q0 = np.array([0.0, 0.0, 0.0, 1.0])
    q1 = np.array([0.0, np.sin(half), 0.0, np.cos(half)])
    assert _rotation_angle(q0, q1) == pytest.approx(0.3, rel=1e-14)
    assert _rotation_angle(q1, q1) == 0.0
    assert _rotation_angle(q1, -q1) == 0.0  # the same attitude
    axis = np.array([1.0, 2.0, 2.0]) / 3.0
    qa = np.array([*np.sin(0.2) * axis, np.cos(0.2)])
    qb = np.array([*np.sin(0.7) * axis, np.cos(0.7)])
    assert _rotation_angle(qa, qb) == pytest.approx(1.0, rel=1e-13)


def test_a_model_file_relative_to_the_spec(tmp_path):
    soadyn.save_model(soadyn.scenes.cassini(), tmp_path / "craft.json")
    (tmp_path / "spec.toml").write_text(
        'seed = 2\nruns = 3\n[model]\nfile = "craft.json"\n[simulation]\nduration = 0.02\nrate = 1000\n'
        '[outputs]\nmetrics = ["max_abs_v:turntable"]\ntrajectory_every = 1\n'
        '[[dispersions]]\nsource = "velocity:turntable"\ndistribution = "normal"\nmean = 0.25\nstd = 0.01\n')
    spec = load_spec(tmp_path / "spec.toml")
    text = (tmp_path / "craft.json").read_text()
    assert spec.scene is None and spec.model_json == text and spec.dt == 0.001
    assert spec.identity()["model"] == {"file_sha256": spec.model_sha256}  # the file's content, not its path
    outcome = run_one(spec, 1)
    rate = outcome.row["velocity:turntable"]
    k = spec.dof_names.index("turntable")
    assert outcome.row["status"] == "ok" and outcome.row["max_abs_v:turntable"] == pytest.approx(rate, rel=1e-12)
    assert np.allclose(outcome.trajectory["v"][1:, k], rate, rtol=1e-12)  # driven from t = 0, from rest
    assert outcome.trajectory["q"][0, spec.coordinate_names.index("bus:qw")] == 1.0  # rest at neutral


def test_a_directory_of_other_files_is_refused_before_any_run(tmp_path):
    from soadyn.campaign import ResultsDirectoryError, run

    (tmp_path / "notes.txt").write_text("mine")
    with pytest.raises(ResultsDirectoryError, match="is not empty and holds no campaign"):
        run(spec_dict(), out=tmp_path, progress=False, verbose=False)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["notes.txt"]


@pytest.mark.parametrize("out, fragment", [("/proc/x", "/proc/x: cannot be created ("),
                                           ("<TMP>/notes.txt", "notes.txt: is a file, not a directory")])
def test_a_results_directory_that_cannot_be_written_is_refused_before_any_run(out, fragment, tmp_path):
    from soadyn.campaign import ResultsDirectoryError, run

    (tmp_path / "notes.txt").write_text("mine")
    with pytest.raises(ResultsDirectoryError) as error:
        run(spec_dict(), out=out.replace("<TMP>", str(tmp_path)), progress=False, verbose=False)
    assert fragment in str(error.value)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["notes.txt"]


def test_run_one_takes_a_spec_by_name_and_refuses_a_run_id_out_of_range():
    assert run_one("cassini-example", 0).row["status"] == "ok"
    spec = load_spec("cassini-example", runs=3)
    for run_id in (3, -1, 1.0, True):
        with pytest.raises(ValueError, match=r"run id must be an integer in 0\.\.2"):
            run_one(spec, run_id)
