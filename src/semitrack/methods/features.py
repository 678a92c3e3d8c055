"""Characteristic frequencies: peaks and dips of the track's response curves (paper Sec. 4.2, 5.1).

Extrema are found on a frequency grid and then refined between grid points, so results do not
depend on the grid step: with a callable (the exact method can be evaluated at any frequency) by
a bounded scalar minimisation of -log|y| or log|y| in the bracket around the grid extremum, and
with sampled data only by a parabola through the three grid points in log|y|.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike
from scipy.optimize import minimize_scalar

from ..base.checks import MAX_FREQUENCIES, as_frequencies, check_band, check_choice, check_positive, check_work
from ..base.conventions import ELEMENTS
from ..base.errors import InputError, InputTypeError
from ..base.paper_values import PAPER_GRID_BAND, PAPER_GRID_STEP
from ..model.tracks import PeriodicCell, Track, require_cell
from .receptance import CentralResponse, Method, central_response, check_frequency_work, semi_infinite_receptance

#: The curves of the paper's Fig. 4/10/5/11 in which peaks and dips are looked for: those of the
#: complete track, then the distinct receptance elements of :data:`semitrack.base.conventions.ELEMENTS`.
QUANTITIES = ("w1", "psi2", "Q2", "M1", "det", *ELEMENTS)
#: Evaluations the refinement of the extrema may add to the grid's, counted in the work check of
#: :func:`characteristic_frequencies` (Brent's method takes ~10-30 per extremum; a slab of many
#: fasteners has hundreds of extrema).
REFINEMENT_ALLOWANCE = 2_000


def response_curves(track: Track | PeriodicCell, f: ArrayLike, method: Method = "transfer",
                    **settings) -> dict[str, np.ndarray]:
    """The complex curves of :data:`QUANTITIES` at frequencies ``f``.

    w1, psi2, Q2, M1 and det(alpha^-1) describe the complete (infinite) track; alpha11, alpha12
    and alpha22 the semi-infinite track.

    Parameters
    ----------
    track : Track or PeriodicCell
        The track.
    f : array_like
        Frequencies (Hz), positive and finite.
    method : {"transfer", "wavenumber"}
        As for :func:`semitrack.central_response`.
    **settings
        Wavenumber settings, as for :func:`semitrack.central_response`.

    Returns
    -------
    dict of str to ndarray
        One complex array of the shape of ``f`` per quantity, in the units of
        :class:`semitrack.CentralResponse` and :data:`semitrack.base.conventions.ELEMENT_UNITS`.
    """
    r = central_response(track, f, method, **settings)
    if r.separable:
        return curves_of(r)
    # A cut inside a flexible slab: Eq. (14) and (18) do not hold there; alpha is that of the
    # track with its slab cut at the cut, and det is its end stiffness's determinant.
    return curves_of(r, semi_infinite_receptance(track, f, method, **settings))


def curves_of(r: CentralResponse, alpha: np.ndarray | None = None) -> dict[str, np.ndarray]:
    """The :data:`QUANTITIES` curves of an already computed :class:`CentralResponse`.

    Parameters
    ----------
    r : CentralResponse
        The central responses.
    alpha : ndarray, optional
        The semi-infinite track's receptance, shape ``r.f.shape + (2, 2)``; by default Eq. (14)
        from ``r``, and det(alpha^-1) by Eq. (18).
    """
    if alpha is None:
        alpha, det = r.alpha, r.det
    else:
        det = 1.0 / np.linalg.det(alpha)
    curves = {"w1": r.w1, "psi2": r.psi2, "Q2": r.Q2, "M1": r.M1, "det": det}
    return curves | {name: alpha[..., i, k] for name, (i, k) in ELEMENTS.items()}


def grid_extrema(y: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """Indices of interior local maxima and minima of ``|y|`` on a grid.

    A plateau of equal values counts once, at its first point.
    """
    m = np.abs(np.asarray(y))
    if m.ndim != 1 or m.size < 3:
        raise InputError(f"y must be a 1-D array with at least 3 points, got shape {m.shape}")
    left, mid, right = m[:-2], m[1:-1], m[2:]
    peaks = np.flatnonzero((mid > left) & (mid >= right)) + 1
    dips = np.flatnonzero((mid < left) & (mid <= right)) + 1
    return peaks, dips


def parabolic_refine(f: ArrayLike, y: ArrayLike, i: int) -> float:
    """Vertex of the parabola through (f, log|y|) at grid points i-1, i, i+1 (Hz)."""
    f = np.asarray(f, dtype=float)
    g = np.log(np.abs(np.asarray(y)[i - 1 : i + 2]))
    x = f[i - 1 : i + 2]
    denom = (x[0] - x[1]) * (x[0] - x[2]) * (x[1] - x[2])
    a = (x[2] * (g[1] - g[0]) + x[1] * (g[0] - g[2]) + x[0] * (g[2] - g[1])) / denom
    b = (x[2] ** 2 * (g[0] - g[1]) + x[1] ** 2 * (g[2] - g[0]) + x[0] ** 2 * (g[1] - g[2])) / denom
    if a == 0:
        return float(x[1])
    return float(np.clip(-b / (2 * a), x[0], x[2]))


def refine_extremum(func: Callable[[float], complex], f_lo: float, f_hi: float, kind: str,
                    xtol: float = 1e-3) -> float:
    """Frequency of the extremum of ``|func|`` in [f_lo, f_hi] (Hz), by bounded Brent search.

    Parameters
    ----------
    func : callable
        ``func(f) -> complex`` for a scalar frequency in Hz.
    f_lo, f_hi : float
        Bracket (Hz), normally the grid neighbours of the grid extremum.
    kind : {"peak", "dip"}
        Which extremum.
    xtol : float
        Absolute tolerance on the frequency (Hz).
    """
    check_choice("kind", kind, ("peak", "dip"))
    sign = -1.0 if kind == "peak" else 1.0
    res = minimize_scalar(lambda x: sign * np.log(abs(func(x))), bounds=(f_lo, f_hi), method="bounded",
                          options={"xatol": xtol})
    return float(res.x)


def _evaluated(evaluate: Callable, f: float, name: str) -> complex:
    """``evaluate(f)[name]``, refused naming ``evaluate`` when it does not give that curve's number."""
    values = evaluate(f)
    if not isinstance(values, Mapping) or name not in values or not _is_number(values[name]):
        raise InputError(f"evaluate must return a dict holding the number of curve {name!r} at f, got "
                         f"{type(values).__name__}")
    return values[name]


