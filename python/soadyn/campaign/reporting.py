"""Report of a results directory: a summary table of every metric and dispersed value, a
histogram of each metric and scatter plots of each metric against each dispersed value (PNG)."""
from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Optional

import numpy as np

from .errors import CampaignError
from .metrics import METRICS
from .movie import worst_run, worst_run_movie
from .replaying import stored_spec
from .store import read_parts

STATISTICS = ("count", "failed", "mean", "std", "min", "p5", "p50", "p95", "max")


@dataclass
class Report:
    """What campaign.report returns: run counts, the summary statistics of each metric and dispersed value,
    the plots and the table it wrote, and the worst run's movie when one was asked for."""

    runs: int                  # runs of the spec
    finished: int              # runs in the results
    failed: int
    summary: list              # (column, kind, {statistic: value}) for the metrics, then the dispersed values
    plots: list                # PNG paths written
    table_path: Optional[Path]
    movie: Optional[tuple] = None  # (path, run id, value) of the worst run's movie, when asked for


def summarize(values: np.ndarray, failed: int) -> dict:
    finite = values[np.isfinite(values)]
    stats = {"count": int(len(finite)), "failed": failed}
    if len(finite):
        p5, p50, p95 = np.percentile(finite, [5, 50, 95])
        stats.update(mean=float(finite.mean()), std=float(finite.std(ddof=1)) if len(finite) > 1 else 0.0,
                     min=float(finite.min()), p5=float(p5), p50=float(p50), p95=float(p95), max=float(finite.max()))
    else:
        stats.update(dict.fromkeys(STATISTICS[2:], math.nan))
    return stats


def report(out, plots_dir=None, plots: bool = True, movie: Optional[str] = None) -> Report:
    """Summarize the finished runs in `out`; with `plots`, write the PNGs to `plots_dir`
    (default DIR/report) and the table to summary.md there; with `movie` (a metric), also a movie of the
    run with its largest value there (soadyn.campaign.movie: needs the view extra and Chromium).

    Raises CampaignError naming `out` when it holds no campaign (no spec.json) or no finished run yet, and
    MovieError saying what is wrong (an unknown metric, the view extra or Chromium missing) when the movie
    cannot be made.
    """
    spec = stored_spec(out)
    table = read_parts(out, spec, spec.runs)
    if table.num_rows == 0:
        raise CampaignError(f"{out}: no finished runs yet")
    ok = np.array([s == "ok" for s in table["status"].to_pylist()])
    failed = int((~ok).sum())

    def column(name) -> np.ndarray:
        return np.array([np.nan if x is None else x for x in table[name].to_pylist()], dtype=float)

    summary = [(m, "metric", summarize(column(m)[ok], failed)) for m in spec.metrics]
    summary += [(c, "dispersed", summarize(column(c), 0)) for c in spec.dispersion_columns]
    written, table_path, movie_made = [], None, None
    target = Path(plots_dir) if plots_dir is not None else Path(out) / "report"
    if movie is not None:
        worst_run(spec, table, movie)  # a metric not in the campaign is refused before any work
    if plots or movie is not None:
        target.mkdir(parents=True, exist_ok=True)
    if movie is not None:
        movie_made = worst_run_movie(spec, table, movie, target)
    if plots:
        written = _plot(spec, column, ok, target)
        table_path = target / "summary.md"
        table_path.write_text(f"# {spec.name}: {table.num_rows} of {spec.runs} runs, {failed} failed\n\n"
                              + format_summary(summary, markdown=True) + "\n", encoding="utf-8")
    return Report(spec.runs, table.num_rows, failed, summary, written, table_path, movie_made)


def format_summary(summary: list, markdown: bool = False) -> str:
    """Report.summary as an aligned text table (or a Markdown table): one row per column, one column per
    statistic (count, failed, mean, std, min, p5, p50, p95, max)."""
    header = ["", *STATISTICS]
    rows = [[name, *(_number(stats[s]) for s in STATISTICS)] for name, _, stats in summary]
    if markdown:
        lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
        return "\n".join(lines + ["| " + " | ".join(r) + " |" for r in rows])
    widths = [max(len(r[k]) for r in [header, *rows]) for k in range(len(header))]

    def fmt(r):
        return "  ".join(x.ljust(widths[0]) if k == 0 else x.rjust(widths[k]) for k, x in enumerate(r))

    lines = [fmt(header)]
    kinds = [kind for _, kind, _ in summary]
    for k, r in enumerate(rows):
        if k and kinds[k] != kinds[k - 1]:
            lines.append("dispersed values:")
        lines.append(fmt(r))
    return "\n".join(lines)


def _number(x) -> str:
    if isinstance(x, int):
        return str(x)
    return "-" if not math.isfinite(x) else f"{x:.4g}"


def _unit(metric: str) -> str:
    found = METRICS.get(metric) or METRICS.get(metric.partition(":")[0])
    return f" ({found.unit})" if found else ""


def _file_name(name: str) -> str:
    return re.sub(r"[^A-Za-z0-9_.-]+", "_", name).strip("_") or "value"


def _plot(spec, column, ok, target: Path) -> list:
    try:
        from matplotlib.figure import Figure
        from matplotlib.ticker import MaxNLocator
    except ImportError:
        raise ImportError("plotting needs matplotlib: pip install 'soadyn[plot]'") from None

    def readable(ax):
        ax.xaxis.set_major_locator(MaxNLocator(5))
        ax.ticklabel_format(style="sci", scilimits=(-2, 4), useOffset=False)

    written = []
    dispersed = spec.dispersion_columns
    for metric in spec.metrics:
        y = column(metric)[ok]
        finite = np.isfinite(y)
        fig = Figure(figsize=(6, 4))
        ax = fig.add_subplot()
        if finite.any():
            ax.hist(y[finite], bins=min(50, max(10, int(np.sqrt(finite.sum())))))
        readable(ax)
        ax.set_xlabel(metric + _unit(metric))
        ax.set_ylabel("runs")
        ax.set_title(f"{spec.name}: {metric} ({int(finite.sum())} runs)")
        fig.tight_layout()
        path = target / f"hist_{_file_name(metric)}.png"
        fig.savefig(path, dpi=100)
        written.append(path)
        if not dispersed:
            continue
        n = len(dispersed)
        cols = min(4, n)
        rows = math.ceil(n / cols)
        fig = Figure(figsize=(3.6 * cols, 3.0 * rows))
        for k, name in enumerate(dispersed):
            ax = fig.add_subplot(rows, cols, k + 1)
            x = column(name)[ok]
            both = finite & np.isfinite(x)
            ax.scatter(x[both], y[both], s=4, alpha=0.5)
            r = np.corrcoef(x[both], y[both])[0, 1] if both.sum() > 2 and np.ptp(x[both]) > 0 \
                and np.ptp(y[both]) > 0 else math.nan
            ax.set_title(f"r = {r:.2f}" if math.isfinite(r) else "r = -", fontsize=9)
            readable(ax)
            ax.set_xlabel(name, fontsize=8)
            ax.tick_params(labelsize=7)
            if k % cols == 0:
                ax.set_ylabel(metric + _unit(metric), fontsize=8)
        fig.suptitle(f"{spec.name}: {metric} against the dispersed values")
        fig.tight_layout()
        path = target / f"scatter_{_file_name(metric)}.png"
        fig.savefig(path, dpi=100)
        written.append(path)
    return written
