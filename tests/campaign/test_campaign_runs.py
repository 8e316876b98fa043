"""Campaigns on Dask: 1 and 2 workers, a separately started scheduler and worker, an interrupted
campaign and a killed worker all give the Parquet content of a plain in-process loop over the same
runs; failed runs are rows, not aborts; replay and report read a results directory."""
import json
import os
import re
import signal
import subprocess
import sys
import time
from pathlib import Path

import imageio.v2 as imageio
import numpy as np
import pyarrow.parquet as pq
import pytest

from soadyn import campaign, cli
from soadyn.campaign import load_spec, run_one
from soadyn.campaign.store import rows_table, trajectory_table

TIMEOUT = 120
# A scheduler serves HTTP (health, metrics) on port 8787 unless told otherwise, dashboard or not: the
# clusters made here take any free port, so that runs in parallel (pytest-xdist) never compete for it.
FREE_HTTP_PORT = {"dashboard_address": ":0"}

# cassini, its scan platform slewing until a dispersed lock, with every kind of dispersion; the
# engine mass N(5, 10) kg is negative in about a third of the runs: those runs fail.
TINY = """
name = "tiny"
seed = 7
runs = 16

[model]
scene = "cassini"

[simulation]
duration = {duration}
dt = 0.001
integrator = "rk4"
events = ["lock scan_el at 0.05"]

[initial]
v = {{ scan_az = 0.1 }}

[outputs]
metrics = ["peak_boom_tip_deflection", "final_attitude_error", "max_hinge_torque", "energy_lost",
           "max_abs_q:scan_az"]
trajectory_every = {every}

[[dispersions]]
parameter = "bus.mass"
distribution = "normal"
scale = 0.05

[[dispersions]]
parameter = "engine.mass"
distribution = "normal"
mean = 5.0
std = 10.0

[[dispersions]]
parameter = "fuel_slosh.placement[2,3]"
distribution = "normal"
std = 0.05

[[dispersions]]
initial = "q:scan_el"
distribution = "uniform"
low = -0.1
high = 0.1

[[dispersions]]
event = "lock scan_az"
name = "scan_az_lock_time"
distribution = "uniform"
low = 0.02
high = 0.08

[[dispersions]]
source = "input:wheel_1"
distribution = "normal"
mean = 0.0
std = 0.1
"""


def write_spec(directory: Path, name: str = "tiny.toml", duration: float = 0.1, every: int = 10, **changes) -> Path:
    text = TINY.format(duration=duration, every=every)
    for key, value in changes.items():
        text = re.sub(rf"^{key} = .*$", f"{key} = {value}", text, count=1, flags=re.M)
    path = directory / name
    path.write_text(text)
    return path


def plain_loop(spec_path: Path, runs=None):
    """The reference: the same runs in a plain loop in this process, as tables."""
    spec = load_spec(spec_path, runs=runs)
    outcomes = [run_one(spec, i) for i in range(spec.runs)]
    trajectories = {o.row["run_id"]: trajectory_table(spec, o.trajectory) for o in outcomes if o.trajectory}
    return rows_table(spec, [o.row for o in outcomes]), trajectories


def results(out: Path):
    return pq.read_table(out / "results.parquet")


def stored_trajectories(out: Path) -> dict:
    return {int(d.name.split("=")[1]): pq.read_table(d / "part.parquet") for d in (out / "trajectories").iterdir()}


def parts(out: Path) -> dict:
    """part file -> (inode, mtime, bytes): a part rewritten or redone would change."""
    return {p.name: (p.stat().st_ino, p.stat().st_mtime_ns, p.read_bytes()) for p in (out / "runs").glob("part-*")}


@pytest.fixture(scope="module")
def tiny(tmp_path_factory):
    """The spec, its plain-loop reference, and its campaign on 1 and on 2 local workers."""
    root = tmp_path_factory.mktemp("campaign")
    spec = write_spec(root)
    table, trajectories = plain_loop(spec)
    one = campaign.run(spec, out=root / "one", workers=1, progress=False, verbose=False, dashboard=False)
    two = campaign.run(spec, out=root / "two", workers=2, chunk_size=3, progress=False, verbose=False,
                       dashboard=False)
    return {"root": root, "spec": spec, "table": table, "trajectories": trajectories, "one": one, "two": two}


