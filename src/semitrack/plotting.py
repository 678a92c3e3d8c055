"""The book's figures, in one house style. The library never selects a matplotlib backend.

Every ``*_figure`` function takes results computed by the package (arrays, tables, the results
of a study), draws one figure and returns ``(fig, axes)``; the notebooks call them and compute
nothing by hand. Methods and kinds of end keep one line style throughout (:data:`METHOD_STYLE`);
element names, labels and units come from :mod:`semitrack.base.conventions`. Legends sit outside the
panels (below them, or in a spare panel), where they cover no curve, and every panel with no panel
below it shows its x tick labels.
"""

from __future__ import annotations

from collections.abc import Mapping
from contextlib import contextmanager

import matplotlib as mpl
import matplotlib.pyplot as plt
import numpy as np
import pandas as pd

from .base.conventions import ALL_ELEMENTS, ELEMENT_TEX, ELEMENT_UNITS, ELEMENTS
from .base.paper_values import PAPER_BETA_MAX, PAPER_DX
from .equivalent.systems import PARAMETER_UNITS

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


def _phase_label(element: str) -> str:
    """Axis label ``arg alpha_ij (rad)`` of a receptance element, with the symbol of its magnitude."""
    return rf"$\arg\,{ELEMENT_TEX[element].strip('$')}$ (rad)"


#: Axis labels of the central responses (paper Eq. 14-18): the receptances' units come from the
#: conventions (w1 per force is alpha11's, psi2 per moment alpha22's).
CENTRAL_LABELS = {
    "w1": rf"$|\tilde w_1|$ ({ELEMENT_UNITS['alpha11']})",
    "psi2": rf"$|\tilde\psi_2|$ ({ELEMENT_UNITS['alpha22']})",
    "Q2": r"$|\tilde Q_2|$ (N/(N m))",
    "M1": r"$|\tilde M_1|$ (N m/N)",
    "det": r"$|\det\alpha^{-1}|$ (N$^2$)",
}


def _show_lowest_tick_labels(axes) -> None:
    """x tick labels on every panel with no panel shown below it in its column.

    A shared x-axis hides the tick labels of all but the bottom row, also above a panel that is
    hidden or turned off; the x label is kept only where the tick labels are.
    """
    for column in np.atleast_2d(axes).T:
        shown = [ax for ax in column if ax.get_visible() and ax.axison]
        for ax in shown[:-1]:
            ax.xaxis.set_tick_params(which="both", labelbottom=False)
            ax.set_xlabel("")
        if shown:
            shown[-1].xaxis.set_tick_params(which="both", labelbottom=True)
            shown[-1].xaxis.offsetText.set_visible(True)


def _legend_below(fig, ax, **kwargs):
    """One legend for the figure, below its panels (where it covers no data), from ``ax``'s lines.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure (with a constrained layout).
    ax : matplotlib.axes.Axes
        The panel whose labelled artists make the legend.
    **kwargs
        Passed to :meth:`matplotlib.figure.Figure.legend`.

    Returns
    -------
    matplotlib.legend.Legend
    """
    handles, labels = ax.get_legend_handles_labels()
    kwargs.setdefault("ncols", min(len(labels), 4))
    return fig.legend(handles, labels, loc="outside lower center", **kwargs)


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
        magnitude_axes(ax, _magnitude_label(name), logx=logx)
        ax.set_title(ELEMENT_TEX[name])
    _legend_below(fig, axes[0])
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
    _legend_below(fig, axes[0, 0])
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
                      label=rf"$\beta_{{max}}$ = {factor:g} x {PAPER_BETA_MAX:.3g} rad/m")
        ax.axvline(PAPER_DX, color="0.5", ls=":", lw=0.8, label=f"the paper's dx = {PAPER_DX:g} m")
        ax.set_title(f"{fr:g} Hz")
        ax.set_xlabel("dx (m)")
    axes[0].set_ylabel(r"max relative error of $\alpha_{ij}$ (-)")
    _legend_below(fig, axes[-1], fontsize=8)
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
    for ax, (attr, label) in zip(axes.flat, CENTRAL_LABELS.items()):
        for name, r in responses.items():
            plot_magnitude(ax, f, getattr(r, attr), name, **METHOD_STYLE.get(name, {}))
        magnitude_axes(ax, label)
    spare = axes.flat[-1]  # the sixth panel holds the legend, clear of every curve
    spare.axis("off")
    spare.legend(*axes.flat[0].get_legend_handles_labels(), loc="center")
    _show_lowest_tick_labels(axes)
    if title:
        fig.suptitle(title)
    return fig, axes


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
        ax.set_ylabel(_phase_label(name))
        ax.set_xlabel("Frequency (Hz)")
    _legend_below(fig, axes[0])
    if title:
        fig.suptitle(title)
    return fig, axes


