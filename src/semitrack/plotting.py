"""The book's figures, in one house style. The library never selects a matplotlib backend.

Every ``*_figure`` function takes results computed by the package (arrays, tables, the results
of a study), draws one figure and returns ``(fig, axes)``; the notebooks call them and compute
nothing by hand. Methods and kinds of end keep one line style throughout (:data:`METHOD_STYLE`);
element names, labels and units come from :mod:`semitrack.base.conventions`.
"""

from __future__ import annotations

from collections.abc import Mapping
from contextlib import contextmanager

import matplotlib as mpl
import matplotlib.pyplot as plt
import numpy as np
import pandas as pd

from .base.conventions import ELEMENT_TEX, ELEMENT_UNITS, ELEMENTS

#: Line styles per method, used in every figure so that a method always looks the same.
METHOD_STYLE = {
    "exact": dict(color="k", lw=1.4, ls="-"),
    "transfer": dict(color="k", lw=1.4, ls="-"),
    "wavenumber": dict(color="tab:orange", lw=1.1, ls="--"),
    "paper system": dict(color="tab:red", lw=1.1, ls=":"),
    "our system": dict(color="tab:blue", lw=1.1, ls="--"),
    "pinned": dict(color="0.45", lw=1.1, ls="-."),
    "free": dict(color="tab:brown", lw=1.0, ls="-."),
    "exact end stiffness": dict(color="tab:green", lw=1.1, ls="-"),
}
#: Colours of the receptance elements, as in the paper's Fig. 8 (black, green, red).
ELEMENT_COLOR = {"alpha11": "k", "alpha12": "tab:green", "alpha22": "tab:red"}

RC = {
    "figure.figsize": (7.0, 4.0), "figure.dpi": 110, "axes.grid": True, "grid.alpha": 0.3,
    "axes.spines.top": False, "axes.spines.right": False, "legend.frameon": False,
    "font.size": 10, "axes.titlesize": 10, "legend.fontsize": 9,
}


@contextmanager
def house_style():
    """Context manager applying the house rcParams (:data:`RC`) inside a ``with`` block."""
    with mpl.rc_context(RC):
        yield


def apply_house_style() -> None:
    """Apply the house rcParams globally (for notebooks)."""
    mpl.rcParams.update(RC)


def magnitude_axes(ax, ylabel: str, xlabel: str = "Frequency (Hz)", logx: bool = False):
    """Log-magnitude axes with units on both axes.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        The axes.
    ylabel, xlabel : str
        Axis labels, with units.
    logx : bool
        Logarithmic frequency axis too.

    Returns
    -------
    matplotlib.axes.Axes
        ``ax``.
    """
    ax.set_yscale("log")
    if logx:
        ax.set_xscale("log")
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    return ax


def plot_magnitude(ax, f, values, label: str, **style):
    """Plot ``|values|`` against ``f``.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        The axes.
    f : array_like
        Frequencies (Hz).
    values : array_like
        Complex values, same length as ``f``.
    label : str
        Legend label.
    **style
        Line properties (e.g. ``**METHOD_STYLE["exact"]``).

    Returns
    -------
    list of matplotlib.lines.Line2D
    """
    return ax.plot(f, np.abs(values), label=label, **style)


def plot_phase(ax, f, values, label: str, **style):
    """Plot the phase of ``values`` (rad, in [-pi, pi]) against ``f``.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        The axes.
    f : array_like
        Frequencies (Hz).
    values : array_like
        Complex values, same length as ``f``.
    label : str
        Legend label.
    **style
        Line properties.

    Returns
    -------
    list of matplotlib.lines.Line2D
    """
    ax.set_ylabel("Phase (rad)")
    ax.set_yticks([-np.pi, -np.pi / 2, 0, np.pi / 2, np.pi], ["$-\\pi$", "$-\\pi/2$", "0", "$\\pi/2$", "$\\pi$"])
    return ax.plot(f, np.angle(values), label=label, **style)


