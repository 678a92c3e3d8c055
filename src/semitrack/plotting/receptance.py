"""Receptance figures: magnitudes and phases of alpha, the central responses, the fields, convergence."""

from __future__ import annotations

import numpy as np

from ..base.conventions import ALL_ELEMENTS, ELEMENT_TEX, ELEMENT_UNITS, ELEMENTS
from ..base.paper_values import PAPER_BETA_MAX, PAPER_DX
from .style import (
    CENTRAL_LABELS,
    METHOD_STYLE,
    house_figure,
    legend_below,
    magnitude_axes,
    magnitude_label,
    new_figure,
    phase_label,
    plot_magnitude,
    plot_phase,
    show_lowest_tick_labels,
)


@house_figure
def receptance_figure(f, receptances: dict, title: str = "", logx: bool = False):
    """Magnitudes of alpha11, alpha12, alpha22, one panel each, one line per method.

    Parameters
    ----------
    f : array_like
        Frequencies (Hz).
    receptances : dict
        Method label (a key of :data:`METHOD_STYLE` or any text) to an array of shape
        ``(n_f, 2, 2)`` (m/N, 1/N, rad/(N m)).
    title : str
        Figure title.
    logx : bool
        Logarithmic frequency axis.

    Returns
    -------
    fig, axes
    """
    fig, axes = new_figure(1, 3, figsize=(10.0, 3.8), sharex=True)
    for ax, (name, (i, k)) in zip(axes, ELEMENTS.items()):
        for label, alpha in receptances.items():
            plot_magnitude(ax, f, np.asarray(alpha)[:, i, k], label, **METHOD_STYLE.get(label, {}))
        magnitude_axes(ax, magnitude_label(name), logx=logx)
        ax.set_title(ELEMENT_TEX[name])
    legend_below(fig, axes[0])
    if title:
        fig.suptitle(title)
    return fig, axes


@house_figure
def fields_figure(x, q, title: str = ""):
    """w and psi around a unit force (left) and a unit moment (right), real and imaginary parts.

    Parameters
    ----------
    x : array_like
        Positions relative to the load (m).
    q : ndarray, shape (n_x, 2, 2)
        Response (w, psi) by load (force, moment).
    title : str
        Figure title.

    Returns
    -------
    fig, axes
    """
    fig, axes = new_figure(2, 2, figsize=(9.0, 5.5), sharex=True)
    symbols = [["w_1", "w_2"], [r"\psi_1", r"\psi_2"]]  # response (row) to load (column), as alpha_ij
    for element, (i, k) in ALL_ELEMENTS.items():
        ax = axes[i, k]
        ax.plot(x, q[:, i, k].real, "k-", lw=1.2, label="real part")
        ax.plot(x, q[:, i, k].imag, color="tab:blue", ls="--", lw=1.0, label="imaginary part")
        ax.set_ylabel(f"${symbols[i][k]}$ ({ELEMENT_UNITS[element]})")
    axes[0, 0].set_title("unit vertical force at $x' = 0$")
    axes[0, 1].set_title("unit moment at $x' = 0$")
    for ax in axes[1]:
        ax.set_xlabel("$x' = x - x_0$ (m)")
    legend_below(fig, axes[0, 0])
    if title:
        fig.suptitle(title)
    return fig, axes


@house_figure
def convergence_figure(study, title: str = ""):
    """Error of the wavenumber alpha against dx, one line per wavenumber range, one panel per f.

    Parameters
    ----------
    study : pandas.DataFrame
        The table of :func:`semitrack.paper.convergence.convergence_study`.
    title : str
        Figure title.

    Returns
    -------
    fig, axes
    """
    freqs = sorted(study["f (Hz)"].unique())
    fig, axes = new_figure(1, len(freqs), figsize=(3.4 * len(freqs), 3.4), sharey=True)
    axes = np.atleast_1d(axes)
    for ax, fr in zip(axes, freqs):
        sub = study[study["f (Hz)"] == fr]
        for factor, grp in sub.groupby("beta factor"):
            grp = grp.sort_values("dx (m)")
            ax.loglog(grp["dx (m)"], grp["error"], marker="o", ms=3,
                      label=rf"$\beta_{{max}}$ = {factor:g} x {PAPER_BETA_MAX:.3g} rad/m")
        ax.axvline(PAPER_DX, color="0.5", ls=":", lw=0.8, label=f"the paper's dx = {PAPER_DX:g} m")
        ax.set_title(f"{fr:g} Hz")
        ax.set_xlabel("dx (m)")
    axes[0].set_ylabel(r"max relative error of $\alpha_{ij}$ (-)")
    legend_below(fig, axes[-1])
    if title:
        fig.suptitle(title)
    return fig, axes


@house_figure
def central_response_figure(f, responses: dict, title: str = ""):
    """|w1|, |psi2|, |Q2|, |M1| and |det(alpha^-1)| (paper Fig. 4/10), one panel each.

    Parameters
    ----------
    f : array_like
        Frequencies (Hz).
    responses : dict
        Method label to a :class:`semitrack.CentralResponse`.
    title : str
        Figure title.

    Returns
    -------
    fig, axes
    """
    fig, axes = new_figure(2, 3, figsize=(10.5, 6.0), sharex=True)
    for ax, (attr, label) in zip(axes.flat, CENTRAL_LABELS.items()):
        for name, r in responses.items():
            plot_magnitude(ax, f, getattr(r, attr), name, **METHOD_STYLE.get(name, {}))
        magnitude_axes(ax, label)
    spare = axes.flat[-1]  # the sixth panel holds the legend, clear of every curve
    spare.axis("off")
    spare.legend(*axes.flat[0].get_legend_handles_labels(), loc="center")
    show_lowest_tick_labels(axes)
    if title:
        fig.suptitle(title)
    return fig, axes


@house_figure
def phase_figure(f, receptances: dict, title: str = ""):
    """Phases of alpha11, alpha12, alpha22 (paper Fig. 6/9/15), one panel each.

    Panels are titled and labelled with the same symbols as the magnitudes of
    :func:`receptance_figure` (:data:`semitrack.base.conventions.ELEMENT_TEX`).

    Parameters
    ----------
    f : array_like
        Frequencies (Hz).
    receptances : dict
        Method label to an array of shape ``(n_f, 2, 2)``.
    title : str
        Figure title.

    Returns
    -------
    fig, axes
    """
    fig, axes = new_figure(1, 3, figsize=(10.0, 3.6), sharex=True, sharey=True)
    for ax, (name, (i, k)) in zip(axes, ELEMENTS.items()):
        for label, alpha in receptances.items():
            plot_phase(ax, f, np.asarray(alpha)[:, i, k], label, **METHOD_STYLE.get(label, {}))
        ax.set_title(ELEMENT_TEX[name])
        ax.set_ylabel(phase_label(name))
        ax.set_xlabel("Frequency (Hz)")
    legend_below(fig, axes[0])
    if title:
        fig.suptitle(title)
    return fig, axes

