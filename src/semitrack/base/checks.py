"""Input checks shared by the package: each error names the parameter, its value and the rule.

Besides bad values, the checks refuse work that no call can finish in reasonable time and memory
on a laptop (:func:`check_work`): a mistyped step must fail at once with a message, not after
minutes of swapping. The limits are module constants, stated in the docstrings that use them.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

from .errors import InputError, InputTypeError
from .notices import ImplausibleValueWarning, warn_user


def _is_real_number(value: object) -> bool:
    return isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, bool)


def check_real(name: str, value: object) -> float:
    """Return ``value`` as a float, or raise TypeError if it is not a real number."""
    if not _is_real_number(value):
        raise InputTypeError(f"{name} must be a real number, got {brief(value)} ({type(value).__name__})")
    try:
        return float(value)
    except OverflowError:  # an integer beyond the largest float (1.8e308)
        raise InputError(f"{name} must be a finite real number, got an integer of {len(str(value))} digits") from None


def check_positive(name: str, value: object) -> float:
    """A real number that is > 0 and finite."""
    v = check_real(name, value)
    if not (math.isfinite(v) and v > 0):
        raise InputError(f"{name} must be positive and finite, got {value!r}")
    return v


def check_nonnegative(name: str, value: object) -> float:
    """A real number that is >= 0 and finite."""
    v = check_real(name, value)
    if not (math.isfinite(v) and v >= 0):
        raise InputError(f"{name} must be non-negative and finite, got {value!r}")
    return v


#: The largest gap under a sleeper (m) taken without a warning: hanging sleepers hang over
#: 0.5-5 mm; a gap typed in millimetres as metres reads 1000 times too large.
PLAUSIBLE_GAP = 0.02


def check_gap(name: str, value: object) -> float:
    """A gap under a sleeper (m): >= 0 and finite; above :data:`PLAUSIBLE_GAP` it warns, naming the unit."""
    g = check_nonnegative(name, value)
    if g > PLAUSIBLE_GAP:
        warn_user(f"{name}={g:g} m is a gap of {1e3 * g:.0f} mm under a sleeper (hanging sleepers hang over "
                  f"0.5-5 mm): gaps are in metres, so {g:g} mm is {g * 1e-3:g} m", ImplausibleValueWarning)
    return g


def check_in_range(name: str, value: float, bounds: tuple[float, float], why: str) -> float:
    """A number (already checked real) within ``bounds`` inclusive; the message says the range and why.

    Parameters
    ----------
    name : str
        The parameter, for messages.
    value : float
        The value.
    bounds : (float, float)
        Lowest and highest value accepted.
    why : str
        The unit and the reason for the range, e.g. ``"kg, a physical wheel"``.

    Returns
    -------
    float
    """
    lo, hi = bounds
    if not lo <= value <= hi:
        raise InputError(f"{name} must be from {lo:g} to {hi:g} ({why}), got {value!r}")
    return value


#: Speeds a vehicle rolls at (m/s): from 1 mm/s (below it a run of any length stands still) to 1 km/s.
SPEED_RANGE = (1e-3, 1e3)


def check_rolling_speed(name: str, value: object) -> float:
    """A vehicle's speed along the rail (m/s), positive and within :data:`SPEED_RANGE`."""
    return check_in_range(name, check_positive(name, value), SPEED_RANGE, "m/s, a vehicle's")


#: Time steps (s): from 1 ns (a step of every stepped model is far longer) to 10 s.
TIME_STEP_RANGE = (1e-9, 10.0)


def check_time_step(name: str, value: object) -> float:
    """A time step (s), positive and within :data:`TIME_STEP_RANGE`."""
    return check_in_range(name, check_positive(name, value), TIME_STEP_RANGE, "s, a time step")


def check_string(name: str, value: object) -> str:
    """A ``str`` (labels such as a track's name)."""
    if not isinstance(value, str):
        raise InputTypeError(f"{name} must be a string, got {brief(value)}")
    return value


def check_choice(name: str, value: object, choices: tuple) -> object:
    """One of ``choices`` (e.g. a method name), compared with ``==``; an array is never one."""
    if isinstance(value, np.ndarray) or not any(_is_choice(value, c) for c in choices):
        raise InputError(f"{name} must be one of {choices}, got {brief(value)}")
    return value


def _is_choice(value: object, choice: object) -> bool:
    """``value`` is ``choice``: equal text, the same None or bool, or an equal value of the same type."""
    if isinstance(choice, str):
        return isinstance(value, str) and value == choice
    if choice is None or isinstance(choice, bool):
        return value is choice
    if _is_real_number(choice):
        return _is_real_number(value) and value == choice
    return type(value) is type(choice) and value == choice