def mark_frequencies(ax, freqs, labels=None, **style):
    """Thin vertical lines at characteristic frequencies, with optional labels at the top.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        The axes.
    freqs : sequence of float
        Frequencies (Hz).
    labels : sequence of str, optional
        One label per frequency.
    **style
        Line properties overriding the thin grey dotted default.
    """
    style = {"color": "0.5", "lw": 0.7, "ls": ":", **style}
    for i, fr in enumerate(freqs):
        ax.axvline(fr, **style)
        if labels is not None:
            ax.annotate(labels[i], (fr, 1.0), xycoords=("data", "axes fraction"), rotation=90,
                        ha="right", va="top", fontsize=8, color="0.35")


def new_figure(nrows: int = 1, ncols: int = 1, **kwargs):
    """``plt.subplots`` with the house style applied and a constrained layout.

    Parameters
    ----------
    nrows, ncols : int
        Grid of panels.
    **kwargs
        Passed to :func:`matplotlib.pyplot.subplots` (``figsize``, ``sharex``...).

    Returns
    -------
    fig, axes
    """
    apply_house_style()
    kwargs.setdefault("layout", "constrained")
    return plt.subplots(nrows, ncols, **kwargs)


def _magnitude_label(element: str) -> str:
    """Axis label ``|alpha_ij| (unit)`` of a receptance element, from the package's conventions."""
    return f"$|{ELEMENT_TEX[element].strip('$')}|$ ({ELEMENT_UNITS[element]})"


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
    fig, axes = new_figure(1, 3, figsize=(10.0, 3.4), sharex=True)
    for ax, (name, (i, k)) in zip(axes, ELEMENTS.items()):
        for label, alpha in receptances.items():
            plot_magnitude(ax, f, np.asarray(alpha)[:, i, k], label, **METHOD_STYLE.get(label, {}))
        magnitude_axes(ax, _magnitude_label(name), logx=logx)
    axes[0].legend()
    if title:
        fig.suptitle(title)
    return fig, axes


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
    labels = [[r"$w_1$ (m/N)", r"$w_2$ (1/N)"], [r"$\psi_1$ (1/N)", r"$\psi_2$ (rad/(N m))"]]
    for i in range(2):
        for k in range(2):
            ax = axes[i, k]
            ax.plot(x, q[:, i, k].real, "k-", lw=1.2, label="real part")
            ax.plot(x, q[:, i, k].imag, color="tab:blue", ls="--", lw=1.0, label="imaginary part")
            ax.set_ylabel(labels[i][k])
    axes[0, 0].set_title("unit vertical force at x' = 0")
    axes[0, 1].set_title("unit moment at x' = 0")
    for ax in axes[1]:
        ax.set_xlabel("x' = x - x0 (m)")
    axes[0, 0].legend()
    if title:
        fig.suptitle(title)
    return fig, axes


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
                      label=rf"$\beta_{{max}}$ = {factor:g} x 78.5 rad/m")
        ax.axvline(0.04, color="0.5", ls=":", lw=0.8)
        ax.set_title(f"{fr:g} Hz")
        ax.set_xlabel("dx (m)")
    axes[0].set_ylabel(r"max relative error of $\alpha_{ij}$ (-)")
    axes[-1].legend(fontsize=8)
    if title:
        fig.suptitle(title)
    return fig, axes


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
    spec = [("w1", r"$|\tilde w_1|$ (m/N)"), ("psi2", r"$|\tilde\psi_2|$ (rad/(N m))"),
            ("Q2", r"$|\tilde Q_2|$ (N/(N m))"), ("M1", r"$|\tilde M_1|$ (N m/N)"),
            ("det", r"$|\det\alpha^{-1}|$ (N$^2$)")]
    for ax, (attr, label) in zip(axes.flat, spec):
        for name, r in responses.items():
            plot_magnitude(ax, f, getattr(r, attr), name, **METHOD_STYLE.get(name, {}))
        magnitude_axes(ax, label)
    axes.flat[-1].set_visible(False)
    axes.flat[0].legend()
    if title:
        fig.suptitle(title)
    return fig, axes


