"""HIL runner: fixed-rate stepping, the UDP packet link (with a controller in
another process), malformed packets, failures and stop requests, and the
`soadyn hil` command. Timings are reported, never asserted."""
import errno
import json
import math
import os
import socket
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest

import soadyn
from soadyn import Simulator, cli, scenes
from soadyn.hil import HilRunner, format_table, parse_event, run_hil
from support import hil_pd_controller
from support.hil_pd_controller import HEADER, command_packet, parse_sensor

CONTROLLER = Path(hil_pd_controller.__file__)  # run as a script in its own process
TIMEOUT = 120  # seconds for anything that waits on another thread or process
PACKET_COUNTERS = {"received", "dropped", "sent", "rejected_sender", "stale", "kernel_drops", "send_failures",
                   "steps_left_pending", "max_per_step"}
NO_PACKETS = dict.fromkeys(PACKET_COUNTERS, 0)


def swinging_chain(n=3, dt=1e-3):
    m = scenes.pendulum_chain(n)
    sim = Simulator(m, dt, "rk4")
    sim.set_state(np.full(m.nq, 0.3), np.zeros(m.nv))
    return m, sim


def assert_consistent(report, steps):
    """The report's fields exist and agree with each other (values are not judged)."""
    assert report.steps == report.requested_steps == steps
    assert report.ok and report.failed_step is None and report.failed_dof is None and not report.interrupted
    c, lat = report.compute_us, report.lateness_us
    assert set(c) == {"p50", "p99", "p999", "max"} and set(lat) == {"p50", "p99", "max"}
    assert 0 <= c["p50"] <= c["p99"] <= c["p999"] <= c["max"]
    assert lat["p50"] <= lat["p99"] <= lat["max"]
    assert len(report.compute_ns) == len(report.lateness_ns) == steps
    assert c["max"] == pytest.approx(report.compute_ns.max() / 1e3)
    assert 0 <= report.deadline_misses <= steps
    assert set(report.packets) == PACKET_COUNTERS
    assert set(report.commands) == {"policy", "saturated", "rejected", "saturated_dofs", "limits"}
    assert list(report.commands["limits"]) == report.dof_names
    assert set(report.energy) == {"start", "end"} and len(report.momentum["end"]) == 6
    assert report.t[0] == 0.0 and report.t[-1] == pytest.approx(report.sim_time)
    assert report.q.shape[0] == report.v.shape[0] == len(report.t)
    data = json.loads(report.to_json())
    for key in ("steps", "deadline_misses", "compute_us", "lateness_us", "packets", "commands", "energy", "momentum",
                "status", "error", "report_errors"):
        assert key in data


def test_as_fast_as_possible_matches_plain_stepping():
    m, sim = swinging_chain()
    report = run_hil(sim, 1000.0, 2.0, progress=False, realtime=False)
    assert_consistent(report, 2000)
    assert report.deadline_misses == 0 and not report.lateness_ns.any()
    _, reference = swinging_chain()
    reference.run(2.0)
    np.testing.assert_array_equal(sim.q, reference.q)
    np.testing.assert_array_equal(sim.v, reference.v)
    # A conservative chain: the report's energies agree with a direct evaluation.
    assert report.energy["end"] == pytest.approx(soadyn.kinetic_energy(m, sim.q, sim.v)
                                                 + soadyn.potential_energy(m, sim.q))
    assert report.energy["end"] == pytest.approx(report.energy["start"], rel=1e-6)


def test_real_rate_run_completes_every_step():
    _, sim = swinging_chain(dt=1 / 200)
    report = run_hil(sim, 200.0, 0.5, progress=True)
    assert_consistent(report, 100)
    assert report.realtime and report.sim_time == pytest.approx(0.5)
    assert report.wall_seconds > 0
    assert report.packets == NO_PACKETS


def test_spinning_run_keeps_the_schedule_and_the_trajectory():
    _, sim = swinging_chain(dt=1 / 200)
    report = run_hil(sim, 200.0, 0.5, progress=False, spin_us=2000.0)
    assert_consistent(report, 100)
    _, reference = swinging_chain(dt=1 / 200)
    reference.run(0.5)
    np.testing.assert_array_equal(sim.q, reference.q)
    # Busy-waiting ends at or after the deadline, never before it.
    assert report.lateness_ns.min() >= 0


