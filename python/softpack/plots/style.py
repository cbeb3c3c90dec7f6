"""One style for softpack's figures: sizes of a journal's columns, legible
fonts at those sizes, mathtext symbols, PNG beside vector PDF."""

from __future__ import annotations

import contextlib
import math
from pathlib import Path

from softpack.plots import DPI

#: Figure widths (inches) of a journal's one and two columns.
SINGLE_COLUMN, DOUBLE_COLUMN = 3.4, 7.0

#: Fonts legible at those widths (pt).
RC = {"font.size": 8, "axes.titlesize": 8, "axes.labelsize": 8,
      "xtick.labelsize": 7, "ytick.labelsize": 7, "legend.fontsize": 7,
      "mathtext.fontset": "dejavusans", "axes.linewidth": 0.6,
      "lines.linewidth": 1.0, "savefig.dpi": DPI, "pdf.fonttype": 42}


def context():
    """Matplotlib's rc parameters of this style, for a ``with`` block."""
    import matplotlib

    return matplotlib.rc_context(RC)


def species_colours(count: int) -> list:
    """An outline colour per species: black for one, else tab10's."""
    import matplotlib

    if count <= 1:
        return ["black"]
    cycle = matplotlib.colormaps["tab10"].colors
    return [cycle[i % len(cycle)] for i in range(count)]


def nice_length(span: float) -> float:
    """A round length (1, 2 or 5 x 10^k) near a fifth of ``span``."""
    target = span / 5
    power = 10 ** math.floor(math.log10(target))
    return max((m * power for m in (1, 2, 5) if m * power <= target),
               default=power)


def scale_bar(ax) -> float:
    """A scale bar under the lower left of the data (m); its length."""
    x0, x1 = ax.get_xlim()
    y0, y1 = ax.get_ylim()
    length = nice_length(x1 - x0)
    y = y0 - 0.04 * (y1 - y0)
    ax.plot([x0, x0 + length], [y, y], "k-", lw=2, solid_capstyle="butt",
            gid="scale_bar", clip_on=False)
    ax.text(x0 + 0.5 * length, y - 0.02 * (y1 - y0), f"{length * 1e3:g} mm",
            ha="center", va="top")
    ax.set_ylim(y - 0.1 * (y1 - y0), y1)
    return length


def save(fig, path) -> list:
    """Write ``fig`` as ``path`` (PNG) and the same name in PDF; close it.
    Returns both paths."""
    import matplotlib.pyplot as plt

    path = Path(path)
    written = [path, path.with_suffix(".pdf")]
    for file in written:
        fig.savefig(file, dpi=DPI, bbox_inches="tight")
    plt.close(fig)
    return written
