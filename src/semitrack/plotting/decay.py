"""The track decay rate by band (EN 15461), beside the ISO 3095 limit."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from .style import house_figure, legend_below, new_figure

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
    for (label, tdr), style in zip(rates.items(), _STYLES * 4):
        ax.plot(tdr.centres, tdr.decay_rate, ls="-", lw=1.2, ms=4, label=f"{label}: EN 15461", color=style["color"])
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
    ax.set_xlabel("One-third-octave band (Hz)")
    ax.set_ylabel("Track decay rate (dB/m)")
    ax.set_title(title or "Track decay rate (open markers: bands the standard's checks reject)")
    legend_below(fig, ax, fontsize=8)
    return fig, ax
