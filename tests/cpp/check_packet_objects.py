"""The packet kernels' objects are compiled for AVX2 (CMakeLists.txt) and linked into a library that runs on
any x86-64 processor. Inline functions they share with the rest of the library (an exception helper, a
destructor) are emitted in every object that uses them, and the linker keeps one copy: a copy of such a
function compiled for AVX2 could then run on a processor without it. This check disassembles the kernels'
objects and fails if a function whose name does not involve a packet (soadyn::Packet4d) uses an AVX
instruction (a VEX-encoded one: its mnemonic starts with 'v') or a 256-bit register. Given a program linked
with the library (--program), it checks the copies the linker kept: no function of the program uses AVX but
the packet ones and the kernels compiled for AVX2 on purpose (their names hold "avx2").

The other way round: the packet path's objects compiled for the baseline (packet_simulation: the Simulator
on packets built and fed; packet_dynamics: the packet model) must define no packet function (one whose name
involves soadyn::Packet4d) that a kernel object defines too. Otherwise the linker may keep their copy, compiled
for the baseline, and the packet step run it (each packet operation two SSE2 instructions and shuffles); they
declare such functions `extern template` and the kernels instantiate them.

Usage: python check_packet_objects.py [--program PROGRAM] OBJECT... (or one ;-separated list; the objects
whose names hold "packet_kernels", "packet_mass_matrix" or "packet_step" are checked; at least one must be
given). Prints one summary line.
"""
from __future__ import annotations

import re
import subprocess
import sys

KERNEL_OBJECTS = ("packet_kernels", "packet_mass_matrix", "packet_step")
BASELINE_PACKET_OBJECTS = ("packet_simulation", "packet_dynamics")
FUNCTION = re.compile(r"^[0-9a-f]+ <(.+)>:$")
INSTRUCTION = re.compile(r"^\s+[0-9a-f]+:\s+(\S+)")


def functions(path: str) -> dict[str, list[str]]:
    """Each function of the object, demangled, with its instructions' mnemonics."""
    text = subprocess.run(["objdump", "-d", "-C", "--no-show-raw-insn", path], check=True, capture_output=True,
                          text=True).stdout
    out: dict[str, list[str]] = {}
    name = None
    for line in text.splitlines():
        match = FUNCTION.match(line)
        if match:
            name = match.group(1)
            out.setdefault(name, [])
            continue
        match = INSTRUCTION.match(line)
        if match and name is not None:
            out[name].append(line)
    return out


def uses_avx(lines: list[str]) -> list[str]:
    return [ln for ln in lines if INSTRUCTION.match(ln).group(1).startswith("v") or "%ymm" in ln]


def defined_packet_functions(path: str) -> set[str]:
    """The packet functions `path` defines for the linker (global or weak), demangled."""
    text = subprocess.run(["nm", "--defined-only", "-C", path], check=True, capture_output=True, text=True).stdout
    return {line.split(" ", 2)[2] for line in text.splitlines()
            if line.count(" ") >= 2 and line.split(" ", 2)[1] in "TWV" and "Packet4d" in line}


def program_leaks(path: str) -> tuple[int, list[str]]:
    """(functions using AVX, those that should not) in a linked program."""
    users, leaks = 0, []
    for name, lines in functions(path).items():
        avx = uses_avx(lines)
        if not avx:
            continue
        users += 1
        if "Packet4d" not in name and "avx2" not in name:
            leaks.append(f"{path}: {name}: {avx[0].strip()}")
    return users, leaks


def main(paths: list[str]) -> int:
    program = None
    if paths[:1] == ["--program"]:
        program, paths = paths[1], paths[2:]
    paths = [p for arg in paths for p in arg.split(";")]  # CTest passes a target's objects as one list
    objects = [p for p in paths if any(k in p for k in KERNEL_OBJECTS)]
    if not objects:
        print("check_packet_objects: no packet kernel object among the arguments")
        return 1
    shared, leaks = 0, []
    for path in objects:
        for name, lines in functions(path).items():
            if "Packet4d" in name:
                continue
            shared += 1
            avx = uses_avx(lines)
            if avx:
                leaks.append(f"{path}: {name}: {avx[0].strip()}")
    users, kept = program_leaks(program) if program else (0, [])
    for leak in leaks + kept:
        print("AVX in a shared function:", leak)
    kernel_functions = set().union(*(defined_packet_functions(path) for path in objects))
    baseline = [p for p in paths if any(k in p for k in BASELINE_PACKET_OBJECTS)]
    doubled = sorted(f"{path}: {name}" for path in baseline for name in defined_packet_functions(path) & kernel_functions)
    for name in doubled:
        print("packet function also compiled for the baseline:", name[:300])
    print(f"check_packet_objects: {len(objects)} objects, {shared} functions shared with the library, "
          f"{len(leaks)} with AVX instructions; the program's functions using AVX: {users}, "
          f"{len(kept)} of them neither packet nor AVX2 kernels; packet functions of the {len(baseline)} baseline "
          f"packet objects also in the kernels: {len(doubled)}")
    return 1 if leaks or kept or doubled or len(baseline) != len(BASELINE_PACKET_OBJECTS) else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
