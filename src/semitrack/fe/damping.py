"""The viscous damping of the FE tracks in the time domain, and its reference frequencies.

Loss factors have no exact viscous counterpart. Each spring family gets the viscous damping
that equals its loss factor at its own reference frequency,
``C = eta_rail K_rail / omega_rail + eta_pad K_pad / omega_pad + eta_ballast K_ballast /
omega_ballast`` (stiffness-proportional for the rail, a dashpot ``eta kv / omega_pad`` per pad,
``eta_ballast kb / omega_ballast`` per ballast spring). A viscous damper can match the
hysteretic one at one frequency only; it is chosen where that family's damping controls the
response (:meth:`semitrack.Track.reference_frequencies`): the pads at the rail-on-pad resonance
``sqrt(kv / (rho A d)) / 2 pi`` (slab 187 Hz, ballasted 495 Hz), the ballast at the
sleeper-on-ballast resonance ``sqrt(kb / (m_s + rho A d)) / 2 pi`` (117 Hz, the paper's f_n1),
the rail at the Euler estimate of the pinned-pinned frequency ``(pi / d)^2 sqrt(EI / rho A) /
2 pi`` (1.2-1.4 kHz), where only the rail damps; a flexible slab's bending at the free slab's
first bending mode on its layer and its layer at the slab's bounce on it (the floating slab of
the examples: 38 Hz and 25 Hz). On the paper's tracks (long FE tracks,
3-1500 Hz) the viscous w1 then deviates from the hysteretic one by a median 3 % (slab) and 7 %
(ballasted) and 7 % / 35 % at most below 750 Hz; a single 250 Hz for all families gives 3 % /
17 % median and 24 % / 66 % max. Below the reference frequency a viscous damper damps less,
above it more. The equivalent systems' dampers are viscous by construction and enter as they
are, although the paper fitted them to the hysteretic track.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from ..base.checks import check_positive
from ..base.errors import InputError
from ..base.notices import HystereticDampingWarning, warn_user
from ..model.tracks import Track, require_track

__all__ = ["reference_frequencies", "warn_hysteretic"]

#: The families whose reference frequency a warning names, with their words.
_FAMILY_WORDS = {"rail": "rail", "pad": "pads", "ballast": "ballast", "slab": "slab", "layer": "slab's layer"}


def reference_frequencies(track: Track, f_ref: float | Mapping[str, float] | None = None) -> dict[str, float]:
    """The reference frequency (Hz) of each spring family, defaults overridden by ``f_ref``.

    Parameters
    ----------
    track : Track
        The track.
    f_ref : None, float or dict
        ``None``: the track's own (:meth:`semitrack.Track.reference_frequencies`); a float: the same for all
        families; a dict: overrides (Hz) for some of the keys "rail", "pad", "ballast", "slab", "layer".

    Returns
    -------
    dict
        ``{"rail": ..., "pad": ..., "ballast": ..., "slab": ..., "layer": ...}`` (Hz), all finite:
        "ballast" is 1 Hz on a slab track, "slab" and "layer" without a flexible slab, where no
        spring uses them.

    Examples
    --------
    >>> from semitrack.model.tracks import slab_track
    >>> fr = reference_frequencies(slab_track(), {"rail": 1000.0})
    >>> fr["rail"], fr["ballast"]
    (1000.0, 1.0)
    """
    fr = require_track(track).reference_frequencies()
    for family, value in fr.items():
        if not np.isfinite(value):
            fr[family] = 1.0  # unused: no such springs (no ballast, no flexible slab)
    if f_ref is None:
        return fr
    if isinstance(f_ref, Mapping):
        unknown = sorted(set(f_ref) - set(fr))
        if unknown:
            raise InputError(f"f_ref keys must be among {sorted(fr)}, got {unknown}")
        fr.update({k: check_positive(f"f_ref[{k!r}]", v) for k, v in f_ref.items()})
        return fr
    v = check_positive("f_ref", f_ref)
    return dict.fromkeys(fr, v)


def warn_hysteretic(tracks, f_ref=None, end_error: float | None = None) -> None:
    """Warn that hysteretic tracks run in the time domain on viscous equivalents (once per user line).

    Parameters
    ----------
    tracks : sequence of Track
        The model's tracks; only the hysteretic ones are named (``damping="viscous"`` runs as it
        is computed in the frequency domain).
    f_ref : None, float or dict
        The reference frequencies asked for (:func:`reference_frequencies`).
    end_error : float, optional
        The largest relative error of a broadband end fitted to the hysteretic track, if the
        model has one: named beside a viscous track's (about 0.3 %).
    """
    parts = []
    for track in tracks:
        eta = track.loss_factors()
        if track.damping != "hysteretic" or not any(eta.values()):
            continue  # a viscous track, or one without damping, runs as the frequency domain computes it
        fr, own = reference_frequencies(track, f_ref), track.reference_frequencies()
        at = ", ".join(f"{_FAMILY_WORDS[k]} {fr[k]:.0f} Hz" for k in _FAMILY_WORDS
                       if eta[k] > 0 and np.isfinite(own[k]))
        parts.append(f"{track.name!r} ({at})")
    if not parts:
        return
    end = (f"; its broadband end follows the hysteretic track to {100 * end_error:.1f} % at worst (a viscous "
           "track's end, about 0.3 %)" if end_error is not None else "")
    warn_user(f"the time domain runs the hysteretic (loss-factor) track{'s' * (len(parts) > 1)} "
              f"{' and '.join(parts)} on viscous dampers equal to each loss factor at those frequencies: more "
              "damping above them, less below (on the paper's tracks w1 moves a median 3-7 %, up to 35 %, below "
              f"750 Hz){end}. Give damping='viscous' to run the track the frequency domain computes too",
              HystereticDampingWarning)
