"""Wheel flats: the tread against the centre's path, impact forces against speed, the contact filter."""

from __future__ import annotations

import itertools
from collections.abc import Mapping

import numpy as np

from .style import house_figure, legend_below, panels


@house_figure
def centre_path_figure(x, curves: Mapping[str, tuple], title: str = ""):
    """Each wheel's tread profile beside its centre's path, a panel per wheel.

    Parameters
    ----------
    x : array_like
        The distance rolled (m), about 0 (the flat's centre).
    curves : mapping of str to (ndarray, ndarray)
        Name to the tread profile and the centre path at ``x`` (m, downward;
        :func:`semitrack.paper.flats_study.centre_path_curves`).
    title : str
        Figure title.

    Returns
    -------
    fig, axes
    """
    x = np.asarray(x, dtype=float)
    fig, axes = panels(len(curves), figsize=(4.6 * len(curves), 3.6), sharey=True)
    for ax, (name, (profile, path)) in zip(axes, curves.items()):
        ax.plot(1e3 * x, 1e3 * np.asarray(profile), color="0.6", lw=2.4,
                label="tread profile (a point contact's input)")
        ax.plot(1e3 * x, 1e3 * np.asarray(path), color="tab:red", lw=1.2,
                label="centre path (the wheel's radius in the contact)")
        ax.set_title(name)
        ax.set_xlabel("Distance rolled (mm; the flat's centre at 0)")
        ax.invert_yaxis()  # a drop is downward
    axes[0].set_ylabel("Drop (mm, downward)")
    legend_below(fig, axes[0])
    if title:
        fig.suptitle(title)
    return fig, axes


@house_figure
def impact_speed_figure(table, title: str = ""):
    """P1 against speed for every flat, a panel per track; open markers where the wheel left the rail.

    Parameters
    ----------
    table : pandas.DataFrame
        :func:`semitrack.paper.flats_study.impact_table`.
    title : str
        Figure title.

    Returns
    -------
    fig, axes
    """
    tracks = list(dict.fromkeys(table.index.get_level_values("track")))
    fig, axes = panels(len(tracks), figsize=(5.2 * len(tracks), 3.9), sharey=True)
    colours = {}
    palette = itertools.cycle(("tab:blue", "tab:orange", "tab:green", "tab:red", "tab:purple", "tab:brown"))
    for ax, name in zip(axes, tracks):
        part = table.xs(name, level="track")
        for (shape, length), rows in part.groupby(level=["shape", "length (mm)"], sort=False):
            colour = colours.setdefault(length, next(palette))
            speeds = rows.index.get_level_values("speed (km/h)").to_numpy()
            p1 = rows["P1 (kN)"].to_numpy()
            lost = rows["without contact (ms)"].to_numpy() > 0
            ls = "-" if shape == "new" else "--"
            ax.plot(speeds, p1, color=colour, ls=ls, lw=1.2, label=f"{shape}, {length:g} mm")
            ax.plot(speeds[~lost], p1[~lost], "o", color=colour, ms=4)
            ax.plot(speeds[lost], p1[lost], "o", mfc="white", color=colour, ms=4)
        ax.set_title(f"{name} track")
        ax.set_xlabel("Speed (km/h)")
    axes[0].set_ylabel("Largest contact force P1 (kN)")
    legend_below(fig, axes[0], fontsize=8)
    if title:
        fig.suptitle(title)
    return fig, axes


@house_figure
def contact_filter_figure(wavelength, factor, semi_length: float, title: str = ""):
    """The contact filter's attenuation against wavelength.

    Parameters
    ----------
    wavelength : array_like
        Wavelengths (m).
    factor : array_like
        :func:`semitrack.contact_filter` at them.
    semi_length : float
        The contact's semi-length (m), marked.
    title : str
        Figure title.

    Returns
    -------
    fig, axes
    """
    lam, h = np.asarray(wavelength, dtype=float), np.abs(np.asarray(factor, dtype=float))
    fig, axes = panels(1, figsize=(6.4, 3.6))
    ax = axes[0]
    ax.semilogx(1e3 * lam, 20 * np.log10(np.maximum(h, 1e-6)), color="k", lw=1.2)
    ax.axvline(2e3 * semi_length, color="tab:red", lw=0.8, ls="--",
               label=f"patch length 2a = {2e3 * semi_length:.1f} mm")
    ax.set_ylim(-40, 3)
    ax.set_xlabel("Roughness wavelength (mm)")
    ax.set_ylabel("Contact filter (dB)")
    legend_below(fig, ax)
    if title:
        fig.suptitle(title)
    return fig, axes