@pytest.fixture(scope="module")
def one_worker():
    """A client of a one-worker local cluster, for the tests whose subject is not the cluster campaign.run
    makes for itself (the tiny fixture's is)."""
    from dask.distributed import Client, LocalCluster

    with LocalCluster(n_workers=1, threads_per_worker=1, processes=True, dashboard_address=None,
                      scheduler_kwargs=FREE_HTTP_PORT) as cluster, Client(cluster) as client:
        yield client


def test_one_and_two_workers_give_the_plain_loops_parquet_content(tiny):
    one, two = tiny["root"] / "one", tiny["root"] / "two"
    assert results(one).equals(tiny["table"])
    assert results(two).equals(tiny["table"])
    assert (one / "results.parquet").read_bytes() == (two / "results.parquet").read_bytes()
    ok = [r["run_id"] for r in tiny["table"].to_pylist() if r["status"] == "ok"]
    assert sorted(tiny["trajectories"]) == ok  # a run failing before its first step has none
    for out in (one, two):
        kept = stored_trajectories(out)
        assert sorted(kept) == ok
        assert all(kept[i].equals(tiny["trajectories"][i]) for i in ok)
    assert tiny["one"].workers == 1 and tiny["two"].workers == 2
    assert tiny["one"].table.equals(tiny["table"]) and tiny["two"].table.equals(tiny["table"])


def test_the_example_runs_by_its_name(tmp_path, capsys):
    out = tmp_path / "example"
    argv = ["campaign", "cassini-example", "--out", str(out), "--runs", "6", "--workers", "1", "--no-progress",
            "--no-dashboard"]
    assert cli.main(argv) == 0
    printed = capsys.readouterr().out
    assert printed.startswith("campaign cassini-example: 6 runs of 1 s (rk4, dt 0.001 s), 11 dispersed values\n")
    assert "done: 6 runs, 0 failed; 6 computed now in " in printed
    table = results(out)
    assert table.column_names[-6:] == ["peak_boom_tip_deflection", "final_attitude_error", "max_hinge_torque",
                                       "energy_lost", "status", "message"]
    assert table["status"].to_pylist() == ["ok"] * 6
    assert table.equals(plain_loop(campaign.EXAMPLES["cassini-example"], runs=6)[0])
    assert (out / "spec.toml").read_text() == campaign.EXAMPLES["cassini-example"].read_text()


def test_failed_runs_are_rows_with_status_and_message(tiny):
    rows = tiny["table"].to_pylist()
    failed = [r for r in rows if r["status"] == "failed"]
    assert 0 < len(failed) < len(rows) and tiny["one"].failed == len(failed)
    for r in failed:
        assert r["engine.mass"] < 0 and r["peak_boom_tip_deflection"] is None
        assert r["message"].startswith("ParameterError: parameter 'engine.mass': mass -")
    ok = [r for r in rows if r["status"] == "ok"]
    assert all(r["engine.mass"] >= 0 and r["message"] == "" and r["energy_lost"] > 0 for r in ok)
    assert [r["run_id"] for r in rows] == list(range(16))


def test_replay_equals_the_stored_row_bit_for_bit(tiny, capsys):
    out = tiny["root"] / "two"
    failed = next(r["run_id"] for r in tiny["table"].to_pylist() if r["status"] == "failed")
    for run_id in (0, failed, 15):
        replayed = campaign.replay(out, run_id)
        assert replayed.equal and replayed.trajectory_equal is True
        assert replayed.outcome.row == tiny["table"].to_pylist()[run_id]
    assert cli.main(["campaign", "replay", str(out), "5"]) == 0
    printed = capsys.readouterr().out
    assert "run 5: the recomputed values equal the stored ones bit for bit" in printed
    assert "trajectory: bit-identical" in printed and "scan_az_lock_time" in printed
    with pytest.raises(SystemExit) as exit_info:
        cli.main(["campaign", "replay", str(out), "16"])
    assert exit_info.value.code == 2
    assert "argument RUN_ID: run id must be an integer in 0..15, got 16" in capsys.readouterr().err