#: Bars lighter than this fraction of the heaviest bar carry no mass worth drawing: they are drawn
#: as a dashed outline and labelled "massless" (fits drive unneeded masses to ~1e-7 kg).
MASSLESS_FRACTION = 1e-6

#: Symbols of the equivalent systems' parameters in the schematic's labels (paper Fig. 7 / 12).
PARAMETER_TEX = {"m": "$m$", "k": "$k$", "c_l": r"$c_\mathrm{l}$", "c_r": r"$c_\mathrm{r}$",
                 "k_phi": r"$k_\varphi$", "c_phi": r"$c_\varphi$", "mu": r"$\mu$", "s": "$s$",
                 "d_l": r"$d_\mathrm{l}$", "d_r": r"$d_\mathrm{r}$"}

# Heights in the schematic (data units): bars at 0, ground at -1, the ballasted layout's support
# masses between _MASS_TOP and _MASS_BOTTOM.
_GROUND, _MASS_TOP, _MASS_BOTTOM = -1.0, -0.42, -0.58
_LABEL_BOX = dict(boxstyle="round,pad=0.15", fc="white", ec="none", alpha=0.85)
_LABEL_FONTSIZE = 7.0
_SUPPORT_PARAMETERS = ("k", "c_l", "c_r", "mu", "s", "d_l", "d_r")


def _compact(value: float) -> str:
    """Three significant digits with a short exponent: ``5.28e6``, ``1.85e-3``, ``589``."""
    mantissa, _, exponent = f"{value:.3g}".partition("e")
    return f"{mantissa}e{int(exponent)}" if exponent else mantissa


def _quantity(p: Mapping[str, np.ndarray], name: str, j: int) -> str:
    """``symbol = value unit`` of parameter ``name`` of bar (or hinge) ``j``, or "" when it is zero."""
    value = p[name][j]
    return f"{PARAMETER_TEX[name]} = {_compact(value)} {PARAMETER_UNITS[name]}" if value > 0 else ""


def _lines(*lines: str) -> str:
    return "\n".join(line for line in lines if line)


def _spring(ax, x0: float, y_top: float, y_bottom: float, half_width: float) -> None:
    """A vertical zig-zag spring."""
    ys = np.linspace(y_top, y_bottom, 14)
    xs = x0 + half_width * np.array([0] + [(-1) ** i for i in range(12)] + [0])
    ax.plot(xs, ys, color="0.3", lw=0.8, gid="spring")


def _dashpot(ax, x0: float, y_top: float, y_bottom: float, half_width: float) -> None:
    """A vertical dashpot: a rod and piston in an open cylinder on a rod."""
    h, mid, hw = y_top - y_bottom, 0.5 * (y_top + y_bottom), half_width
    piston, cup_top, cup_bottom = mid + 0.05 * h, mid + 0.2 * h, mid - 0.15 * h
    xs = [x0, x0, np.nan, x0 - 0.7 * hw, x0 + 0.7 * hw, np.nan, x0 - hw, x0 - hw, x0 + hw, x0 + hw, np.nan, x0, x0]
    ys = [y_top, piston, np.nan, piston, piston, np.nan, cup_top, cup_bottom, cup_bottom, cup_top, np.nan,
          cup_bottom, y_bottom]
    ax.plot(xs, ys, color="0.3", lw=0.8, gid="damper")