def send_all(packets, port):
    client = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    client.bind(("127.0.0.1", 0))
    for packet in packets:
        client.sendto(packet, ("127.0.0.1", port))
    return client


def receive_all(client, n):
    client.settimeout(10.0)
    return [client.recv(65536) for _ in range(n)]


def test_malformed_packets_are_dropped_and_the_latest_command_wins():
    m = scenes.pendulum_chain(3)
    m.set_prescribed("link_3")  # held: its command is ignored
    sim = Simulator(m, 1e-3)
    nq, nv = m.nq, m.nv
    runner = HilRunner(sim, 1000.0, 50, udp_port=0, as_fast_as_possible=True)
    good = command_packet(0, 0.0, [1.0, 2.0, 3.0])
    latest = command_packet(1, 0.0, [-0.5, 0.25, 7.0])
    malformed = [
        good[:10],                                                    # too short
        good + bytes(8),                                              # too long
        b"XDYN" + good[4:],                                           # wrong magic
        good[:4] + (2).to_bytes(2, "little") + good[6:],              # wrong version
        good[:6] + (2).to_bytes(2, "little") + good[8:],              # wrong kind (a sensor packet)
        good[:12] + (nv + 1).to_bytes(4, "little") + good[16:],       # count disagrees with the size
        command_packet(2, 0.0, [float("nan"), 0.0, 0.0]),             # not finite
    ]
    client = send_all(malformed[:4] + [good] + malformed[4:] + [latest], runner.udp_port)
    runner.run()  # the datagrams wait in the socket: the first step drains them
    s = runner.summary()
    assert s.status == "ok" and s.steps == 50
    assert (s.packets_dropped, s.packets_received, s.packets_sent) == (len(malformed), 2, 50)
    np.testing.assert_array_equal(sim.inputs, [-0.5, 0.25, 0.0])  # latest wins; prescribed DOF ignored
    sensors = receive_all(client, 50)  # replies go to the command's sender
    assert [HEADER.unpack_from(p)[3] for p in sensors] == list(range(50))  # sequence numbers
    t, q, v = parse_sensor(sensors[-1], nq, nv)
    assert t == sim.time and np.array_equal(q, sim.q) and np.array_equal(v, sim.v)
    client.close()


def test_closed_loop_with_a_controller_in_another_process():
    """A PD controller process holds link_1 of a weightless pendulum at 0.5 rad;
    without its commands the pendulum would stay at 0. It also sends garbage."""
    m = scenes.pendulum_chain(1, length=1.0)
    m.gravity = [0.0, 0.0, 0.0]
    rate, setpoint = 200.0, 0.5
    sim = Simulator(m, 1 / rate)
    controller = subprocess.Popen(
        [sys.executable, str(CONTROLLER), "--nq", "1", "--nv", "1", "--setpoint", str(setpoint), "--kp", "3",
         "--kd", "2", "--garbage-every", "25"], stdout=subprocess.PIPE, text=True)
    try:
        port = int(controller.stdout.readline())  # the controller is listening
        # floor_periods=0: the machine's floor, timed after a paced run for as long again (hil/test_hil_floor.py),
        # is not what this test looks at
        report = run_hil(sim, rate, 5.0, udp_port=0, udp_destination_port=port, progress=False, floor_periods=0)
        with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as end:  # the run is over: the controller reports
            end.sendto(hil_pd_controller.END, ("127.0.0.1", port))
        out, _ = controller.communicate(timeout=TIMEOUT)
    finally:
        controller.kill()
    seen = json.loads(out.strip().splitlines()[-1])
    assert report.ok and report.steps == 1000
    assert seen["sensor_packets"] > 0 and seen["bad_sensor_packets"] == 0
    assert 0 < report.packets["received"] <= seen["commands"]
    assert 1 <= report.packets["dropped"] <= seen["garbage"]
    assert 0 < seen["sensor_packets"] <= report.packets["sent"] <= report.steps
    assert abs(sim.q[0] - setpoint) < 0.05 and abs(sim.v[0]) < 0.1
    assert abs(report.q[:, 0] - setpoint).max() > 0.4  # it started far from the setpoint


