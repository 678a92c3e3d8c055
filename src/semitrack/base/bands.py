"""One-third-octave bands, base 10 (IEC 61260): the series every band average in the package uses.

The roughness spectra (wavelength bands, m), the contact force's band levels and the track decay
rate of EN 15461 (frequency bands, Hz) all read their centres and edges from
:func:`third_octave_bands`.
"""

from __future__ import annotations

import numpy as np

from .checks import check_in_range, check_positive, check_work
from .errors import InputError

__all__ = ["HALF_BAND", "MAX_BANDS", "third_octave_bands"]

#: Half the width of a one-third-octave band on a log10 scale (base-10 bands, IEC 61260).
HALF_BAND = 0.05
#: Most bands one call returns (a guard against a mistyped range).
MAX_BANDS = 100_000
#: The band centres one may ask for (Hz or m): their edges, a factor 10^(1/20) away, stay finite and normal.
BAND_RANGE = (1e-300, 1e300)


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
