"""What a fit aims at: the target receptance, its characteristic frequencies and the fit frequencies.

**Characteristic frequencies** are detected, never hard-coded: they are extrema of
``|det(alpha^-1)|`` (Eq. 18), whose local minima are the resonances of the semi-infinite track.
Slab: the dip of ``|det|`` closest to the bouncing-frequency estimate ``sqrt(kv/(rho A d))/(2 pi)``
gives ``f_n`` (183.7 Hz for the paper's track). Ballasted: the two lowest dips give ``f_n1``
and ``f_n2`` (114.9, 500.5 Hz) and the highest peak of ``|det|`` between them gives
``f_anti`` (244.8 Hz). The paper reads 117, 489 (or 465) and 243 Hz off its curves.

**Targets.** The receptance to fit is the exact one of the track
(:func:`~semitrack.methods.receptance.semi_infinite_receptance`), a callable ``alpha(f)``, or
sampled ``(f, alpha)`` pairs; the fit frequencies are :func:`default_fit_frequencies`, the
paper's sets (Tables 4 and 7), or the caller's.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike

from ..base.checks import MAX_FREQUENCIES, as_frequencies, check_band, check_int_at_least, check_positive, check_work
from ..base.conventions import ELEMENTS
from ..base.errors import InputError, InputTypeError
from ..base.paper_values import TABLE4_FIT_FREQUENCIES, TABLE7_FIT_FREQUENCIES
from ..methods.features import find_extrema, search_grid
from ..methods.receptance import central_response, semi_infinite_receptance
from ..model.tracks import Track, require_track
from .assembly import Layout, check_layout
from .metrics import error_band_grid

__all__ = [
    "CHARACTERISTIC_SEARCH_BAND",
    "Target",
    "FitFrequencies",
    "fit_characteristic_frequencies",
    "default_fit_frequencies",
    "normalise_target",
    "check_characteristic",
    "resolve_characteristic",
    "select_frequencies",
    "target_values",
]

#: Where characteristic frequencies are looked for by default (Hz): the paper's range.
CHARACTERISTIC_SEARCH_BAND = (3.0, 3000.0)

#: The receptance to fit: None (the track's exact one), a callable ``alpha(f)`` returning
#: (n_f, 2, 2) for frequencies in Hz, or sampled ``(f, alpha)``.
Target = Callable[[np.ndarray], ArrayLike] | tuple[ArrayLike, ArrayLike] | None

#: The fit frequencies: None (the default set), "paper" (Tables 4 and 7) or frequencies in Hz.
FitFrequencies = Literal["paper"] | ArrayLike | None

_CHAR_KEYS = {"slab": ("f_n",), "ballasted": ("f_n1", "f_n2", "f_anti")}
_PAPER_FIT_FREQUENCIES = {"slab": TABLE4_FIT_FREQUENCIES, "ballasted": TABLE7_FIT_FREQUENCIES}
_ROWS, _COLS = (list(ix) for ix in zip(*ELEMENTS.values()))


# --- targets ----------------------------------------------------------------------------------
def check_alpha(alpha: np.ndarray, n_f: int, name: str) -> np.ndarray:
    """``alpha`` as complex (n_f, 2, 2), finite, with non-zero compared elements (relative residuals)."""
    if alpha.shape != (n_f, 2, 2):
        raise InputError(f"{name} must have shape ({n_f}, 2, 2), got {alpha.shape}")
    if alpha.dtype.kind not in "fc" or not np.all(np.isfinite(alpha)):
        raise InputError(f"{name} must hold finite (complex) receptances")
    if np.any(alpha[:, _ROWS, _COLS] == 0):
        raise InputError(f"{name} must have non-zero alpha11, alpha12, alpha22 (relative residuals)")
    return alpha.astype(complex)


def normalise_target(target: Target):
    """None, a callable, or ``(f, alpha)`` with validated arrays; TypeError for anything else."""
    if target is None or callable(target):
        return target
    if isinstance(target, (tuple, list)) and len(target) == 2:
        f = as_frequencies(target[0], "target[0] (frequencies)")
        if f.ndim != 1 or f.size < 3 or np.any(np.diff(f) <= 0):
            raise InputError(f"target[0] must be a 1-D increasing array of at least 3 frequencies (Hz), "
                             f"got shape {f.shape}")
        alpha = check_alpha(np.asarray(target[1]), f.size, "target[1]")
        return f, alpha
    raise InputTypeError("target must be None (exact receptance of track), a callable alpha(f) -> (n_f, 2, 2), "
                    f"or a pair (f, alpha) of sampled receptances, got {type(target).__name__}")


def _evaluate(target, f: np.ndarray) -> np.ndarray:
    return check_alpha(np.asarray(target(f)), f.size, "target(f)")


def _sampled(target, f_req: np.ndarray, what: str) -> np.ndarray:
    """Receptances of a sampled target at frequencies that must be among its samples."""
    f_s, alpha = target
    idx = np.searchsorted(f_s, f_req)
    idx = np.clip(idx, 0, f_s.size - 1)
    lower = np.clip(idx - 1, 0, f_s.size - 1)
    pick = np.where(np.abs(f_s[lower] - f_req) < np.abs(f_s[idx] - f_req), lower, idx)
    bad = ~np.isclose(f_s[pick], f_req, rtol=1e-9, atol=0)
    if np.any(bad):
        raise InputError(f"{what} must be among the sampled frequencies of target, e.g. "
                         f"{float(f_req[bad][0])!r} Hz is not")
    return alpha[pick]


def target_values(track: Track, target, f: np.ndarray, what: str) -> np.ndarray:
    """The (normalised) target's receptance at ``f`` (Hz), checked, shape (n_f, 2, 2).

    ``what`` names the frequencies in the error raised when a sampled target lacks one.
    """
    if target is None:
        return check_alpha(np.asarray(semi_infinite_receptance(track, f)), f.size, "the track receptance")
    if callable(target):
        return _evaluate(target, f)
    return _sampled(target, f, what)


# --- characteristic frequencies ----------------------------------------------------------------
def check_characteristic(layout: Layout, characteristic: Mapping[str, float]) -> dict[str, float]:
    """Given characteristic frequencies (Hz): exactly the layout's keys, positive, ordered."""
    if not isinstance(characteristic, dict):
        raise InputTypeError(f"characteristic must be a dict of frequencies (Hz), got {type(characteristic).__name__}")
    keys = _CHAR_KEYS[layout]
    if set(characteristic) != set(keys):
        raise InputError(f"characteristic for the {layout} layout must have exactly the keys {keys}, "
                         f"got {sorted(characteristic)}")
    out = {}
    for k in keys:
        v = characteristic[k]
        if isinstance(v, bool) or not isinstance(v, (int, float, np.integer, np.floating)):
            raise InputTypeError(f"characteristic[{k!r}] must be a real number (Hz), got {v!r}")
        if not (math.isfinite(v) and v > 0):
            raise InputError(f"characteristic[{k!r}] must be positive and finite (Hz), got {v!r}")
        out[k] = float(v)
    if layout == "ballasted" and not (out["f_n1"] < out["f_anti"] < out["f_n2"]):
        raise InputError("characteristic must satisfy f_n1 < f_anti < f_n2 (Eq. 30 gives s > 0 only then), "
                         f"got {out}")
    return out