def test_a_failing_step_stops_the_run_and_names_the_dof():
    m = soadyn.Model()
    m.add_body("ghost", None, soadyn.Joint.revolute([0, 0, 1]), mass=0.0, inertia=[0, 0, 0])
    m.set_prescribed("ghost")  # held: fine; released: its articulated inertia is singular
    sim = Simulator(m, 1e-3)
    sim.schedule(0.0095, "release", "ghost")
    report = run_hil(sim, 1000.0, 1.0, progress=False, realtime=False)
    assert not report.ok and report.status == "singular articulated inertia"
    assert report.failed_dof == "ghost" and report.failed_step == report.steps == 10
    assert len(report.compute_ns) == 10


def test_stop_request_from_another_thread():
    _, sim = swinging_chain(2)
    runner = HilRunner(sim, 1000.0, 1_000_000)  # 1000 s unless stopped
    worker = threading.Thread(target=runner.run)
    worker.start()
    deadline = time.monotonic() + TIMEOUT
    while runner.steps_done < 20 and time.monotonic() < deadline:
        time.sleep(0.01)
    runner.request_stop()
    worker.join(TIMEOUT)
    assert not worker.is_alive()
    s = runner.summary()
    assert s.stopped and s.status == "ok" and 20 <= s.steps < s.requested_steps
    assert len(runner.compute_ns) == s.steps == runner.steps_done


def test_bad_runner_arguments():
    _, sim = swinging_chain(1)
    with pytest.raises(ValueError, match="rate"):
        HilRunner(sim, 0.0, 10)
    with pytest.raises(ValueError, match="step count"):
        HilRunner(sim, 100.0, -1)
    with pytest.raises(ValueError, match="port"):
        HilRunner(sim, 100.0, 10, udp_port=70000)
    with pytest.raises(ValueError, match="duration"):
        run_hil(sim, 100.0, math.nan, progress=False)
    for spin in (-1.0, 10000.0, math.nan):  # the period at 100 Hz is 10000 us
        with pytest.raises(ValueError, match="spin_us"):
            run_hil(sim, 100.0, 0.1, progress=False, spin_us=spin)


def fifo_permitted() -> bool:
    """Whether this process may use SCHED_FIFO (asked of the kernel directly, then undone)."""
    before, param = os.sched_getscheduler(0), os.sched_getparam(0)
    try:
        os.sched_setscheduler(0, os.SCHED_FIFO, os.sched_param(1))
    except PermissionError:
        return False
    os.sched_setscheduler(0, before, param)
    return True


def test_realtime_scheduling_holds_during_the_loop_and_is_undone_after():
    _, sim = swinging_chain(dt=1 / 200)
    cpu = max(os.sched_getaffinity(0))
    runner = HilRunner(sim, 200.0, 60, fifo_priority=7, cpu=cpu, lock_memory=True)
    seen = {}

    def work():
        seen["thread"] = threading.get_native_id()
        seen["policy"], seen["affinity"] = os.sched_getscheduler(0), os.sched_getaffinity(0)
        runner.run()
        seen["policy after"], seen["affinity after"] = os.sched_getscheduler(0), os.sched_getaffinity(0)

    worker = threading.Thread(target=work)
    worker.start()
    deadline = time.monotonic() + TIMEOUT
    while runner.steps_done < 5 and time.monotonic() < deadline:
        time.sleep(0.01)
    during = os.sched_getscheduler(seen["thread"]), os.sched_getparam(seen["thread"]).sched_priority
    affinity_during = os.sched_getaffinity(seen["thread"])
    worker.join(TIMEOUT)
    s = runner.summary()
    assert s.steps == 60 and s.status == "ok"
    granted = s.realtime
    assert granted["fifo_priority"] == 7 and granted["cpu"] == cpu and granted["lock_memory"]
    if fifo_permitted():
        assert granted["fifo_granted"] and granted["fifo_errno"] == 0
        assert during == (os.SCHED_FIFO, 7)
    else:
        assert not granted["fifo_granted"] and granted["fifo_errno"] == errno.EPERM
        assert during[0] == seen["policy"]
    assert granted["cpu_granted"] and affinity_during == {cpu}
    assert granted["memory_locked"] or granted["lock_errno"] in (errno.EPERM, errno.ENOMEM)
    assert seen["policy after"] == seen["policy"] and seen["affinity after"] == seen["affinity"]


