"""The path of a rigid wheel's centre rolled slowly over a rigid rail: the wheel's radius in the contact.

A wheel meets the rail over its outline, not at a point under its centre. Rolled slowly (no
dynamics, no elastic contact), a rigid wheel rests where its outline first touches the rail,
and its centre's drop below that of a perfect wheel on a smooth rail is the geometric input
that the Hertzian contact is fed with (the "wheel-centre trajectory" of impact studies). This
module computes it exactly in two cases, each by its own geometry:

a wheel with defects on a smooth rail (:func:`tread_drop`)
    the wheel rolls on the convex hull of its outline: it pivots about a new flat's edges and
    bridges a rounded flat's hollow. With ``h(theta)`` the hull's support function (the depth of
    its lowest point below the centre when the wheel has turned through ``theta``), rolling
    without slip on a line moves the centre by ``dx = h dtheta``; on the hull's vertex v (radius
    ``rho_v`` from the centre) the centre therefore runs on the arc ``R - sqrt(rho_v^2 - (x -
    c_v)^2)`` about the vertex's place ``c_v`` on the rail. The outline is sampled every
    :data:`TREAD_SPACING` with its corners exactly (a sag below 1e-10 m between samples).
a perfect wheel over a rail profile (:func:`rail_drop`)
    the circle rests on the piecewise-linear rail (a :class:`semitrack.DippedWeld`, a
    :class:`semitrack.RailProfile`) at the highest of its contacts with the knots and its
    tangencies with the segments, in closed form: it bridges a dip's bottom and pivots about
    its edges.

Both together (:func:`wheel_centre_path`) add up: exact while the defect and the rail's profile are
not under the wheel at the same time, an approximation where they are.

Convention: the drop is downward positive, as a dip in the rail (m), so that it enters the
contact as the rail's irregularity does (the approach is ``w_wheel - w_rail - r``). ``x`` is the
horizontal distance the centre has rolled from where the tread's origin ``u = 0`` was straight
below it (a flat at ``position = 0``: its centre), which differs from R times the rotation where
the wheel pivots.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ..base.checks import as_real_array, check_work
from ..base.errors import InputTypeError
from .irregularity import DippedWeld, Irregularity, RailProfile
from .wheel import Wheel

__all__ = ["TREAD_SPACING", "wheel_centre_path", "tread_drop", "rail_drop", "TreadRolling", "tread_rolling",
           "rail_knots"]

#: Arc length between the samples of a defective wheel's outline (m): the outline's sag between two
#: is ``TREAD_SPACING^2 / (8 R)``, 1e-10 m on a 0.46 m wheel.
TREAD_SPACING = 2e-5
#: Arc length between the samples of the intact circle between defects (m).
CIRCLE_SPACING = 1e-3
#: Most (position, rail knot) pairs one call of :func:`rail_drop` weighs.
MAX_RAIL_PAIRS = 5e8
_CHUNK = 2_000_000  # elements per block of the pairs


@dataclass(frozen=True)
class TreadRolling:
    """A defective wheel rolled on a line, one revolution: piece j is the arc about hull vertex j.

    Attributes
    ----------
    radius : float
        The wheel's nominal radius R (m).
    start : ndarray, shape (n,)
        The distance rolled (m) where each piece starts, from 0, increasing.
    pivot : ndarray, shape (n,)
        The vertex's place on the rail (m): the centre is above it at ``x = pivot``; NaN where the
        piece is the intact circle (no drop).
    rho : ndarray, shape (n,)
        The vertex's distance from the centre (m).
    period : float
        The distance rolled per revolution (m): the hull's perimeter, 2 pi R less what flats cut off.
    """

    radius: float
    start: np.ndarray
    pivot: np.ndarray
    rho: np.ndarray
    period: float

    def drop(self, x: np.ndarray) -> np.ndarray:
        """The centre's drop (m) after rolling ``x`` (m), periodic."""
        xm = np.mod(x, self.period)
        j = np.clip(np.searchsorted(self.start, xm, side="right") - 1, 0, self.start.size - 1)
        offset = xm - self.pivot[j]
        on_hull = np.isfinite(offset)  # elsewhere the intact circle: no drop
        safe = np.where(on_hull, offset, 0.0)
        return np.where(on_hull, self.radius - np.sqrt(np.maximum(self.rho[j] ** 2 - safe**2, 0.0)), 0.0)


