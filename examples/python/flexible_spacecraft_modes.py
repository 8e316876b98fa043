"""The vibration modes of a flexible spacecraft: cassini linearized at rest, free in space.

`soadyn.modes` linearizes the scene about its neutral configuration (the exact Jacobians of the dynamics,
`soadyn.linearize`) and solves the eigenproblem: the free bus, the hinges and the slosh pendulums give
rigid-body modes at zero frequency; the two flexible booms (the 11 m magnetometer boom and the 10 m
plasma-wave antenna, each with bending modes in two planes) give the rest. Printed: every mode above zero
frequency with the DOFs that move most in it, and, for comparison, each boom's first bending frequency
when clamped to a fixed base (`FlexibleBody.natural_frequencies_clamped`): on the free spacecraft the
bus swings with the boom, so the coupled frequency is higher. Plotted (--plot): the frequencies.

    python examples/python/flexible_spacecraft_modes.py [--plot modes.png]
"""
from __future__ import annotations

import argparse

import numpy as np

import soadyn

BOOMS = ("magnetometer_boom", "plasma_wave_antenna")
RIGID = 1e-6  # Hz: below this a mode is a rigid-body motion


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--plot", help="write the modes' frequencies to this PNG")
    args = parser.parse_args(argv)
    m = soadyn.scenes.cassini()
    result = soadyn.modes(m, soadyn.neutral_configuration(m))
    flexible = np.flatnonzero(np.nan_to_num(result.frequencies_hz) > RIGID)
    rows = result.table().splitlines()
    print(rows[0])
    for k in flexible:
        print(rows[k + 1])
    clamped = {boom: float(m.flexible_body(boom).natural_frequencies_clamped()[0] / (2 * np.pi)) for boom in BOOMS}
    for boom, f in clamped.items():
        print(f"{boom}: first bending mode clamped to a fixed base {f:.4f} Hz")
    print(f"{len(result.frequencies_hz) - len(flexible)} rigid-body modes at zero frequency")
    if args.plot:
        from matplotlib.figure import Figure

        fig = Figure(figsize=(7, 3.5))
        ax = fig.add_subplot()
        ax.bar(np.arange(len(flexible)) + 1, result.frequencies_hz[flexible])
        for boom, f in clamped.items():
            ax.axhline(f, linestyle=":", color="grey")
            ax.annotate(f"{boom}, clamped", (0.6, f), fontsize=8, va="bottom")
        ax.set_xlabel("flexible mode")
        ax.set_ylabel("frequency (Hz)")
        ax.set_title("cassini, free in space: the booms' modes")
        fig.tight_layout()
        fig.savefig(args.plot, dpi=100)
    return {"frequencies_hz": result.frequencies_hz[flexible], "clamped_hz": clamped}


if __name__ == "__main__":
    main()
