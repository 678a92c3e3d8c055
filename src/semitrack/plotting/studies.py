"""A study's table drawn: percentiles with their confidence intervals, exceedance curves, a result against an input."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from pandas.api.types import is_numeric_dtype

from ..base.checks import check_real
from ..base.errors import InputError
from ..studies.statistics import check_columns, exceedance_table, percentile_table
from .style import house_figure, new_figure


def _label(name: str, labels: dict | None) -> str:
    return str((labels or {}).get(name, name))


def _value(value) -> str:
    """A group's value in a legend: a number short (``0.1``), anything else as it is."""
    return f"{value:g}" if isinstance(value, (int, float, np.integer, np.floating)) else str(value)


@house_figure
def percentile_figure(table, column: str, by: str, q: Sequence[float] = (50.0, 95.0, 99.0), *,
                      confidence: float = 0.95, scale: float = 1.0, labels: dict | None = None, ax=None,
                      title: str = ""):
    """Percentiles of a study's result against an input, each with its bootstrap confidence interval.

    Parameters
    ----------
    table : pandas.DataFrame
        A study's table (:func:`semitrack.run_study`).
    column : str
        The result drawn (y).
    by : str
        The input it is grouped by (x), e.g. the void fraction.
    q : sequence of float
        Percentiles, one line each.
    confidence : float
        Level of the intervals (:func:`semitrack.studies.statistics.percentiles`).
    scale : float
        Factor on the result (1e-3 for kN from N).
    labels : dict, optional
        Axis labels ``{column name: label}``.
    ax : matplotlib.axes.Axes, optional
        Draw here (else a new figure).
    title : str
        Panel title.

    Returns
    -------
    fig, ax
    """
    scale = check_real("scale", scale)
    stats = percentile_table(table, column, by, q, confidence=confidence)  # checks the table first
    fig, ax = new_figure(figsize=(7.0, 4.0)) if ax is None else (ax.figure, ax)
    if not is_numeric_dtype(stats[by]):
        raise InputError(f"by={by!r} must hold numbers (the x axis), got {stats[by].dtype}")
    for level, part in stats.groupby("q", sort=True):
        x = part[by].to_numpy(float)
        y = part.value.to_numpy() * scale
        err = np.vstack([y - part.low.to_numpy() * scale, part.high.to_numpy() * scale - y])
        ax.errorbar(x, y, yerr=err, marker="o", capsize=3, label=f"{level:g}th percentile")
    ax.set_xlabel(_label(by, labels))
    ax.set_ylabel(_label(column, labels))
    ax.legend(title=f"{100 * confidence:g} % intervals")
    ax.set_title(title)
    return fig, ax


@house_figure
def exceedance_figure(table, column: str, by: str | None = None, *, scale: float = 1.0, labels: dict | None = None,
                      ax=None, title: str = ""):
    """The probability of exceeding each value of a study's result, one curve per value of ``by``.

    Parameters
    ----------
    table : pandas.DataFrame
        A study's table.
    column : str
        The result (x).
    by : str, optional
        One curve per value of this input; None: one curve.
    scale : float
        Factor on the result.
    labels : dict, optional
        Axis and legend labels ``{column name: label}``.
    ax : matplotlib.axes.Axes, optional
        Draw here (else a new figure).
    title : str
        Panel title.

    Returns
    -------
    fig, ax
    """
    scale = check_real("scale", scale)
    curves = exceedance_table(table, column, by)  # checks the table first
    fig, ax = new_figure(figsize=(7.0, 4.0)) if ax is None else (ax.figure, ax)
    groups = [(None, curves)] if by is None else curves.groupby(by, sort=True, dropna=False)
    for value, part in groups:  # each sample at its plotting position, joined
        ax.plot(part.value.to_numpy() * scale, part.exceedance.to_numpy(), "o-", ms=3, lw=1.2,
                label=None if by is None else _value(value))
    ax.set_yscale("log")
    ax.set_xlabel(_label(column, labels))
    ax.set_ylabel("probability of exceedance")
    if by is not None:
        ax.legend(title=_label(by, labels), loc="upper right")
    ax.set_title(title)
    return fig, ax


@house_figure
def scatter_figure(table, x: str, y: str, by: str | None = None, *, scale: tuple[float, float] = (1.0, 1.0),
                   labels: dict | None = None, ax=None, title: str = ""):
    """A study's result against an input (or another result), coloured by a third column.

    Parameters
    ----------
    table : pandas.DataFrame
        A study's table.
    x, y : str
        The columns drawn.
    by : str, optional
        Colour the points by this column's values (one legend entry each).
    scale : (float, float)
        Factors on x and y.
    labels : dict, optional
        Axis labels ``{column name: label}``.
    ax : matplotlib.axes.Axes, optional
        Draw here (else a new figure).
    title : str
        Panel title.

    Returns
    -------
    fig, ax
    """
    check_columns(table, x=x, y=y, by=by)
    if not (isinstance(scale, (tuple, list)) and len(scale) == 2):
        raise InputError(f"scale must be a pair (x factor, y factor), got {scale!r}")
    scale = (check_real("scale[0]", scale[0]), check_real("scale[1]", scale[1]))
    for name in (x, y):
        if not is_numeric_dtype(table[name]):
            raise InputError(f"column {name!r} must hold numbers to be drawn, got {table[name].dtype}")
    fig, ax = new_figure(figsize=(7.0, 4.0)) if ax is None else (ax.figure, ax)
    groups = [(None, table)] if by is None else table.groupby(by, sort=True, dropna=False)
    for value, part in groups:
        ax.plot(part[x].to_numpy(float) * scale[0], part[y].to_numpy(float) * scale[1], "o", ms=4, alpha=0.7,
                label=None if by is None else _value(value))
    ax.set_xlabel(_label(x, labels))
    ax.set_ylabel(_label(y, labels))
    if by is not None:
        ax.legend(title=_label(by, labels))
    ax.set_title(title)
    return fig, ax