def _support(ax, end: float, inward: int, slot: float, heights: tuple[float, float], k: float, c: float) -> None:
    """Spring ``k`` (if > 0) and dashpot ``c`` (if > 0) in parallel, beside a bar end.

    ``inward`` is +1 at a bar's left end and -1 at its right end; ``slot`` (m) is the room taken
    beside the end, so that the supports of two bars meeting at a hinge stay apart.
    """
    if k > 0:
        _spring(ax, end + inward * 0.25 * slot, *heights, 0.15 * slot)
    if c > 0:
        _dashpot(ax, end + inward * 0.7 * slot, *heights, 0.15 * slot)


def _bar(ax, x0: float, x1: float, mass: float, m_max: float, j: int) -> bool:
    """Bar ``j``, thicker the heavier; a massless one as a dashed outline. Returns whether it is massless."""
    massless = mass <= MASSLESS_FRACTION * m_max
    if massless:
        ax.add_patch(mpl.patches.Rectangle((x0, -0.03), x1 - x0, 0.06, fill=False, ls="--", ec="tab:blue",
                                           lw=0.9, gid=f"bar {j + 1}"))
    else:
        ax.plot([x0, x1], [0, 0], color="tab:blue", lw=1.5 + 6.5 * mass / m_max, solid_capstyle="butt",
                gid=f"bar {j + 1}")
    return massless


def _draw_bar_and_supports(ax, p: Mapping[str, np.ndarray], x: np.ndarray, j: int) -> bool:
    """Bar ``j`` with the spring-damper pairs at its two ends (and, ballasted, the support masses)."""
    massless = _bar(ax, x[j], x[j + 1], p["m"][j], max(p["m"].max(), 1e-300), j)
    slot = min(0.4 * p["L"][j], 0.06 * x[-1])
    ballasted = "mu" in p
    for end, inward, c, d in ((x[j], 1, "c_l", "d_l"), (x[j + 1], -1, "c_r", "d_r")):
        if not ballasted:
            _support(ax, end, inward, slot, (0.0, _GROUND), p["k"][j], p[c][j])
            continue
        _support(ax, end, inward, slot, (0.0, _MASS_TOP), p["k"][j], p[c][j])
        left = end + 0.05 * slot if inward > 0 else end - 0.95 * slot
        ax.add_patch(mpl.patches.Rectangle((left, _MASS_BOTTOM), 0.9 * slot, _MASS_TOP - _MASS_BOTTOM,
                                           color="tab:orange", gid="support mass"))
        _support(ax, end, inward, slot, (_MASS_BOTTOM, _GROUND), p["s"][j], p[d][j])
    return massless


def _isotonic(values: np.ndarray) -> np.ndarray:
    """Least-squares non-decreasing fit of ``values`` (pool adjacent violators)."""
    means: list[float] = []
    counts: list[int] = []
    for v in values:
        means.append(float(v))
        counts.append(1)
        while len(means) > 1 and means[-2] > means[-1]:
            v2, c2 = means.pop(), counts.pop()
            means[-1] = (means[-1] * counts[-1] + v2 * c2) / (counts[-1] + c2)
            counts[-1] += c2
    return np.repeat(means, counts)


def _spread(anchors, widths, lo: float, hi: float) -> np.ndarray:
    """Centres of labels in a row, as near their anchors as possible, none overlapping, all in [lo, hi].

    Packed side by side in the anchors' order, the labels' common start is the least-squares
    non-decreasing fit of where each one wants it; clipping keeps them inside the bounds (which
    needs ``sum(widths) <= hi - lo``).

    Parameters
    ----------
    anchors, widths : array_like
        Preferred centres and widths of the labels (any one unit, e.g. pixels).
    lo, hi : float
        Bounds of the row (same unit).

    Returns
    -------
    ndarray
        The centres, in the order of ``anchors``.
    """
    anchors, widths = np.asarray(anchors, dtype=float), np.asarray(widths, dtype=float)
    order = np.argsort(anchors, kind="stable")
    a, w = anchors[order], widths[order]
    before = np.concatenate([[0.0], np.cumsum(w)[:-1]])  # width packed before each label
    start = np.clip(_isotonic(a - w / 2 - before), lo, hi - w.sum())
    centres = np.empty_like(a)
    centres[order] = start + before + w / 2
    return centres


