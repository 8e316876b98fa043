"""The command line refuses every bad argument, and every output path it could
not write, with one error line naming it (exit code 2, no traceback) before any
work, and `--udp 0` announces the port it bound."""
import json
import socket
import subprocess
import sys

import pytest

from soadyn import cli
from support.hil_pd_controller import command_packet

TIMEOUT = 120


def refused(argv, capsys):
    """The error line of a refused command line (exit code 2)."""
    with pytest.raises(SystemExit) as exit_info:
        cli.main(argv)
    assert exit_info.value.code == 2
    err = capsys.readouterr().err
    assert "Traceback" not in err
    return err.strip().splitlines()[-1]


HIL = ["hil", "--no-progress", "--duration", "0.01"]


@pytest.mark.parametrize("argv, line", [
    (HIL + ["--rate", "inf"], "argument --rate: must be a finite number > 0, got inf"),
    (HIL + ["--rate", "nan"], "argument --rate: must be a finite number > 0, got nan"),
    (HIL + ["--rate", "-5"], "argument --rate: must be a finite number > 0, got -5.0"),
    (["hil", "--rate", "1e7", "--duration", "1e3"], "argument --duration: 1000 s at --rate 1e+07 is 1e+10 steps"),
    (HIL[:2] + ["--duration", "inf"], "argument --duration: must be a finite number >= 0, got inf"),
    (HIL + ["--rate", "abc"], "argument --rate: invalid float value: 'abc'"),
    (HIL + ["--udp", "70000"], "argument --udp: 70000 is not a port (0..65535)"),
    (HIL + ["--udp-peer", "-1"], "argument --udp-peer: -1 is not a port (0..65535)"),
    (HIL + ["--udp-command-port", "65536"], "argument --udp-command-port: 65536 is not a port"),
    (HIL + ["--max-packets-per-step", "0"], "argument --max-packets-per-step: must be >= 1, got 0"),
    (HIL + ["--spin-us", "nan"], "argument --spin-us: must be in [0, 1000)"),
    (HIL + ["--command-limit", "fast"], "argument --command-limit: 'fast': expected LIMIT or DOF=LIMIT"),
    (HIL + ["--command-limit", "scan_az=-1"], "argument --command-limit: 'scan_az=-1': a limit is >= 0"),
    (HIL + ["--command-limit", "nope=1"], "argument --command-limit: 'nope=1': no DOF named 'nope'"),
    (HIL + ["--command-policy", "ignore"], "argument --command-policy: invalid choice: 'ignore'"),
    (HIL + ["--event", "lock scan_az at inf"], "argument --event: bad event 'lock scan_az at inf'"),
    (HIL + ["--fifo-priority", "100"], "priority 100"),
    (["demo", "--duration", "inf"], "argument --duration: must be a finite number > 0, got inf"),
    (["demo", "--dt", "0"], "argument --dt: must be a finite number > 0, got 0.0"),
    (["demo", "--boom-duration", "nan"], "argument --boom-duration: must be a finite number >= 0, got nan"),
    (["check", "robot.urdf", "--states", "0"], "argument --states: must be >= 1, got 0"),
    (["check", "robot.urdf", "--tolerance", "nan"], "argument --tolerance: must be a finite number >= 0, got nan"),
    ([], "a command is required: demo, check, hil, view, campaign, robots or fmu"),
])
def test_bad_arguments_get_one_line_naming_them(argv, line, capsys):
    assert line in refused(argv, capsys)


def test_plot_without_matplotlib_is_refused_before_the_run(monkeypatch, capsys, tmp_path):
    monkeypatch.setitem(sys.modules, "matplotlib", None)  # import matplotlib raises ImportError
    line = refused(HIL + ["--plot", str(tmp_path / "out.png")], capsys)
    assert line.endswith("argument --plot: plotting needs matplotlib: pip install 'soadyn[plot]'")
    line = refused(["demo", "--duration", "0.01", "--plot", str(tmp_path / "out.png")], capsys)
    assert "argument --plot: plotting needs matplotlib" in line