@functools.lru_cache(maxsize=32)
def tread_rolling(wheel: Wheel) -> TreadRolling | None:
    """How ``wheel`` (a :class:`semitrack.Wheel`) rolls on a smooth rail; None for a perfect wheel.

    Parameters
    ----------
    wheel : Wheel
        The wheel, its defects on its nominal circle.

    Returns
    -------
    TreadRolling or None
    """
    if not wheel.defects:
        return None
    from scipy.spatial import ConvexHull  # only a defective wheel needs it

    R = wheel.radius
    u, corner = _outline_samples(wheel)
    deviation = wheel.tread_profile(u)
    rho = R - deviation
    beta = u / R
    points = np.column_stack([rho * np.sin(beta), -rho * np.cos(beta)])  # beta = 0 straight down, +x ahead
    vertices = ConvexHull(points).vertices  # counter-clockwise: beta increasing
    vertices = np.roll(vertices, -int(np.argmin(beta[vertices])))
    b, r = beta[vertices], rho[vertices]
    # a vertex on the intact circle supports the circle itself, on which the centre rolls level
    circle = (deviation[vertices] == 0) & ~corner[vertices]
    p = points[vertices]
    edge = np.roll(p, -1, axis=0) - p
    # edge j's outward normal's angle: vertex j supports gamma[j-1]..gamma[j]
    gamma = np.unwrap(np.arctan2(edge[:, 1], edge[:, 0]))
    gamma = gamma - 2 * math.pi * math.floor(gamma[0] / (2 * math.pi))  # gamma[0] in [0, 2 pi)
    # over three turns, clipped to the revolution 0 <= theta < 2 pi that starts at the run's start
    turns = np.concatenate([gamma - 2 * math.pi, gamma, gamma + 2 * math.pi])
    lo, hi = turns[:-1], turns[1:]
    vb, vr, vc = (np.concatenate([v, v, v])[1:] for v in (b, r, circle))
    keep = (hi > 0) & (lo < 2 * math.pi)
    lo, hi = np.maximum(lo[keep], 0.0), np.minimum(hi[keep], 2 * math.pi)
    vb, vr, vc = vb[keep], vr[keep], vc[keep]
    vb = np.where(vb - lo > math.pi, vb - 2 * math.pi, np.where(lo - vb > math.pi, vb + 2 * math.pi, vb))
    rolled = np.where(vc, R * (hi - lo), vr * (np.sin(hi - vb) - np.sin(lo - vb)))  # dx = h dtheta over the piece
    start = np.r_[0.0, np.cumsum(rolled)[:-1]]
    pivot = np.where(vc, np.nan, start - vr * np.sin(lo - vb))
    return TreadRolling(radius=R, start=start, pivot=pivot, rho=vr, period=float(np.sum(rolled)))


def _outline_samples(wheel: Wheel) -> tuple[np.ndarray, np.ndarray]:
    """Where the outline is sampled (arc lengths in [0, 2 pi R), m) and which are corners.

    Every :data:`TREAD_SPACING` over each defect (and a margin), every :data:`CIRCLE_SPACING` on
    the intact circle between (whose pieces roll exactly level, whatever the spacing), and the
    corners exactly.
    """
    R = wheel.radius
    circumference = 2 * math.pi * R
    spans = [d._span(R) for d in wheel.defects]
    if any(s is None for s in spans):  # a defect all round: the whole tread finely
        pieces = [np.linspace(0.0, circumference, int(math.ceil(circumference / TREAD_SPACING)), endpoint=False)]
    else:
        pieces = [np.linspace(0.0, circumference, int(math.ceil(circumference / CIRCLE_SPACING)), endpoint=False)]
        for a, b in spans:
            margin = 2e-3 + 0.1 * (b - a)
            pieces.append(np.arange(a - margin, b + margin, TREAD_SPACING))
    corners = np.mod(np.concatenate([d._corners(R) for d in wheel.defects]), circumference)
    u = np.unique(np.concatenate([np.mod(np.concatenate(pieces), circumference), corners]))
    corner = np.isin(u, corners)
    # a sample within 1e-9 m of a corner is dropped: the corner stands for it (sorted, so only neighbours)
    close = np.diff(u) <= 1e-9
    drop = ~corner & (np.r_[close & corner[1:], False] | np.r_[False, close & corner[:-1]])
    return u[~drop], corner[~drop]


def tread_drop(wheel: Wheel, x: ArrayLike) -> np.ndarray:
    """The centre's drop (m) of ``wheel`` rolled ``x`` (m) on a smooth rail (see the module docstring)."""
    x = as_real_array(x, "x")
    rolling = tread_rolling(wheel)
    return np.zeros(x.shape) if rolling is None else rolling.drop(x)


def rail_knots(rail: Irregularity, name: str = "rail") -> tuple[np.ndarray, np.ndarray]:
    """The knots ``(x, r)`` (m) of a piecewise-linear rail profile, zero at both ends.

    Parameters
    ----------
    rail : DippedWeld or RailProfile
        The profile.
    name : str
        Its parameter name in messages.

    Returns
    -------
    x, r : ndarray
    """
    if isinstance(rail, DippedWeld):
        lo, hi = rail.extent
        return np.array([lo, rail.x, hi]), np.array([0.0, rail.depth, 0.0])
    if isinstance(rail, RailProfile):
        return rail.x, rail.r
    raise InputTypeError(f"{name} must be None (a smooth rail), a DippedWeld or a RailProfile (piecewise linear, "
                         f"on which the wheel's rest is exact), got {type(rail).__name__}")


