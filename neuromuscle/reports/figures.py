"""One figure style for every command: sizes, fonts, grid, units on every axis, PNG drawn by Agg.

Figures are ``matplotlib.figure.Figure`` objects made without pyplot: they are drawn by the Agg canvas whatever
backend the caller's session uses (no display needed, the session's backend is left alone), no global figure
state is kept and nothing needs closing.  Build panels with :func:`new_figure`, label them with
:func:`label_axes` (both axes, each with its unit in parentheses), title them with :func:`set_title` (through
:func:`readable_title`), and write them with :func:`save_figure`.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any, Mapping, Sequence

import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure
from numpy.typing import ArrayLike

from .outdir import atomic_path

#: Figure size (inches): width of a figure of rows, height of one row, height added by each further row, width of
#: one column of a figure of columns.
WIDTH_IN, ROW_HEIGHT_IN, EXTRA_ROW_IN, COLUMN_WIDTH_IN = 7.0, 4.0, 1.0, 5.0
FONT_SIZE, SMALL_FONT_SIZE = 9, 8
DPI = 100
MEASURED_COLOR, SIMULATED_COLOR = "0.5", "C3"

_UNIT = re.compile(r"\(.+\)")
_NO_BRACES = str.maketrans("{}", "()")


def new_figure(n_panels: int = 1, *, columns: bool = False, height_ratios: Sequence[float] | None = None,
               sharex: bool = False) -> tuple[Figure, list[Axes]]:
    """A figure of ``n_panels`` panels stacked in rows (or side by side with ``columns``), with grid."""
    if columns:
        fig = Figure(figsize=(COLUMN_WIDTH_IN * n_panels, ROW_HEIGHT_IN))
        grid = fig.subplots(1, n_panels, squeeze=False)[0]
    else:
        fig = Figure(figsize=(WIDTH_IN, ROW_HEIGHT_IN + EXTRA_ROW_IN * (n_panels - 1)))
        kw = {"height_ratios": list(height_ratios)} if height_ratios else None
        grid = fig.subplots(n_panels, 1, squeeze=False, sharex=sharex, gridspec_kw=kw)[:, 0]
    axes = list(grid)
    for ax in axes:
        ax.grid(True, lw=0.4, alpha=0.4)
        ax.tick_params(labelsize=SMALL_FONT_SIZE)
    return fig, axes


def label_axes(ax: Axes, *, x: str | None, y: str) -> None:
    """Label the y axis and (unless ``x`` is None, for a panel sharing the x axis of the one below) the x axis;
    every label names its unit in parentheses, e.g. ``"time (s)"``, ``"q (dimensionless)"``."""
    for label in (y,) if x is None else (x, y):
        if not _UNIT.search(label):
            raise ValueError(f"axis label {label!r} names no unit in parentheses")
    if x is not None:
        ax.set_xlabel(x, fontsize=FONT_SIZE)
    ax.set_ylabel(y, fontsize=FONT_SIZE)


def readable_title(*parts: str | float | Mapping[str, Any]) -> str:
    """Join ``parts`` with "; ": text as it is (braces, which would read as a Python repr, become parentheses),
    numbers with 4 significant digits, mappings as "k = v, ...".  Raises ValueError for any other object."""
    def one(p: Any) -> str:
        if isinstance(p, Mapping):
            return ", ".join(f"{k} = {one(v)}" for k, v in p.items())
        if isinstance(p, (int, float)) and not isinstance(p, bool):
            return f"{p:.4g}"
        if isinstance(p, str):
            return p.translate(_NO_BRACES)
        raise ValueError(f"title part {p!r} is not readable text")
    return "; ".join(one(p) for p in parts)


def set_title(ax: Axes, *parts: str | float | Mapping[str, Any]) -> None:
    """Title ``ax`` with :func:`readable_title` of ``parts``."""
    ax.set_title(readable_title(*parts), fontsize=FONT_SIZE)


def legend(ax: Axes, small: bool = False) -> None:
    """The legend of ``ax`` in the shared font size."""
    ax.legend(fontsize=SMALL_FONT_SIZE - (1 if small else 0))


def measured_vs_simulated(ax: Axes, t: ArrayLike, measured: ArrayLike, simulated: ArrayLike, *,
                          measured_label: str = "measured", simulated_label: str = "simulated",
                          points: bool = False) -> None:
    """Measured (grey; dots with ``points``) and simulated (coloured line) against ``t``."""
    if points:
        ax.plot(t, measured, ".", ms=2, color=MEASURED_COLOR, label=measured_label)
    else:
        ax.plot(t, measured, color=MEASURED_COLOR, lw=1, label=measured_label)
    ax.plot(t, simulated, color=SIMULATED_COLOR, lw=1.2, label=simulated_label)


def residual_panel(ax: Axes, t: ArrayLike, residual: ArrayLike, *, x: str, y: str) -> None:
    """``residual`` against ``t`` with a zero line, labelled ``x`` and ``y`` (units in parentheses)."""
    ax.plot(t, residual, "k", lw=0.7)
    ax.axhline(0.0, color="0.7", lw=0.5)
    label_axes(ax, x=x, y=y)


def fit_figure(t: ArrayLike, measured: ArrayLike, simulated: ArrayLike, *, x: str, y: str, residual_y: str,
               points: bool = False, measured_label: str = "measured", simulated_label: str = "simulated"
               ) -> tuple[Figure, list[Axes]]:
    """Two panels sharing the time axis: measured vs simulated above (3/4), residual simulated - measured below;
    ``x``, ``y``, ``residual_y`` are the axis labels with units."""
    fig, axes = new_figure(2, height_ratios=(3, 1), sharex=True)
    measured_vs_simulated(axes[0], t, measured, simulated, points=points, measured_label=measured_label,
                          simulated_label=simulated_label)
    label_axes(axes[0], x=None, y=y)
    residual_panel(axes[1], t, np.asarray(simulated) - np.asarray(measured), x=x, y=residual_y)
    return fig, axes


def mark_times(ax: Axes, times_s: ArrayLike, limit: int = 200) -> None:
    """Thin vertical lines at the first ``limit`` event times (e.g. stimuli)."""
    for s in list(times_s)[:limit]:
        ax.axvline(s, color="k", lw=0.4, ls=":", alpha=0.6)


def save_figure(fig: Figure, path: str | Path) -> None:
    """Lay out and write ``fig`` as PNG at ``path`` (atomically)."""
    fig.tight_layout()
    with atomic_path(path) as part:
        fig.savefig(part, format="png", dpi=DPI)