@pytest.mark.parametrize("argv, line", [
    (HIL + ["--report", "<TMP>/missing/out.json"],
     "argument --report: <TMP>/missing/out.json: the directory <TMP>/missing does not exist"),
    (HIL + ["--report", "<TMP>/file.txt/out.json"],
     "argument --report: <TMP>/file.txt/out.json: <TMP>/file.txt is not a directory"),
    (HIL + ["--plot", "<TMP>"], "argument --plot: <TMP>: is a directory"),
    (HIL + ["--report", "/proc/out.json"], "argument --report: /proc/out.json: cannot be written ("),
    (["demo", "--duration", "0.01", "--plot", "<TMP>/missing/x.png"],
     "argument --plot: <TMP>/missing/x.png: the directory <TMP>/missing does not exist"),
    (["campaign", "cassini-example", "--out", "/proc/x"], "argument --out: /proc/x: cannot be created ("),
    (["campaign", "cassini-example", "--out", "<TMP>/file.txt"], "argument --out: <TMP>/file.txt: is a file, not a "
                                                                 "directory"),
    (["campaign", "cassini-example", "--out", "<TMP>/file.txt/out"],
     "argument --out: <TMP>/file.txt/out: <TMP>/file.txt is not a directory"),
    (["campaign", "report", "<TMP>", "--plots", "/proc/plots"], "argument --plots: /proc/plots: cannot be created ("),
])
def test_every_output_path_is_checked_before_any_work(argv, line, tmp_path, capsys):
    (tmp_path / "file.txt").write_text("mine")
    before = sorted(tmp_path.rglob("*"))
    with pytest.raises(SystemExit) as exit_info:
        cli.main([a.replace("<TMP>", str(tmp_path)) for a in argv])
    assert exit_info.value.code == 2
    printed = capsys.readouterr()
    assert printed.out == ""  # nothing ran: no scene described, no campaign started
    assert "Traceback" not in printed.err and printed.err.count("error:") == 1
    last = printed.err.strip().splitlines()[-1]
    assert last.startswith(f"soadyn {argv[0]}: error: {line.replace('<TMP>', str(tmp_path))}")
    assert sorted(tmp_path.rglob("*")) == before and (tmp_path / "file.txt").read_text() == "mine"


@pytest.mark.parametrize("content, culprit", [
    (None, "does not exist"),
    ("<robot name='r'><link name='a'/><joint name='j' type='revolute'><parent link='a'/>"
     "<child link='b'/></joint></robot>", "r.urdf"),
    ("this is not XML <", "r.urdf"),
])
def test_check_on_a_bad_urdf_is_one_line(content, culprit, tmp_path, capsys):
    path = tmp_path / "r.urdf"
    if content is not None:
        path.write_text(content)
    line = refused(["check", str(path)], capsys)
    assert line.startswith(f"soadyn check: error: {path}: ") and culprit in line


def run_cli(*args):
    return subprocess.run([sys.executable, "-m", "soadyn", *args], capture_output=True, text=True, timeout=TIMEOUT)


def test_version_and_bare_command():
    from soadyn import __version__

    version = run_cli("--version")
    assert version.returncode == 0 and version.stdout.strip() == f"soadyn {__version__}"
    bare = run_cli()
    assert bare.returncode == 2 and "Traceback" not in bare.stderr
    assert bare.stderr.strip().splitlines()[-1].endswith("a command is required: demo, check, hil, view, "
                                                          "campaign, robots or fmu (soadyn COMMAND --help for its "
                                                          "options)")


def test_udp_0_announces_the_port_it_bound(tmp_path):
    """A controller that reads the announced port can command the run."""
    report = tmp_path / "r.json"
    run = subprocess.Popen([sys.executable, "-m", "soadyn", "hil", "--scene", "pendulum-chain", "--rate", "100",
                            "--duration", "1", "--udp", "0", "--no-progress", "--report", str(report),
                            "--floor-periods", "0"],  # the machine's floor is hil/test_hil_floor.py's
                           stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        for line in run.stdout:
            if line.startswith("commands on 127.0.0.1:"):
                port = int(line.rsplit(":", 1)[1])
                break
        assert port != 0
        controller = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        controller.bind(("127.0.0.1", 0))
        controller.sendto(command_packet(0, 0.0, [0.0] * 10), ("127.0.0.1", port))
        _, err = run.communicate(timeout=TIMEOUT)
    finally:
        run.kill()
    assert run.returncode == 0, err
    data = json.loads(report.read_text())
    # One sensor packet per step once the command has named the peer (the
    # steps before it arrived had nobody to send to).
    assert data["packets"]["received"] == 1 and 1 <= data["packets"]["sent"] <= 100
    assert data["packets"]["send_failures"] == 0
    assert data["commands"]["policy"] == "clamp" and data["packets"]["max_per_step"] == 16