def test_report_writes_pngs_and_the_summary_table(tiny, capsys):
    out = tiny["root"] / "one"
    plots = tiny["root"] / "plots"
    assert cli.main(["campaign", "report", str(out), "--plots", str(plots)]) == 0
    printed = capsys.readouterr().out
    failed = tiny["one"].failed
    assert f"16 of 16 runs finished, {failed} failed" in printed
    header = printed.splitlines()[1].split()
    assert header == ["count", "failed", "mean", "std", "min", "p5", "p50", "p95", "max"]
    line = next(li for li in printed.splitlines() if li.startswith("peak_boom_tip_deflection "))
    assert line.split()[1:3] == [str(16 - failed), str(failed)]
    names = sorted(p.name for p in plots.iterdir())
    assert names == sorted([f"{kind}_{m}.png" for kind in ("hist", "scatter") for m in
                            ("peak_boom_tip_deflection", "final_attitude_error", "max_hinge_torque",
                             "energy_lost", "max_abs_q_scan_az")] + ["summary.md"])
    assert all((plots / n).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" for n in names if n.endswith(".png"))
    assert "| peak_boom_tip_deflection |" in (plots / "summary.md").read_text()


def test_another_spec_is_refused_in_a_results_directory(tiny, capsys):
    out = tiny["root"] / "one"
    before = parts(out)
    other = write_spec(tiny["root"], "other.toml", seed=8)
    with pytest.raises(SystemExit) as exit_info:
        cli.main(["campaign", str(other), "--out", str(out), "--no-progress"])
    assert exit_info.value.code == 2
    line = capsys.readouterr().err.strip().splitlines()[-1]
    assert line.startswith("soadyn campaign: error: argument --out: ")
    assert "holds the results of another spec (it differs in: seed)" in line
    assert parts(out) == before


def test_fewer_runs_never_shrink_a_campaigns_results(tiny, capsys):
    out = tiny["root"] / "one"
    kept = {name: (out / name).read_bytes() for name in ("results.parquet", "spec.json")}
    before = parts(out)
    with pytest.raises(campaign.ResultsDirectoryError) as error:
        campaign.run(tiny["spec"], out=out, runs=10, workers=1, progress=False, verbose=False, dashboard=False)
    assert "holds a campaign of 16 runs of this spec: 10 runs would shrink it; give runs >= 16" in str(error.value)
    with pytest.raises(SystemExit) as exit_info:
        cli.main(["campaign", str(tiny["spec"]), "--out", str(out), "--runs", "10", "--no-progress"])
    assert exit_info.value.code == 2
    printed = capsys.readouterr()
    assert printed.out == "" and printed.err.count("error:") == 1
    assert printed.err.strip().splitlines()[-1].startswith(f"soadyn campaign: error: argument --out: {out} holds a "
                                                           f"campaign of 16 runs of this spec: 10 runs would shrink it")
    assert {name: (out / name).read_bytes() for name in kept} == kept and parts(out) == before
    assert campaign.report(out, plots=False).finished == 16


def test_an_interrupted_campaign_resumes_without_redoing_finished_runs(tiny, one_worker):
    out = tiny["root"] / "interrupted"
    batches = []

    def interrupt_after_three(outcomes):
        batches.append([o.row["run_id"] for o in outcomes])
        if len(batches) == 3:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        campaign.run(tiny["spec"], one_worker, out=out, chunk_size=2, progress=False, verbose=False,
                     on_batch=interrupt_after_three)
    assert not (out / "results.parquet").exists()
    before = parts(out)
    assert len(before) == 3
    done = sorted(i for batch in batches for i in batch)
    again = []
    result = campaign.run(tiny["spec"], one_worker, out=out, chunk_size=2, progress=False, verbose=False,
                          on_batch=lambda o: again.extend(r.row["run_id"] for r in o))
    assert (result.done_before, result.computed) == (6, 10)
    assert sorted(again) == sorted(set(range(16)) - set(done))  # nothing done twice
    now = parts(out)
    assert {name: now[name] for name in before} == before  # the first parts untouched
    assert results(out).equals(tiny["table"])
    assert all(t.equals(tiny["trajectories"][i]) for i, t in stored_trajectories(out).items())
    more = campaign.run(tiny["spec"], one_worker, out=out, runs=20, progress=False, verbose=False)
    assert (more.done_before, more.computed, more.table.num_rows) == (16, 4, 20)  # more runs extend it
    assert more.table.slice(0, 16).equals(tiny["table"])
    assert json.loads((out / "spec.json").read_text())["spec"]["runs"] == 20


def test_a_worker_killed_mid_campaign_changes_nothing(tmp_path):
    spec = write_spec(tmp_path, duration=1.0, every=0, runs=24)
    table, _ = plain_loop(spec)
    from dask.distributed import Client, LocalCluster

    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None,
                      scheduler_kwargs=FREE_HTTP_PORT) as cluster, Client(cluster) as client:
        pids = client.run(os.getpid)
        victim = pids[sorted(pids)[0]]
        killed = []

        def kill_once(outcomes):
            if not killed:
                os.kill(victim, signal.SIGKILL)
                killed.append(victim)

        result = campaign.run(spec, client, out=tmp_path / "out", chunk_size=1, progress=False, verbose=False,
                              on_batch=kill_once)
        assert killed and victim not in client.run(os.getpid).values()
    assert result.table.equals(table) and results(tmp_path / "out").equals(table)


