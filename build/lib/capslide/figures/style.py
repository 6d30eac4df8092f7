"""Journal style of every capslide figure: serif 8 pt, inward ticks, the paper's marker colours; atomic saving."""

from __future__ import annotations

import contextlib
from collections.abc import Iterator
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from ..io.atomic import replacing  # noqa: E402

__all__ = ["BLUE", "ORANGE", "YELLOW", "PURPLE", "GREEN", "SINGLE_COLUMN", "DOUBLE_COLUMN", "journal_style", "save",
           "star"]

# Marker colours of the paper's asterisks (its captions name them).
BLUE, ORANGE, YELLOW, PURPLE, GREEN = "#0072BD", "#D95319", "#EDB120", "#7E2F8E", "#77AC30"
SINGLE_COLUMN = 3.4  # inch
DOUBLE_COLUMN = 7.0  # inch

_STYLE = {
    "font.family": "serif",
    "font.serif": ["STIXGeneral", "DejaVu Serif"],
    "mathtext.fontset": "stix",
    "font.size": 8,
    "axes.labelsize": 8,
    "axes.titlesize": 8,
    "legend.fontsize": 7,
    "xtick.labelsize": 7,
    "ytick.labelsize": 7,
    "xtick.direction": "in",
    "ytick.direction": "in",
    "xtick.top": True,
    "ytick.right": True,
    "axes.linewidth": 0.6,
    "lines.linewidth": 1.2,
    "lines.markersize": 5,
    "legend.frameon": False,
    "savefig.dpi": 300,
    "savefig.bbox": "tight",
    "savefig.pad_inches": 0.02,
    "pdf.fonttype": 42,
}


@contextlib.contextmanager
def journal_style() -> Iterator[None]:
    """Matplotlib settings of a journal figure (serif, 8 pt, inward ticks)."""
    with plt.rc_context(_STYLE):
        yield


def save(fig, paths) -> None:
    """Write ``fig`` to every path (format from the suffix), atomically; then close it."""
    for path in map(Path, paths):
        with replacing(path) as tmp:
            fig.savefig(tmp, format=path.suffix.lstrip("."))
    plt.close(fig)


def star(ax, x, y, color, label=None):
    """The paper's asterisk marker."""
    ax.plot(x, y, "*", color=color, markersize=8, markeredgewidth=0.4, markeredgecolor="k", label=label, zorder=5)
