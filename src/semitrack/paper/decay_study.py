"""The chapter "the track away from the load": decay rates, the length a pinned model needs, local changes.

Each function runs one of the chapter's studies and returns tables and curves for its figures
(:mod:`semitrack.plotting.decay`); the chapter asserts the numbers its prose quotes.

The paper (its Sec. 1) argues for long truncated models from the decay rate: with a rate of
about 0.5 dB/m (a value it cites for slab tracks above some hundreds of hertz) 20 dB of decay
takes 40 m, and a model's ends must be that far from the nearest wheelset. :func:`pinned_length_table` rebuilds
the argument from the decay rates computed here: for a 20 dB decay between the load and an
end, ``20 / DR`` metres of track on each side.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike

from ..base.bands import HALF_BAND
from ..base.checks import as_frequencies
from ..methods.decay import ISO3095_TDR_LIMIT, TrackDecayRate
from ..methods.infinite import InfiniteTrack
from ..model.tracks import Track

__all__ = ["decay_table", "pinned_length_table", "local_change_curves", "change_ratio_table", "transition_cases"]


def _limit(centre: float) -> float:
    """The ISO 3095 limit of the band with this exact centre (NaN where it sets none)."""
    nominal = {round(10 * np.log10(b)): v for b, v in ISO3095_TDR_LIMIT.items()}
    return nominal.get(round(10 * np.log10(centre)), np.nan)


def decay_table(rates: Mapping[str, TrackDecayRate]) -> pd.DataFrame:
    """The decay rates of several tracks side by side, with the ISO 3095 limit and the standard's checks.

    Parameters
    ----------
    rates : mapping of str to TrackDecayRate
        Track name to :func:`semitrack.track_decay_rate`'s result (the same bands).

    Returns
    -------
    pandas.DataFrame
        Indexed by band (Hz): per track the rate (dB/m), the least attenuated wave (dB/m),
        whether the band is valid, and whether the rate meets the limit; the limit (dB/m).
    """
    first = next(iter(rates.values()))
    table = pd.DataFrame(index=pd.Index(first.centres.round(0), name="band (Hz)"))
    table["ISO 3095 limit (dB/m)"] = [_limit(c) for c in first.centres]
    for name, tdr in rates.items():
        table[f"{name}: decay rate (dB/m)"] = tdr.decay_rate
        table[f"{name}: least attenuated wave (dB/m)"] = tdr.wave_attenuation
        table[f"{name}: valid"] = tdr.valid
        table[f"{name}: meets the limit"] = np.where(np.isnan(table["ISO 3095 limit (dB/m)"]), np.nan,
                                                     tdr.decay_rate >= table["ISO 3095 limit (dB/m)"])
    return table


def pinned_length_table(rates: Mapping[str, TrackDecayRate], spacings: Mapping[str, float], drop_db: float = 20.0,
                        above: float = 250.0) -> pd.DataFrame:
    """The paper's argument for long models, from the decay rates: the track an end must be away.

    Parameters
    ----------
    rates : mapping of str to TrackDecayRate
        Track name to its decay rates.
    spacings : mapping of str to float
        Track name to its support spacing (m), for the length in bays.
    drop_db : float
        The decay a vibration must have between the load and an end (dB); the paper's 20.
    above : float
        Bands from this centre (Hz) on count (the paper's range: some hundreds of hertz and up).

    Returns
    -------
    pandas.DataFrame
        Per track: the lowest decay rate above ``above`` and its band, the distance ``drop_db /
        DR`` an end must be from the load (m and bays), and the pinned model that holds a wheel
        with that much track each side (m).
    """
    rows = []
    for name, tdr in rates.items():
        keep = tdr.centres >= above * 10**-HALF_BAND  # the band that ``above`` names, and up
        i = int(np.argmin(np.where(keep, tdr.decay_rate, np.inf)))
        length = drop_db / tdr.decay_rate[i]
        rows.append({"track": name, "lowest decay rate (dB/m)": tdr.decay_rate[i], "its band (Hz)": tdr.centres[i],
                     f"{drop_db:g} dB away (m)": length, "bays": length / spacings[name],
                     "pinned model around one wheel (m)": 2 * length})
    return pd.DataFrame(rows).set_index("track")


def local_change_curves(cases: Mapping[str, InfiniteTrack], f: ArrayLike, x: ArrayLike) -> dict[str, np.ndarray]:
    """The point receptance w/F (m/N) at each position ``x`` (load and response there), per case.

    A load at a changed support moves every response by the same factor (the change only adds a
    force at the load point), so what a wheel feels beside a change is read with the load moved
    there too, not with a response one bay from the load.

    Parameters
    ----------
    cases : mapping of str to InfiniteTrack
        The tracks compared (the perfect one among them).
    f : array_like
        Frequencies (Hz).
    x : array_like
        The positions (m from the centre) of the load and its response.

    Returns
    -------
    dict
        Case to an ``(n_f, n_x)`` complex array (m/N).
    """
    f = np.atleast_1d(as_frequencies(f))
    xs = np.atleast_1d(np.asarray(x, dtype=float)).ravel()
    return {label: np.stack([inf.receptance(f, p, [p])[:, 0, 0, 0] for p in xs], axis=1)
            for label, inf in cases.items()}


def change_ratio_table(f: np.ndarray, curves: Mapping[str, np.ndarray], reference: str, labels: tuple[str, ...],
                       bands: Mapping[str, tuple[float, float]]) -> pd.DataFrame:
    """How much a change moves |w/F| from the reference track's, by frequency range.

    Parameters
    ----------
    f : ndarray
        Frequencies (Hz) of the curves.
    curves : mapping of str to ndarray
        :func:`local_change_curves`' result.
    reference : str
        The case the others are compared with (the perfect track).
    labels : tuple of str
        A name for each response position (columns of the curves).
    bands : mapping of str to (float, float)
        Frequency ranges (Hz) by name.

    Returns
    -------
    pandas.DataFrame
        Indexed by (case, position): the largest ratio of |w/F| to the reference's in each range (-).
    """
    rows = {}
    for case, h in curves.items():
        if case == reference:
            continue
        ratio = np.abs(h) / np.abs(curves[reference])
        for j, label in enumerate(labels):
            rows[case, label] = {name: float(ratio[(f >= lo) & (f <= hi), j].max()) for name, (lo, hi) in bands.items()}
    table = pd.DataFrame.from_dict(rows, orient="index")
    table.index = pd.MultiIndex.from_tuples(table.index, names=["change", "response"])
    return table


def transition_cases(left: Track, right: Track, kt: int = 0) -> dict[str, InfiniteTrack]:
    """Each periodic track and the transition from one to the other at the mid-span ``kt d``.

    Parameters
    ----------
    left, right : Track
        The track before and after the transition.
    kt : int
        The transition's mid-span index.

    Returns
    -------
    dict
        Label to InfiniteTrack.
    """
    return {f"{left.name} (periodic)": InfiniteTrack(left), f"{right.name} (periodic)": InfiniteTrack(right),
            f"{left.name} to {right.name}": InfiniteTrack(left, right=right, transition=kt)}

