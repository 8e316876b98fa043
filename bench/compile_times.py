"""Compile time of each translation unit of a build, from the build tree's Ninja log.

    python bench/compile_times.py BUILD_DIR [--wall SECONDS] [--name compile_times]

BUILD_DIR is a Ninja build tree (the one pip keeps, build/<cache tag>, or any `cmake -G Ninja` tree).
Ninja logs each command's start and end; the last entry of each output is its latest compile. Every unit
is listed with its seconds and its share, grouped by what it builds (the core library, the real-time
library, the scenes, the Python module, the timing module, the C++ tests); the sum is the work a build
does, and on a machine with N cores a build from scratch takes about the sum over N. --wall records the
build's wall time as measured by the caller (for example `time pip install .` from a fresh clone).
"""
from __future__ import annotations

import argparse
import re
from pathlib import Path

import report

GROUPS = [  # (group, pattern of the output's path)
    ("core library (soadyn::core)", r"CMakeFiles/soadyn\.dir/"),
    ("real-time library (soadyn::realtime)", r"CMakeFiles/soadyn_realtime\.dir/"),
    ("scenes (soadyn::scenes)", r"CMakeFiles/soadyn_scenes\.dir/"),
    ("Python module (_soadyn)", r"CMakeFiles/_soadyn\.dir/|_soadyn\.cpython"),
    ("timing module (_timing)", r"CMakeFiles/_timing\.dir/|_timing\.cpython"),
    ("C++ tests", r"^tests/"),
    ("benchmarks", r"^bench/"),
]


def latest_entries(log: Path) -> dict[str, float]:
    """Seconds of the latest run of each output in a .ninja_log (format v5: start end mtime output hash)."""
    seconds = {}
    for line in log.read_text().splitlines():
        if line.startswith("#"):
            continue
        fields = line.split("\t")
        if len(fields) >= 4:
            seconds[fields[3]] = (int(fields[1]) - int(fields[0])) / 1000.0
    return seconds


def group_of(output: str) -> str:
    for name, pattern in GROUPS:
        if re.search(pattern, output):
            return name
    return "other"


def unit_name(output: str) -> str:
    """The source a .o came from (cpp/src/model/model.cpp), or the linked file's name."""
    match = re.search(r"\.dir/(.+)\.o$", output)
    return match.group(1) if match else output


def cache_settings(build: Path) -> dict:
    """The build's options that change what is compiled."""
    cache = build / "CMakeCache.txt"
    settings = {}
    if cache.is_file():
        for line in cache.read_text().splitlines():
            match = re.match(r"(SOADYN_[A-Z_]+|CMAKE_BUILD_TYPE):\w+=(.*)", line)
            if match and not match.group(1).endswith("_DIR"):
                settings[match.group(1)] = match.group(2)
    return settings


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("build", type=Path, help="a Ninja build tree")
    parser.add_argument("--wall", type=float, help="the build's wall time in seconds, measured by the caller")
    parser.add_argument("--name", default="compile_times", help="results file name (bench/results/NAME.json)")
    args = parser.parse_args(argv)
    log = args.build / ".ninja_log"
    if not log.is_file():
        parser.error(f"{log} not found: BUILD_DIR must be a Ninja build tree")
    seconds = latest_entries(log)
    groups: dict[str, list[tuple[str, float]]] = {}
    for output, s in seconds.items():
        groups.setdefault(group_of(output), []).append((unit_name(output), s))
    total = sum(seconds.values())

    per_group = report.Table("Compile and link seconds by group", ["group", "units", "seconds", "share (%)"],
                             {"seconds": ".1f", "share (%)": ".1f"}, headline=["seconds"])
    units = report.Table("Compile seconds per unit (slowest first)", ["unit", "group", "seconds", "share (%)"],
                         {"seconds": ".1f", "share (%)": ".1f"}, key=2, summary=False)
    for name, _ in GROUPS + [("other", "")]:
        entries = groups.get(name, [])
        if entries:
            s = sum(t for _, t in entries)
            per_group.add(name, len(entries), s, 100 * s / total)
    per_group.add("all", len(seconds), total, 100.0)
    for name, entries in groups.items():
        for unit, s in entries:
            units.add(unit, name, s, 100 * s / total)
    units.rows.sort(key=lambda row: -row[2])
    settings = {"options": cache_settings(args.build), "units": len(seconds), "sum_seconds": round(total, 1)}
    if args.wall is not None:
        settings["wall_seconds"] = args.wall
    notes = ["Seconds per command from Ninja's log (the latest run of each output); with -j2 on 2 cores "
             "each command has a core to itself, so the sum over 2 is about the wall time of a build from scratch."]
    for table in (per_group, units):
        print(f"\n### {table.title}\n")
        print("\n".join(table.markdown()))
    report.write(args.name, "Compile time per translation unit", [per_group, units], settings, notes)


if __name__ == "__main__":
    main()
