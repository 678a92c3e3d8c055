"""The equivalent multi-rigid-body systems drawn to scale (the paper's Figs. 7 and 12)."""

from __future__ import annotations

from collections.abc import Mapping

import matplotlib as mpl
import numpy as np

from ..equivalent.systems import PARAMETER_UNITS
from .style import house_figure, new_figure

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
_LABEL_FONTSIZE = 9.5
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


@house_figure
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
        _, ax = new_figure(figsize=(9.0, 5.6 if "mu" in p else 4.6))
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

