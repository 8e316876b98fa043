"""A PD controller for one DOF, run as a separate process by tests/hil/test_hil.py.

It speaks the soadyn HIL packet format (cpp/include/soadyn/realtime/udp_link.hpp)
with nothing but the standard library, as an independent implementation:
binds 127.0.0.1 on a free port and prints the port, then answers every sensor
packet (kind 2: q then v) with a command packet (kind 1: nv torques, zero
except `--dof`). With --garbage-every N it also sends a malformed packet after
every N commands. It stops on an END datagram (the test sends one once its run
is over), when no sensor packet has come for --idle seconds (after the first
one) or after --timeout seconds, and prints one JSON line with what it saw.
"""
from __future__ import annotations

import argparse
import json
import socket
import struct
import sys
import time

HEADER = struct.Struct("<4sHHIId")  # magic, version, kind, sequence, count, time: 24 bytes
MAGIC, VERSION, COMMAND, SENSOR = b"SDYN", 1, 1, 2
END = b"END"  # not a packet of the format: from the test, the run is over


def command_packet(sequence: int, time_s: float, torques: list[float]) -> bytes:
    return HEADER.pack(MAGIC, VERSION, COMMAND, sequence, len(torques), time_s) + struct.pack(
        f"<{len(torques)}d", *torques)


def parse_sensor(packet: bytes, nq: int, nv: int):
    """(time, q, v) of a well-formed sensor packet, else None."""
    if len(packet) != HEADER.size + 8 * (nq + nv):
        return None
    magic, version, kind, _sequence, count, time_s = HEADER.unpack_from(packet)
    if (magic, version, kind, count) != (MAGIC, VERSION, SENSOR, nq + nv):
        return None
    values = struct.unpack_from(f"<{nq + nv}d", packet, HEADER.size)
    return time_s, values[:nq], values[nq:]


def main() -> int:
    p = argparse.ArgumentParser()
    p.add_argument("--nq", type=int, required=True)
    p.add_argument("--nv", type=int, required=True)
    p.add_argument("--dof", type=int, default=0, help="velocity index of the controlled DOF")
    p.add_argument("--coordinate", type=int, default=0, help="index of its coordinate in q")
    p.add_argument("--setpoint", type=float, required=True)
    p.add_argument("--kp", type=float, required=True)
    p.add_argument("--kd", type=float, required=True)
    p.add_argument("--garbage-every", type=int, default=0)
    p.add_argument("--idle", type=float, default=3.0)
    p.add_argument("--timeout", type=float, default=120.0)
    args = p.parse_args()

    sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    sock.bind(("127.0.0.1", 0))
    print(sock.getsockname()[1], flush=True)

    sensors = commands = garbage = bad_sensors = 0
    last = None
    started = time.monotonic()
    sock.settimeout(args.timeout)
    while time.monotonic() - started < args.timeout:
        try:
            packet, simulator = sock.recvfrom(65536)
        except socket.timeout:
            break
        if packet == END:
            break
        state = parse_sensor(packet, args.nq, args.nv)
        if state is None:
            bad_sensors += 1
            continue
        sensors += 1
        sock.settimeout(args.idle)  # the run is over once the packets stop
        t, q, v = state
        torque = args.kp * (args.setpoint - q[args.coordinate]) - args.kd * v[args.dof]
        torques = [0.0] * args.nv
        torques[args.dof] = torque
        sock.sendto(command_packet(commands, t, torques), simulator)
        commands += 1
        last = {"time": t, "q": q[args.coordinate], "v": v[args.dof], "torque": torque}
        if args.garbage_every and commands % args.garbage_every == 0:
            sock.sendto(b"SDYN" + bytes(10), simulator)  # too short
            garbage += 1
    print(json.dumps({"sensor_packets": sensors, "bad_sensor_packets": bad_sensors, "commands": commands,
                      "garbage": garbage, "last": last}), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