def phase_figure(f, receptances: dict, title: str = ""):
    """Phases of alpha11, alpha12, alpha22 (paper Fig. 6/9/15), one panel each.

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
    fig, axes = new_figure(1, 3, figsize=(10.0, 3.2), sharex=True, sharey=True)
    for ax, (name, (i, k)) in zip(axes, ELEMENTS.items()):
        for label, alpha in receptances.items():
            plot_phase(ax, f, np.asarray(alpha)[:, i, k], label, **METHOD_STYLE.get(label, {}))
        ax.set_title(ELEMENT_TEX[name])
        ax.set_xlabel("Frequency (Hz)")
    axes[0].legend()
    if title:
        fig.suptitle(title)
    return fig, axes


def equivalent_schematic(system, ax=None, title: str = ""):
    """Draw an equivalent system to scale in x (bar lengths in m), as the paper's Fig. 7 / 12.

    Bars are drawn with a thickness that grows with their mass, springs as zig-zags whose
    labels give the stiffness; support masses (ballasted layout) as boxes labelled with mu.

    Parameters
    ----------
    system : EquivalentSystem
        The system.
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new figure by default.
    title : str
        Axes title; by default the layout and N.

    Returns
    -------
    matplotlib.axes.Axes
    """
    if ax is None:
        _, ax = new_figure(figsize=(10.0, 3.2))
    p = system.parameters()
    lengths = p["L"]
    x = np.concatenate([[0.0], np.cumsum(lengths)])
    m_max = max(p["m"].max(), 1e-12)
    ballasted = "mu" in p
    spring_top, spring_bottom = 0.0, (-1.0 if not ballasted else -0.55)

    def zigzag(x0, y0, y1, label=None, shift=0.0):
        ys = np.linspace(y0, y1, 14)
        xs = x0 + 0.012 * np.array([0] + [(-1) ** i for i in range(12)] + [0]) * (x[-1] or 1)
        ax.plot(xs, ys, color="0.3", lw=0.8)
        if label:  # labels of neighbouring bars are staggered in height so that short bars stay readable
            ax.annotate(label, (x0, 0.5 * (y0 + y1) + shift), xytext=(4, 0), textcoords="offset points",
                        fontsize=7, va="center", color="0.3")

    for j in range(system.n_bars):
        lw = 1.0 + 7.0 * p["m"][j] / m_max
        ax.plot([x[j], x[j + 1]], [0, 0], color="tab:blue", lw=lw, solid_capstyle="butt")
        ax.annotate(f"bar {j + 1}\nm={p['m'][j]:.3g} kg", ((x[j] + x[j + 1]) / 2, 0.12), ha="center", fontsize=7)
        shift = 0.12 * (j % 2)
        for end in (x[j], x[j + 1]):
            first = end == x[j]
            if p["k"][j] > 0:
                zigzag(end, spring_top, spring_bottom, f"k={p['k'][j]:.3g}" if first else None, shift)
            if ballasted and p["mu"][j] > 0:
                ax.add_patch(mpl.patches.Rectangle((end - 0.01 * x[-1], -0.7), 0.02 * x[-1], 0.15, color="tab:orange"))
                zigzag(end, -0.7, -1.0, f"s={p['s'][j]:.3g}" if first else None, shift / 3)
    for j in range(system.n_bars - 1):
        ax.plot(x[j + 1], 0, "o", mfc="white", mec="k", ms=5)
    ax.axhline(-1.0, color="0.2", lw=1.2)
    ax.annotate("load (Q, M) at the left end of bar 1", (0, 0), xytext=(0, 0.45), fontsize=8,
                arrowprops=dict(arrowstyle="->", lw=0.8))
    ax.set_ylim(-1.15, 0.6)
    ax.set_yticks([])
    ax.set_xlabel("position along the equivalent system (m)")
    ax.grid(False)
    ax.spines["left"].set_visible(False)
    ax.set_title(title or f"{system.layout} equivalent system, N = {system.n_bars} (springs labelled in N/m)")
    return ax


# ------------------------------------------------------------------------------------------------
# Finite-element tracks (book chapter "truncated track models")
# ------------------------------------------------------------------------------------------------
def _panels(n: int, **kwargs):
    fig, axes = new_figure(1, n, **kwargs)
    return fig, np.atleast_1d(axes)


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
    fig, axes = _panels(len(errors), figsize=(10.0, 3.4), sharey=True)
    for ax, (name, e) in zip(axes, errors.items()):
        ax.semilogy(e["f (Hz)"], e["alpha error"], label=r"$\alpha$ (largest element)", color="k", lw=1)
        ax.semilogy(e["f (Hz)"], e["w1 error"], label=r"$\tilde w_1$", color="tab:blue", lw=1)
        ax.set_title(f"{name} track: long FE track vs exact")
        ax.set_xlabel("Frequency (Hz)")
    axes[0].set_ylabel("relative error (-)")
    axes[0].legend()
    return fig, axes


def truncation_figure(studies: Mapping[str, pd.DataFrame], bands: Mapping[str, tuple[float, float]],
                      median: float = 0.05, maximum: float = 0.10):
    """Median (top) and maximum (bottom) error of w1 of truncated tracks against their length.

    One column per track, one line per kind of end (styled by :data:`METHOD_STYLE`, solid).

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
    fig, axes = new_figure(2, len(studies), figsize=(10.5, 6.5), sharex=True, squeeze=False)
    for col, (name, study) in enumerate(studies.items()):
        for label, grp in study.groupby("ends", sort=False):
            style = {k: v for k, v in METHOD_STYLE.get(label, {}).items() if k != "ls"}
            for row, column in enumerate(("median error", "max error")):
                axes[row, col].loglog(grp["n_bays"], grp[column], marker="o", ms=3, label=label, **style)
        axes[0, col].axhline(median, color="0.5", ls=":")
        axes[1, col].axhline(maximum, color="0.5", ls=":")
        lo, hi = bands[name]
        axes[0, col].set_title(f"{name} track, {lo:g}-{hi:g} Hz")
        axes[1, col].set_xlabel("bays on each side of the centre")
    axes[0, 0].set_ylabel("median error of w1 (-)")
    axes[1, 0].set_ylabel("max error of w1 (-)")
    axes[0, 0].legend(fontsize=8)
    return fig, axes


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
    return _w1_panels(curves, bands, n_bays, METHOD_STYLE, logx=False, height=3.6)


