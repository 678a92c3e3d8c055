"""The track decay rate by band (EN 15461) beside the ISO 3095 limit; a local change beside the perfect track."""

from __future__ import annotations

import itertools
from collections.abc import Mapping

import numpy as np
from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter

from .style import house_figure, legend_below, new_figure, panels

#: Line styles of the decay rates of several tracks, in turn.
_STYLES = (dict(color="k", marker="o"), dict(color="tab:blue", marker="s"), dict(color="tab:red", marker="^"),
           dict(color="tab:green", marker="v"))


@house_figure
def decay_rate_figure(rates: Mapping[str, object], limit: Mapping[float, float] | None = None,
                      waves: bool = True, title: str = ""):
    """Decay rates by one-third-octave band (dB/m, log scale), a line per track.

    Bands the standard finds unfit (an unsuitable rate or too little far-point drop) are drawn
    as open markers; the least attenuated Bloch wave dotted beside each; the limit as a step.

    Parameters
    ----------
    rates : mapping of str to TrackDecayRate
        Label to :func:`semitrack.track_decay_rate`'s result.
    limit : mapping of float to float, optional
        A lower limit, band (Hz) to rate (dB/m), e.g. :data:`semitrack.ISO3095_TDR_LIMIT`.
    waves : bool
        Draw the Bloch waves' attenuation.
    title : str
        Axes title.

    Returns
    -------
    fig, ax
    """
    fig, ax = new_figure(figsize=(8.0, 4.2))
    for (label, tdr), style in zip(rates.items(), itertools.cycle(_STYLES)):  # no track left out
        ax.plot(tdr.centres, tdr.decay_rate, ls="-", lw=1.2, label=f"{label}: EN 15461", color=style["color"])
        ok = tdr.valid
        ax.plot(tdr.centres[ok], tdr.decay_rate[ok], ls="", ms=5, **style)
        ax.plot(tdr.centres[~ok], tdr.decay_rate[~ok], ls="", ms=5, mfc="white", **style)
        if waves and np.any(np.isfinite(tdr.wave_attenuation)):
            ax.plot(tdr.centres, tdr.wave_attenuation, ls=":", lw=1.0, color=style["color"],
                    label=f"{label}: least attenuated wave")
    if limit:
        bands = np.array(sorted(limit))
        ax.step(bands, [limit[b] for b in bands], where="mid", color="0.4", lw=1.4, ls="--", label="ISO 3095 limit")
    ax.set_xscale("log")
    ax.set_yscale("log")
    # 1-2-5 in every decade, as plain numbers (not only the powers of ten), on both axes
    for axis in (ax.xaxis, ax.yaxis):
        axis.set_major_locator(LogLocator(base=10.0, subs=(1.0, 2.0, 5.0)))
        axis.set_major_formatter(FuncFormatter(lambda value, _: f"{value:g}"))
        axis.set_minor_formatter(NullFormatter())
    ax.set_xlabel("One-third-octave band (Hz)")
    ax.set_ylabel("Track decay rate (dB/m)")
    ax.set_title(title or "Track decay rate (open markers: bands the standard's checks reject)")
    legend_below(fig, ax)
    return fig, ax


@house_figure
def local_change_figure(f, curves: Mapping[str, np.ndarray], positions: tuple[str, ...], reference: str,
                        title: str = ""):
    """|w/F| at each response position (a panel each), a line per case, the reference in black.

    Parameters
    ----------
    f : array_like
        Frequencies (Hz).
    curves : mapping of str to ndarray
        Case to ``(n_f, n_positions)`` w per F (m/N), from
        :func:`semitrack.paper.decay_study.local_change_curves`.
    positions : tuple of str
        A title for each position's panel.
    reference : str
        The case drawn in black (the perfect track).
    title : str
        Figure title.

    Returns
    -------
    fig, axes
    """
    fig, axes = panels(len(positions), figsize=(5.2 * len(positions), 3.8), sharey=True)
    colours = itertools.cycle(("tab:red", "tab:blue", "tab:green", "tab:purple", "tab:orange"))
    styles = {case: (dict(color="k", lw=1.4) if case == reference else dict(color=next(colours), lw=1.0, ls="--"))
              for case in curves}
    for j, (ax, label) in enumerate(zip(axes, positions)):
        for case, h in curves.items():
            ax.loglog(f, np.abs(h[:, j]), label=case, **styles[case])
        ax.set_title(label)
        ax.set_xlabel("Frequency (Hz)")
    axes[0].set_ylabel("|w / F| (m/N)")
    legend_below(fig, axes[0])
    if title:
        fig.suptitle(title)
    return fig, axes
