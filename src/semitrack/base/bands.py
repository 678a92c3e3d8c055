"""One-third-octave bands, base 10 (IEC 61260): the series every band average in the package uses.

The roughness spectra (wavelength bands, m), the contact force's band levels and the track decay
rate of EN 15461 (frequency bands, Hz) all read their centres and edges from
:func:`third_octave_bands`.
"""

from __future__ import annotations

import numpy as np

from .checks import as_real_array, brief, check_in_range, check_positive, check_work
from .errors import InputError

__all__ = ["HALF_BAND", "MAX_BANDS", "R10", "band_index", "nominal_bands", "third_octave_bands"]

#: Half the width of a one-third-octave band on a log10 scale (base-10 bands, IEC 61260).
HALF_BAND = 0.05
#: Most bands one call returns (a guard against a mistyped range).
MAX_BANDS = 100_000
#: The band centres one may ask for (Hz or m): their edges, a factor 10^(1/20) away, stay finite and normal.
BAND_RANGE = (1e-300, 1e300)
#: The preferred numbers R10 within a decade: the nominal names of the one-third-octave bands
#: (IEC 61260, ISO 266), by which the standards tabulate their limits (1250 Hz names 1258.9 Hz).
R10 = (1.0, 1.25, 1.6, 2.0, 2.5, 3.15, 4.0, 5.0, 6.3, 8.0)
#: How far (in tenths of a decade) a value may lie from a band centre and still name it: the
#: nominal names sit within 0.041 of their centres (1600 against 1584.9), the next band 1 away.
_NAME_TOLERANCE = 0.1


def third_octave_bands(lo: float, hi: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The base-10 one-third-octave bands whose centres lie in ``[lo, hi]`` (within half a band).

    Centres are ``10^(n/10)`` for integers n (50 Hz is 10^1.7 = 50.12 Hz), edges a factor
    ``10^(+-1/20)`` away; the same series serves frequencies (Hz) and wavelengths (m).

    Parameters
    ----------
    lo, hi : float
        The lowest and highest band centre wanted (Hz or m), ``0 < lo <= hi``; nominal values
        such as 50 or 2500 select the band they name.

    Returns
    -------
    centres, lower, upper : ndarray
        Exact band centres and their lower and upper edges, ascending (units of ``lo``).

    Examples
    --------
    >>> c, lower, upper = third_octave_bands(50.0, 100.0)
    >>> c.round(1).tolist(), round(float(upper[0] / lower[0]), 4)
    ([50.1, 63.1, 79.4, 100.0], 1.2589)
    """
    lo, hi = check_positive("lo", lo), check_positive("hi", hi)
    for name, value in (("lo", lo), ("hi", hi)):  # the edges 10^(+-1/20) away stay finite and normal
        check_in_range(name, value, BAND_RANGE, "Hz or m: the bands' edges must be finite numbers")
    if not lo <= hi:
        raise InputError(f"hi must be >= lo={lo!r}, got {hi!r}")
    n = np.arange(round(10 * np.log10(lo)), round(10 * np.log10(hi)) + 1)
    check_work(n.size, MAX_BANDS, f"lo={lo!r} to hi={hi!r} give {n.size} bands", "ask for a narrower range")
    centres = 10.0 ** (n / 10)
    return centres, centres * 10**-HALF_BAND, centres * 10**HALF_BAND


def band_index(values, name: str = "band") -> np.ndarray:
    """The integer n of the band ``10^(n/10)`` each value names, exact centre or nominal name.

    Parameters
    ----------
    values : array_like
        Band centres or nominal names (Hz or m), positive.
    name : str
        The argument's name, for the error.

    Returns
    -------
    ndarray of int

    Raises
    ------
    InputError
        A value that names no band (more than a tenth of a band away from every centre).

    Examples
    --------
    >>> band_index([1250, 1258.925, 315]).tolist()
    [31, 31, 25]
    """
    values = as_real_array(values, name)
    if values.ndim > 1:
        raise InputError(f"{name} must be a number or a 1-D sequence of bands, got an array of shape {values.shape}")
    values = np.atleast_1d(values)
    if np.any((values < BAND_RANGE[0]) | (values > BAND_RANGE[1])):
        raise InputError(f"{name} must be band frequencies (Hz) or wavelengths (m) from {BAND_RANGE[0]:g} to "
                         f"{BAND_RANGE[1]:g}, got {brief(values)}")
    exponent = 10 * np.log10(values)
    n = np.rint(exponent)
    off = np.abs(exponent - n) > _NAME_TOLERANCE
    if np.any(off):
        raise InputError(f"{name} must name one-third-octave bands (a centre 10^(n/10) or its nominal name, "
                         f"e.g. 1250 or 1258.9), got {values[off][0]:g}")
    return n.astype(int)


def nominal_bands(centres) -> np.ndarray:
    """The nominal names of one-third-octave bands (IEC 61260): 1250 for 1258.9, 315 for 316.2.

    Parameters
    ----------
    centres : array_like
        Exact band centres (or names) ``10^(n/10)`` (Hz or m).

    Returns
    -------
    ndarray
        The R10 preferred number times the decade (:data:`R10`), to three significant digits.

    Examples
    --------
    >>> nominal_bands(third_octave_bands(100.0, 1000.0)[0]).tolist()
    [100.0, 125.0, 160.0, 200.0, 250.0, 315.0, 400.0, 500.0, 630.0, 800.0, 1000.0]
    """
    n = band_index(centres, "centres")
    decade, step = np.divmod(n, 10)
    return np.array([float(f"{R10[s] * 10.0 ** int(d):.3g}") for s, d in zip(step, decade)])