def _det_extrema(track, target, search_band, df):
    """Peaks and dips of |det(alpha^-1)| as a DataFrame (see features.find_extrema)."""
    if target is None:
        # Only det's extrema are needed: refining those of the other curves too
        # (characteristic_frequencies) cost ~0.8 s of a ~4 s fit. Same grid, same refinement.
        f = search_grid(search_band, df)

        def det_at(x: float) -> dict[str, complex]:
            return {"det": central_response(track, np.array([x])).det[0]}

        return find_extrema(f, {"det": central_response(track, f).det}, det_at)
    if callable(target):
        f = np.arange(search_band[0], search_band[1] + 1e-9, df)

        def det_inv(ff):
            a = _evaluate(target, np.atleast_1d(ff))
            return 1.0 / np.linalg.det(a)

        return find_extrema(f, {"det": det_inv(f)}, lambda x: {"det": det_inv(x)[0]})
    f, alpha = target
    return find_extrema(f, {"det": 1.0 / np.linalg.det(alpha)})


# What to do when the track has no characteristic frequency to constrain, for both audiences.
_WITHOUT_CONSTRAINTS = ("fit without them (constrained=False; on the command line --unconstrained) or give "
                        "the frequencies yourself (characteristic={'f_n': ...}, or f_n1, f_n2, f_anti)")