def _w1_panels(curves: Mapping[str, pd.DataFrame], bands: Mapping[str, tuple[float, float]], n_bays: int,
               styles: Mapping[str, dict], logx: bool, height: float):
    """|w1| of the infinite track and of truncated tracks, one panel per track, above-band shaded."""
    fig, axes = _panels(len(curves), figsize=(10.5, height), sharey=True)
    for ax, (name, table) in zip(axes, curves.items()):
        f = table.index.to_numpy()
        for label, w1 in table.items():
            if label == "infinite track (exact)":
                plot_magnitude(ax, f, w1, label, **METHOD_STYLE["exact"])
            else:
                plot_magnitude(ax, f, w1, f"{n_bays} bays, {label} ends", **styles.get(label, {}))
        magnitude_axes(ax, r"$|\tilde w_1|$ (m/N)", logx=logx)
        _shade_above(ax, bands[name][1], f[-1])
        ax.set_title(f"{name} track")
    axes[0].legend(fontsize=8)
    return fig, axes


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
    end = ("equivalent", METHOD_STYLE["our system"], f"{n_bays} bays, our equivalent ends")
    return _pulse_panels(results, n_bays, reference_bays, end, "track: Hann pulse at the centre")


def _pulse_panels(results: Mapping[str, dict], n_bays: int, reference_bays: int, end: tuple, subtitle: str):
    """Reference, pinned ends and one more end model (``(key, style, label)``), per track and position."""
    n_rows = next(iter(results.values()))["reference"].u.shape[1]
    fig, axes = new_figure(n_rows, len(results), figsize=(10.5, 3.0 * n_rows), sharex=True, squeeze=False)
    lines = (("reference", METHOD_STYLE["exact"], f"{reference_bays}-bay reference"),
             ("pinned", dict(color="tab:red", lw=0.9, ls=":"), f"{n_bays} bays, pinned ends"), end)
    for col, (name, res) in enumerate(results.items()):
        t_ms = 1e3 * res["reference"].t
        for row in range(n_rows):
            ax = axes[row, col]
            for key, style, label in lines:
                ax.plot(t_ms, 1e9 * res[key].u[:, row], label=label, **style)
            ax.set_ylabel(f"w at {res['reference'].labels[row][2:-1]} (nm per N)")
        axes[0, col].set_title(f"{name} {subtitle}")
        axes[-1, col].set_xlabel("time (ms)")
    axes[0, 0].legend(fontsize=8)
    return fig, axes


