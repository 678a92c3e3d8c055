"""An imperfect track under wheels: force histories over a dipped weld, forces in the track around it."""

from __future__ import annotations

import itertools
from collections.abc import Mapping

from .style import house_figure, legend_below, panels


@house_figure
def weld_force_figure(runs: Mapping[tuple[float, str], object], reference: str = "pinned, long", title: str = ""):
    """The contact force over the weld at each speed (a panel each), the short model over the long one.

    Parameters
    ----------
    runs : mapping
        :func:`semitrack.paper.imperfect_study.weld_runs`: ``{(speed, model): WeldRun}``.
    reference : str
        The model drawn wide in grey beneath the others (the long pinned one).
    title : str
        Figure title.

    Returns
    -------
    fig, axes
    """
    speeds = sorted({k for k, _ in runs})
    fig, axes = panels(len(speeds), figsize=(4.6 * len(speeds), 3.6), sharey=True)
    colours = itertools.cycle(("tab:red", "tab:blue", "tab:green"))
    # the reference wide and light beneath, so that a model on top of it stays visible
    styles = {name: (dict(color="0.65", lw=3.2, zorder=1) if name == reference else
                     dict(color=next(colours), lw=1.1, ls="--", zorder=2)) for _, name in runs}
    for ax, kmh in zip(axes, speeds):
        for (speed, name), run in runs.items():
            if speed == kmh:
                res = run.response
                ax.plot(res.x, res.force / 1e3, label=name, **styles[name])
        ax.set_title(f"{kmh:g} km/h")
        ax.set_xlabel("Wheel position (m; the weld's bottom at 0)")
        ax.set_xlim(-0.5, 1.5)
    axes[0].set_ylabel("Contact force (kN)")
    legend_below(fig, axes[0])
    if title:
        fig.suptitle(title)
    return fig, axes


@house_figure
def track_force_figure(response, title: str = ""):
    """Rail-seat and ballast forces at the watched supports and the bending at the weld, against wheel position.

    Parameters
    ----------
    response : ContactResponse
        A rolling run with ``watch_supports`` and ``bending_at`` (its ``track_forces``).
    title : str
        Figure title.

    Returns
    -------
    fig, axes
    """
    forces = response.track_forces
    n = 3 if forces.ballast is not None else 2
    fig, axes = panels(n, figsize=(4.6 * n, 3.6))
    colours = ("tab:blue", "tab:orange", "tab:green", "tab:red", "tab:purple", "tab:brown")
    for j, (k, xs) in enumerate(zip(forces.supports, forces.x_supports)):
        style = dict(color=colours[j % len(colours)], lw=1.0)
        axes[0].plot(response.x, forces.rail_seat[:, j] / 1e3, label=f"support {k} (x = {xs:.2f} m)", **style)
        if forces.ballast is not None:
            axes[1].plot(response.x, forces.ballast[:, j] / 1e3, **style)
    axes[0].set_title("Rail seat (pad)")
    axes[0].set_ylabel("Force (kN, compression)")
    if forces.ballast is not None:
        axes[1].set_title("Sleeper on ballast")
    for i in range(forces.x_bending.size):
        axes[-1].plot(response.x, forces.bending[:, i] / 1e3, color="k", lw=1.0)
    axes[-1].set_title(f"Rail bending at x = {forces.x_bending[0]:.2f} m" if forces.x_bending.size else "Rail bending")
    axes[-1].set_ylabel("Moment (kN m, sagging)")
    for ax in axes:
        ax.set_xlabel("Wheel position (m)")
    legend_below(fig, axes[0])
    if title:
        fig.suptitle(title)
    return fig, axes


@house_figure
def gap_figure(runs: Mapping[float, object], title: str = ""):
    """A hanging sleeper under a passing wheel, a line per gap: its displacement, the ballast force, the wheel's force.

    Parameters
    ----------
    runs : mapping of float to ContactResponse
        :func:`semitrack.paper.imperfect_study.gap_runs`: ``{gap (m): run}``.
    title : str
        Figure title.

    Returns
    -------
    fig, axes
    """
    fig, axes = panels(3, figsize=(13.8, 3.6))
    for (gap, res), colour in zip(runs.items(), itertools.cycle(("k", "tab:red", "tab:blue", "tab:green"))):
        label = "no contact (linear kb = 0)" if res.gaps.contact_time[0] == 0 else f"gap {gap * 1e3:g} mm"
        sleeper = res.gaps.gaps[0] - res.gaps.opening[:, 0]  # its downward displacement
        axes[0].plot(res.x, sleeper * 1e3, color=colour, lw=1.1, label=label)
        if res.gaps.contact_time[0] > 0:
            axes[0].axhline(gap * 1e3, color=colour, lw=0.8, ls="--")  # the ballast's surface
        axes[1].plot(res.x, res.gaps.force[:, 0] / 1e3, color=colour, lw=1.1)
        axes[2].plot(res.x, res.force / 1e3, color=colour, lw=1.1)
    for ax, (name, unit) in zip(axes, (("Sleeper (dashed: its gap)", "mm, downward"), ("Ballast force", "kN"),
                                       ("Contact force", "kN"))):
        ax.set_title(name)
        ax.set_ylabel(unit)
        ax.set_xlabel("Wheel position (m)")
    legend_below(fig, axes[0], fontsize=8)
    if title:
        fig.suptitle(title)
    return fig, axes