def _ballasted_extrema(table, dips: np.ndarray, search_band) -> dict[str, float]:
    """``f_n1, f_n2`` = the two lowest dips, ``f_anti`` = the highest peak between them."""
    if dips.size < 2:
        raise InputError(f"layout 'ballasted' needs two dips of |det(alpha^-1)| in {search_band} Hz, found "
                         f"{dips.size} (is it a ballasted track?): "
                         f"cannot set f_n1, f_n2 for the paper's constraints; {_WITHOUT_CONSTRAINTS}")
    f1, f2 = float(dips[0]), float(dips[1])
    peaks = table[(table["kind"] == "peak") & (table["f"] > f1) & (table["f"] < f2)]
    if peaks.empty:
        raise InputError(f"no peak of |det(alpha^-1)| between its dips at {f1:.4g} and {f2:.4g} Hz: "
                         f"cannot set f_anti for the paper's constraints; {_WITHOUT_CONSTRAINTS}")
    fa = float(peaks["f"].to_numpy(float)[np.argmax(peaks["magnitude"].to_numpy(float))])
    return {"f_n1": f1, "f_n2": f2, "f_anti": fa}


def fit_characteristic_frequencies(track: Track, layout: Layout, *, target: Target = None,
                                   search_band: tuple[float, float] = CHARACTERISTIC_SEARCH_BAND,
                                   df: float = 6.0) -> dict[str, float]:
    """The characteristic frequencies (Hz) that the paper's constraints need, detected on the track.

    They are extrema of ``|det(alpha^-1)|`` (Eq. 18), whose local minima are the resonances of
    the semi-infinite track (where the end dynamic stiffness is nearly singular):

    * slab: ``f_n`` = the dip closest to the bouncing-frequency estimate
      ``sqrt(kv / (rho A d)) / (2 pi)`` (Eq. 19-20 make both frequencies of every bar equal to it);
    * ballasted: ``f_n1``, ``f_n2`` = the two lowest dips and ``f_anti`` = the highest peak of
      ``|det(alpha^-1)|`` between them (the anti-resonance, Eq. 23, 28-30).

    Parameters
    ----------
    track : Track
        The track (its bouncing-frequency estimate selects the slab dip).
    layout : {"slab", "ballasted"}
        Which set to return.
    target : None, callable or (f, alpha), optional
        As in :func:`~semitrack.equivalent.fitting.fit_equivalent`: None for the exact
        receptance of ``track`` (searched with
        the grid and refinement of :func:`~semitrack.methods.features.characteristic_frequencies`,
        on det only), a callable ``alpha(f)``
        (extrema refined by Brent's method), or sampled ``(f, alpha)`` (parabolic refinement).
    search_band : (float, float)
        Frequency range searched (Hz); default the paper's 3-3000 Hz.
    df : float
        Grid step of the search (Hz).

    Returns
    -------
    dict
        ``{"f_n": ...}`` or ``{"f_n1": ..., "f_n2": ..., "f_anti": ...}`` in Hz.

    Raises
    ------
    ValueError
        When the needed extrema are not found in ``search_band``.

    Examples
    --------
    >>> import semitrack as st
    >>> round(st.fit_characteristic_frequencies(st.slab_track(), "slab")["f_n"], 1)
    183.7
    """
    layout = check_layout(layout)
    track = require_track(track)
    search_band = check_band(search_band, "search_band")
    if target is not None:
        target = normalise_target(target)
    else:  # keep to where a measured table is defined
        lo, hi = track.frequency_band
        search_band = check_band((max(search_band[0], lo), min(search_band[1], hi)), "search_band within the "
                                 f"track's measured band {lo:g}-{hi:g} Hz")
    table = _det_extrema(track, target, search_band, df)
    dips = np.sort(table.loc[table["kind"] == "dip", "f"].to_numpy(float))
    if layout == "ballasted":
        return _ballasted_extrema(table, dips, search_band)
    if dips.size == 0:
        raise InputError(f"no dip of |det(alpha^-1)| found in {search_band} Hz: cannot set f_n for the "
                         f"paper's constraints; {_WITHOUT_CONSTRAINTS}")
    f_b = track.bouncing_frequency_estimate
    return {"f_n": float(dips[np.argmin(np.abs(dips - f_b))])}


