"""What the wheels meet on the rail: each wheel's roughness and the profiles fixed on the rail, sampled once.

A roughness (:class:`semitrack.Roughness`) is given as the first wheel meets it; a wheel a
distance s further along +x meets it s / v earlier (:meth:`Roughness.shifted`), and all are faded
in over the run's ``ramp`` (:func:`semitrack.dynamics.signals.sin2_ramp`). A geometric
irregularity fixed on the rail (:class:`semitrack.DippedWeld`, :class:`semitrack.RailProfile`)
is met by each wheel where it is, ``r(x_i(t))``, on top of the roughness and not faded in.
A wheel's own defects (:class:`semitrack.WheelFlat`, :class:`semitrack.WheelPolygon`) are met
as it turns, at the distance it has rolled, once per revolution. A wheel with
``contact="centre_path"`` (the default) meets the profile and its defects by its centre's path
over them (:func:`semitrack.wheel_centre_path`: its radius in the contact), one with
``contact="point"`` by the profile under its centre and the tread's deviation at the point in
contact. Every route samples its input here (:func:`rail_input`).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ..base.errors import InputError, InputTypeError
from ..base.notices import warn_user
from ..dynamics.signals import sin2_ramp
from ..model.centre_path import rail_drop, tread_drop, tread_rolling
from ..model.irregularity import DippedWeld, Irregularity, RailProfile
from ..model.roughness import Roughness
from ..model.wheel import Wheel

__all__ = ["rail_input", "profile_along"]


def rail_input(roughness: Roughness | None, x: np.ndarray, dt: float, ramp: float,
               profile: Irregularity | None = None, wheels: Sequence[Wheel] = (),
               rolled: np.ndarray | None = None) -> np.ndarray:
    """Each wheel's input ``r_i`` at each step (m, downward: r > 0 a dip): roughness faded in, profile, defects.

    Parameters
    ----------
    roughness : Roughness or None
        The roughness under the first wheel, at the speed the route runs (None: a smooth rail).
    x : ndarray, shape (n_steps + 1, k)
        The wheels' positions at each step (m); the roughness's shift between wheels is taken
        from the first row.
    dt : float
        Time step (s).
    ramp : float
        The roughness's fade-in (s).
    profile : Irregularity, optional
        A profile fixed on the rail, met where the wheels are (they must start off it).
    wheels : sequence of Wheel
        The k wheels: their contact (``"centre_path"`` or ``"point"``), radii and defects. Empty:
        point contacts of perfect wheels.
    rolled : ndarray, shape (n_steps + 1, k), optional
        The distance each wheel has rolled at each step (m), from 0; default ``x - x[0]`` (a
        stationary model's wheels turn too: it gives ``speed t``).

    Returns
    -------
    ndarray, shape (n_steps + 1, k)
    """
    rows, k = x.shape
    if roughness is None:
        r = np.zeros((rows, k))
    else:
        fade = sin2_ramp(dt * np.arange(rows), ramp)
        r = _roughness_under(roughness, x[0] - x[0, 0], dt, rows) * fade[:, None]
    if profile is not None:
        r = r + profile_along(profile, x, wheels)
    if any(w.defects for w in wheels):
        r = r + tread_along(wheels, x - x[0] if rolled is None else rolled)
    return r


def tread_along(wheels: Sequence[Wheel], rolled: np.ndarray) -> np.ndarray:
    """Each wheel's input from its own defects (m, downward) after rolling ``rolled`` (m), ``(steps, k)``.

    A wheel that does not reach a defect within the run is said so: its run is that of a perfect wheel.
    """
    r = np.zeros(rolled.shape)
    for i, wheel in enumerate(wheels):
        if not wheel.defects:
            continue
        if wheel.contact == "point":
            r[:, i] = wheel.tread_profile(rolled[:, i])
        else:
            r[:, i] = tread_drop(wheel, rolled[:, i])
        if not np.any(r[:, i]):
            reach = tread_rolling(wheel).period if wheel.contact == "centre_path" else wheel.circumference
            warn_user(f"wheel {i} rolls {np.ptp(rolled[:, i]):.6g} m in the run and meets none of its defects (it "
                      f"turns once per {reach:.6g} m): its run is a perfect wheel's; run longer, or place the "
                      "defect (its position) nearer the start", RuntimeWarning)
    return r


def _roughness_under(roughness: Roughness, shifts: np.ndarray, dt: float, rows: int) -> np.ndarray:
    """The roughness under wheels ``shifts`` (m) from the first at the steps ``k dt``, ``k < rows``: (rows, k) (m).

    Wheels whole steps ``speed dt`` apart (the moving Green's functions' grid) read one sampling of
    the roughness at different rows; others each their own.
    """
    steps = shifts / (roughness.speed * dt)
    whole = np.round(steps).astype(np.int64)
    if np.all(np.abs(steps - whole) <= 1e-9 * np.maximum(1.0, np.abs(steps))):
        low = int(whole.min())
        once = roughness.shifted(low * roughness.speed * dt).sampled(dt, rows + int(whole.max()) - low)
        return np.column_stack([once[g - low:g - low + rows] for g in whole])
    return np.column_stack([roughness.shifted(d).sampled(dt, rows) for d in shifts])


def profile_along(profile: Irregularity, x: np.ndarray, wheels: Sequence[Wheel] = ()) -> np.ndarray:
    """Each wheel's input from the rail's profile (m), checked zero where the wheels start.

    Parameters
    ----------
    profile : Irregularity
        The irregularity fixed on the rail.
    x : ndarray, shape (steps, wheels)
        The wheels' positions (m).
    wheels : sequence of Wheel
        The wheels: one with ``contact="centre_path"`` meets the profile by its centre's path over
        it (:func:`semitrack.model.centre_path.rail_drop`), one with ``"point"`` (or none given) by
        ``r(x_i(t))``.

    Returns
    -------
    ndarray
        The shape of ``x`` (m, downward).
    """
    if not isinstance(profile, Irregularity):
        raise InputTypeError(f"profile must be an Irregularity (st.DippedWeld, st.RailProfile), got "
                             f"{type(profile).__name__}")
    r = profile(x)
    for i, wheel in enumerate(wheels):
        if wheel.contact == "centre_path":
            if not isinstance(profile, (DippedWeld, RailProfile)):
                raise InputTypeError(f"profile: wheel {i} meets the rail by its centre's path, exact on a piecewise-"
                                     f"linear profile (st.DippedWeld, st.RailProfile), got {type(profile).__name__}; "
                                     "give the wheel contact='point' to meet it under its centre")
            r[:, i] = rail_drop(profile, wheel.radius, x[:, i])
    if np.any(r[0] != 0):
        raise InputError(f"the wheels must start off the profile (it spans {profile.extent} m): at x = "
                         f"{x[0].tolist()} m it is {r[0].tolist()} m under them at the start; start them elsewhere")
    lo, hi = profile.extent
    if hi < x.min() or lo > x.max():  # nothing silently ignored: a profile no wheel reaches is said so
        warn_user(f"the profile spans {lo:.6g} to {hi:.6g} m, and the wheels run from {x.min():.6g} to "
                  f"{x.max():.6g} m: no wheel meets it, and the run is that of a smooth rail; start the "
                  "wheels before it or run longer", RuntimeWarning)
    return r
