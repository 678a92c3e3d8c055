"""The house style of the book's figures: line styles, rcParams, figures, axes and legends.

Figures are :class:`matplotlib.figure.Figure` objects made by :func:`new_figure`, attached to no
pyplot backend, and each figure function runs inside :func:`house_style` (:func:`house_figure`),
so that nothing here changes the global rcParams and the command line draws the same figures
without selecting a backend. Methods and kinds of end keep one line style throughout
(:data:`METHOD_STYLE`); element names, labels and units come from
:mod:`semitrack.base.conventions`. Legends sit outside the panels (below them, or in a spare
panel), where they cover no curve, and every panel with no panel below it shows its x tick labels.
"""

from __future__ import annotations

import functools
import textwrap
from contextlib import contextmanager
from pathlib import Path

import matplotlib as mpl
import matplotlib.text  # noqa: F401 - mpl.text, for the figures' text artists
import numpy as np
from matplotlib import font_manager
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from ..base.conventions import ELEMENT_TEX, ELEMENT_UNITS, EXACT_LABEL
from ..fe.ends import FREE, PINNED

#: Line styles per method, used in every figure so that a method always looks the same.
METHOD_STYLE = {
    EXACT_LABEL: dict(color="k", lw=1.4, ls="-"),
    "transfer": dict(color="k", lw=1.4, ls="-"),
    "wavenumber": dict(color="tab:orange", lw=1.1, ls="--"),
    "paper system": dict(color="tab:red", lw=1.1, ls=":"),
    "our system": dict(color="tab:blue", lw=1.1, ls="--"),
    PINNED.label: dict(color="0.45", lw=1.1, ls="-."),
    FREE.label: dict(color="tab:brown", lw=1.0, ls="-."),
    "exact end stiffness": dict(color="tab:green", lw=1.1, ls="-"),
}
#: Colours of the receptance elements, as in the paper's Fig. 8 (black, green, red).
ELEMENT_COLOR = {"alpha11": "k", "alpha12": "tab:green", "alpha22": "tab:red"}

#: The house rcParams. The book shows a figure at the theme's text width (about 690 px on a
#: 1280 px screen), so a 10.5 in figure drawn at 110 dpi is scaled to about 0.6: its text is set
#: large enough (12 pt, legends 11 pt) to read at that scale, about 11 px on the screen.
RC = {
    "figure.figsize": (7.0, 4.0), "figure.dpi": 110, "axes.grid": True, "grid.alpha": 0.3,
    "axes.spines.top": False, "axes.spines.right": False, "legend.frameon": False,
    "font.size": 12, "axes.titlesize": 12, "legend.fontsize": 11, "figure.titlesize": 13,
}


#: The book's text column on a 1280-px screen (px), where a figure is shown scaled to its width,
#: and the least height of its text there (px): :func:`legible_text` keeps every figure above it.
PAGE_WIDTH_PX, MIN_TEXT_PX = 690.0, 10.0


def _register_shipped_fonts() -> None:
    """Register matplotlib's own fonts (DejaVu, STIX, Computer Modern) if its font cache lacks them.

    A cache written by another matplotlib of the same version (a virtual environment since
    removed) lists fonts that are gone and none of this one's, and mathematics then logs a
    "findfont ... not found" line per glyph family into every notebook's output.
    """
    folder = Path(mpl.get_data_path()) / "fonts" / "ttf"
    known = {Path(font.fname).name for font in font_manager.fontManager.ttflist}
    for path in sorted(folder.glob("*.ttf")):
        if path.name not in known:
            font_manager.fontManager.addfont(str(path))


_register_shipped_fonts()


def legible_text(fig) -> None:
    """Raise a figure's text to at least :data:`MIN_TEXT_PX` when it is shown at the page's width.

    A figure ``W`` inches wide at ``dpi`` wider than :data:`PAGE_WIDTH_PX` is scaled down to it,
    so a font of ``s`` points shows ``s / 72 * PAGE_WIDTH_PX / W`` px high: a wide multi-panel
    figure (13.8 in) would show its 12-pt text at 8 px. A narrower one is shown at its own size,
    ``s / 72 * dpi`` px. Text below the floor (ticks, labels, legends, titles) is raised to it.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure, changed in place.
    """
    floor = MIN_TEXT_PX * 72.0 * max(fig.get_figwidth() / PAGE_WIDTH_PX, 1.0 / fig.dpi)  # pt: scaled down, or not
    for ax in fig.axes:
        for name, axis in (("x", ax.xaxis), ("y", ax.yaxis)):
            labels = axis.get_ticklabels(which="both")  # the sizes the axis draws at (set by the figure or rc)
            sizes = [t.get_fontsize() for t in labels] or [font_manager.FontProperties(
                size=mpl.rcParams[f"{name}tick.labelsize"]).get_size_in_points()]
            if min(sizes) < floor:  # raised only: a figure's larger tick labels stay as they are
                ax.tick_params(axis=name, which="both", labelsize=floor)
    for text in fig.findobj(mpl.text.Text):
        if text.get_text() and text.get_fontsize() < floor:
            text.set_fontsize(floor)


