"""Figures of the broadband boundary: band errors, receptances, order, passivity, truncated tracks, pulses."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import pandas as pd

from ..base.conventions import ELEMENT_TEX, ELEMENTS
from ..fe.ends import BoundaryEnd
from .style import (
    METHOD_STYLE,
    house_figure,
    legend_below,
    magnitude_axes,
    magnitude_label,
    new_figure,
    panels,
    plot_magnitude,
    shade_above,
    show_lowest_tick_labels,
)
from .truncation import pulse_panels, w1_panels

#: Line styles of the boundary chapter: the house styles plus the broadband boundary and the
#: N = 5 systems (drawn like "our system") under the chapter's labels.
BOUNDARY_STYLE = {
    **METHOD_STYLE,
    "broadband boundary": dict(color="tab:purple", lw=1.2, ls="--"),
    "broadband boundary (viscous track)": dict(color="tab:purple", lw=1.0, ls=(0, (1, 1))),
    "N = 5 system": METHOD_STYLE["our system"] | dict(ls=":"),
}


@house_figure
def band_error_figure(curves: Mapping[str, pd.DataFrame], bands: Mapping[str, tuple[float, float]], title: str = ""):
    """Largest element error of alpha against frequency, one panel per track, a line per model.

    Parameters
    ----------
    curves : dict
        Track name to the table of :func:`semitrack.paper.boundary_study.error_curves`
        (indexed by frequency in Hz, one column per model, errors as fractions).
    bands : dict
        Track name to the N = 5 systems' fit band (Hz); frequencies above it are shaded.
    title : str
        Figure title.

    Returns
    -------
    fig, axes
    """
    fig, axes = panels(len(curves), figsize=(10.5, 3.6), sharey=True)
    for ax, (name, table) in zip(axes, curves.items()):
        f = table.index.to_numpy()
        for label, err in table.items():
            ax.loglog(f, err.to_numpy(), label=label, **BOUNDARY_STYLE.get(label, {}))
        shade_above(ax, bands[name][1], f[-1])
        ax.set_title(f"{name} track")
        ax.set_xlabel("Frequency (Hz)")
    axes[0].set_ylabel(f"largest error of {', '.join(ELEMENT_TEX[e] for e in ELEMENTS)} (-)")
    legend_below(fig, axes[0])
    if title:
        fig.suptitle(title)
    return fig, axes


@house_figure
def boundary_receptance_figure(f, curves: Mapping[str, Mapping[str, np.ndarray]], title: str = ""):
    """|alpha11|, |alpha12|, |alpha22| on log-log axes: one row per track, one line per model.

    Parameters
    ----------
    f : array_like
        Frequencies (Hz).
    curves : dict
        Track name to ``{label: alpha}`` (arrays of shape ``(n_f, 2, 2)``, m/N, 1/N,
        rad/(N m)), e.g. from :func:`semitrack.paper.boundary_study.receptance_curves`.
    title : str
        Figure title.

    Returns
    -------
    fig, axes
        ``axes`` of shape (n_tracks, 3).
    """
    fig, axes = new_figure(len(curves), 3, figsize=(10.5, 3.2 * len(curves)), sharex=True, squeeze=False)
    for row, (name, alphas) in enumerate(curves.items()):
        for ax, (element, (i, k)) in zip(axes[row], ELEMENTS.items()):
            for label, alpha in alphas.items():
                plot_magnitude(ax, f, np.asarray(alpha)[:, i, k], label, **BOUNDARY_STYLE.get(label, {}))
            magnitude_axes(ax, magnitude_label(element), logx=True)
            ax.set_title(f"{name} track: {ELEMENT_TEX[element]}")
    show_lowest_tick_labels(axes)
    legend_below(fig, axes[0, 0])
    if title:
        fig.suptitle(title)
    return fig, axes


@house_figure
def order_error_figure(tables: Mapping[str, pd.DataFrame], title: str = ""):
    """Median (left) and maximum (right) error of the boundary against its number of poles.

    Parameters
    ----------
    tables : dict
        Label (track and damping) to the table of
        :func:`semitrack.paper.boundary_study.order_study` (errors in per cent).
    title : str
        Figure title.

    Returns
    -------
    fig, axes
    """
    fig, axes = panels(2, figsize=(10.0, 3.4), sharex=True)
    for label, table in tables.items():
        for ax, column in zip(axes, ("median error (%)", "max error (%)")):
            ax.semilogy(table["n_poles"], table[column], marker="o", ms=3, label=label,
                        ls=":" if "viscous" in label else "-")
    for ax, what in zip(axes, ("median", "maximum")):
        ax.set_xlabel("number of poles (complex pairs count twice)")
        ax.set_ylabel(rf"{what} error of $\alpha$ (%)")
    legend_below(fig, axes[0])
    if title:
        fig.suptitle(title)
    return fig, axes


@house_figure
def passivity_margin_figure(f, margins: Mapping[str, np.ndarray], band: tuple[float, float], title: str = ""):
    """Smallest eigenvalue of the scaled damping of boundaries over a wide frequency range.

    Parameters
    ----------
    f : array_like
        Frequencies (Hz), positive.
    margins : dict
        Label to the eigenvalues of :func:`semitrack.paper.boundary_study.passivity_margin` (-).
    band : tuple of float
        The fit band (Hz), shaded.
    title : str
        Figure title.

    Returns
    -------
    fig, ax
    """
    fig, ax = new_figure(figsize=(7.5, 3.6))
    for label, lam in margins.items():
        ax.loglog(f, lam, label=label)
    ax.axvspan(band[0], band[1], color="0.92", zorder=-1, label=f"fit band {band[0]:g}-{band[1]:g} Hz")
    ax.set_xlabel("Frequency (Hz)")
    ax.set_ylabel("smallest eigenvalue of\n" r"$D^{-1/2}\,\mathrm{Re}\,Z\,D^{-1/2}$ (-)")
    legend_below(fig, ax)
    if title:
        ax.set_title(title)
    return fig, ax


@house_figure
def boundary_w1_figure(curves: Mapping[str, pd.DataFrame], bands: Mapping[str, tuple[float, float]],
                       n_bays: int, title: str = ""):
    """|w1| of the infinite track and of truncated tracks with several ends, log frequency axis.

    Parameters
    ----------
    curves : dict
        Track name to the table of :func:`semitrack.fe.truncation.truncated_w1` (indexed by
        frequency in Hz; ``"infinite track (exact)"`` and one column per kind of end, m/N).
    bands : dict
        Track name to the N = 5 systems' fit band (Hz); frequencies above it are shaded.
    n_bays : int
        Bays on each side of the truncated models (for the legend).
    title : str
        Figure title.

    Returns
    -------
    fig, axes
    """
    fig, axes = w1_panels(curves, bands, n_bays, BOUNDARY_STYLE, logx=True, height=3.8)
    if title:
        fig.suptitle(title)
    return fig, axes


@house_figure
def boundary_pulse_figure(results: Mapping[str, dict], n_bays: int, reference_bays: int, title: str = ""):
    """Rail displacement after a pulse: long reference, pinned ends and broadband-boundary ends.

    One column per track, one row per recorded position.

    Parameters
    ----------
    results : dict
        Track name to the result of :func:`semitrack.paper.boundary_study.pulse_study`
        (``"reference"``, ``"pinned"`` and ``"boundary"`` TimeHistory, ``t`` in s, ``u`` in m
        per N of peak force).
    n_bays, reference_bays : int
        Bays on each side of the truncated models and of the reference (for the legend).
    title : str
        Figure title.

    Returns
    -------
    fig, axes
        ``axes`` of shape (n_positions, n_tracks).
    """
    end = (BoundaryEnd.name, BOUNDARY_STYLE["broadband boundary"], f"{n_bays} bays, broadband-boundary ends")
    fig, axes = pulse_panels(results, n_bays, reference_bays, end, "track (viscous damping)")
    if title:
        fig.suptitle(title)
    return fig, axes
