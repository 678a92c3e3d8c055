"""A study's table drawn: percentiles with their confidence intervals, exceedance curves, a result against an input."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ..base.errors import InputError
from ..studies.statistics import exceedance_table, percentile_table
from .style import house_figure, new_figure


def _label(name: str, labels: dict | None) -> str:
    return (labels or {}).get(name, name)


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
    fig, ax = new_figure(figsize=(7.0, 4.0)) if ax is None else (ax.figure, ax)
    stats = percentile_table(table, column, by, q, confidence=confidence)
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
    fig, ax = new_figure(figsize=(7.0, 4.0)) if ax is None else (ax.figure, ax)
    curves = exceedance_table(table, column, by)
    groups = [(None, curves)] if by is None else curves.groupby(by, sort=True)
    for value, part in groups:  # each sample at its plotting position, joined
        ax.plot(part.value.to_numpy() * scale, part.exceedance.to_numpy(), "o-", ms=3, lw=1.2,
                label=None if by is None else f"{value:g}")
    ax.set_yscale("log")
    ax.set_xlabel(_label(column, labels))
    ax.set_ylabel("probability of exceedance")
    if by is not None:
        ax.legend(title=_label(by, labels), loc="lower left")
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
    fig, ax = new_figure(figsize=(7.0, 4.0)) if ax is None else (ax.figure, ax)
    for name in (x, y, by):
        if name is not None and name not in table.columns:
            raise InputError(f"{name!r} is not a column of the table; its columns are "
                             f"{list(map(str, table.columns))[:20]}")
    groups = [(None, table)] if by is None else table.groupby(by, sort=True)
    for value, part in groups:
        ax.plot(part[x].to_numpy(float) * scale[0], part[y].to_numpy(float) * scale[1], "o", ms=4, alpha=0.7,
                label=None if by is None else f"{value:g}")
    ax.set_xlabel(_label(x, labels))
    ax.set_ylabel(_label(y, labels))
    if by is not None:
        ax.legend(title=_label(by, labels))
    ax.set_title(title)
    return fig, ax
