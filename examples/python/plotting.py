"""The examples' figures: panels one above the other, sharing their abscissa's label."""
from __future__ import annotations


def stacked_panels(panels, x_label: str, title: str, path: str, marks=()) -> None:
    """Write a PNG of one panel per entry of `panels`, each (x, y, y_label, legend): y one curve or an
    (n, k) array of k curves named by `legend` (None: no legend); a dotted line at each of `marks`."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(7, 1 + 1.5 * len(panels)))
    axes = fig.subplots(len(panels), 1, squeeze=False)[:, 0]
    for ax, (x, y, y_label, legend) in zip(axes, panels):
        ax.plot(x, y)
        ax.set_ylabel(y_label)
        if legend:
            ax.legend(legend, fontsize="small", ncol=len(legend), loc="best")
        for mark in marks:
            ax.axvline(mark, color="grey", linestyle=":")
    axes[-1].set_xlabel(x_label)
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=100)


def two_panels(x, top, bottom, labels: tuple[str, str, str], title: str, path: str, marks=()) -> None:
    """Write a PNG: `top` and `bottom` against `x`; labels = (x, top, bottom); a dotted line at each of
    `marks` (abscissae)."""
    stacked_panels([(x, top, labels[1], None), (x, bottom, labels[2], None)], labels[0], title, path, marks)
