"""Figures of the wheel on the rail: the linear force per roughness, band levels, force histories and spectra,
and one run with the forces in its track."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from .style import house_figure, legend_below, magnitude_axes, new_figure, panels, plot_magnitude

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


@house_figure
def run_figure(response, reference=None, title: str = ""):
    """One run as an engineer looks at it: each wheel's contact force, and the track's forces beside it.

    Panels: the contact force of every wheel against time (the reference run dashed in the same
    colour); with watched supports, their rail-seat forces; with ballast forces (a ballasted
    track's watched supports, or hanging sleepers), those. Wheels are named as the vehicle
    names them.

    Parameters
    ----------
    response : ContactResponse
        The run (any route).
    reference : ContactResponse, optional
        A run to draw beside it, dashed (the perfect track, say).
    title : str
        Figure title.

    Returns
    -------
    fig, axes
    """
    forces, gaps = response.track_forces, response.gaps
    ballast = (forces is not None and forces.ballast is not None) or gaps is not None
    n = 1 + (forces is not None) + ballast
    fig, axes = panels(n, figsize=(4.8 * n + 1.0, 3.6))
    colours = ("k", "tab:blue", "tab:red", "tab:green", "tab:purple", "tab:brown")
    width = response.force.reshape(response.t.size, -1).shape[1]
    names = response.vehicle.wheel_names if response.vehicle is not None else tuple(
        f"wheel {i}" for i in range(1, width + 1))
    for run, style in ((response, "-"), (reference, "--")):
        if run is None:
            continue
        force = run.force.reshape(run.t.size, -1)
        for j, name in enumerate(names[:force.shape[1]]):
            label = name if run is response else f"{name}, reference"
            axes[0].plot(1e3 * run.t, force[:, j] / 1e3, ls=style, color=colours[j % len(colours)], lw=1.0,
                         label=label)
    axes[0].set_title("Contact force")
    axes[0].set_xlabel("Time (ms)")
    axes[0].set_ylabel("Force (kN, compression)")
    if forces is not None:
        for j, k in enumerate(forces.supports):
            axes[1].plot(1e3 * response.t, forces.rail_seat[:, j] / 1e3, lw=1.0, color=colours[(j + 1) % 6],
                         label=f"support {k}")
        axes[1].set_title("Rail seat (pad) at the watched supports")
        axes[1].set_xlabel("Time (ms)")
        axes[1].set_ylabel("Force (kN, compression)")
        axes[1].legend(loc="best")
    if ballast:
        ax = axes[-1]
        if forces is not None and forces.ballast is not None:
            for j, k in enumerate(forces.supports):
                ax.plot(1e3 * response.t, forces.ballast[:, j] / 1e3, lw=1.0, color=colours[(j + 1) % 6],
                        label=f"support {k}")
        if gaps is not None:
            for j, k in enumerate(gaps.supports):
                ax.plot(1e3 * response.t, gaps.force[:, j] / 1e3, lw=1.4, ls=":", color="tab:orange",
                        label=f"hanging sleeper {k} ({1e3 * gaps.gaps[j]:.3g} mm)")
        ax.set_title("Sleeper on ballast")
        ax.set_xlabel("Time (ms)")
        ax.set_ylabel("Force (kN, compression)")
        ax.legend(loc="best")
    legend_below(fig, axes[0])
    if title:
        fig.suptitle(title)
    return fig, axes
