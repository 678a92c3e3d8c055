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
from ..base.errors import InputError
from ..methods.decay import EN15461_BAYS, TrackDecayRate
from ..methods.infinite import InfiniteTrack
from ..model.tracks import Track

__all__ = ["decay_table", "pinned_length_table", "long_grid", "local_change_curves", "change_ratio_table",
           "change_measure_table", "damping_sensitivity_table", "transition_cases"]


def decay_table(rates: Mapping[str, TrackDecayRate]) -> pd.DataFrame:
    """The decay rates of several tracks side by side, with the ISO 3095 limit and the standard's checks.

    Parameters
    ----------
    rates : mapping of str to TrackDecayRate
        Track name to :func:`semitrack.track_decay_rate`'s result (the same bands).

    Returns
    -------
    pandas.DataFrame
        Indexed by band (Hz), with two column levels (track, quantity) so that each track's name
        heads its columns once: ``("", "ISO 3095 limit (dB/m)")``, then per track its
        ``"decay rate (dB/m)"``, ``"least attenuated wave (dB/m)"``, ``"valid"`` (the band passes
        the standard's checks) and ``"meets the limit"`` (``pd.NA`` where the standard sets none).
    """
    first = next(iter(rates.values()))
    columns = {("", "ISO 3095 limit (dB/m)"): first.limits()}
    for name, tdr in rates.items():
        columns |= {(name, "decay rate (dB/m)"): tdr.decay_rate,
                    (name, "least attenuated wave (dB/m)"): tdr.wave_attenuation, (name, "valid"): tdr.valid,
                    (name, "meets the limit"): tdr.table()["meets ISO 3095"].to_numpy()}
    return pd.DataFrame(columns, index=pd.Index(first.nominal, name="band (Hz)"))


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
        Per track: the lowest decay rate above ``above`` among the bands the standard's checks
        accept (a rejected band's rate is biased high: its grid ends before the response has
        died) and its band, the grid's length (m), the distance ``drop_db / DR`` an end must be
        from the load (m and bays), and the pinned model that holds a wheel with that much track
        each side (m).
    """
    rows = []
    for name, tdr in rates.items():
        keep = (tdr.centres >= above * 10**-HALF_BAND) & tdr.valid  # the band ``above`` names, and up
        if not keep.any():
            raise InputError(f"rates[{name!r}]: no band from {above:g} Hz on passes the standard's checks; give a "
                             "longer grid (track_decay_rate's bays=)")
        i = int(np.argmin(np.where(keep, tdr.decay_rate, np.inf)))
        length = drop_db / tdr.decay_rate[i]
        rows.append({"track": name, "lowest decay rate (dB/m)": tdr.decay_rate[i], "its band (Hz)": tdr.nominal[i],
                     "grid (m)": tdr.distances[-1], f"{drop_db:g} dB away (m)": length,
                     "bays": length / spacings[name], "pinned model around one wheel (m)": 2 * length})
    return pd.DataFrame(rows).set_index("track")


def long_grid(last: float = 300.0, step: float = 6.0) -> np.ndarray:
    """The standard's hammer grid carried on past its 66 bays: every ``step`` bays out to ``last``.

    A slowly decaying track fails the standard's far-point check on its own grid (the response
    66 bays away is not 10 dB down), and the integral, missing the tail beyond, reads a rate
    too high. On this grid the same formula sees the tail.

    Parameters
    ----------
    last : float
        The farthest position (bays); 300 bays of 0.65 m are 195 m.
    step : float
        The spacing of the added positions (bays).

    Returns
    -------
    ndarray
        Positions in bays, from 0, for ``st.track_decay_rate(..., bays=)``.
    """
    return np.concatenate((EN15461_BAYS, np.arange(EN15461_BAYS[-1] + step, last + 0.5 * step, step)))


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


def change_measure_table(cases: Mapping[str, InfiniteTrack], f: np.ndarray, curves: Mapping[str, np.ndarray],
                         reference: str, x: ArrayLike, labels: tuple[str, ...],
                         band: tuple[float, float] = (20.0, 200.0), static_f: float = 0.1) -> pd.DataFrame:
    """Three measures of how much a change softens the rail at low frequency, side by side.

    The largest ratio of two curves is taken where the changed track's resonance has moved to, and
    sits on the reference's slope there: it grows as the damping falls. The ratio of the two peaks
    (each at its own frequency) depends on the damping less, and the static stiffness ratio not
    at all.

    Parameters
    ----------
    cases : mapping of str to InfiniteTrack
        The tracks of ``curves``, for the static receptance.
    f : ndarray
        Frequencies (Hz) of the curves.
    curves : mapping of str to ndarray
        :func:`local_change_curves`' result (one column per position).
    reference : str
        The perfect track's case.
    x : array_like
        The curves' positions (m), one per column, as given to :func:`local_change_curves`.
    labels : tuple of str
        A name for each position.
    band : (float, float)
        The range (Hz) the ratios are read in.
    static_f : float
        The frequency (Hz) taken as static: far below every resonance.

    Returns
    -------
    pandas.DataFrame
        Indexed by (change, response): the largest ratio of |w/F| in ``band`` (-), the ratio of the
        peaks of |w/F| in ``band`` (-), and the static stiffness of the reference over the
        changed track's (-).
    """
    inside = (f >= band[0]) & (f <= band[1])
    ref = np.abs(curves[reference][inside])
    rows = {}
    for case, h in curves.items():
        if case == reference:
            continue
        ratio, peaks = np.abs(h[inside]) / ref, np.abs(h[inside]).max(axis=0) / ref.max(axis=0)
        for j, (p, label) in enumerate(zip(np.atleast_1d(np.asarray(x, dtype=float)), labels)):
            static = (cases[case].receptance([static_f], p, [p])[0, 0, 0, 0].real
                      / cases[reference].receptance([static_f], p, [p])[0, 0, 0, 0].real)
            rows[case, label] = {"largest ratio of |w/F|": float(ratio[:, j].max()),
                                 "peak over peak": float(peaks[j]), "static stiffness drop": float(static)}
    table = pd.DataFrame.from_dict(rows, orient="index")
    table.index = pd.MultiIndex.from_tuples(table.index, names=["change", "response"])
    return table


def damping_sensitivity_table(track: Track, changes: Mapping[str, Mapping], f: np.ndarray, x: ArrayLike,
                              labels: tuple[str, ...], scales: tuple[float, ...] = (1.0, 0.5)) -> pd.DataFrame:
    """:func:`change_measure_table` with the track's pad and ballast loss factors scaled.

    Parameters
    ----------
    track : Track
        The perfect track.
    changes : mapping of str to mapping
        Name to the ``changes=`` of :class:`InfiniteTrack`.
    f : ndarray
        Frequencies (Hz).
    x : array_like
        Positions (m) of the load and response.
    labels : tuple of str
        A name for each position.
    scales : tuple of float
        Factors on ``eta_pad`` and ``eta_ballast``.

    Returns
    -------
    pandas.DataFrame
        The measures (columns) for each damping scale (outer column level, "damping x s").
    """
    tables = {}
    for scale in scales:
        damped = track.replace(eta_pad=scale * track.eta_pad, eta_ballast=scale * track.eta_ballast)
        cases = {"perfect track": InfiniteTrack(damped)}
        cases |= {name: InfiniteTrack(damped, c) for name, c in changes.items()}
        curves = local_change_curves(cases, f, x)
        tables[f"damping x {scale:g}"] = change_measure_table(cases, f, curves, "perfect track", x, labels)
    return pd.concat(tables, axis=1)


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