def check_flag(name: str, value: object) -> bool:
    """A boolean (``True``/``False``, or numpy's): NaN, 1, ``'no'`` or an array are not read as one."""
    if not isinstance(value, (bool, np.bool_)):
        raise InputTypeError(f"{name} must be True or False, got {brief(value)} ({type(value).__name__})")
    return bool(value)


def check_int_at_least(name: str, value: object, minimum: int) -> int:
    """An integer (not a bool) that is >= ``minimum``."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise InputTypeError(f"{name} must be an integer, got {brief(value)} ({type(value).__name__})")
    if value < minimum:
        raise InputError(f"{name} must be an integer >= {minimum}, got {value!r}")
    return int(value)


#: Most frequencies that one call evaluates (~0.1 ms each by the exact method, ~50 ms by the
#: paper's; the batched solves hold ~1 kB per frequency at a time).
MAX_FREQUENCIES = 200_000


def check_work(size: float, limit: float, request: str, hint: str) -> None:
    """Refuse a request whose ``size`` (e.g. a number of grid points) exceeds ``limit``.

    Parameters
    ----------
    size : float
        The amount of work asked for (grid points, elements, time steps, ...).
    limit : float
        The most the function handles in reasonable time and memory.
    request : str
        What was asked, naming the parameter and its value, e.g.
        ``"df=1e-05 over band (3.0, 3000.0) gives 299700001 grid frequencies"``.
    hint : str
        How to ask for less (e.g. ``"use a larger df"``).

    Raises
    ------
    ValueError
        ``"<request>, more than the limit of <limit> (time and memory); <hint>"``.
    """
    if not size <= limit:  # also catches NaN
        raise InputError(f"{request}, more than the limit of {limit:.0f} (time and memory); {hint}")


#: Most time steps counted by :func:`check_steps` (beyond, no run is possible; the runs' own
#: limits, in ``dynamics.simulate.check_limits``, are far lower).
MAX_STEPS = 10**15


def check_steps(dt: float, duration: float, names: tuple[str, str] = ("dt", "duration"), ceil: bool = False) -> int:
    """The number of steps ``dt`` (checked > 0) takes to cover ``duration`` (checked > 0): at least one.

    Parameters
    ----------
    dt : float
        Time step (s).
    duration : float
        What the steps cover (s).
    names : (str, str)
        How messages call the two.
    ceil : bool
        Round the number of steps up (cover at least ``duration``); else to the nearest.

    Returns
    -------
    int

    Raises
    ------
    ValueError
        When ``dt`` is longer than ``duration`` (no step would be taken) or the count is beyond
        :data:`MAX_STEPS`, naming both values.
    """
    dt, duration = check_positive(names[0], dt), check_positive(names[1], duration)
    if dt > duration:
        raise InputError(f"{names[0]}={dt!r} s is longer than {names[1]}={duration!r} s: no step would be taken; "
                         f"give {names[0]} <= {names[1]}")
    ratio = duration / dt
    check_work(ratio, MAX_STEPS, f"{names[1]}={duration!r} s / {names[0]}={dt!r} s gives {ratio:.3g} steps",
               f"use a larger {names[0]}")
    return max(int(math.ceil(ratio - 1e-9 * ratio) if ceil else round(ratio)), 1)


#: Highest frequency any call takes (Hz): far above any track's physics (rolling noise stops near
#: 10 kHz; the ends' high-frequency limits are checked up to 1e8 Hz), far below where omega^2 m
#: overflows (1e276 Hz made every linear solve fail).
MAX_FREQUENCY = 1e9
#: Lowest frequency any call takes (Hz): far below any track's dynamics (a static limit is read at
#: 1e-9 Hz in the tests), far above where 1 / (omega^2 m) of a free mass overflows (1e-154 Hz, and a
#: complex division by zero at 1e-308 Hz).
MIN_FREQUENCY = 1e-12


def as_real_array(value: ArrayLike, name: str, *, finite: bool = True, ndim: int | None = None,
                  empty: bool = True) -> np.ndarray:
    """``value`` as a float array, or the package's refusal naming ``name``: never a raw numpy error.

    Strings (``'0.3'`` too), bytes, booleans, None, objects and ragged sequences are refused as a
    type error: a number is never read from text.

    Parameters
    ----------
    value : array_like
        A number or (nested) sequence of numbers.
    name : str
        The parameter, for messages.
    finite : bool
        Refuse NaN and infinities.
    ndim : int, optional
        The number of dimensions required (a scalar has 0).
    empty : bool
        Accept an empty array.

    Returns
    -------
    numpy.ndarray
        A new float array.

    Raises
    ------
    InputTypeError
        If ``value`` is not numbers.
    InputError
        If it has the wrong number of dimensions, is empty (``empty=False``) or not finite.
    """
    try:
        raw = np.array(value)
    except (TypeError, ValueError):  # a ragged sequence
        raise InputTypeError(f"{name} must be a number or an array of numbers, got a ragged sequence") from None
    if raw.dtype.kind not in "iuf":
        raise InputTypeError(f"{name} must be a number or an array of numbers, got {brief(value)} "
                             f"({type(value).__name__})")
    arr = raw.astype(float)
    if ndim is not None and arr.ndim != ndim:
        raise InputError(f"{name} must be {'a number' if ndim == 0 else f'a {ndim}-D array'}, got shape {arr.shape}")
    if not empty and arr.size == 0:
        raise InputError(f"{name} must hold at least one value, got an empty array")
    if finite and not np.all(np.isfinite(arr)):
        raise InputError(f"{name} must be finite, got {arr[~np.isfinite(arr)].ravel()[0]!r} in it")
    return arr


def shown(value: object) -> str:
    """A number as a message shows it: six significant digits, no type (``np.float64(23.77...)`` reads
    ``23.7778``); anything else as :func:`brief`."""
    if _is_real_number(value):
        return f"{float(value):.6g}"
    return brief(value)


def brief(value: object) -> str:
    """``repr(value)`` on one line, at most 60 characters: what a message quotes of a bad value."""
    text = " ".join(repr(value).split())
    return text if len(text) <= 60 else text[:57] + "..."


def as_frequencies(f: ArrayLike, name: str = "f") -> np.ndarray:
    """Frequencies in Hz as a float array (any shape); all must be positive and finite.

    At most :data:`MAX_FREQUENCIES` of them per call, each at most :data:`MAX_FREQUENCY`.

    Raises
    ------
    TypeError
        If ``f`` is not numeric: strings, booleans and None are refused, as for track parameters.
    ValueError
        If ``f`` is empty, holds too many frequencies, or any value is <= 0, NaN or infinite.
    """
    try:
        raw = np.asarray(f)
    except (TypeError, ValueError):  # e.g. a ragged list
        raw = np.asarray(None)
    if raw.dtype.kind not in "iuf":
        raise InputTypeError(f"{name} must be a number or an array of numbers in Hz, got {brief(f)}")
    arr = raw.astype(float)
    check_work(arr.size, MAX_FREQUENCIES, f"{name} holds {arr.size} frequencies", "split them over several calls")
    if arr.size == 0:
        raise InputError(f"{name} must hold at least one frequency, got an empty array")
    bad = ~(np.isfinite(arr) & (arr > 0))
    if np.any(bad):
        first = arr[bad].ravel()[0]
        raise InputError(
            f"{name} must be positive and finite (Hz); {int(bad.sum())} value(s) are not, e.g. {first!r}"
        )
    if arr.min() < MIN_FREQUENCY:
        raise InputError(f"{name} must be at least {MIN_FREQUENCY:g} Hz, got {arr.min()!r}: below it a free mass's "
                         "receptance overflows; a static value is the limit at low frequency")
    if arr.max() > MAX_FREQUENCY:
        raise InputError(f"{name} must be at most {MAX_FREQUENCY:g} Hz, got {arr.max()!r}: no track model here "
                         f"holds at such frequencies")
    return arr


def check_positive_pair(name: str, value: object) -> tuple[float, float]:
    """Two real numbers, each > 0 and finite (e.g. a fit's ``(median, max)`` error tolerances).

    Parameters
    ----------
    name : str
        The parameter, for messages.
    value : object
        The value to check.

    Returns
    -------
    tuple of float
    """
    try:
        a, b = value
    except (TypeError, ValueError):
        a = b = None
    if not (_is_real_number(a) and _is_real_number(b)):
        raise InputTypeError(f"{name} must be a pair of numbers, got {value!r}")
    if not all(math.isfinite(float(v)) and float(v) > 0 for v in (a, b)):
        raise InputError(f"{name} must be two positive finite numbers, got {value!r}")
    return float(a), float(b)


def check_band(band: ArrayLike, name: str = "band") -> tuple[float, float]:
    """A frequency band ``(f_lo, f_hi)`` in Hz with ``0 < f_lo < f_hi``, both finite."""
    try:
        lo, hi = band
    except (TypeError, ValueError):
        lo = hi = None
    if not (_is_real_number(lo) and _is_real_number(hi)):
        raise InputTypeError(f"{name} must be a pair of frequencies (f_lo, f_hi) in Hz, got {band!r}")
    lo, hi = float(lo), float(hi)
    if not (math.isfinite(lo) and math.isfinite(hi) and 0 < lo < hi):
        raise InputError(f"{name} must satisfy 0 < {name}[0] < {name}[1] (finite, Hz), got {band!r}")
    return lo, hi