@contextmanager
def house_style():
    """Context manager applying the house rcParams (:data:`RC`) inside a ``with`` block."""
    with mpl.rc_context(RC):
        yield


def house_figure(draw):
    """Decorator: ``draw`` runs inside :func:`house_style`, so its figure has the house style and
    the global rcParams are left as they were."""

    @functools.wraps(draw)
    def drawn(*args, **kwargs):
        with house_style():
            result = draw(*args, **kwargs)
            fig = result[0] if isinstance(result, tuple) else getattr(result, "figure", None)
            if isinstance(fig, Figure):
                legible_text(fig)
                wrap_titles(fig)
            return result

    return drawn


def _wrapped(text_artist, available_px: float, renderer) -> None:
    """Break the text of ``text_artist`` into lines no wider than ``available_px`` (at spaces)."""
    text = text_artist.get_text()
    if not text or "\n" in text or "$" in text:
        return
    width = text_artist.get_window_extent(renderer).width
    if width <= available_px:
        return
    chars = max(20, int(len(text) * available_px / width))
    text_artist.set_text(textwrap.fill(text, chars, break_long_words=False))


def wrap_titles(fig) -> None:
    """Break a figure's title and its panels' titles into lines that fit the figure and the panels.

    A constrained layout makes room for a title but does not break it: a long title at the
    house font sizes would run past the figure's edge, where the book crops it. Titles with
    line breaks or mathematics are left as they are.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure, with a canvas that renders (as :func:`new_figure` gives); its titles are
        changed in place.
    """
    renderer = fig.canvas.get_renderer()
    fig_px = fig.get_figwidth() * fig.dpi
    if fig._suptitle is not None:
        _wrapped(fig._suptitle, 0.97 * fig_px, renderer)
    for ax in fig.axes:
        if ax.get_visible() and ax.axison:
            _wrapped(ax.title, 1.1 * ax.get_position().width * fig_px, renderer)


def apply_house_style() -> None:
    """Apply the house rcParams globally: a notebook's own choice, for the panels it draws itself."""
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
                        ha="right", va="top", fontsize=10, color="0.35")


#: Keywords of :func:`new_figure` that go to :meth:`matplotlib.figure.Figure.subplots`.
_SUBPLOTS_KEYWORDS = ("sharex", "sharey", "squeeze", "width_ratios", "height_ratios", "subplot_kw", "gridspec_kw")


def new_figure(nrows: int = 1, ncols: int = 1, **kwargs):
    """A :class:`matplotlib.figure.Figure` with a grid of panels, the house style and a constrained layout.

    The figure belongs to no pyplot backend: it is drawn and saved the same way in a notebook
    (display it), a script or the command line, which selects no backend.

    Parameters
    ----------
    nrows, ncols : int
        Grid of panels.
    **kwargs
        ``figsize``, ``dpi`` and the other :class:`~matplotlib.figure.Figure` arguments, and
        ``sharex``, ``sharey``, ``squeeze``... for :meth:`~matplotlib.figure.Figure.subplots`.

    Returns
    -------
    fig, axes

    Examples
    --------
    >>> fig, axes = new_figure(1, 2)
    >>> type(fig).__name__, axes.shape
    ('Figure', (2,))
    """
    kwargs.setdefault("layout", "constrained")
    subplots = {key: kwargs.pop(key) for key in _SUBPLOTS_KEYWORDS if key in kwargs}
    with house_style():
        fig = Figure(**kwargs)
        FigureCanvasAgg(fig)  # a canvas that renders (text sizes, savefig) without selecting a backend
        return fig, fig.subplots(nrows, ncols, **subplots)


def panels(n: int, **kwargs):
    """A row of ``n`` panels from :func:`new_figure`, the axes always an array."""
    fig, axes = new_figure(1, n, **kwargs)
    return fig, np.atleast_1d(axes)


def magnitude_label(element: str) -> str:
    """Axis label ``|alpha_ij| (unit)`` of a receptance element, from the package's conventions."""
    return f"$|{ELEMENT_TEX[element].strip('$')}|$ ({ELEMENT_UNITS[element]})"


def phase_label(element: str) -> str:
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


def show_lowest_tick_labels(axes) -> None:
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


def legend_below(fig, ax, **kwargs):
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


def shade_above(ax, f_from: float, f_to: float) -> None:
    """Shade the frequencies above a fit band (where the N = 5 systems were not fitted), with a legend entry."""
    ax.axvspan(f_from, f_to, color="0.92", zorder=-1, label="above the N = 5 fit band")