def cli_command(*args) -> list:
    return [sys.executable, "-m", "soadyn", "campaign", *map(str, args)]


def test_the_command_killed_mid_campaign_resumes_to_the_same_result(tmp_path):
    spec = write_spec(tmp_path, duration=2.0, every=0, runs=60)
    table, _ = plain_loop(spec)
    out = tmp_path / "out"
    command = cli_command(spec, "--out", out, "--workers", "1", "--chunk", "1", "--no-progress", "--no-dashboard")
    process = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)
    try:
        deadline = time.monotonic() + TIMEOUT
        while len(list((out / "runs").glob("part-*"))) < 3 and process.poll() is None:
            assert time.monotonic() < deadline
            time.sleep(0.01)
    finally:
        os.killpg(process.pid, signal.SIGKILL)  # the command and its cluster's processes
        process.wait(TIMEOUT)
    before = parts(out)
    assert 3 <= len(before) < 60 and not (out / "results.parquet").exists()
    resumed = subprocess.run(command, capture_output=True, text=True, timeout=TIMEOUT)
    assert resumed.returncode == 0, resumed.stderr
    assert f"; {len(before)} already done in {out}, {60 - len(before)} to run" in resumed.stdout
    now = parts(out)
    assert {name: now[name] for name in before} == before and len(now) == 60
    assert results(out).equals(table)


def test_ctrl_c_stops_the_command_with_one_line(tmp_path):
    spec = write_spec(tmp_path, duration=2.0, every=0, runs=60)
    out = tmp_path / "out"
    command = cli_command(spec, "--out", out, "--workers", "2", "--chunk", "1", "--no-progress", "--no-dashboard")
    process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                               start_new_session=True)
    try:
        deadline = time.monotonic() + TIMEOUT
        while len(list((out / "runs").glob("part-*"))) < 2 and process.poll() is None:
            assert time.monotonic() < deadline
            time.sleep(0.01)
        os.killpg(process.pid, signal.SIGINT)  # what a terminal's Ctrl-C does: the whole process group
        _, err = process.communicate(timeout=TIMEOUT)
    finally:
        if process.poll() is None:
            os.killpg(process.pid, signal.SIGKILL)
            process.wait(TIMEOUT)
    assert process.returncode == 130
    assert "Traceback" not in err
    assert err.strip().splitlines()[-1] == (f"soadyn campaign: interrupted; the finished runs are in {out}: the same "
                                            f"command resumes the campaign")


