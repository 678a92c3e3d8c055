"""Figures of the truncated FE tracks: long-track errors, errors by length and end, w1 curves, pulses."""

from __future__ import annotations

from collections.abc import Mapping

import pandas as pd

from ..base.conventions import EXACT_LABEL
from ..fe.ends import PINNED, EquivalentEnd
from .style import (
    CENTRAL_LABELS,
    METHOD_STYLE,
    house_figure,
    legend_below,
    magnitude_axes,
    new_figure,
    panels,
    plot_magnitude,
    shade_above,
)


@house_figure
def long_track_error_figure(errors: Mapping[str, pd.DataFrame]):
    """Relative error of the long FE tracks' alpha and w1 against the exact method, one panel per track.

    Parameters
    ----------
    errors : dict
        Track name to the table of :func:`semitrack.fe.accuracy.long_track_errors`
        (columns ``f (Hz)``, ``alpha error``, ``w1 error``).

    Returns
    -------
    fig, axes
    """
    fig, axes = panels(len(errors), figsize=(10.0, 3.4), sharey=True)
    for ax, (name, e) in zip(axes, errors.items()):
        ax.semilogy(e["f (Hz)"], e["alpha error"], label=r"$\alpha$ (largest element)", color="k", lw=1)
        ax.semilogy(e["f (Hz)"], e["w1 error"], label=r"$\tilde w_1$", color="tab:blue", lw=1)
        ax.set_title(f"{name} track: long FE track vs exact")
        ax.set_xlabel("Frequency (Hz)")
    axes[0].set_ylabel("relative error (-)")
    legend_below(fig, axes[0])
    return fig, axes


@house_figure
def truncation_figure(studies: Mapping[str, pd.DataFrame], bands: Mapping[str, tuple[float, float]],
                      median: float = 0.05, maximum: float = 0.10):
    """Median (top) and maximum (bottom) error of w1 of truncated tracks against their length.

    One column per track, one line per kind of end (styled by :data:`METHOD_STYLE`, solid); the
    legend sits below the panels, where it covers no curve.

    Parameters
    ----------
    studies : dict
        Track name to the table of :func:`semitrack.fe.truncation.truncation_study`.
    bands : dict
        Track name to the band (Hz) the errors were taken over (for the titles).
    median, maximum : float
        Targets drawn as dotted lines (fractions).

    Returns
    -------
    fig, axes
        ``axes`` of shape (2, n_tracks).
    """
    fig, axes = new_figure(2, len(studies), figsize=(10.5, 7.0), sharex=True, squeeze=False)
    for col, (name, study) in enumerate(studies.items()):
        for label, grp in study.groupby("ends", sort=False):
            style = {k: v for k, v in METHOD_STYLE.get(label, {}).items() if k != "ls"}
            for row, column in enumerate(("median error", "max error")):
                axes[row, col].loglog(grp["n_bays"], grp[column], marker="o", ms=3, label=label, **style)
        target = f"targets: {100 * median:g} % median, {100 * maximum:g} % max"
        axes[0, col].axhline(median, color="0.5", ls=":", label=target)
        axes[1, col].axhline(maximum, color="0.5", ls=":")
        lo, hi = bands[name]
        axes[0, col].set_title(f"{name} track, {lo:g}-{hi:g} Hz")
        axes[1, col].set_xlabel("bays on each side of the centre")
    axes[0, 0].set_ylabel(r"median error of $\tilde w_1$ (-)")
    axes[1, 0].set_ylabel(r"max error of $\tilde w_1$ (-)")
    legend_below(fig, axes[0, 0], ncols=3)
    return fig, axes


@house_figure
def truncated_w1_figure(curves: Mapping[str, pd.DataFrame], bands: Mapping[str, tuple[float, float]],
                        n_bays: int):
    """|w1| of the infinite track and of truncated tracks, the band above each fit band shaded.

    Parameters
    ----------
    curves : dict
        Track name to the table of :func:`semitrack.fe.truncation.truncated_w1` (indexed by
        frequency in Hz; a column ``"infinite track (exact)"`` and one per kind of end, m/N).
    bands : dict
        Track name to its fit band (Hz); frequencies above it are shaded.
    n_bays : int
        Bays on each side of the truncated models (for the legend).

    Returns
    -------
    fig, axes
    """
    return w1_panels(curves, bands, n_bays, METHOD_STYLE, logx=False, height=3.6)


def w1_panels(curves: Mapping[str, pd.DataFrame], bands: Mapping[str, tuple[float, float]], n_bays: int,
               styles: Mapping[str, dict], logx: bool, height: float):
    """|w1| of the infinite track and of truncated tracks, one panel per track, above-band shaded."""
    fig, axes = panels(len(curves), figsize=(10.5, height), sharey=True)
    for ax, (name, table) in zip(axes, curves.items()):
        f = table.index.to_numpy()
        for label, w1 in table.items():
            if label == "infinite track (exact)":
                plot_magnitude(ax, f, w1, label, **METHOD_STYLE[EXACT_LABEL])
            else:
                plot_magnitude(ax, f, w1, f"{n_bays} bays, {label} ends", **styles.get(label, {}))
        magnitude_axes(ax, CENTRAL_LABELS["w1"], logx=logx)
        shade_above(ax, bands[name][1], f[-1])
        ax.set_title(f"{name} track")
    legend_below(fig, axes[0])
    return fig, axes


@house_figure
def pulse_figure(results: Mapping[str, dict], n_bays: int, reference_bays: int):
    """Rail displacement after a pulse: long reference, pinned ends and equivalent ends.

    One column per track, one row per recorded position.

    Parameters
    ----------
    results : dict
        Track name to the result of :func:`semitrack.fe.truncation.truncation_errors` with a
        ``"pulse"`` excitation and ``"pinned"`` and ``"equivalent"`` ends (TimeHistory ``t`` in
        s, ``u`` in m per N of peak force).
    n_bays, reference_bays : int
        Bays on each side of the truncated models and of the reference (for the legend).

    Returns
    -------
    fig, axes
        ``axes`` of shape (n_positions, n_tracks).
    """
    end = (EquivalentEnd.name, METHOD_STYLE["our system"], f"{n_bays} bays, our equivalent ends")
    return pulse_panels(results, n_bays, reference_bays, end, "track: Hann pulse at the centre")


def pulse_panels(results: Mapping[str, dict], n_bays: int, reference_bays: int, end: tuple, subtitle: str):
    """Reference, pinned ends and one more end model (``(key, style, label)``), per track and position."""
    n_rows = next(iter(results.values()))["reference"].u.shape[1]
    fig, axes = new_figure(n_rows, len(results), figsize=(10.5, 3.0 * n_rows), sharex=True, squeeze=False)
    lines = (("reference", METHOD_STYLE[EXACT_LABEL], f"{reference_bays}-bay reference"),
             (PINNED.name, dict(color="tab:red", lw=0.9, ls=":"), f"{n_bays} bays, pinned ends"), end)
    for col, (name, res) in enumerate(results.items()):
        t_ms = 1e3 * res["reference"].t
        for row in range(n_rows):
            ax = axes[row, col]
            for key, style, label in lines:
                ax.plot(t_ms, 1e9 * res[key].u[:, row], label=label, **style)
            ax.set_ylabel(f"w at {res['reference'].labels[row][2:-1]} (nm per N)")
        axes[0, col].set_title(f"{name} {subtitle}")
        axes[-1, col].set_xlabel("time (ms)")
    legend_below(fig, axes[0, 0])
    return fig, axes