def resolve_characteristic(track: Track, layout: Layout, band: tuple[float, float], target,
                           characteristic: Mapping[str, float] | None) -> dict[str, float]:
    """The given characteristic frequencies, checked, or those detected on the (normalised) target.

    The search covers :data:`CHARACTERISTIC_SEARCH_BAND` and ``band`` (a sampled target: its
    samples).
    """
    if characteristic is not None:
        return check_characteristic(layout, characteristic)
    search = (min(CHARACTERISTIC_SEARCH_BAND[0], band[0]), max(CHARACTERISTIC_SEARCH_BAND[1], band[1]))
    if isinstance(target, tuple):
        search = (float(target[0][0]), float(target[0][-1]))
    return fit_characteristic_frequencies(track, layout, target=target, search_band=search)


# --- fit frequencies ---------------------------------------------------------------------------
def default_fit_frequencies(band: tuple[float, float], characteristic: Mapping[str, float] | None = None,
                            n: int = 80) -> np.ndarray:
    """The default fit frequencies (Hz).

    ``n // 2`` log-spaced and ``n - n // 2`` uniformly spaced frequencies over ``band`` (the
    log-spaced ones resolve the low-frequency end, the uniform ones weight the band as the
    dense error grid does), plus each characteristic frequency inside the band and its
    neighbours at +-1, 3 and 6 % (the receptance varies fastest around the resonances).

    Parameters
    ----------
    band : (float, float)
        Frequency range (Hz).
    characteristic : dict, optional
        Characteristic frequencies (Hz), e.g. from :func:`fit_characteristic_frequencies`.
    n : int
        Number of frequencies spread over the band, >= 4.

    Returns
    -------
    ndarray
        Sorted, unique frequencies (Hz).

    Examples
    --------
    >>> import semitrack as st
    >>> st.default_fit_frequencies((3.0, 900.0), {"f_n": 183.7}).size
    85
    """
    lo, hi = check_band(band)
    n = check_int_at_least("n", n, 4)
    check_work(n, MAX_FREQUENCIES, f"n={n} frequencies", "a fit needs a few hundred")
    characteristic = {} if characteristic is None else characteristic
    if not isinstance(characteristic, Mapping):
        raise InputTypeError(f"characteristic must be a dict of frequencies (Hz) by name, got "
                             f"{type(characteristic).__name__}")
    f = [np.geomspace(lo, hi, n // 2), np.linspace(lo, hi, n - n // 2)]
    for key, v in characteristic.items():
        extra = np.array([0.94, 0.97, 0.99, 1.0, 1.01, 1.03, 1.06]) * check_positive(f"characteristic[{key!r}]", v)
        f.append(extra[(extra >= lo) & (extra <= hi)])
    return np.unique(np.concatenate(f))


def _explicit_fit_frequencies(layout: Layout, fit_freqs) -> np.ndarray:
    """``"paper"`` or an array of frequencies, checked, sorted and unique."""
    if isinstance(fit_freqs, str):
        if fit_freqs != "paper":
            raise InputError(f"fit_freqs must be None, 'paper' or an array of frequencies (Hz), got {fit_freqs!r}")
        return np.array(_PAPER_FIT_FREQUENCIES[layout])
    f_fit = as_frequencies(fit_freqs, "fit_freqs")
    if f_fit.ndim != 1:
        raise InputError(f"fit_freqs must be one-dimensional, got shape {f_fit.shape}")
    return np.unique(f_fit)


def select_frequencies(layout: Layout, band: tuple[float, float], target, fit_freqs: FitFrequencies,
                       char: dict[str, float], error_df: float) -> tuple[np.ndarray, np.ndarray]:
    """The fit frequencies and the error frequencies (Hz) of a fit.

    The errors are measured on the dense grid of ``band`` (spacing <= ``error_df``) or, for a
    sampled target, on its samples in ``band``; those samples are also the default fit
    frequencies, otherwise :func:`default_fit_frequencies`.

    Returns
    -------
    f_fit, f_err : ndarray
    """
    if isinstance(target, tuple):
        f_s = target[0]
        f_err = f_s[(f_s >= band[0]) & (f_s <= band[1])]
        if f_err.size < 2:
            raise InputError(f"target must have at least 2 samples inside band {band} Hz, got {f_err.size}")
    else:
        f_err = error_band_grid(band, error_df)
    if fit_freqs is not None:
        return _explicit_fit_frequencies(layout, fit_freqs), f_err
    return (f_err if isinstance(target, tuple) else default_fit_frequencies(band, char)), f_err