@pytest.fixture
def dask_scheduler_and_worker(tmp_path):
    """A `dask scheduler` on 127.0.0.1 and one `dask worker`, started as separate processes."""
    scheduler_file = tmp_path / "scheduler.json"
    processes = []
    try:
        processes.append(subprocess.Popen(
            [sys.executable, "-m", "distributed.cli.dask_scheduler", "--host", "127.0.0.1", "--port", "0",
             "--no-dashboard", "--dashboard-address", ":0", "--scheduler-file", str(scheduler_file)],
            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True))
        deadline = time.monotonic() + TIMEOUT
        while not scheduler_file.exists() or not scheduler_file.read_text().strip():
            assert processes[0].poll() is None and time.monotonic() < deadline, "the scheduler did not start"
            time.sleep(0.05)
        address = json.loads(scheduler_file.read_text())["address"]
        processes.append(subprocess.Popen(
            [sys.executable, "-m", "distributed.cli.dask_worker", address, "--nworkers", "1", "--nthreads", "1",
             "--no-dashboard"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True))
        from dask.distributed import Client

        with Client(address, timeout=TIMEOUT) as client:
            client.wait_for_workers(1, timeout=TIMEOUT)
        yield address
    finally:
        for process in reversed(processes):
            try:
                os.killpg(process.pid, signal.SIGTERM)
                process.wait(20)
            except subprocess.TimeoutExpired:
                os.killpg(process.pid, signal.SIGKILL)
                process.wait(TIMEOUT)
            except ProcessLookupError:
                pass


def test_a_separately_started_scheduler_runs_the_spec(dask_scheduler_and_worker, tiny, tmp_path, capsys):
    address = dask_scheduler_and_worker
    assert address.startswith("tcp://127.0.0.1:")
    out = tmp_path / "out"
    assert cli.main(["campaign", str(tiny["spec"]), "--scheduler", address, "--out", str(out), "--no-progress"]) == 0
    printed = capsys.readouterr().out
    assert "done: 16 runs" in printed
    assert results(out).equals(tiny["table"])
    assert (out / "results.parquet").read_bytes() == (tiny["root"] / "one" / "results.parquet").read_bytes()


def test_an_unreachable_scheduler_is_one_line_exit_1(tiny, tmp_path, capsys, monkeypatch):
    from soadyn.campaign import execute

    monkeypatch.setattr(execute, "CONNECT_TIMEOUT", 1)
    import socket

    with socket.socket() as s:  # a port nothing listens on
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    with pytest.raises(SystemExit) as exit_info:
        cli.main(["campaign", str(tiny["spec"]), "--scheduler", f"tcp://127.0.0.1:{port}",
                  "--out", str(tmp_path / "out"), "--no-progress"])
    assert exit_info.value.code == 1
    err = capsys.readouterr().err
    assert "Traceback" not in err
    assert err.strip().splitlines()[-1].startswith(
        f"soadyn campaign: error: cannot reach the Dask scheduler at tcp://127.0.0.1:{port}: ")


class _WorkersReporting:
    """A Dask client stand-in whose `run` returns what each worker reports."""

    def __init__(self, reports: dict):
        self.reports = reports

    def run(self, function):
        return dict(self.reports)


@pytest.mark.parametrize("kernel, names", [("joint_angle_kernel", ("polynomial AVX2", "libmvec SSE2", "std")),
                                           ("mass_matrix_kernel", ("AVX2 FMA", "baseline")),
                                           ("appendage_kernel", ("AVX2 FMA", "baseline"))])
def test_a_worker_with_another_kernel_stops_the_campaign(kernel, names):
    """Processors whose sines and cosines of the joint angles round differently (libmvec's AVX2 or
    SSE2 kernel, or std::sin), or whose mass matrix or flexible appendages' step is formed with or
    without fused multiply-adds, would not give bit-identical runs: such a worker is refused by name, and one
    that agrees on everything is accepted."""
    from soadyn.campaign import execute

    mine = execute._versions()
    assert mine[kernel] in names
    other_kernel = next(name for name in names if name != mine[kernel])
    differing = {"tcp://10.0.0.2:4000": dict(mine, **{kernel: other_kernel})}
    with pytest.raises(campaign.CampaignError, match=rf"worker tcp://10\.0\.0\.2:4000 has .*{kernel} "
                                                      + re.escape(other_kernel)):
        execute._check_workers(_WorkersReporting(differing), say=lambda line: None)
    agreeing = {"tcp://10.0.0.3:4000": dict(mine)}
    assert execute._check_workers(_WorkersReporting(agreeing), say=lambda line: None) == 1


def test_report_makes_a_movie_of_the_run_with_the_largest_metric(tiny, capsys):
    out, plots = tiny["root"] / "one", tiny["root"] / "movie"
    metric = "peak_boom_tip_deflection"
    table = results(out).to_pydict()
    finished = [(value, run) for value, run, status in zip(table[metric], table["run_id"], table["status"])
                if status == "ok" and value is not None]
    value, worst = max(finished)
    assert cli.main(["campaign", "report", str(out), "--no-plots", "--plots", str(plots), "--movie", metric]) == 0
    assert f"the run with the largest {metric} (run {worst}, {value:.6g})" in capsys.readouterr().out
    movie = plots / f"worst_{metric}_run{worst}.mp4"
    frames = [np.asarray(f) for f in imageio.get_reader(movie)]
    assert len(frames) == 4  # 0.1 s at 30 frames per second: 0, 1/30, 2/30, 3/30
    assert all((f.min(axis=2) < 245).mean() >= 0.01 for f in frames)
    with pytest.raises(SystemExit) as exit_info:
        cli.main(["campaign", "report", str(out), "--no-plots", "--movie", "peak_tip"])
    assert exit_info.value.code == 2
    assert "argument --movie: no metric 'peak_tip' in this campaign" in capsys.readouterr().err
