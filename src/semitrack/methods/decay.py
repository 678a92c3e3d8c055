"""The track decay rate of EN 15461, from the exact infinite track, and the Bloch waves beside it.

The standard measures how fast the rail's vibration dies away along the track. An accelerometer
sits on the rail at the middle of a sleeper bay, a hammer strikes the rail at 29 positions out to
66 bays (:data:`EN15461_BAYS`, in bays from the accelerometer), and each transfer function,
reduced to one-third-octave bands, gives ``A(x_n)``. If ``A`` fell as ``e^(-beta x)`` the rate
would be ``20 lg e^beta = 8.686 beta`` dB/m, and the integral of ``|A|^2`` along the rail
``|A(0)|^2 / 2 beta``; the standard takes the rate from that integral (its Formula 1):

    DR = 4.343 / sum_n ( |A(x_n)|^2 / |A(x_0)|^2 ) dx_n     (dB/m),

``dx_n`` the rail each position stands for: from halfway to the one before to halfway to the one
after, from 0 for the first, symmetric about the last. A grid that stops at ``x_max`` cannot
show a rate below ``4.343 / x_max`` (its Formula 2): a band whose rate is less than twice that
floor is unsuitable (an upper bound only); and the response at the last position must be at
least 10 dB below the direct one. Here the transfer functions are the exact ones of
:class:`semitrack.InfiniteTrack` (by reciprocity a load at the accelerometer and the responses at
the hammer's positions), averaged as ``|A|^2`` over narrow-band lines ``df`` apart in each band.

The grid and the formulas are read from two open-source implementations of the standard (the
acoustics package phonometry and the track-dynamics package rolland), not from the standard's
text, which is not public. The measured transfer function is the accelerance (an accelerometer
under a hammer; the standard allows mobility too); in a band the three kinds differ only by the
weighting of the lines by omega^2 or omega^4, and so slightly.

The physics beside the standard's number: the least attenuated free (Bloch) wave of the periodic
track, ``-20 lg |lambda| / d`` dB/m with ``lambda`` its factor over one period
(:func:`bloch_attenuation`): the rate far from the load, where that wave is all that is left.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ..base.bands import band_index, nominal_bands, third_octave_bands
from ..base.checks import MAX_FREQUENCIES, as_real_array, brief, check_choice, check_positive, check_real, check_work
from ..base.deprecation import deprecated_alias, renamed_keywords
from ..base.errors import InputError, InputTypeError
from ..base.fields import check_fields, check_rows
from ..base.notices import warn_user
from ..model.tracks import Track
from .infinite import InfiniteTrack
from .transfer import cyclic_reduction, period_dynamic_stiffness, vanishing_damping

__all__ = ["EN15461_BAYS", "ISO3095_TDR_LIMIT", "FRF_KINDS", "MAX_LIMIT_BANDS", "TrackDecayRate", "track_decay_rate",
           "bloch_attenuation", "formula_1", "decay_intervals"]

#: The hammer's positions of EN 15461 (its Figure 2), in sleeper bays from the accelerometer at
#: the middle of bay 0: every quarter bay to 2.5, every half bay to 4, every bay to 8, then 10,
#: 12, 16, 20, 24, 30, 36, 42, 48, 54 and 66.
EN15461_BAYS = (0.0, 0.25, 0.5, 0.75, 1.0, 1.25, 1.5, 1.75, 2.0, 2.25, 2.5, 3.0, 3.5, 4.0, 5.0, 6.0, 7.0, 8.0,
                10.0, 12.0, 16.0, 20.0, 24.0, 30.0, 36.0, 42.0, 48.0, 54.0, 66.0)
#: Most hammer positions a grid may hold, and the farthest (bays): a study beyond the standard's
#: 66 bays, not a hammer every centimetre of a kilometre.
MAX_GRID_POSITIONS, MAX_GRID_BAYS = 1000, 5000.0
#: Highest band centre of a decay rate (Hz): EN 15461 stops at 5 kHz, rolling noise near 10 kHz.
MAX_BAND_CENTRE = 20_000.0

#: The lower limits of the vertical track decay rate of ISO 3095:2013 (its Figure 3), dB/m by
#: one-third-octave band (Hz); below 250 Hz it sets none. As transcribed by the acoustics package
#: phonometry (``REFERENCE_TRACK_DECAY_LIMITS_DB_PER_M["vertical"]``), not checked against the
#: standard itself.
ISO3095_TDR_LIMIT = {250: 2.0, 315: 2.0, 400: 6.0, 500: 6.0, 630: 6.0, 800: 2.19, 1000: 0.8, 1250: 0.8,
                     1600: 0.8, 2000: 0.8, 2500: 0.8, 3150: 0.8, 4000: 0.8, 5000: 0.8}
#: The kinds of transfer function: displacement, velocity or acceleration per force.
FRF_KINDS = ("accelerance", "mobility", "receptance")
#: 10 lg e, as the standard prints it (half 8.686: the sum is of squared amplitudes).
_DECAY_CONSTANT = 4.343
#: The far-point drop the standard asks for (dB), and the fraction of the rate its floor may reach.
_FAR_DROP, _FLOOR_FRACTION = 10.0, 0.5


def formula_1(levels: ArrayLike, positions: ArrayLike) -> np.ndarray:
    """The decay rate of EN 15461's Formula 1 from band levels along the grid (dB/m).

    Parameters
    ----------
    levels : array_like, shape (n_bands, n_positions)
        ``|A(x_n)|^2`` per band at each position (any unit; the first is the direct response).
    positions : array_like, shape (n_positions,)
        Distances from the accelerometer (m), from 0, increasing.

    Returns
    -------
    ndarray, shape (n_bands,)
        ``4.343 / sum_n (|A(x_n)|^2 / |A(x_0)|^2) dx_n``.

    Examples
    --------
    A response falling as exp(-beta x) on a fine grid gives 8.686 beta dB/m:

    >>> x = np.linspace(0.0, 40.0, 4001)
    >>> float(formula_1([np.exp(-2 * 0.5 * x)], x)[0].round(2))
    4.35
    """
    levels = np.atleast_2d(np.asarray(levels, dtype=float))
    return _DECAY_CONSTANT / (levels / levels[:, :1] * decay_intervals(positions)).sum(axis=1)


def decay_intervals(x: ArrayLike) -> np.ndarray:
    """The rail each position stands for in Formula 1: from halfway to the previous position to
    halfway to the next; from 0 for the first, symmetric about the last (m).

    Parameters
    ----------
    x : array_like
        Distances from the accelerometer (m), from 0, increasing.

    Returns
    -------
    ndarray

    Examples
    --------
    >>> decay_intervals([0.0, 1.0, 3.0]).tolist()
    [0.5, 1.5, 2.0]
    """
    x = np.asarray(x, dtype=float)
    mid = 0.5 * (x[1:] + x[:-1])
    return np.concatenate((mid, [x[-1] + 0.5 * (x[-1] - x[-2])])) - np.concatenate(([0.0], mid))


@dataclass(frozen=True, eq=False)
class TrackDecayRate:
    """The track decay rate by one-third-octave band (EN 15461), with what the standard checks.

    Attributes
    ----------
    centres : ndarray
        Band centre frequencies (Hz), exact base-10 values (50 Hz is 50.12 Hz).
    decay_rate : ndarray
        Formula 1 per band (dB/m).
    floor : float
        Formula 2, ``4.343 / x_max`` (dB/m): the least rate the grid can show.
    suitable : ndarray of bool
        Per band, the floor at most half the rate (else the rate is an upper bound only).
    far_point_drop : ndarray
        Per band, the response at the last position below the direct one (dB).
    valid : ndarray of bool
        Per band, suitable and a far-point drop of at least 10 dB.
    wave_attenuation : ndarray
        Per band, the least attenuated Bloch wave at the band centre (dB/m); NaN for a track
        with changes or a transition, which has no single periodic wave.
    distances : ndarray
        The hammer's distances from the accelerometer (m; ``positions`` until 0.3).
    levels : ndarray, shape (n_bands, n_distances)
        ``|A(x_n)|^2`` averaged over each band's lines (in the FRF's unit squared).
    frf : str
        The transfer function: accelerance (m/(N s^2)), mobility (m/(N s)) or receptance (m/N).
    df : float
        The line spacing (Hz).
    """

    centres: np.ndarray
    decay_rate: np.ndarray
    floor: float
    suitable: np.ndarray
    far_point_drop: np.ndarray
    valid: np.ndarray
    wave_attenuation: np.ndarray
    distances: np.ndarray
    levels: np.ndarray
    frf: str
    df: float

    positions = deprecated_alias("distances", "positions")

    def __post_init__(self):
        check_fields(self)  # a record built by hand is refused here, not in a method
        check_rows(self, ("centres", "decay_rate", "suitable", "far_point_drop", "valid", "wave_attenuation"))

    @property
    def nominal(self) -> np.ndarray:
        """The bands' nominal names (Hz): 1250 for the centre 1258.9, as the standards name them."""
        return nominal_bands(self.centres)

    def limits(self, limit: Mapping[float, float] | None = None) -> np.ndarray:
        """Each band's lower limit (dB/m), NaN where the limit names none.

        Parameters
        ----------
        limit : mapping of float to float, optional
            Band (nominal name or exact centre, Hz) to the least decay rate (dB/m);
            :data:`ISO3095_TDR_LIMIT` when omitted.

        Returns
        -------
        ndarray, shape (n_bands,)
        """
        by_index = _limit_by_band(ISO3095_TDR_LIMIT if limit is None else limit)
        return np.array([by_index.get(n, np.nan) for n in band_index(self.centres, "centres")])

    def meets(self, limit: Mapping[float, float] | None = None) -> dict[float, bool]:
        """The verdict per band: does the decay rate reach the lower limit?

        Only the bands the limit names are judged (ISO 3095 sets none below 250 Hz). A rate the
        standard's checks find unfit (``valid`` False) is judged as computed: here the transfer
        functions are exact, and the grid's floor is reported beside it in :meth:`table`.

        Parameters
        ----------
        limit : mapping of float to float, optional
            Band (nominal name or exact centre, Hz) to the least decay rate (dB/m);
            :data:`ISO3095_TDR_LIMIT` when omitted.

        Returns
        -------
        dict of float to bool
            Nominal band name (Hz) to ``decay_rate >= limit``, ascending.

        Examples
        --------
        >>> import semitrack as st
        >>> st.track_decay_rate(st.ballasted_track(), band=(800, 1250)).meets()  # 1 kHz: 0.796 against 0.8 dB/m
        {800.0: False, 1000.0: False, 1250.0: True}
        """
        bound = self.limits(limit)
        judged = np.isfinite(bound)
        return {float(b): bool(r >= x) for b, r, x in zip(self.nominal[judged], self.decay_rate[judged], bound[judged])}

    def table(self, limit: Mapping[float, float] | None = None):
        """The rates as a :class:`pandas.DataFrame`, a row per band, with the checks and the verdict.

        Parameters
        ----------
        limit : mapping of float to float, optional
            Band to the least decay rate (dB/m), as :meth:`meets`; :data:`ISO3095_TDR_LIMIT` when
            omitted. Its columns are named for ISO 3095 only when it is that limit.

        Returns
        -------
        pandas.DataFrame
            ``band (Hz)`` (nominal), ``centre (Hz)`` (exact), the rate, the Bloch wave, the
            far-point drop, ``suitable``, ``valid``, the limit (NaN where none) and whether the
            rate meets it (``<NA>`` where there is no limit).
        """
        import pandas as pd  # the tables' library: imported for the table only

        bound = self.limits(limit)
        iso = limit is None or limit is ISO3095_TDR_LIMIT
        bound_name, verdict_name = ("ISO 3095 limit", "meets ISO 3095") if iso else ("limit", "meets the limit")
        judged = self.meets(limit)
        verdict = pd.array([judged.get(band, pd.NA) for band in self.nominal], dtype="boolean")
        return pd.DataFrame({"band (Hz)": self.nominal, "centre (Hz)": self.centres,
                             "decay rate (dB/m)": self.decay_rate, "Bloch wave (dB/m)": self.wave_attenuation,
                             "far-point drop (dB)": self.far_point_drop,
                             "suitable": self.suitable, "valid": self.valid, f"{bound_name} (dB/m)": bound,
                             verdict_name: verdict})


