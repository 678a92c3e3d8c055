"""Figures of the wheel on the rail: the linear force per roughness, band levels, force histories and spectra."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from .style import house_figure, legend_below, magnitude_axes, new_figure, plot_magnitude

#: Line styles of the two contact positions of the linear theory.
POSITION_STYLE = {"above a support": dict(color="k"), "at mid-span": dict(color="tab:blue", ls="--")}


@house_figure
def linear_force_figure(linear, title: str = ""):
    """|F / r| of the linear theory, one panel per track, above a support and at mid-span.

    Parameters
    ----------
    linear : LinearForce
        From :func:`semitrack.paper.wheelrail_study.linear_force` (N/m against Hz).
    title : str
        Figure title.

    Returns
    -------
    fig, axes
    """
    names = list(dict.fromkeys(name for name, _ in linear.curves))
    fig, axes = new_figure(1, len(names), figsize=(11.0, 4.0), sharey=True, squeeze=False)
    for ax, name in zip(axes[0], names):
        for where, style in POSITION_STYLE.items():
            plot_magnitude(ax, linear.f, linear.curves[name, where], where, **style)
        magnitude_axes(ax, "|F / r| (N/m)", logx=True)
        ax.set_title(f"{name} track")
    legend_below(fig, axes[0, 0])
    if title:
        fig.suptitle(title)
    return fig, axes[0]


@house_figure
def band_level_figure(transfers: Mapping[tuple, object], markers: Mapping[str, dict], reference: str, title: str = ""):
    """Force per unit roughness by one-third-octave band: linear theory and time-domain models, per track.

    Parameters
    ----------
    transfers : mapping
        ``{(track, model label): ContactTransfer}`` (dB re 1 N/m by band, Hz).
    markers : mapping of str to dict
        The model labels to draw, with their marker styles.
    reference : str
        The model label whose transfer gives the linear theory's curve.
    title : str
        Figure title.

    Returns
    -------
    fig, axes
    """
    names = list(dict.fromkeys(name for name, _ in transfers))
    fig, axes = new_figure(1, len(names), figsize=(11.0, 4.0), sharey=True, squeeze=False)
    for ax, name in zip(axes[0], names):
        linear = transfers[name, reference]
        ax.plot(linear.centres, linear.linear_level, "k-", label="linear theory, infinite track")
        for label, style in markers.items():
            ax.plot(linear.centres, transfers[name, label].level, label=f"time domain, {label}", **style)
        ax.set_xscale("log")
        ax.set_xlabel("One-third-octave band (Hz)")
        ax.set_ylabel("Force per unit roughness (dB re 1 N/m)")
        ax.set_title(f"{name} track (viscous damping)")
    legend_below(fig, axes[0, 0])
    if title:
        fig.suptitle(title)
    return fig, axes[0]


@house_figure
def force_history_figure(runs: Mapping[str, object], window: tuple[float, float], title: str = "",
                         styles=("k-", "b--", "r:"), zero_line: bool = False):
    """Contact force against time (kN, ms) of several runs over a window.

    Parameters
    ----------
    runs : mapping of str to ContactResponse
        Label to run.
    window : (float, float)
        Times shown (s).
    title : str
        Axes title.
    styles : sequence of str
        Matplotlib format strings, one per run.
    zero_line : bool
        Draw F = 0.

    Returns
    -------
    fig, ax
    """
    fig, ax = new_figure(figsize=(9.0, 3.2))
    for (label, res), style in zip(runs.items(), styles):
        shown = (res.t >= window[0]) & (res.t <= window[1])
        ax.plot(1e3 * res.t[shown], res.force[shown] / 1e3, style, lw=1.0, label=label)
    if zero_line:
        ax.axhline(0.0, color="0.5", lw=0.7)
    ax.set_xlabel("Time (ms)")
    ax.set_ylabel("Contact force (kN)")
    legend_below(fig, ax)
    ax.set_title(title)
    return fig, ax


@house_figure
def rolling_figure(runs: Mapping[str, object], spacing: float, after: float, near: float = 1.3, title: str = ""):
    """A rolling wheel's force against its position (left) and its amplitude spectrum (right, v/d dotted).

    Parameters
    ----------
    runs : mapping of str to ContactResponse
        Label to a rolling run.
    spacing : float
        Support spacing (m): supports are drawn in grey.
    after : float
        Start of the analysed record of the spectra (s).
    near : float
        Positions shown either side of the centre (m).
    title : str
        Figure title.

    Returns
    -------
    fig, axes
    """
    fig, axes = new_figure(1, 2, figsize=(11.0, 3.6))
    styles = (dict(color="0.6", lw=0.6), dict(color="k", lw=0.8), dict(color="tab:blue", lw=0.8))
    for (label, res), style in zip(runs.items(), styles):
        shown = np.abs(res.x) <= near
        axes[0].plot(res.x[shown], res.force[shown] / 1e3, label=label, **style)
        axes[1].semilogy(*res.force_spectrum(after=after), label=label, **style)
        axes[1].axvline(res.speed / spacing, ls=":", **style)
    for x_support in spacing * (np.arange(-np.ceil(near / spacing), np.ceil(near / spacing)) + 0.5):
        axes[0].axvline(x_support, color="0.6", lw=0.6, zorder=0)
    axes[0].set(xlabel="Wheel position (m; supports in grey)", ylabel="Contact force (kN)")
    axes[1].set(xlabel="Frequency (Hz)", ylabel="Force amplitude (N)", xlim=(0.0, 2200.0), ylim=(0.1, None))
    legend_below(fig, axes[1])
    if title:
        fig.suptitle(title)
    return fig, axes
