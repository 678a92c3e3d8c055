"""Defects of the wheel's tread: flats and out-of-roundness, as a radial deviation along the tread.

A defect is described by the tread's radial deviation ``p(u)`` (m) at arc length ``u`` (m) along
the nominal circle of radius R, positive where material is missing (the wheel's counterpart of a
dip in the rail, :mod:`semitrack.model.irregularity`). ``u = 0`` is the point of the tread in
contact at the start of a run; the wheel rolls onto ``u > 0``. A wheel's deviations add up
(:meth:`semitrack.Wheel.tread_profile`).

:class:`WheelFlat`
    a flat made by a wheel sliding locked on the rail. NEW, a chord of length l of the circle:
    depth d = R - sqrt(R^2 - l^2 / 4) and ``p = R - R cos(alpha) / cos(u / R)`` over the chord's
    half-angle ``alpha = asin(l / 2R)``. ROUNDED, the same flat worn round by running (the form
    of Newton & Clark 1979, used since by Dukkipati & Dong 1999 and Pieringer et al. 2014):
    ``p = (d / 2)(1 + cos(2 pi s / l))`` over the arc |s| < l / 2 about its centre, of depth
    d = l^2 / (16 R) unless given.
:class:`WheelPolygon`
    out-of-roundness of order n (n waves round the wheel): ``p = a cos(n u / R - phase)``.

What the wheel's centre does on the rail with these defects (it pivots about a new flat's edges
and bridges a rounded flat's hollow) is :func:`semitrack.wheel_centre_path`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..base.checks import (
    check_choice,
    check_in_range,
    check_int_at_least,
    check_nonnegative,
    check_positive,
    check_real,
)
from ..base.errors import InputError

__all__ = ["WheelDefect", "WheelFlat", "WheelPolygon", "FLAT_SHAPES", "MAX_DEFECT_DEPTH", "MAX_POLYGON_ORDER",
           "RADIUS_RANGE"]

#: The shapes a flat may have: as made (a chord) or worn round (a cosine).
FLAT_SHAPES = ("new", "rounded")
#: Deepest defect accepted (m): 1 cm, far beyond a flat that stays in service (about 1-3 mm).
MAX_DEFECT_DEPTH = 0.01
#: Longest flat (m): its chord is less than a wheel's diameter (the largest wheel's radius is 1 m).
MAX_FLAT_LENGTH = 2.0
#: The radii a wheel may have (m): from a 1 cm model wheel to 5 m, around every rail wheel (0.3-0.6 m).
RADIUS_RANGE = (0.01, 5.0)
#: Highest order of out-of-roundness accepted (waves per revolution): measured polygons reach ~30.
MAX_POLYGON_ORDER = 200


class WheelDefect:
    """A deviation of the tread from the wheel's circle (the base of :class:`WheelFlat`, :class:`WheelPolygon`)."""

    def _deviation(self, u: np.ndarray, radius: float) -> np.ndarray:
        """The radial deviation (m, positive where material is missing) at tread arc lengths ``u`` (m)."""
        raise NotImplementedError

    def _check_on(self, radius: float) -> None:
        """Raise :class:`semitrack.BadInput` if the defect cannot lie on a wheel of ``radius`` (m)."""
        raise NotImplementedError

    def _corners(self, radius: float) -> np.ndarray:
        """Arc lengths (m) where the tread has a corner, to be sampled exactly (none by default)."""
        return np.empty(0)

    def _span(self, radius: float) -> tuple[float, float] | None:
        """The arc lengths ``(start, end)`` (m, start may be negative) outside which the deviation is
        zero; None where it is nowhere zero."""
        return None


