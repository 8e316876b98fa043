"""Property-based fuzz of the HIL packet parser (hypothesis): random datagrams
of 0 to 65,507 bytes, and well-formed commands with one field mutated, sent to
a live runner one per step. An independent parser written from the
documented format (fuzz/packet_cases.py) says what each datagram is; the runner must agree on every
counter and on the command it applies, and its state must stay finite."""
import random
import socket
import struct

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from soadyn import Simulator, scenes
from soadyn.hil import HilRunner
from fuzz.packet_cases import HEADER, LIMITS, MAX_DATAGRAM, NV, classify

floats = st.floats(allow_nan=True, allow_infinity=True) | st.sampled_from([1e30, -1e308, 5e-324, 0.0, -0.0])


@st.composite
def mutated_command(draw):
    fields = {"magic": b"SDYN", "version": 1, "kind": 1, "sequence": draw(st.integers(0, 2**32 - 1)),
              "count": NV, "time": draw(floats), "values": draw(st.lists(floats, min_size=NV, max_size=NV))}
    which = draw(st.sampled_from(["none", "magic", "version", "kind", "count", "size"]))
    if which == "magic":
        fields["magic"] = draw(st.binary(min_size=4, max_size=4))
    elif which in ("version", "kind"):
        fields[which] = draw(st.integers(0, 2**16 - 1))
    elif which == "count":
        fields["count"] = draw(st.integers(0, 2**32 - 1))
    packet = HEADER.pack(fields["magic"], fields["version"], fields["kind"], fields["sequence"], fields["count"],
                         fields["time"]) + struct.pack(f"<{NV}d", *fields["values"])
    if which == "size":
        cut = draw(st.integers(0, len(packet) + 64))
        packet = packet[:cut] if cut <= len(packet) else packet + bytes(cut - len(packet))
    return packet


@st.composite
def random_datagram(draw):
    size = draw(st.integers(0, MAX_DATAGRAM) | st.sampled_from([0, 1, 23, 24, 47, 48, 49, MAX_DATAGRAM]))
    return random.Random(draw(st.integers(0, 2**32 - 1))).randbytes(size)


class Rig:
    """One runner (one step per run) and its controller, shared by the examples."""

    def __init__(self):
        self.sim = Simulator(scenes.pendulum_chain(NV), 1e-3)
        self.controller = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        self.controller.bind(("127.0.0.1", 0))
        self.controller.setblocking(False)
        self.runner = HilRunner(self.sim, 1000.0, 1, udp_port=0, udp_destination_port=self.controller.getsockname()[1],
                                as_fast_as_possible=True)
        self.runner.command_limits = LIMITS
        self.last_sequence = None
        self.applied = np.zeros(NV)

    def counters(self):
        s = self.runner.summary()
        return {"accepted": s.packets_received, "malformed": s.packets_dropped, "stale": s.packets_stale,
                "saturated": s.commands_saturated, "other": s.packets_rejected_sender}


RIG = None


def rig():
    global RIG
    if RIG is None:
        RIG = Rig()
    return RIG


@settings(max_examples=400, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow])
@given(packet=mutated_command() | random_datagram())
def test_every_datagram_is_classified_as_the_format_says(packet):
    r = rig()
    before = r.counters()
    verdict, command = classify(packet, r.last_sequence)
    r.controller.sendto(packet, ("127.0.0.1", r.runner.udp_port))
    r.runner.run()
    s = r.runner.summary()
    assert s.status == "ok" and s.steps == 1
    after = r.counters()
    expected = dict(before)
    expected[verdict] += 1
    if verdict == "accepted":
        r.last_sequence, values = command
        r.applied = np.clip(values, -LIMITS, LIMITS)
        expected["saturated"] += bool((np.abs(values) > LIMITS).any())
    assert after == expected
    np.testing.assert_array_equal(r.sim.inputs, r.applied)
    assert np.isfinite(r.sim.q).all() and np.isfinite(r.sim.v).all()
    while True:  # the sensor packet of the step
        try:
            r.controller.recv(65536)
        except BlockingIOError:
            break