def rail_drop(rail: Irregularity, radius: float, x: ArrayLike, name: str = "rail") -> np.ndarray:
    """The centre's drop (m) of a perfect wheel of ``radius`` (m) over ``rail`` with its centre at ``x`` (m).

    The centre's height is the highest at which the circle touches the rail: at a knot
    ``(xi, r)``, ``sqrt(R^2 - (xi - x)^2) - r``; tangent to a segment of slope ``m`` (the drop
    per metre), ``R / sqrt(1 + m^2) - r(xi_t)`` at ``xi_t = x - m R / sqrt(1 + m^2)`` when that is
    on the segment; on the smooth rail beyond the profile, R.

    Parameters
    ----------
    rail : DippedWeld or RailProfile
        The rail's profile (m, downward positive).
    radius : float
        The wheel's radius (m).
    x : array_like
        The centre's positions along the rail (m).
    name : str
        The profile's parameter name in messages.

    Returns
    -------
    ndarray
        The drop at each (m, downward positive), the shape of ``x``.
    """
    x = as_real_array(x, "x")
    xk, rk = rail_knots(rail, name)
    R = radius
    flat = x.ravel()
    drop = np.zeros(flat.size)
    near = np.flatnonzero((flat > xk[0] - R) & (flat < xk[-1] + R))
    if near.size == 0:
        return drop.reshape(x.shape)
    dx = np.diff(xk)
    slope = np.diff(rk) / dx
    cos = 1.0 / np.sqrt(1.0 + slope**2)
    # knots within R of each position: a window over the sorted positions
    order = near[np.argsort(flat[near])]
    first = np.searchsorted(xk, flat[order] - R, side="left")
    last = np.searchsorted(xk, flat[order] + R, side="right")
    check_work(float(np.sum(last - first + 2)), MAX_RAIL_PAIRS, f"the wheel over a rail profile of {xk.size} knots at "
               f"{near.size} positions", "sample the profile more coarsely, or give fewer positions")
    i = 0
    while i < order.size:
        width = max(int(last[i:].max(initial=0) - first[i]), 1)
        j = min(order.size, i + max(1, _CHUNK // (width + 2)))
        lo, hi = int(first[i:j].min()), int(last[i:j].max())
        lo, hi = max(lo - 1, 0), min(hi + 1, xk.size)  # the segments reaching into the window too
        xs = flat[order[i:j]][:, None]
        kx, kr = xk[lo:hi][None, :], rk[lo:hi][None, :]
        reach = np.abs(kx - xs) < R
        height = np.where(reach, np.sqrt(np.maximum(R**2 - (kx - xs) ** 2, 0.0)) - kr, -np.inf).max(axis=1)
        seg = slice(lo, max(hi - 1, lo))
        m, c, a, w = slope[seg][None, :], cos[seg][None, :], xk[seg][None, :], dx[seg][None, :]
        touch = xs - m * R * c  # where the circle is tangent to the segment's line
        on = (touch >= a) & (touch <= a + w)
        tangent = np.where(on, R * c - (rk[seg][None, :] + m * (touch - a)), -np.inf)
        height = np.maximum(height, tangent.max(axis=1, initial=-np.inf))
        beyond = (xs[:, 0] <= xk[0]) | (xs[:, 0] >= xk[-1])  # the smooth rail under the centre
        height = np.where(beyond, np.maximum(height, R), height)
        drop[order[i:j]] = R - height
        i = j
    return drop.reshape(x.shape)


def wheel_centre_path(wheel: Wheel, x: ArrayLike, profile: Irregularity | None = None) -> np.ndarray:
    """The centre's height below a perfect wheel's on a smooth rail (m, downward positive), rolled slowly.

    A rigid ``wheel`` (its radius and defects, :class:`semitrack.Wheel`) rolled without slip over
    a rigid rail; the geometric input that the contact is fed with (module docstring). A
    wheel's centre drops into a flat by less than the flat's profile where it pivots about the
    edges (new) and by much less where it bridges the hollow (rounded).

    Parameters
    ----------
    wheel : Wheel
        The wheel.
    x : array_like
        The horizontal distance the centre has rolled (m), along the rail's coordinates: at
        ``x = 0`` the tread's origin (``u = 0``) is straight below it.
    profile : DippedWeld or RailProfile, optional
        The rail's profile (m, downward positive); None: a smooth rail.

    Returns
    -------
    ndarray
        The drop (m, downward positive: into a flat or a dip), the shape of ``x``.

    Examples
    --------
    >>> import semitrack as st
    >>> wheel = st.Wheel(radius=0.46, defects=[st.WheelFlat(0.05)])
    >>> float(wheel_centre_path(wheel, 0.0)) == wheel.defects[0].depth_on(0.46)
    True
    """
    if not isinstance(wheel, Wheel):
        raise InputTypeError(f"wheel must be a Wheel, got {type(wheel).__name__}")
    x = as_real_array(x, "x")
    drop = tread_drop(wheel, x)
    if profile is not None:
        drop = drop + rail_drop(profile, wheel.radius, x, name="profile")
    return drop
