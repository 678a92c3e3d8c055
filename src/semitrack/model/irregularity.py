"""Geometric irregularities fixed on the rail: a dipped weld or joint, or any measured profile.

A profile is the rail surface's vertical position along the rail, ``r(x)`` in metres, downward
positive (a dip is r > 0, the convention of the roughness, :mod:`semitrack.model.roughness`), in the
model's coordinates (m from the central mid-span). Unlike a roughness, which the package treats
as passing under a wheel, a profile stays where it is: a rolling wheel meets it at ``r(x(t))``.

:class:`DippedWeld`
    the classic V-shaped dip of a weld or a joint: two straight ramps of slope ``angle / 2``
    meeting at the dip, over ``length`` (m), so that the rail turns through ``angle`` (the
    "total dip angle 2 alpha" of Jenkins et al. 1974) at its bottom. Its kinks are where a wheel's
    vertical speed changes suddenly, ``v angle / 2`` in and out, which excite the high-frequency
    P1 force (wheel on the contact and the rail's local mass) and then the P2 force (unsprung
    mass on the track's stiffness) at the bottom.
:class:`RailProfile`
    any profile sampled along the rail (a measured weld geometry), linearly interpolated, zero
    outside its samples.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ..base.checks import as_real_array, check_in_range, check_positive, check_real, shown
from ..base.errors import InputError

__all__ = ["Irregularity", "DippedWeld", "RailProfile"]


class Irregularity:
    """A geometric irregularity fixed on the rail: ``r(x)`` (m, downward positive) at positions x (m)."""

    def __call__(self, x: ArrayLike) -> np.ndarray:
        raise NotImplementedError

    @property
    def extent(self) -> tuple[float, float]:
        """Where the profile is not zero (m)."""
        raise NotImplementedError


@dataclass(frozen=True)
class DippedWeld(Irregularity):
    """A V-shaped dip of total angle ``angle`` (rad) over ``length`` (m), its bottom at ``x`` (m).

    Parameters
    ----------
    angle : float
        The total dip angle 2 alpha (rad): each ramp falls by ``angle / 2`` m per m.
    length : float
        Length of the dip (m): the ramps run from ``x - length / 2`` to ``x + length / 2``.
    x : float
        Position of the bottom (m, model coordinates).

    Examples
    --------
    >>> weld = DippedWeld(angle=0.01, length=0.4, x=0.0)
    >>> weld.depth, float(weld(0.1))
    (0.001, 0.0005)
    """

    angle: float
    length: float = 0.4
    x: float = 0.0

    def __post_init__(self):
        object.__setattr__(self, "angle", check_positive("angle", self.angle))
        if self.angle > 0.2:
            raise InputError(f"angle is the total dip angle in rad (a weld: 0.005-0.05), got {self.angle!r}")
        object.__setattr__(self, "length", check_in_range("length", check_positive("length", self.length),
                                                           (0.0, 100.0), "m, a dip decimetres long"))
        object.__setattr__(self, "x", check_in_range("x", check_real("x", self.x), (-1e7, 1e7),
                                                      "m, a finite position on a line"))

    @property
    def depth(self) -> float:
        """Depth of the dip at its bottom (m)."""
        return 0.25 * self.angle * self.length

    @property
    def extent(self) -> tuple[float, float]:
        return (self.x - 0.5 * self.length, self.x + 0.5 * self.length)

    def __call__(self, x: ArrayLike) -> np.ndarray:
        """The rail surface's drop at x (m, downward positive).

        Parameters
        ----------
        x : array_like
            Positions (m).

        Returns
        -------
        ndarray
        """
        s = np.abs(as_real_array(x, "x") - self.x)
        return np.where(s < 0.5 * self.length, 0.5 * self.angle * (0.5 * self.length - s), 0.0)


@dataclass(frozen=True, eq=False)
class RailProfile(Irregularity):
    """A profile sampled along the rail, linearly interpolated, zero outside the samples.

    Parameters
    ----------
    x : array_like
        Increasing positions (m).
    r : array_like
        The rail surface's drop at each (m, downward positive); zero at both ends, so that the
        profile starts and ends on the undisturbed rail.
    """

    x: np.ndarray
    r: np.ndarray

    def __post_init__(self):
        x, r = (as_real_array(v, name, finite=False).ravel() for name, v in (("x", self.x), ("r", self.r)))
        if x.size < 2 or x.shape != r.shape or not np.all(np.isfinite(x) & np.isfinite(r)):
            raise InputError(f"x and r must be finite samples of the same size >= 2, got {x.size} and {r.size}")
        if not np.all(np.diff(x) > 0):
            raise InputError("x must be increasing positions (m)")
        if r[0] != 0 or r[-1] != 0:
            raise InputError(f"r must be zero at both ends (the undisturbed rail), got {shown(r[0])} and "
                             f"{shown(r[-1])} m")
        object.__setattr__(self, "x", x)
        object.__setattr__(self, "r", r)

    @property
    def extent(self) -> tuple[float, float]:
        return (float(self.x[0]), float(self.x[-1]))

    def __call__(self, x: ArrayLike) -> np.ndarray:
        """The rail surface's drop at x (m).

        Parameters
        ----------
        x : array_like
            Positions (m).

        Returns
        -------
        ndarray
        """
        return np.interp(as_real_array(x, "x"), self.x, self.r, left=0.0, right=0.0)