#: Most bands a limit may name (a guard against a mistyped table).
MAX_LIMIT_BANDS = 1000


def _limit_by_band(limit: Mapping[float, float]) -> dict[int, float]:
    """A lower limit checked and keyed by band index n (centre ``10^(n/10)``)."""
    if not isinstance(limit, Mapping):
        raise InputTypeError(f"limit must be a mapping of band (Hz) to the least decay rate (dB/m), got "
                             f"{type(limit).__name__}")
    check_work(len(limit), MAX_LIMIT_BANDS, f"limit names {len(limit)} bands", "name the one-third-octave bands")
    keys = band_index(list(limit), "limit's bands") if limit else np.zeros(0, dtype=int)
    by_index = {}
    for n, (band, rate) in zip(keys.tolist(), limit.items()):
        rate = check_real(f"limit[{band!r}]", rate)
        if not (np.isfinite(rate) and rate >= 0):
            raise InputError(f"limit[{band!r}] must be a finite decay rate >= 0 (dB/m), got {rate!r}")
        if n in by_index:
            raise InputError(f"limit names the band of {band!r} twice")
        by_index[n] = rate
    return by_index


def _grid(bays: ArrayLike) -> np.ndarray:
    """The hammer's grid in bays, checked: from 0, strictly increasing, bounded."""
    grid = as_real_array(bays, "bays", ndim=1)
    if grid.size < 2 or grid.size > MAX_GRID_POSITIONS:
        raise InputError(f"bays must hold 2 to {MAX_GRID_POSITIONS} positions, got {grid.size}")
    if grid[0] != 0.0 or np.any(np.diff(grid) <= 0):
        raise InputError(f"bays must start at 0 (the accelerometer) and increase, got {brief(bays)}")
    if grid[-1] > MAX_GRID_BAYS:
        raise InputError(f"bays must end within {MAX_GRID_BAYS:g} bays, got {grid[-1]:g}")
    return grid


