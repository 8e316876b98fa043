"""A Monte Carlo campaign on Dask: the bundled cassini example, dispersed and flown many times.

The spec `cassini-example` (python/soadyn/campaign/examples/cassini.toml) flies cassini for 1 s while its
scan platform slews until its azimuth axis locks, with the masses, the slosh pendulums, the lock-up time
and more dispersed. `soadyn.campaign.run` runs it on a local Dask cluster (here one worker) and writes the
results to Parquet; `soadyn.campaign.report` summarises every metric and dispersed value. Printed: the
summary table; plotted (--plot): the histogram of the booms' peak tip deflection.

    python examples/python/monte_carlo_campaign.py [--runs 32] [--out campaign] [--plot campaign.png]
"""
from __future__ import annotations

import argparse
import shutil
import tempfile
from pathlib import Path

import soadyn.campaign

METRIC = "peak_boom_tip_deflection"


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=32, help="runs of the campaign (default 32)")
    parser.add_argument("--out", help="results directory (default: a temporary one, removed after)")
    parser.add_argument("--plot", help="write the histogram of the peak boom tip deflection to this PNG")
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory(prefix="soadyn-campaign-") as scratch:
        out = Path(args.out) if args.out else Path(scratch) / "results"
        spec = soadyn.campaign.load_spec("cassini-example", runs=args.runs)
        soadyn.campaign.run(spec, out=out, workers=1, progress=False, dashboard=False, verbose=False)
        report = soadyn.campaign.report(out, plots_dir=Path(scratch) / "plots", plots=args.plot is not None)
        print(f"{report.finished} of {report.runs} runs finished, {report.failed} failed")
        print(soadyn.campaign.format_summary(report.summary))
        if args.plot:
            shutil.copyfile(Path(scratch) / "plots" / f"hist_{METRIC}.png", args.plot)
    return report


if __name__ == "__main__":
    main()
