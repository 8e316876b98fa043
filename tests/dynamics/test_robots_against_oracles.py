"""soadyn on real robots (example-robot-data) against Pinocchio, DART and MuJoCo.

Forward, inverse dynamics and the mass matrix against Pinocchio and MuJoCo's URDF importer
(anymal_c: MuJoCo's compiler refuses one of its inertias, which the check reports); hybrid
dynamics with random prescribed masks (whole joints, as DART switches them)
against DART's ACCELERATION actuators. DOFs are matched by name. 1e-9
relative everywhere; what is actually seen is near 1e-15.
"""
import numpy as np
import pytest

import soadyn
from soadyn.check import cross_check, relative_difference
from soadyn.oracles import DartOracle, PinocchioOracle
from support.robots import ROBOTS, robot

TOLERANCE = 1e-9


@pytest.mark.parametrize("name", sorted(ROBOTS))
@pytest.mark.parametrize("floating", [False, True])
def test_robot_against_pinocchio_and_dart(name, floating):
    path, _ = robot(name)
    rows = cross_check(path, floating_base=floating, states=4, seed=7)
    tree = {("forward dynamics", "pinocchio"), ("inverse dynamics", "pinocchio"), ("mass matrix", "pinocchio"),
            ("hybrid qdd", "dart"), ("hybrid tau", "dart")}
    if name != "anymal_c":
        tree |= {("forward dynamics", "mujoco"), ("inverse dynamics", "mujoco"), ("mass matrix", "mujoco")}
    assert {(r.quantity, r.oracle) for r in rows} == tree
    worst = {f"{r.quantity} ({r.oracle})": r.max_relative for r in rows}
    print(name, "floating" if floating else "fixed", worst)
    assert max(worst.values()) <= TOLERANCE, worst


@pytest.mark.parametrize("name", ["talos", "solo12"])
def test_dofs_are_matched_by_name(name):
    """Every oracle DOF maps to the soadyn DOF of the same name, one to one."""
    path, floating = robot(name)
    model = soadyn.load_urdf(path, floating_base=floating)
    pin_oracle = PinocchioOracle(model, path, floating)
    dart_oracle = DartOracle(model, path, floating)
    assert sorted(pin_oracle.v_of_pin) == list(range(model.nv))
    assert sorted(dart_oracle.v_of_dart) == list(range(model.nv))
    for i in range(pin_oracle.model.njoints - 1):
        joint = pin_oracle.model.joints[i + 1]
        if joint.nv == 1:
            assert model.dof_names[pin_oracle.v_of_pin[joint.idx_v]] == pin_oracle.model.names[i + 1]
    first = 6 if floating else 0
    for i in range(first, dart_oracle.skeleton.getNumDofs()):
        assert model.dof_names[dart_oracle.v_of_dart[i]] == dart_oracle.skeleton.getDof(i).getName()


def test_oracle_comparison_detects_a_wrong_model():
    """The comparison is not vacuous: a 1% heavier link shows up far above the tolerance."""
    path, _ = robot("panda")
    model = soadyn.load_urdf(path)
    oracle = PinocchioOracle(model, path, False)
    oracle.model.inertias[3].mass *= 1.01
    oracle.data = oracle.model.createData()
    q = soadyn.random_configuration(model, 1)
    v = np.ones(model.nv)
    assert relative_difference(soadyn.inverse_dynamics(model, q, v, v), oracle.inverse_dynamics(q, v, v)) > 1e-4


def test_check_command_exit_codes(capsys):
    from soadyn.cli import main

    path, _ = robot("ur5")
    assert main(["check", str(path), "--states", "1"]) == 0
    out = capsys.readouterr().out
    assert "hybrid tau" in out and "pinocchio" in out and "ABOVE" not in out
    assert main(["check", str(path), "--states", "1", "--tolerance", "1e-30"]) == 1