def _band_edges(band) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    try:
        lo, hi = (check_positive("band", b) for b in band)
    except (TypeError, ValueError):
        raise InputTypeError(f"band must be a pair (lowest, highest) of band centres in Hz, got {band!r}") from None
    if not lo <= hi:
        raise InputError(f"band must be (lowest, highest) band centres, lowest first, got {band!r}")
    if hi > MAX_BAND_CENTRE:
        raise InputError(f"band must end at most at {MAX_BAND_CENTRE:g} Hz (EN 15461 asks 100-5000 Hz), got {band!r}")
    return third_octave_bands(lo, hi)


#: The bands EN 15461 asks for (Hz), the default.
STANDARD_BAND = (100.0, 5000.0)


def _default_bands(inf: InfiniteTrack) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The standard's bands less those a measured table's band does not hold (warned), or a refusal."""
    centres, lower, upper = third_octave_bands(*STANDARD_BAND)
    tracks = [inf.track] + ([inf.right] if inf.right is not None else [])
    lo = max(t.frequency_band[0] for t in tracks)
    hi = min(t.frequency_band[1] for t in tracks)
    inside = (lower >= lo) & (upper <= hi)
    if not np.any(inside):
        raise InputError(f"the track's measured curves hold {lo:g}-{hi:g} Hz, which covers none of the standard's "
                         f"bands' lines (100-5000 Hz, edges {lower[0]:.4g}-{upper[-1]:.4g} Hz): give band= within "
                         "them, or extend the tables (or outside='hold')")
    if not np.all(inside):
        left = nominal_bands(centres[~inside])
        names = ", ".join(f"{b:g} Hz (lines {lo_:.4g}-{hi_:.4g} Hz)"
                          for b, lo_, hi_ in zip(left, lower[~inside], upper[~inside]))
        warn_user(f"track_decay_rate: the track's measured curves hold {lo:g}-{hi:g} Hz, so the band"
                  f"{'s' * (left.size > 1)} {names} {'are' if left.size > 1 else 'is'} left out of the standard's "
                  "100-5000 Hz; give band= to choose, or extend the tables")
    return centres[inside], lower[inside], upper[inside]


def bloch_attenuation(track: Track, f: ArrayLike) -> np.ndarray:
    """The attenuation of the least attenuated free wave of the periodic track (dB/m).

    From the solvent ``G`` of the Bloch recurrence over one period (the exact method,
    :mod:`semitrack.methods.transfer`): its eigenvalues are the decaying waves' factors over one
    period, and the largest in modulus is the wave that goes farthest.

    Parameters
    ----------
    track : Track
        The periodic track.
    f : array_like
        Frequencies (Hz).

    Returns
    -------
    ndarray
        ``-20 lg |lambda_max| / L`` (dB/m), L the period.
    """
    f = np.atleast_1d(np.asarray(f, dtype=float))
    cell = track.cell()
    extra = vanishing_damping(track)
    with np.errstate(all="ignore"):
        d = period_dynamic_stiffness(cell, 2 * np.pi * f, cell.joint, extra)
        g_right, _, converged = cyclic_reduction(d)
    lam = np.abs(np.linalg.eigvals(g_right)).max(axis=1)
    return np.where(converged, -20 * np.log10(lam) / cell.period, np.nan)


@renamed_keywords({"bands": "band", "x_load": "x"})
def track_decay_rate(track: Track | InfiniteTrack, *, band: tuple[float, float] | None = None,
                     frf: str = "accelerance", df: float = 2.0, x: float = 0.0,
                     bays: ArrayLike = EN15461_BAYS) -> TrackDecayRate:
    """The track decay rate of EN 15461 by one-third-octave band, from the exact transfer functions.

    Parameters
    ----------
    track : Track or InfiniteTrack
        The track, periodic, or with changes, a transition or joints (then the grid runs in +x
        from ``x``).
    band : (float, float), optional
        The lowest and highest band centres (Hz); nominal values name their band (``bands=``
        until 0.3). By default the standard's 100-5000 Hz, less the end bands whose lines a
        measured table of the track does not reach (with a warning naming them): a table to
        5 kHz covers the 5 kHz band's centre, not its upper edge at 5.62 kHz.
    frf : {"accelerance", "mobility", "receptance"}
        The transfer function averaged in the bands; the standard's is the accelerance.
    df : float
        Spacing of the narrow-band lines averaged in each band (Hz); a band holds its lines
        ``k df`` within its edges (at least one).
    x : float
        Where the accelerometer sits (m from the centre, a mid-span by default; ``x_load=`` until
        0.3); the hammer's positions are ``x + bays d``.
    bays : array_like
        The hammer's distances from the accelerometer, in support spacings: from 0, increasing, at
        most 1000 of them and 5000 bays. The standard's 29 (:data:`EN15461_BAYS`, out to 66 bays)
        by default; a longer grid shows a track that decays too slowly for the standard's (its
        far-point check fails), and what its rate is there.

    Returns
    -------
    TrackDecayRate

    Examples
    --------
    >>> import semitrack as st
    >>> tdr = st.track_decay_rate(st.ballasted_track(), band=(500, 1000))
    >>> tdr.centres.round().tolist(), bool(np.all(tdr.decay_rate > 0))
    ([501.0, 631.0, 794.0, 1000.0], True)
    """
    inf = track if isinstance(track, InfiniteTrack) else InfiniteTrack(track)
    frf = check_choice("frf", frf, FRF_KINDS)
    df, x = check_positive("df", df), check_real("x", x)
    centres, lower, upper = _default_bands(inf) if band is None else _band_edges(band)
    check_work(float(np.sum(upper - lower)) / df, MAX_FREQUENCIES, f"df={df!r} Hz puts "
               f"{float(np.sum(upper - lower)) / df:.3g} lines in the bands", "give a larger df")  # before arange
    lines = [np.arange(np.ceil(lo / df), np.ceil(hi / df)) * df for lo, hi in zip(lower, upper)]
    if any(line.size == 0 for line in lines):
        raise InputError(f"df={df!r} Hz leaves a band without a line: the narrowest band, {lower[0]:.4g}-"
                         f"{upper[0]:.4g} Hz, needs df below {upper[0] - lower[0]:.3g} Hz")
    f = np.concatenate(lines)
    distances = _grid(bays) * inf.track.spacing
    h = inf.receptance(f, x, x + distances)[:, :, 0, 0]  # w per F, (n_f, n_distances)
    power = {"receptance": 0, "mobility": 2, "accelerance": 4}[frf]
    squared = np.abs(h) ** 2 * (2 * np.pi * f[:, None]) ** power
    band = np.repeat(np.arange(centres.size), [line.size for line in lines])
    levels = np.array([squared[band == b].mean(axis=0) for b in range(centres.size)])
    rate = formula_1(levels, distances)
    floor = _DECAY_CONSTANT / distances[-1]
    drop = 10 * np.log10(levels[:, 0] / levels[:, -1])
    suitable = floor <= _FLOOR_FRACTION * rate
    periodic = isinstance(track, Track) or not (inf.changes or inf.joints or inf.right is not None)
    wave = bloch_attenuation(inf.track, centres) if periodic else np.full(centres.size, np.nan)
    return TrackDecayRate(centres=centres, decay_rate=rate, floor=floor, suitable=suitable, far_point_drop=drop,
                          valid=suitable & (drop >= _FAR_DROP), wave_attenuation=wave, distances=distances,
                          levels=levels, frf=frf, df=df)
