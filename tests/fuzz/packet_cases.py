"""Hostile datagrams for the HIL link, each case drawn from one integer seed,
for the long fuzz campaign (bench/fuzz_campaign.py); tests/fuzz/test_hil_fuzz.py
holds the quick property test.

A case starts a runner on a 3-link chain with a UDP link on a free port,
sends it 1 to 8 datagrams (random bytes of 0 to 65,507 bytes, or command
packets with a field mutated: magic, version, kind, count, size, sequence,
NaN/inf/1e30 time or values), runs one step, and checks that the run is
alive, the state finite, and every counter what an independent reading of
the documented format predicts.
"""
from __future__ import annotations

import socket
import struct

import numpy as np

from soadyn import Simulator, scenes
from soadyn.hil import HilRunner

HEADER = struct.Struct("<4sHHIId")
NV = 3
LIMITS = np.array([2.0, 3.0, 4.0])
MAX_DATAGRAM = 65507
FLOATS = (np.nan, np.inf, -np.inf, 1e30, -1e308, 5e-324, 0.0, -0.0, 0.5)


def classify(packet: bytes, last_sequence):
    """('malformed' | 'stale' | 'accepted', (sequence, values) or None), from the HIL guide's table (docs/guides/hil.md)."""
    if len(packet) != HEADER.size + 8 * NV:
        return "malformed", None
    magic, version, kind, sequence, count, time_s = HEADER.unpack_from(packet)
    values = np.array(struct.unpack_from(f"<{NV}d", packet, HEADER.size))
    if (magic, version, kind, count) != (b"SDYN", 1, 1, NV) or not np.isfinite([time_s, *values]).all():
        return "malformed", None
    if last_sequence is not None and not 0 < (sequence - last_sequence) % 2**32 < 2**31:
        return "stale", None
    return "accepted", (sequence, values)


def datagram(rng: np.random.Generator) -> bytes:
    if rng.uniform() < 0.3:
        size = int(rng.choice([0, 1, 23, 24, 47, 48, 49, MAX_DATAGRAM])) if rng.uniform() < 0.3 \
            else int(rng.integers(0, MAX_DATAGRAM + 1))
        return rng.bytes(size)
    field = lambda: float(FLOATS[rng.integers(len(FLOATS))]) if rng.uniform() < 0.3 else float(rng.normal())
    magic, version, kind, count = b"SDYN", 1, 1, NV
    which = ["none", "none", "magic", "version", "kind", "count", "size"][rng.integers(7)]
    if which == "magic":
        magic = rng.bytes(4)
    elif which in ("version", "kind"):
        version, kind = (int(rng.integers(0, 2**16)), kind) if which == "version" else (version, int(rng.integers(0, 2**16)))
    elif which == "count":
        count = int(rng.integers(0, 2**32))
    packet = HEADER.pack(magic, version, kind, int(rng.integers(0, 2**32)), count, field()) + \
        struct.pack(f"<{NV}d", *[field() for _ in range(NV)])
    if which == "size":
        cut = int(rng.integers(0, len(packet) + 65))
        packet = packet[:cut] if cut <= len(packet) else packet + bytes(cut - len(packet))
    return packet


def run_case(seed: int) -> str:
    rng = np.random.default_rng(seed)
    sim = Simulator(scenes.pendulum_chain(NV), 1e-3)
    controller = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    controller.bind(("127.0.0.1", 0))
    try:
        runner = HilRunner(sim, 1000.0, 1, udp_port=0, udp_destination_port=controller.getsockname()[1],
                           as_fast_as_possible=True)
        runner.command_limits = LIMITS
        expected = {"accepted": 0, "malformed": 0, "stale": 0}
        last, applied = None, np.zeros(NV)
        for _ in range(int(rng.integers(1, 9))):
            packet = datagram(rng)
            verdict, command = classify(packet, last)
            expected[verdict] += 1
            if verdict == "accepted":
                last, values = command
                applied = np.clip(values, -LIMITS, LIMITS)
            controller.sendto(packet, ("127.0.0.1", runner.udp_port))
        runner.run()
        s = runner.summary()
        if s.status != "ok" or s.steps != 1:
            raise AssertionError(f"the run did not survive: status {s.status}, {s.steps} steps")
        got = {"accepted": s.packets_received, "malformed": s.packets_dropped, "stale": s.packets_stale}
        if s.kernel_drops == 0 and got != {k: expected[k] for k in got}:
            raise AssertionError(f"counters {got}, expected {expected}")
        if s.kernel_drops == 0 and expected["accepted"] and not np.array_equal(sim.inputs, applied):
            raise AssertionError(f"applied {sim.inputs}, expected the latest command clamped: {applied}")
        if not (np.isfinite(sim.q).all() and np.isfinite(sim.v).all()):
            raise AssertionError("non-finite state after the step")
        return "ok"
    finally:
        controller.close()