def _is_number(value: object) -> bool:
    return isinstance(value, (int, float, complex, np.number)) and not isinstance(value, (bool, np.bool_))


def find_extrema(f: ArrayLike, curves: dict[str, np.ndarray],
                 evaluate: Callable[[float], dict[str, complex]] | None = None) -> pd.DataFrame:
    """All peaks and dips of the magnitude of each curve, refined between grid points.

    Parameters
    ----------
    f : array_like
        The frequency grid (Hz), increasing.
    curves : dict of str to ndarray
        Complex curves sampled on ``f``.
    evaluate : callable, optional
        ``evaluate(f_scalar) -> dict`` of the same curves at any frequency; with it the extrema are
        refined by Brent's method, otherwise by a parabola through the grid points.

    Returns
    -------
    pandas.DataFrame
        Columns ``quantity, kind, f_grid, f (refined, Hz), magnitude``, sorted by quantity and f.
    """
    f = as_frequencies(f)
    if f.ndim != 1 or np.any(np.diff(f) <= 0):
        raise InputError("f must be a 1-D increasing frequency grid")
    if evaluate is not None and not callable(evaluate):
        raise InputTypeError(f"evaluate must be a function of f (Hz) or None, got {type(evaluate).__name__}")
    if not isinstance(curves, Mapping):
        raise InputTypeError(f"curves must be a dict of curves by name, got {type(curves).__name__}")
    rows = []
    for name, y in curves.items():
        y = np.asarray(y)
        if y.shape != f.shape or y.dtype.kind not in "iufc":
            raise InputError(f"curves[{name!r}] must be numbers sampled on f ({f.size} values), got "
                             f"{y.dtype} of shape {y.shape}")
        peaks, dips = grid_extrema(y)
        for kind, idx in (("peak", peaks), ("dip", dips)):
            for i in idx:
                if evaluate is None:
                    fr = parabolic_refine(f, y, i)
                else:
                    fr = refine_extremum(lambda x, n=name: _evaluated(evaluate, x, n), f[i - 1], f[i + 1], kind)
                mag = abs(_evaluated(evaluate, fr, name)) if evaluate is not None else float(np.abs(y[i]))
                rows.append((name, kind, float(f[i]), fr, mag))
    df = pd.DataFrame(rows, columns=["quantity", "kind", "f_grid", "f", "magnitude"])
    return df.sort_values(["quantity", "f"], ignore_index=True)


def characteristic_frequencies(track: Track | PeriodicCell, band: tuple[float, float] = PAPER_GRID_BAND,
                               df: float = PAPER_GRID_STEP) -> pd.DataFrame:
    """Peaks and dips of all :data:`QUANTITIES` of a track by the exact method.

    The grid is ``band[0], band[0] + df, ...`` up to ``band[1]``; each extremum is then refined
    to 1e-3 Hz with the exact method.

    Parameters
    ----------
    track : Track or PeriodicCell
        The track.
    band : tuple of float
        ``(f_lo, f_hi)`` of the search grid (Hz); the paper's grid by default (3-3000 Hz).
    df : float
        Step of the search grid (Hz); the paper's 6 Hz by default. The grid may hold at most
        :data:`semitrack.base.checks.MAX_FREQUENCIES` (200 000) frequencies.

    Returns
    -------
    pandas.DataFrame
        As :func:`find_extrema`: ``quantity, kind, f_grid, f (refined, Hz), magnitude``.
    """
    f = search_grid(check_band(band), df)
    check_frequency_work(require_cell(track), f.size + REFINEMENT_ALLOWANCE,
                         f"band={tuple(map(float, band))} Hz with df={df!r} Hz (and up to {REFINEMENT_ALLOWANCE} "
                         "refinements)")

    def evaluate(x: float) -> dict[str, complex]:
        return {k: v[0] for k, v in response_curves(track, np.array([x])).items()}

    return find_extrema(f, response_curves(track, f), evaluate)


def search_grid(band: tuple[float, float], df: float) -> np.ndarray:
    """The search grid ``band[0], band[0] + df, ...`` up to ``band[1]`` (Hz), checked.

    Parameters
    ----------
    band : tuple of float
        Lowest and highest frequency (Hz), already checked (:func:`semitrack.base.checks.check_band`).
    df : float
        Grid step (Hz), positive; the grid may hold at most
        :data:`semitrack.base.checks.MAX_FREQUENCIES` frequencies and needs at least 3.

    Returns
    -------
    ndarray
        The grid (Hz).
    """
    lo, hi = band
    df = check_positive("df", df)
    n_grid = np.floor((hi - lo) / df + 1e-9) + 1
    check_work(n_grid, MAX_FREQUENCIES, f"df={df!r} over band {(lo, hi)} gives {n_grid:.0f} grid frequencies",
               "use a larger df")
    f = np.arange(lo, hi + 1e-9, df)
    if f.size < 3:
        raise InputError(f"band {band!r} with df={df!r} gives fewer than 3 grid points; use a smaller df")
    return f
