"""Support properties that depend on frequency: a pad's complex stiffness, a foundation's receptance.

A measured rail pad is stiffer and more lossy at high frequency than at rest, and a measured
sleeper (or slab) is a receptance table, not a mass on a spring (the paper's Eq. 3 lets
``k_v``, ``k_phi`` and the foundation receptance depend on frequency). A
:class:`FrequencyCurve` is such a property: evaluated at the frequencies of a call, it returns
complex values that already hold the damping (no loss factor is applied to them).

Two kinds, by what they relate:

* ``"stiffness"``: force per displacement (N/m; N m/rad for ``kphi``), a pad;
* ``"receptance"``: displacement per force (m/N) under the pad, the foundation of the paper's
  Eq. 3 (a sleeper on ballast, a slab). A measured mobility (m/s/N) or accelerance (m/s^2/N)
  table is converted to receptance when it is read: ``R = Y / (i omega) = -A / omega^2``.

Passivity is the one physical rule: a passive element takes in power at every frequency. With the
time factor ``exp(i omega t)`` that is ``Im k >= 0`` for a stiffness and ``Im R <= 0`` for a
receptance. The real part may have either sign: a foundation above its resonance (a mass) has a
negative real dynamic stiffness and is still passive. Every evaluation checks it at the
frequencies asked for, and a table is checked at its points when it is built (linear
interpolation of the real and imaginary parts then keeps the sign in between).

The curves:

* :class:`FrequencyTable`: a table of frequency and complex value, interpolated linearly in the
  real and imaginary parts; outside the table it refuses (default) or holds the end values,
  as the caller chose;
* :class:`FrequencyFunction`: any Python callable ``func(f) -> complex array``;
* :class:`StandardLinearSolid`: the causal three-parameter pad (a spring in series with a spring
  and dashpot in parallel), ``k(omega) = (k_static + i omega tau k_high) / (1 + i omega tau)``.

A curve is a frequency-domain description. The time-domain models refuse it: a measured curve is
not a causal system (:mod:`semitrack.fe.supports`).
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from ..base.checks import as_real_array, brief, check_choice, check_positive, check_string
from ..base.deprecation import renamed_keywords
from ..base.errors import InputError, InputTypeError

__all__ = ["CURVE_KINDS", "TABLE_QUANTITIES", "OUTSIDE", "FrequencyCurve", "FrequencyTable", "FrequencyFunction",
           "StandardLinearSolid", "as_curve", "stiffness_values", "check_passive"]

#: What a curve relates: a stiffness (a pad) or a receptance (the foundation under a pad).
CURVE_KINDS = ("stiffness", "receptance")
#: The quantities a table may hold, and the kind each becomes.
TABLE_QUANTITIES = {"stiffness": "stiffness", "receptance": "receptance", "mobility": "receptance",
                    "accelerance": "receptance"}
#: What a table does outside its frequencies: refuse the call, or hold its first and last values.
OUTSIDE = ("refuse", "hold")
#: Most points of a table (a measured curve has some thousands at most).
MAX_TABLE_POINTS = 100_000
#: Passivity is checked to this fraction of the value's magnitude: rounding in a conversion
#: (mobility to receptance) must not make a lossless table "active".
PASSIVITY_TOLERANCE = 1e-12


class FrequencyCurve:
    """A support property as a function of frequency: complex, damping included, checked passive.

    Subclasses implement ``_evaluate(f)``; :meth:`__call__` checks what it returns.

    Attributes
    ----------
    kind : {"stiffness", "receptance"}
        What the values relate (:data:`CURVE_KINDS`).
    """

    kind: str

    def __call__(self, f: ArrayLike, name: str = "curve", allow_zero: bool = False) -> np.ndarray:
        """The complex values at frequencies ``f`` (Hz), checked finite, passive and (by default) nonzero.

        Parameters
        ----------
        f : array_like
            Frequencies (Hz), >= 0, any shape.
        name : str
            What the curve is (e.g. ``"kv"``), for messages.
        allow_zero : bool
            Accept zero values (a rotational pad ``kphi`` may be 0; a vertical pad may not).

        Returns
        -------
        ndarray of complex
            The shape of ``f``: N/m (or N m/rad) for a stiffness, m/N for a receptance.

        Raises
        ------
        ValueError
            Naming ``name``, the first offending frequency and the rule.
        """
        f = as_real_array(f, "f", finite=False)
        values = np.asarray(self._evaluate(f))
        if values.dtype.kind not in "iufc":
            raise InputTypeError(f"{name}: the curve returned {values.dtype} values, not numbers")
        try:
            values = np.broadcast_to(values.astype(complex), f.shape)
        except ValueError:
            raise InputError(f"{name}: the curve returned shape {values.shape} for frequencies of shape "
                             f"{f.shape}; it must return one value per frequency") from None
        check_passive(name, self.kind, f, values, allow_zero)
        return values

    def _evaluate(self, f: np.ndarray) -> np.ndarray:  # pragma: no cover - abstract
        raise NotImplementedError

    @property
    def domain(self) -> tuple[float, float]:
        """The frequencies (Hz) at which the curve gives values: all, unless a table refuses beyond its band."""
        return 0.0, math.inf

    def key(self) -> list:
        """A canonical identity (for caches): the curve's parameters or data.

        Raises
        ------
        TypeError
            For a curve without a stable identity (a Python callable).
        """
        raise InputTypeError(f"a {type(self).__name__} has no stable identity to key a cache by (a Python "
                             "function's code and state): call the uncached function, or give the curve as a "
                             "FrequencyTable")

    def sample(self, f: float) -> complex:
        """The value at one frequency, for the estimates that only need a scale (the bouncing
        frequency, a fit's starting point): read at the nearest frequency of :attr:`domain`.

        Parameters
        ----------
        f : float
            Frequency (Hz).

        Returns
        -------
        complex
        """
        lo, hi = self.domain
        return complex(self(np.array([min(max(float(f), lo), hi)]), "curve")[0])


def check_passive(name: str, kind: str, f: np.ndarray, values: np.ndarray, allow_zero: bool = False) -> None:
    """Refuse values that are not finite, zero, or would make the support give out power.

    Parameters
    ----------
    name : str
        What the values are, for messages.
    kind : {"stiffness", "receptance"}
        Stiffness: ``Im k >= 0``; receptance: ``Im R <= 0`` (time factor ``exp(i omega t)``).
    f : ndarray
        Their frequencies (Hz).
    values : ndarray of complex
        The values, the shape of ``f``.
    allow_zero : bool
        Accept a zero stiffness (no support in that direction).

    Notes
    -----
    At 0 Hz the rule is the static one: ``Re k(0) >= 0`` (``Re R(0) >= 0``); a negative static
    stiffness is unstable, not merely lossless. At other frequencies the real part may have either
    sign (a mass above its resonance).
    """
    bad = ~np.isfinite(values)
    if np.any(bad):
        i = np.flatnonzero(bad.ravel())[0]
        raise InputError(f"{name} is not finite at {f.ravel()[i]:g} Hz of f: got {values.ravel()[i]!r}")
    if kind == "stiffness" and not allow_zero and np.any(values == 0):
        i = np.flatnonzero(values.ravel() == 0)[0]
        raise InputError(f"{name} is zero at {f.ravel()[i]:g} Hz: a pad that carries nothing is no support "
                         "(remove the support instead)")
    sign = 1.0 if kind == "stiffness" else -1.0
    active = sign * values.imag < -PASSIVITY_TOLERANCE * np.abs(values)
    if np.any(active):
        i = np.flatnonzero(active.ravel())[0]
        rule = "Im(k) >= 0" if kind == "stiffness" else "Im(R) <= 0"
        raise InputError(f"{name} is not passive at {f.ravel()[i]:g} Hz: {values.ravel()[i]:.6g} breaks {rule} "
                         f"(with exp(i omega t), a passive {kind} takes in power at every frequency)")
    static = (f == 0) & (values.real < 0)
    if np.any(static):
        raise InputError(f"{name} is {values[static].ravel()[0]:.6g} at 0 Hz: a negative static {kind} is unstable; "
                         "a passive support has Re >= 0 at rest")


@dataclass(frozen=True, eq=False)
class FrequencyTable(FrequencyCurve):
    """A measured or computed curve: complex values at frequencies, interpolated in between.

    Parameters
    ----------
    f : array_like
        Frequencies (Hz), >= 0, strictly increasing, at least two.
    values : array_like of complex
        The values at ``f``, in the units of ``quantity``: N/m or N m/rad (stiffness), m/N
        (receptance), m/(s N) (mobility), m/(s^2 N) (accelerance).
    quantity : {"stiffness", "receptance", "mobility", "accelerance"}
        What the table holds (:data:`TABLE_QUANTITIES`); mobility and accelerance become a
        receptance (:attr:`kind`), which needs ``f > 0``.
    outside : {"refuse", "hold"}
        Below the first or above the last frequency: refuse the call (default: no value is made
        up), or hold the end value (a choice the caller makes knowingly).
    source : str
        Where the table comes from, quoted in messages.
    file : str or None
        The CSV file it was read from (:func:`semitrack.load_frequency_table`), which a track
        file written from the track refers to; None for a table built in Python.

    Attributes
    ----------
    points : ndarray of complex
        The values at ``f`` as the curve gives them: ``values`` for a stiffness or a receptance,
        the receptance a mobility or an accelerance stands for (``Y / (i omega)``, ``-A / omega^2``).

    Notes
    -----
    The real and imaginary parts are interpolated linearly in frequency: a passive table stays
    passive in between, and the curve is exact at the points. The values follow the package's
    time factor ``exp(i omega t)``; a table in the ``exp(-i omega t)`` convention holds the complex
    conjugates (a receptance or a stiffness then fails the passivity check; a mobility would
    pass it with the sign of Re R flipped, which is why a receptance that starts negative, a mass
    at the lowest frequency, is warned about).

    Two tables are equal when their data, quantity and ``outside`` are (not their labels).
    """

    f: np.ndarray
    values: np.ndarray
    quantity: str = "stiffness"
    outside: str = "refuse"
    source: str = "table"
    file: str | None = None
    kind: str = field(init=False)
    points: np.ndarray = field(init=False, repr=False)

    def __post_init__(self):
        check_string("source", self.source)
        check_choice("quantity", self.quantity, tuple(TABLE_QUANTITIES))
        check_choice("outside", self.outside, OUTSIDE)
        f = _real_array(f"{self.source}: f", self.f)
        values = _complex_array(f"{self.source}: values", self.values)
        if f.ndim != 1 or values.shape != f.shape:
            raise InputError(f"{self.source}: f and values must be 1-D and of one length, got shapes "
                             f"{f.shape} and {values.shape}")
        if not 2 <= f.size <= MAX_TABLE_POINTS:
            raise InputError(f"{self.source}: a table needs 2 to {MAX_TABLE_POINTS} frequencies, got {f.size}")
        if not (np.all(np.isfinite(f)) and f[0] >= 0 and np.all(np.diff(f) > 0)):
            raise InputError(f"{self.source}: the frequencies must be finite, >= 0 and strictly increasing, "
                             f"got {_first_bad_order(f)}")
        kind = TABLE_QUANTITIES[self.quantity]
        if self.quantity in ("mobility", "accelerance"):
            if f[0] == 0:
                raise InputError(f"{self.source}: a {self.quantity} table cannot start at 0 Hz (its receptance "
                                 "is infinite there); start at the first measured frequency")
        omega = 2 * np.pi * f
        points = {"mobility": lambda: values / (1j * omega), "accelerance": lambda: -values / omega**2}.get(
            self.quantity, lambda: values.copy())()
        for arr in (f, values, points):
            arr.setflags(write=False)
        object.__setattr__(self, "f", f)
        object.__setattr__(self, "values", values)
        object.__setattr__(self, "points", points)
        object.__setattr__(self, "kind", kind)
        check_passive(f"{self.source} ({self.quantity})", kind, f, points, allow_zero=kind == "stiffness")
        if kind == "receptance" and points[0].real < 0:
            warnings.warn(f"{self.source}: the receptance at the table's lowest frequency, {f[0]:g} Hz, has a negative "
                          "real part (a mass there); if the table was measured with the time factor exp(-i omega t), "
                          "conjugate its values", RuntimeWarning, stacklevel=3)

    @property
    def band(self) -> tuple[float, float]:
        """The frequencies the table covers (Hz)."""
        return float(self.f[0]), float(self.f[-1])

    @property
    def domain(self) -> tuple[float, float]:
        """The table's band, or all frequencies when it holds its end values (Hz)."""
        return self.band if self.outside == "refuse" else (0.0, math.inf)

    def _evaluate(self, f: np.ndarray) -> np.ndarray:
        lo, hi = self.band
        if self.outside == "refuse":
            out = (f < lo * (1 - 1e-12)) | (f > hi * (1 + 1e-12))
            if np.any(out):
                raise InputError(f"{self.source} covers {lo:g}-{hi:g} Hz and was asked for {f[out].ravel()[0]:g} Hz: "
                                 "extend the table, keep to its band, or let it hold its end values "
                                 "(outside='hold'; in a track file outside = \"hold\")")
        fc = np.clip(f, lo, hi)
        return np.interp(fc, self.f, self.points.real) + 1j * np.interp(fc, self.f, self.points.imag)

    def key(self) -> list:
        return ["table", self.kind, self.outside, self.f.tobytes().hex(), self.points.tobytes().hex()]

    def __eq__(self, other: object) -> bool:
        return isinstance(other, FrequencyTable) and self.key() == other.key()

    def __hash__(self) -> int:
        return hash(tuple(self.key()))

    def __repr__(self) -> str:
        lo, hi = self.band
        return f"FrequencyTable({self.source!r}, {self.kind}, {self.f.size} points, {lo:g}-{hi:g} Hz)"


@dataclass(frozen=True, eq=False)
class FrequencyFunction(FrequencyCurve):
    """A curve given as a Python function of frequency.

    Parameters
    ----------
    func : callable
        ``func(f) -> values``: ``f`` an ndarray of frequencies (Hz), the values complex (N/m or
        N m/rad for a stiffness, m/N for a receptance), one per frequency.
    quantity : {"stiffness", "receptance"}
        What the values relate (its :attr:`kind`; ``kind=`` until 0.3, as :class:`FrequencyTable`
        names it).
    name : str
        A label for messages.
    """

    func: Callable[[np.ndarray], ArrayLike]
    quantity: str = "stiffness"
    name: str = "function"
    kind: str = field(init=False)

    def __post_init__(self):
        if not callable(self.func):
            raise InputTypeError(f"func must be callable as func(f) -> complex values, got {type(self.func).__name__}")
        object.__setattr__(self, "kind", check_choice("quantity", self.quantity, CURVE_KINDS))
        check_string("name", self.name)

    def _evaluate(self, f: np.ndarray) -> np.ndarray:
        return self.func(f)

    def __repr__(self) -> str:
        return f"FrequencyFunction({self.name!r}, {self.kind})"


FrequencyFunction.__init__ = renamed_keywords({"kind": "quantity"})(FrequencyFunction.__init__)


@dataclass(frozen=True)
class StandardLinearSolid(FrequencyCurve):
    """The causal three-parameter pad: stiffer and lossier with frequency, passive by construction.

    ``k(omega) = (k_static + i omega tau k_high) / (1 + i omega tau)``: ``k_static`` at rest,
    ``k_high`` at high frequency, the change around ``1 / (2 pi tau)``. It is a spring ``k_high``
    in series with a spring ``k_static k_high / (k_high - k_static)`` and a dashpot in parallel
    (:meth:`series_form`), so a time-domain model can carry it as a massless internal DOF.

    Parameters
    ----------
    k_static : float
        Stiffness at 0 Hz (N/m, or N m/rad for a rotational pad), > 0.
    k_high : float
        Stiffness as the frequency grows without bound, >= ``k_static``.
    tau : float
        Relaxation time (s), > 0.
    """

    k_static: float
    k_high: float
    tau: float
    kind: str = field(default="stiffness", init=False)

    def __post_init__(self):
        k0 = check_positive("k_static", self.k_static)
        k1 = check_positive("k_high", self.k_high)
        if k1 < k0:
            raise InputError(f"k_high must be >= k_static for a passive standard linear solid, got k_high={k1!r} "
                             f"< k_static={k0!r}")
        object.__setattr__(self, "k_static", k0)
        object.__setattr__(self, "k_high", k1)
        object.__setattr__(self, "tau", check_positive("tau", self.tau))

    def _evaluate(self, f: np.ndarray) -> np.ndarray:
        iwt = 2j * np.pi * f * self.tau
        return (self.k_static + iwt * self.k_high) / (1 + iwt)

    def series_form(self) -> tuple[float, float, float]:
        """The spring ``k1`` in series with a spring ``k2`` and a dashpot ``c`` in parallel.

        Returns
        -------
        k1, k2, c : float
            N/m, N/m and N s/m (``k2`` is infinite when ``k_high == k_static``).
        """
        k0, k1 = self.k_static, self.k_high
        k2 = math.inf if k1 == k0 else k0 * k1 / (k1 - k0)
        return k1, k2, self.tau * (k1 + k2) if math.isfinite(k2) else math.inf

    def key(self) -> list:
        return ["standard linear solid", self.k_static, self.k_high, self.tau]


def as_curve(name: str, value: object, kind: str) -> float | FrequencyCurve:
    """A Track field that may depend on frequency: a number as it is, a curve of the right kind.

    Parameters
    ----------
    name : str
        The field (e.g. ``"kv"``), for messages.
    value : number, FrequencyCurve or callable
        A callable becomes a :class:`FrequencyFunction` of ``kind``.
    kind : {"stiffness", "receptance"}
        What the field must relate.

    Returns
    -------
    float or FrequencyCurve
        A number is returned unchecked (the field's own rule applies to it).
    """
    if isinstance(value, FrequencyCurve):
        if value.kind != kind:
            raise InputError(f"{name} must be a {kind} curve, got a {value.kind} curve {value!r}")
        return value
    if callable(value):
        return FrequencyFunction(value, kind, name)
    return value


def stiffness_values(name: str, value: float | FrequencyCurve, f: np.ndarray, factor: ArrayLike,
                     allow_zero: bool = False) -> np.ndarray:
    """A stiffness field at frequencies ``f`` (Hz): a curve's values, or the number times ``factor``.

    ``factor`` is the number's damping, ``1 + i eta`` (a curve holds its own); ``allow_zero`` as
    for :meth:`FrequencyCurve.__call__` (a rotational pad may be 0).
    """
    if isinstance(value, FrequencyCurve):
        return value(f, name, allow_zero)
    return value * np.asarray(factor)


def _array(name: str, value: object) -> np.ndarray:
    """A private copy of ``value`` as an array; a ragged or unreadable sequence is refused, naming ``name``."""
    if isinstance(value, (str, bytes)):
        raise InputTypeError(f"{name} must be numbers, got {brief(value)}")
    try:
        return np.array(value, copy=True)
    except (TypeError, ValueError):  # a ragged sequence, or objects numpy cannot hold as one array
        raise InputTypeError(f"{name} must be numbers (one value per frequency), got {brief(value)}") from None


def _real_array(name: str, value: object) -> np.ndarray:
    arr = _array(name, value)
    if arr.dtype.kind not in "iuf":
        raise InputTypeError(f"{name} must be real numbers, got {arr.dtype}")
    return arr.astype(float)


def _complex_array(name: str, value: object) -> np.ndarray:
    arr = _array(name, value)
    if arr.dtype.kind not in "iufc":
        raise InputTypeError(f"{name} must be numbers, got {arr.dtype}")
    return arr.astype(complex)


def _first_bad_order(f: np.ndarray) -> str:
    if not np.all(np.isfinite(f)):
        return f"a non-finite frequency {f[~np.isfinite(f)][0]!r}"
    if f[0] < 0:
        return f"a negative frequency {f[0]!r}"
    i = int(np.flatnonzero(np.diff(f) <= 0)[0])
    return f"{f[i]:g} Hz followed by {f[i + 1]:g} Hz"