def _label_row(ax, renderer, items, y: float, va: str = "center", zorder: float = 4.0) -> list:
    """Labels at height ``y``, each as near its anchor as the others allow, none overlapping.

    ``items`` are ``((x, y) anchor, text, arrowstyle)``; a label with an arrowstyle, or moved off
    its anchor, gets a leader line to it. The font shrinks when the row would not fit the axes.
    """
    items = [item for item in items if item[1]]
    if not items:
        return []
    box = ax.get_window_extent(renderer)
    fontsize, gap = _LABEL_FONTSIZE, 6.0 * ax.figure.dpi / 72
    widths = _text_sizes(ax, renderer, [text for _, text, _ in items], fontsize)[0] + gap
    if widths.sum() > box.width:
        fontsize *= box.width / widths.sum()
        widths = _text_sizes(ax, renderer, [text for _, text, _ in items], fontsize)[0] + gap
    y_px = ax.transData.transform((0.0, y))[1]
    anchors = ax.transData.transform([anchor for anchor, _, _ in items])[:, 0]
    centres = _spread(anchors, widths, box.x0, box.x1)
    xs = ax.transData.inverted().transform(np.column_stack([centres, np.full_like(centres, y_px)]))[:, 0]
    texts = []
    for (anchor, text, style), x_text, a, c, w in zip(items, xs, anchors, centres, widths):
        leader = style or ("-" if abs(c - a) > 0.3 * w else None)
        arrow = dict(arrowstyle=leader, lw=0.5, color="0.45", shrinkA=0, shrinkB=1) if leader else None
        texts.append(ax.annotate(text, anchor, xytext=(x_text, y), ha="center", va=va, fontsize=fontsize,
                                 color="0.2", bbox=_LABEL_BOX, arrowprops=arrow, zorder=zorder))
    return texts


def _text_sizes(ax, renderer, texts, fontsize: float) -> np.ndarray:
    """Widths and heights (pixels) of texts drawn at ``fontsize``, shape (2, n)."""
    sizes = []
    for text in texts:
        artist = ax.text(0.0, 0.0, text, fontsize=fontsize)
        extent = artist.get_window_extent(renderer)
        sizes.append((extent.width, extent.height))
        artist.remove()
    return np.array(sizes).T


def _room_below_ground(ax, depth_px: float) -> None:
    """Lower the axes' bottom so that ``depth_px`` pixels lie between the ground and the bottom."""
    top = ax.get_ylim()[1]
    height = ax.get_window_extent().height
    # (ground - bottom) / (top - bottom) * height = depth, solved for bottom
    ax.set_ylim((_GROUND * height - top * depth_px) / (height - depth_px), top)


def _schematic_labels(ax, p: Mapping[str, np.ndarray], x: np.ndarray, massless: list[bool]) -> None:
    """The rows of labels: load and hinges on top, the bars above them, the supports below the ground.

    The supports' labels stay out of the drawing, so that those of short bars hide no spring.
    """
    ax.figure.draw_without_rendering()  # the layout fixes the axes' size, in which the labels are placed
    renderer = ax.figure.canvas.get_renderer()
    centres, n = 0.5 * (x[:-1] + x[1:]), len(x) - 1
    supports = [_lines(*(_quantity(p, name, j) for name in _SUPPORT_PARAMETERS if name in p)) for j in range(n)]
    gap = 0.08  # between the ground and the supports' labels (data units)
    _room_below_ground(ax, _text_sizes(ax, renderer, supports, _LABEL_FONTSIZE)[1].max() + 12.0 * ax.figure.dpi / 72)
    _label_row(ax, renderer, [((c, _GROUND), text, None) for c, text in zip(centres, supports)], _GROUND - gap,
               va="top")
    hinges = [((x[j + 1], 0.0), _lines(_quantity(p, "k_phi", j), _quantity(p, "c_phi", j)), "-")
              for j in range(n - 1)]
    _label_row(ax, renderer, [((0.0, 0.0), "load Q, M", "->"), *hinges], 0.8, zorder=3.0)
    bars = [_lines(f"bar {j + 1}" + (" (massless)" if massless[j] else ""),
                   f"$m$ = {_compact(p['m'][j])} {PARAMETER_UNITS['m']}") for j in range(n)]
    _label_row(ax, renderer, [((c, 0.04), text, None) for c, text in zip(centres, bars)], 0.32)