@dataclass(frozen=True)
class WheelFlat(WheelDefect):
    """A flat on the tread: its length, its depth, new or rounded, and where it is.

    Parameters
    ----------
    length : float
        Length of the flat (m): a new flat's chord, a rounded flat's arc (typically 20-100 mm).
    depth : float, optional
        Depth at the flat's centre (m). None (default): the depth its length gives on the wheel,
        ``R - sqrt(R^2 - l^2/4)`` new, ``l^2 / (16 R)`` rounded. A new flat's depth follows from its
        length; a depth given for one must be that one.
    shape : {"new", "rounded"}
        As made by a locked wheel (a chord, sharp edges) or worn round (a cosine dip).
    position : float
        Arc length on the tread (m) from the point in contact at the run's start to the flat's
        centre, in ``[0, 2 pi R)``: the wheel meets the flat's centre after rolling about this far.

    Examples
    --------
    >>> import semitrack as st
    >>> flat = st.WheelFlat(0.05)
    >>> round(flat.depth_on(0.46) * 1e3, 3)  # mm, a 50 mm new flat on a 0.46 m wheel
    0.68
    """

    length: float
    depth: float | None = None
    shape: str = "new"
    position: float = 0.0

    def __post_init__(self):
        object.__setattr__(self, "length", check_in_range("length", check_positive("length", self.length),
                                                          (0.0, MAX_FLAT_LENGTH), "m, a flat's chord"))
        if self.depth is not None:
            object.__setattr__(self, "depth", check_positive("depth", self.depth))
            check_in_range("depth", self.depth, (0.0, MAX_DEFECT_DEPTH), "m, a flat millimetres deep")
        check_choice("shape", self.shape, FLAT_SHAPES)
        object.__setattr__(self, "position", check_nonnegative("position", self.position))

    def depth_on(self, radius: float) -> float:
        """The flat's depth at its centre on a wheel of ``radius`` (m).

        Parameters
        ----------
        radius : float
            The wheel's radius R (m).

        Returns
        -------
        float
            ``depth`` if given, else ``R - sqrt(R^2 - l^2/4)`` (new) or ``l^2 / (16 R)`` (rounded) (m).
        """
        radius = check_in_range("radius", check_positive("radius", radius), RADIUS_RANGE, "m, a wheel's rolling radius")
        if self.depth is not None:
            return self.depth
        if self.shape == "new":
            if not self.length < 2 * radius:
                raise InputError(f"radius: a new flat of length {self.length!r} m is a chord, on a wheel of radius "
                                 f"above {0.5 * self.length!r} m, got {radius!r}")
            return self._chord_depth(radius)
        return self.length**2 / (16.0 * radius)

    def _chord_depth(self, radius: float) -> float:
        """The depth of a chord of ``length`` on a circle of ``radius`` (m): a new flat's."""
        return radius - math.sqrt(radius**2 - 0.25 * self.length**2)

    def _check_on(self, radius: float) -> None:
        circumference = 2 * math.pi * radius
        if self.shape == "new" and not self.length < 2 * radius:
            raise InputError(f"length of a new flat is a chord of the wheel, shorter than its diameter "
                             f"{2 * radius!r} m, got {self.length!r}")
        if not self.length < circumference:
            raise InputError(f"length of a flat must be shorter than the wheel's circumference {circumference!r} m, "
                             f"got {self.length!r}")
        if not self.position < circumference:
            raise InputError(f"position is an arc length on the tread, in [0, {circumference!r}) m for this wheel's "
                             f"circumference, got {self.position!r}")
        if self.shape == "new" and self.depth is not None:
            chord = self._chord_depth(radius)
            if not math.isclose(self.depth, chord, rel_tol=1e-3):
                raise InputError(f"depth of a new flat follows from its length: {chord!r} m for length="
                                 f"{self.length!r} m on a wheel of radius {radius!r} m, got {self.depth!r}; a flat of "
                                 "another depth is shape='rounded'")
        check_in_range("depth", self.depth_on(radius), (0.0, MAX_DEFECT_DEPTH), "m, a flat millimetres deep")

    def _deviation(self, u: np.ndarray, radius: float) -> np.ndarray:
        circumference = 2 * math.pi * radius
        s = np.mod(u - self.position + 0.5 * circumference, circumference) - 0.5 * circumference  # from its centre
        if self.shape == "new":
            alpha = math.asin(0.5 * self.length / radius)
            beta = s / radius
            inside = np.abs(beta) < alpha
            # the chord at distance R cos(alpha) from the centre, along the radius at angle beta
            return np.where(inside, radius - radius * math.cos(alpha) / np.cos(np.where(inside, beta, 0.0)), 0.0)
        d = self.depth_on(radius)
        return np.where(np.abs(s) < 0.5 * self.length, 0.5 * d * (1.0 + np.cos(2 * np.pi * s / self.length)), 0.0)

    def _span(self, radius: float) -> tuple[float, float]:
        half = 0.5 * self.length if self.shape == "rounded" else radius * math.asin(0.5 * self.length / radius)
        return (self.position - half, self.position + half)

    def _corners(self, radius: float) -> np.ndarray:
        if self.shape != "new":
            return np.empty(0)
        half = radius * math.asin(0.5 * self.length / radius)  # the chord's ends, as arc lengths
        return np.array([self.position - half, self.position + half])


@dataclass(frozen=True)
class WheelPolygon(WheelDefect):
    """Out-of-roundness of order n: ``p(u) = amplitude cos(order u / R - phase)``.

    Parameters
    ----------
    order : int
        Waves per revolution, 1 (eccentricity) to :data:`MAX_POLYGON_ORDER`.
    amplitude : float
        Amplitude of the radial deviation (m), half its peak to peak (a polygonal wheel: 0.01-0.1 mm).
    phase : float
        Phase (rad): material is most missing at ``u = R phase / order`` (and every ``2 pi R / order``).

    Examples
    --------
    >>> import semitrack as st
    >>> wheel = st.Wheel(defects=[st.WheelPolygon(order=20, amplitude=5e-5)])
    >>> float(wheel.tread_profile(0.0))
    5e-05
    """

    order: int
    amplitude: float
    phase: float = 0.0

    def __post_init__(self):
        order = check_int_at_least("order", self.order, 1)
        if order > MAX_POLYGON_ORDER:
            raise InputError(f"order must be from 1 to {MAX_POLYGON_ORDER} (waves per revolution), got {self.order!r}")
        object.__setattr__(self, "order", order)
        amplitude = check_nonnegative("amplitude", self.amplitude)
        check_in_range("amplitude", amplitude, (0.0, MAX_DEFECT_DEPTH), "m, out-of-roundness of a fraction of a mm")
        object.__setattr__(self, "amplitude", amplitude)
        phase = check_real("phase", self.phase)
        check_in_range("phase", phase, (-1e3, 1e3), "rad, an angle")
        object.__setattr__(self, "phase", phase)

    def _check_on(self, radius: float) -> None:
        pass  # any wheel carries it: its amplitude is bounded well below any radius

    def _deviation(self, u: np.ndarray, radius: float) -> np.ndarray:
        return self.amplitude * np.cos(self.order * np.asarray(u) / radius - self.phase)
