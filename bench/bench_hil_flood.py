"""The HIL loop under a UDP flood: cassini at 1 kHz for 4 s while another
process sends valid commands from the accepted peer as fast as it can, with
the per-step read bound at its default (16) and effectively unbounded.
Prints the compute-time median and p99, the deadline misses and the packet
counters of each run (and of a quiet run for reference). Loopback only.

Writes bench/results/hil_flood.json.
Usage: python bench/bench_hil_flood.py [--seconds 4] [--rounds 1]
"""
from __future__ import annotations

import argparse
import socket
import subprocess
import sys

from fixtures import cassini_simulator
from report import Table, write
from soadyn.hil import run_hil

FLOODER = r"""
import socket, struct, sys, time
nv, port, seconds = int(sys.argv[1]), int(sys.argv[2]), float(sys.argv[3])
s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
s.bind(("127.0.0.1", 0))
print(s.getsockname()[1], flush=True)
sys.stdin.readline()  # go
header = struct.Struct("<4sHHIId")
end, k = time.monotonic() + seconds, 0
while time.monotonic() < end:
    for _ in range(200):
        k += 1
        s.sendto(header.pack(b"SDYN", 1, 1, k, nv, 0.0) + bytes(8 * nv), ("127.0.0.1", port))
print(k, flush=True)
"""


def free_port() -> int:
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def one_run(seconds: float, bound: int | None, flood: bool) -> tuple:
    """(label, p50, p99, misses, steps, sent, read, kernel drops, steps at the bound) of one run."""
    sim = cassini_simulator(1000.0)
    port = free_port()
    flooder = None
    if flood:
        flooder = subprocess.Popen([sys.executable, "-c", FLOODER, str(sim._model.nv), str(port), str(seconds)],
                                   stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
        peer = int(flooder.stdout.readline())
    else:
        peer = 0

    def go(_runner):
        if flooder:
            flooder.stdin.write("go\n")
            flooder.stdin.flush()

    report = run_hil(sim, 1000.0, seconds, udp_port=port, udp_destination_port=peer, progress=False,
                     max_packets_per_step=bound or 10**9, on_start=go)
    sent = int(flooder.stdout.readline()) if flooder else 0
    if flooder:
        flooder.wait()
    p, c = report.packets, report.compute_us
    label = "quiet" if not flood else f"flood, bound {bound or 'none'}"
    return (label, c["p50"], c["p99"], report.deadline_misses, report.steps, sent,
            p["received"] + p["stale"] + p["dropped"] + p["rejected_sender"], p["kernel_drops"],
            p["steps_left_pending"])


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=4.0)
    parser.add_argument("--rounds", type=int, default=1)
    args = parser.parse_args()
    table = Table("Cassini at 1 kHz under a UDP flood", [
        "run", "compute p50 (us)", "compute p99 (us)", "deadline misses", "steps", "datagrams sent",
        "datagrams read", "kernel drops", "steps at the read bound"],
        {"compute p50 (us)": ".1f", "compute p99 (us)": ".1f"}, summary=True)
    for _ in range(args.rounds):
        for bound, flood in ((None, False), (16, True), (None, True)):
            print(table.add(*one_run(args.seconds, bound, flood)), flush=True)
    table.print()
    write("hil_flood", "The HIL loop under a UDP flood", [table], {"seconds": args.seconds, "rounds": args.rounds},
          ["Another process sends valid commands from the accepted peer as fast as it can; the per-step read "
           "bound at its default (16) and effectively unbounded; a quiet run for reference. Loopback only."])
    return 0


if __name__ == "__main__":
    sys.exit(main())