def equivalent_schematic(system, ax=None, title: str = ""):
    """Draw an equivalent system to scale in x (bar lengths in m), as the paper's Fig. 7 / 12.

    Bars are drawn with a thickness that grows with their mass (a bar lighter than
    :data:`MASSLESS_FRACTION` of the heaviest as a dashed outline, labelled massless); each bar end
    rests on a spring and, where its damping coefficient is positive, a dashpot in parallel (on a
    support mass, drawn as a box, in the ballasted layout). Labels give every non-zero parameter
    with its unit (:data:`semitrack.equivalent.systems.PARAMETER_UNITS`): the hinges' rotational
    springs and dampers on top, then the bars, then their supports; labels of short bars move
    aside, with a leader line, so that none overlaps another.

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
    p = system.parameters()
    if ax is None:
        _, ax = new_figure(figsize=(10.0, 5.0 if "mu" in p else 4.0))
    x = np.concatenate([[0.0], np.cumsum(p["L"])])
    massless = [_draw_bar_and_supports(ax, p, x, j) for j in range(system.n_bars)]
    ax.plot(x[1:-1], np.zeros(system.n_bars - 1), "o", mfc="white", mec="k", ms=5, zorder=5, gid="hinge")
    ax.axhline(_GROUND, color="0.2", lw=1.2)
    ax.set_xlim(-0.04 * x[-1], 1.1 * x[-1])
    ax.set_ylim(_GROUND - 0.1, 1.0)  # the bottom moves down to make room for the supports' labels
    ax.set_yticks([])
    ax.set_xlabel("position along the equivalent system (m)")
    ax.grid(False)
    ax.spines["left"].set_visible(False)
    ax.set_title(title or f"{system.layout} equivalent system, N = {system.n_bars}")
    _schematic_labels(ax, p, x, massless)
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
    _legend_below(fig, axes[0])
    return fig, axes


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
    _legend_below(fig, axes[0, 0], ncols=3)
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
        magnitude_axes(ax, CENTRAL_LABELS["w1"], logx=logx)
        _shade_above(ax, bands[name][1], f[-1])
        ax.set_title(f"{name} track")
    _legend_below(fig, axes[0], fontsize=8)
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
    _legend_below(fig, axes[0, 0], fontsize=8)
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
    """Shade the frequencies above a fit band (where the N = 5 systems were not fitted), with a legend entry."""
    ax.axvspan(f_from, f_to, color="0.92", zorder=-1, label="above the N = 5 fit band")


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
    axes[0].set_ylabel(f"largest error of {', '.join(ELEMENT_TEX[e] for e in ELEMENTS)} (-)")
    _legend_below(fig, axes[0], fontsize=8)
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
            ax.set_title(f"{name} track: {ELEMENT_TEX[element]}", fontsize=9)
    _show_lowest_tick_labels(axes)
    _legend_below(fig, axes[0, 0], fontsize=8)
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
        ax.set_ylabel(rf"{what} error of $\alpha$ (%)")
    _legend_below(fig, axes[0], fontsize=8)
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
    ax.set_ylabel("smallest eigenvalue of\n" r"$D^{-1/2}\,\mathrm{Re}\,Z\,D^{-1/2}$ (-)")
    _legend_below(fig, ax, fontsize=8)
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