# ------------------------------------------------------------------------------------------------
# The broadband boundary (book chapter "beyond the pinned-pinned frequency")
# ------------------------------------------------------------------------------------------------
#: Line styles of the boundary chapter: the house styles plus the broadband boundary and the
#: N = 5 systems (drawn like "our system") under the chapter's labels.
BOUNDARY_STYLE = {
    **METHOD_STYLE,
    "broadband boundary": dict(color="tab:purple", lw=1.2, ls="--"),
    "broadband boundary (viscous track)": dict(color="tab:purple", lw=1.0, ls=(0, (1, 1))),
    "N = 5 system": METHOD_STYLE["our system"] | dict(ls=":"),
}


def _shade_above(ax, f_from: float, f_to: float) -> None:
    """Shade the frequencies above a fit band (where the N = 5 systems were not fitted)."""
    ax.axvspan(f_from, f_to, color="0.92", zorder=-1)


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
    fig, axes = _panels(len(curves), figsize=(10.5, 3.6), sharey=True)
    for ax, (name, table) in zip(axes, curves.items()):
        f = table.index.to_numpy()
        for label, err in table.items():
            ax.loglog(f, err.to_numpy(), label=label, **BOUNDARY_STYLE.get(label, {}))
        _shade_above(ax, bands[name][1], f[-1])
        ax.set_title(f"{name} track")
        ax.set_xlabel("Frequency (Hz)")
    axes[0].set_ylabel(r"largest error of $\alpha_{11}, \alpha_{12}, \alpha_{22}$ (-)")
    axes[0].legend(fontsize=8)
    if title:
        fig.suptitle(title)
    return fig, axes


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
            magnitude_axes(ax, _magnitude_label(element), logx=True)
            ax.set_title(f"{name} track", fontsize=9)
    axes[0, 0].legend(fontsize=8)
    if title:
        fig.suptitle(title)
    return fig, axes


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
    fig, axes = _panels(2, figsize=(10.0, 3.4), sharex=True)
    for label, table in tables.items():
        for ax, column in zip(axes, ("median error (%)", "max error (%)")):
            ax.semilogy(table["n_poles"], table[column], marker="o", ms=3, label=label,
                        ls=":" if "viscous" in label else "-")
    for ax, what in zip(axes, ("median", "maximum")):
        ax.set_xlabel("number of poles (complex pairs count twice)")
        ax.set_ylabel(f"{what} error of alpha (%)")
    axes[0].legend(fontsize=8)
    if title:
        fig.suptitle(title)
    return fig, axes


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
    ax.set_ylabel(r"smallest eigenvalue of $D^{-1/2}\,\mathrm{Re}\,Z\,D^{-1/2}$ (-)")
    ax.legend(fontsize=8)
    if title:
        ax.set_title(title)
    return fig, ax


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
    fig, axes = _w1_panels(curves, bands, n_bays, BOUNDARY_STYLE, logx=True, height=3.8)
    if title:
        fig.suptitle(title)
    return fig, axes


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
    end = ("boundary", BOUNDARY_STYLE["broadband boundary"], f"{n_bays} bays, broadband-boundary ends")
    fig, axes = _pulse_panels(results, n_bays, reference_bays, end, "track (viscous damping)")
    if title:
        fig.suptitle(title)
    return fig, axes
