"""The examples' one kind of figure: two curves against the same abscissa, one above the other."""
from __future__ import annotations


def two_panels(x, top, bottom, labels: tuple[str, str, str], title: str, path: str, marks=()) -> None:
    """Write a PNG: `top` and `bottom` against `x`; labels = (x, top, bottom); a dotted line at each of
    `marks` (abscissae)."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(7, 4))
    upper, lower = fig.subplots(2, 1, sharex=True)
    upper.plot(x, top)
    lower.plot(x, bottom)
    upper.set_ylabel(labels[1])
    lower.set_ylabel(labels[2])
    lower.set_xlabel(labels[0])
    for ax in (upper, lower):
        for mark in marks:
            ax.axvline(mark, color="grey", linestyle=":")
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