def test_report_says_what_scheduling_the_run_got():
    _, sim = swinging_chain(dt=1 / 200)
    cpu = min(os.sched_getaffinity(0))  # a CPU this process may run on
    report = run_hil(sim, 200.0, 0.05, progress=False, fifo_priority=3, cpu=cpu)
    assert_consistent(report, 10)
    s = report.scheduling
    assert s["fifo_granted"] == fifo_permitted() and s["cpu_granted"] and not s["memory_locked"]
    assert s["fifo_refused"] is None if s["fifo_granted"] else s["fifo_refused"] == os.strerror(errno.EPERM)
    line = format_table(report).splitlines()[2]
    assert line.startswith("scheduling") and "SCHED_FIFO 3" in line and f"on CPU {cpu}" in line
    assert json.loads(report.to_json())["scheduling"] == s
    _, sim = swinging_chain(dt=1 / 200)
    plain = run_hil(sim, 200.0, 0.02, progress=False)
    assert "default" in format_table(plain) and not plain.scheduling["fifo_granted"]


@pytest.mark.parametrize("kwargs, culprit", [
    ({"fifo_priority": 100}, "priority 100"), ({"fifo_priority": -1}, "priority -1"),
    ({"cpu": -2}, "CPU -2"), ({"cpu": 4096}, "CPU 4096"),
])
def test_bad_realtime_requests_name_the_field(kwargs, culprit):
    _, sim = swinging_chain(1)
    with pytest.raises(ValueError, match=culprit):
        HilRunner(sim, 100.0, 10, **kwargs)
    with pytest.raises(SystemExit) as exit_info:
        flag, value = next(iter(kwargs.items()))
        cli.main(["hil", "--duration", "0.01", "--no-progress", "--" + flag.replace("_", "-"), str(value)])
    assert exit_info.value.code == 2


def test_cli_end_to_end_with_report_and_plot(tmp_path):
    out_json, out_png = tmp_path / "report.json", tmp_path / "plot.png"
    result = subprocess.run(
        [sys.executable, "-m", "soadyn", "hil", "--scene", "cassini", "--rate", "200", "--duration", "0.5",
         "--event", "lock scan_az at 0.2", "--event", "release scan_az at 0.4", "--report", str(out_json),
         "--plot", str(out_png), "--no-progress"], capture_output=True, text=True, timeout=TIMEOUT)
    assert result.returncode == 0, result.stderr
    assert "deadline misses" in result.stdout and "event: lock scan_az at 0.2" in result.stdout
    data = json.loads(out_json.read_text())
    assert data["scene"] == "cassini" and data["steps"] == 100 and data["status"] == "ok"
    assert set(data["compute_us"]) == {"p50", "p99", "p999", "max"}
    for key in ("deadline_misses", "lateness_us", "packets", "energy", "momentum", "events"):
        assert key in data
    assert out_png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


@pytest.mark.parametrize("event, culprit", [
    ("explode scan_az at 1", "explode scan_az at 1"),
    ("lock scan_az", "lock scan_az"),
    ("lock scan_az at soon", "soon"),
    ("lock scan_az at -1", "lock scan_az at -1"),
    ("lock no_such_joint at 1", "no_such_joint"),
])
def test_cli_rejects_bad_events(event, culprit, capsys):
    with pytest.raises(SystemExit) as exit_info:
        cli.main(["hil", "--duration", "0.01", "--no-progress", "--event", event])
    assert exit_info.value.code == 2
    err = capsys.readouterr().err
    assert "--event" in err and culprit in err


def test_parse_event():
    e = parse_event("  release gimbal_yaw at 2.5 ")
    assert (e.kind, e.target, e.time) == ("release", "gimbal_yaw", 2.5)
