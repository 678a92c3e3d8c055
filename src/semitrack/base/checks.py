"""Input checks shared by the package: each error names the parameter, its value and the rule."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike


def _is_real_number(value: object) -> bool:
    return isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, bool)


def check_real(name: str, value: object) -> float:
    """Return ``value`` as a float, or raise TypeError if it is not a real number."""
    if not _is_real_number(value):
        raise TypeError(f"{name} must be a real number, got {value!r} ({type(value).__name__})")
    return float(value)


def check_positive(name: str, value: object) -> float:
    """A real number that is > 0 and finite."""
    v = check_real(name, value)
    if not (math.isfinite(v) and v > 0):
        raise ValueError(f"{name} must be positive and finite, got {value!r}")
    return v


def check_nonnegative(name: str, value: object) -> float:
    """A real number that is >= 0 and finite."""
    v = check_real(name, value)
    if not (math.isfinite(v) and v >= 0):
        raise ValueError(f"{name} must be non-negative and finite, got {value!r}")
    return v


def check_string(name: str, value: object) -> str:
    """A ``str`` (labels such as a track's name)."""
    if not isinstance(value, str):
        raise TypeError(f"{name} must be a string, got {value!r}")
    return value


def check_choice(name: str, value: object, choices: tuple) -> object:
    """One of ``choices`` (e.g. a method name), compared with ``==``."""
    if value not in choices:
        raise ValueError(f"{name} must be one of {choices}, got {value!r}")
    return value


def check_int_at_least(name: str, value: object, minimum: int) -> int:
    """An integer (not a bool) that is >= ``minimum``."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise TypeError(f"{name} must be an integer, got {value!r} ({type(value).__name__})")
    if value < minimum:
        raise ValueError(f"{name} must be an integer >= {minimum}, got {value!r}")
    return int(value)


def as_frequencies(f: ArrayLike, name: str = "f") -> np.ndarray:
    """Frequencies in Hz as a float array (any shape); all must be positive and finite.

    Raises
    ------
    TypeError
        If ``f`` is not numeric.
    ValueError
        If ``f`` is empty or any value is <= 0, NaN or infinite.
    """
    try:
        arr = np.asarray(f, dtype=float)
    except (TypeError, ValueError):
        raise TypeError(f"{name} must be a number or an array of numbers in Hz, got {f!r}") from None
    if arr.size == 0:
        raise ValueError(f"{name} must hold at least one frequency, got an empty array")
    bad = ~(np.isfinite(arr) & (arr > 0))
    if np.any(bad):
        first = arr[bad].ravel()[0]
        raise ValueError(
            f"{name} must be positive and finite (Hz); {int(bad.sum())} value(s) are not, e.g. {first!r}"
        )
    return arr


def check_band(band: ArrayLike, name: str = "band") -> tuple[float, float]:
    """A frequency band ``(f_lo, f_hi)`` in Hz with ``0 < f_lo < f_hi``, both finite."""
    try:
        lo, hi = (float(b) for b in band)
    except (TypeError, ValueError):
        raise TypeError(f"{name} must be a pair of frequencies (f_lo, f_hi) in Hz, got {band!r}") from None
    if not (math.isfinite(lo) and math.isfinite(hi) and 0 < lo < hi):
        raise ValueError(f"{name} must satisfy 0 < {name}[0] < {name}[1] (finite, Hz), got {band!r}")
    return lo, hi
