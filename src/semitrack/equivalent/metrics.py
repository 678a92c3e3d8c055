"""Error metrics between an equivalent system's receptance and the track's (paper Sec. 4.4).

The paper fits with the residuals ``Re(alpha_E - alpha)/|alpha|`` and ``Im(alpha_E - alpha)/|alpha|``;
the matching scalar error per element and frequency is the complex relative error
``|alpha_E - alpha| / |alpha|``, taken here for alpha11, alpha12 and alpha22 (alpha21 equals
alpha12 by reciprocity).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ..base.checks import MAX_FREQUENCIES, check_band, check_work
from ..base.conventions import ELEMENTS
from ..base.errors import InputError, InputTypeError
from ..base.fields import check_fields

# ELEMENTS (the compared elements and their (row, column) index) is re-exported from
# base.conventions, where every layer reads it.
__all__ = ["ELEMENTS", "ELEMENT_ERROR", "ELEMENT_ERROR_DEFINITION", "ErrorSummary", "receptance_errors",
           "error_summary", "error_band_grid"]

#: Name of the measure of :func:`error_summary`, as the book and the printed fits quote it. The
#: book defines it, beside the "worst-element error" of the derivation chapter (at each
#: frequency the largest of the element errors), in the derivation chapter.
ELEMENT_ERROR = "element error"

#: One-line definition of :data:`ELEMENT_ERROR`.
ELEMENT_ERROR_DEFINITION = "|alpha_E - alpha|/|alpha| of alpha11, alpha12, alpha22, pooled over the grid"


@dataclass(frozen=True)
class ErrorSummary:
    """Median and maximum relative error over frequency and the three elements.

    Attributes
    ----------
    median, max : float
        Over all frequencies and the three elements (-).
    per_element : dict
        ``{"alpha11": errors, "alpha12": errors, "alpha22": errors}``, arrays over frequency (-).
    """

    median: float
    max: float
    per_element: dict[str, np.ndarray]

    def __post_init__(self):
        check_fields(self)  # a record built by hand is refused here, not in a method

    def element_medians(self) -> dict[str, float]:
        """Median error of each element over frequency (-)."""
        return {name: float(np.median(e)) for name, e in self.per_element.items()}

    def element_maxima(self) -> dict[str, float]:
        """Maximum error of each element over frequency (-)."""
        return {name: float(np.max(e)) for name, e in self.per_element.items()}


def _as_receptance(name: str, alpha) -> np.ndarray:
    try:
        a = np.asarray(alpha, dtype=complex)
    except (TypeError, ValueError):
        raise InputTypeError(f"{name} must be an array of complex receptances, got {type(alpha).__name__}") from None
    if a.shape == (2, 2):
        a = a[None]
    if a.ndim != 3 or a.shape[1:] != (2, 2):
        raise InputError(f"{name} must have shape (n_f, 2, 2) or (2, 2), got {a.shape}")
    if not np.all(np.isfinite(a)):
        raise InputError(f"{name} must be finite, got {int((~np.isfinite(a)).sum())} non-finite entries")
    return a


def receptance_errors(alpha_eq: ArrayLike, alpha_ref: ArrayLike) -> dict[str, np.ndarray]:
    """Complex relative errors ``|alpha_E - alpha| / |alpha|`` per element and frequency.

    Parameters
    ----------
    alpha_eq : array_like, shape (n_f, 2, 2) or (2, 2)
        Receptance of the equivalent system (elements in m/N, 1/N, 1/N, rad/(N m)).
    alpha_ref : array_like, same shape
        Reference receptance (the semi-infinite track); must be non-zero where compared.

    Returns
    -------
    dict
        ``{"alpha11": e11, "alpha12": e12, "alpha22": e22}``, each of shape (n_f,) (-).
    """
    a_e = _as_receptance("alpha_eq", alpha_eq)
    a_r = _as_receptance("alpha_ref", alpha_ref)
    if a_e.shape != a_r.shape:
        raise InputError(f"alpha_eq and alpha_ref must have the same shape, got {a_e.shape} and {a_r.shape}")
    out = {}
    for name, (i, j) in ELEMENTS.items():
        ref = np.abs(a_r[:, i, j])
        if np.any(ref == 0):
            raise InputError(f"alpha_ref {name} must be non-zero for a relative error, got zero at index "
                             f"{int(np.argmax(ref == 0))}")
        out[name] = np.abs(a_e[:, i, j] - a_r[:, i, j]) / ref
    return out


def error_summary(alpha_eq: ArrayLike, alpha_ref: ArrayLike) -> ErrorSummary:
    """Median and maximum of the complex relative errors of :func:`receptance_errors`.

    Parameters
    ----------
    alpha_eq : array_like, shape (n_f, 2, 2) or (2, 2)
        Receptance of the equivalent system (elements in m/N, 1/N, 1/N, rad/(N m)).
    alpha_ref : array_like, same shape
        Reference receptance (the semi-infinite track); alpha11, alpha12 and alpha22 must be
        non-zero.

    Returns
    -------
    ErrorSummary
        Over all frequencies and the three elements (-).

    Examples
    --------
    >>> import numpy as np
    >>> import semitrack as st
    >>> ref = np.array([[1e-9, 2e-9], [2e-9, 5e-8]])
    >>> round(st.error_summary(1.1 * ref, ref).max, 12)
    0.1
    """
    errors = receptance_errors(alpha_eq, alpha_ref)
    allv = np.concatenate(list(errors.values()))
    return ErrorSummary(median=float(np.median(allv)), max=float(np.max(allv)), per_element=errors)


def error_band_grid(band: tuple[float, float], df: float = 3.0) -> np.ndarray:
    """A uniform frequency grid (Hz) from ``band[0]`` to ``band[1]`` inclusive, spacing <= ``df``.

    Parameters
    ----------
    band : (float, float)
        Lower and upper frequency (Hz), ``0 < band[0] < band[1]``, finite.
    df : float
        Largest allowed spacing (Hz), positive.

    Returns
    -------
    ndarray
        Equally spaced frequencies (Hz), at least 2.

    Examples
    --------
    >>> import semitrack as st
    >>> st.error_band_grid((3.0, 900.0)).size
    300
    """
    lo, hi = check_band(band)
    if isinstance(df, bool) or not isinstance(df, (int, float)) or not (math.isfinite(df) and df > 0):
        raise InputError(f"df must be positive and finite (Hz), got {df!r}")
    check_work((hi - lo) / df, MAX_FREQUENCIES, f"band={band!r} at df={df!r} Hz holds {(hi - lo) / df:.3g} frequencies",
               "give a larger df")
    n = int(math.ceil((hi - lo) / df - 1e-12)) + 1
    return np.linspace(lo, hi, max(n, 2))
