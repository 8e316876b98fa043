"""`soadyn check FILE` on URDF and MJCF: every oracle that can load the file is compared
(URDF: Pinocchio, DART, MuJoCo's URDF importer; MJCF: MuJoCo and Pinocchio's MJCF parser),
an oracle that cannot is listed with its reason, and the verdict is one line."""
from __future__ import annotations

import os

import pytest

from soadyn.check import cross_check_report, is_mjcf
from soadyn.cli import main
from support.mujoco_models import FOUR_BAR, gymnasium_assets
from support.robots import robot

TOLERANCE = 1e-9


@pytest.mark.parametrize("name", ["ant.xml", "hopper.xml", "humanoid.xml", "walker2d.xml"])
def test_mjcf_against_mujoco_and_pinocchio(name):
    report = cross_check_report(os.path.join(gymnasium_assets(), name), states=2)
    assert report.format == "MJCF"
    oracles = {r.oracle for r in report.rows}
    assert oracles == {"mujoco", "pinocchio"}
    assert {r.quantity for r in report.rows} == {"forward dynamics", "inverse dynamics", "mass matrix"}
    assert all(r.max_relative < TOLERANCE for r in report.rows), report.rows
    assert [o for o, _ in report.not_compared] == ["dart"]
    assert report.verdict(TOLERANCE).startswith(f"PASS: MJCF {name} against mujoco, pinocchio")


@pytest.mark.parametrize("name, reason", [("pusher.xml", "builds 7 DOFs where MuJoCo compiles 11"),
                                          ("half_cheetah.xml", "settotalmass")])
def test_an_oracle_that_cannot_load_the_file_is_named_with_its_reason(name, reason):
    report = cross_check_report(os.path.join(gymnasium_assets(), name), states=1)
    assert {r.oracle for r in report.rows} == {"mujoco"}
    assert all(r.max_relative < TOLERANCE for r in report.rows)
    reasons = dict(report.not_compared)
    assert reason in reasons["pinocchio"] and "dart" in reasons


def test_urdf_adds_mujoco(capsys):
    path, _ = robot("panda")
    assert main(["check", str(path), "--states", "1"]) == 0
    out = capsys.readouterr().out
    for oracle in ("pinocchio", "dart", "mujoco"):
        assert oracle in out
    assert "ABOVE" not in out and out.strip().splitlines()[-1].startswith("PASS: URDF panda.urdf")


def test_floating_urdf_and_a_urdf_mujoco_refuses():
    path, _ = robot("solo12")
    report = cross_check_report(path, floating_base=True, states=1)
    assert {"pinocchio", "dart", "mujoco"} <= {r.oracle for r in report.rows}
    assert report.passed(TOLERANCE), report.rows
    path, _ = robot("anymal_c")  # MuJoCo's compiler refuses one of its inertias (A + B >= C)
    report = cross_check_report(path, floating_base=True, states=1)
    assert "inertia must satisfy A + B >= C" in dict(report.not_compared)["mujoco"]
    assert report.passed(TOLERANCE)


def test_check_command_on_mjcf_with_loops_and_bad_files(tmp_path, capsys):
    four_bar = tmp_path / "four_bar.xml"
    four_bar.write_text(FOUR_BAR)
    assert is_mjcf(four_bar)
    assert main(["check", str(four_bar), "--states", "2"]) == 0
    lines = capsys.readouterr().out.strip().splitlines()
    assert lines[0].startswith(f"{four_bar}: MJCF") and lines[-1].startswith("PASS: MJCF four_bar.xml")
    assert main(["check", str(four_bar), "--states", "1", "--tolerance", "0"]) == 1
    capsys.readouterr()
    broken = tmp_path / "broken.xml"
    broken.write_text("<mujoco><worldbody><body></worldbody></mujoco>")
    with pytest.raises(SystemExit) as exit_info:
        main(["check", str(broken)])
    assert exit_info.value.code == 2
    assert "soadyn check: error:" in capsys.readouterr().err
