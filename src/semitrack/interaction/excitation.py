"""What the wheels meet on the rail: each wheel's roughness and the profiles fixed on the rail, sampled once.

A roughness (:class:`semitrack.Roughness`) is given as the first wheel meets it; a wheel a
distance s further along +x meets it s / v earlier (:meth:`Roughness.shifted`), and all are faded
in over the run's ``ramp`` (:func:`semitrack.dynamics.signals.sin2_ramp`). A geometric
irregularity fixed on the rail (:class:`semitrack.DippedWeld`, :class:`semitrack.RailProfile`)
is met by each wheel where it is, ``r(x_i(t))``, on top of the roughness and not faded in.
Every route samples its input here (:func:`rail_input`).
"""

from __future__ import annotations

import warnings

import numpy as np

from ..base.errors import InputError, InputTypeError
from ..dynamics.signals import sin2_ramp
from ..model.irregularity import Irregularity
from ..model.roughness import Roughness

__all__ = ["rail_input", "profile_along"]


def rail_input(roughness: Roughness | None, x: np.ndarray, dt: float, ramp: float,
               profile: Irregularity | None = None) -> np.ndarray:
    """Each wheel's input ``r_i`` at each step (m, downward: r > 0 a dip), roughness faded in plus profile.

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
    return r if profile is None else r + profile_along(profile, x)


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


def profile_along(profile: Irregularity, x: np.ndarray) -> np.ndarray:
    """Each wheel's drop of the rail ``r(x_i(t))`` (m), checked zero where the wheels start.

    Parameters
    ----------
    profile : Irregularity
        The irregularity fixed on the rail.
    x : ndarray, shape (steps, wheels)
        The wheels' positions (m).

    Returns
    -------
    ndarray
        The shape of ``x`` (m, downward).
    """
    if not isinstance(profile, Irregularity):
        raise InputTypeError(f"profile must be an Irregularity (st.DippedWeld, st.RailProfile), got "
                             f"{type(profile).__name__}")
    r = profile(x)
    if np.any(r[0] != 0):
        raise InputError(f"the wheels must start off the profile (it spans {profile.extent} m): it is "
                         f"{r[0].tolist()} m under them at the start")
    lo, hi = profile.extent
    if hi < x.min() or lo > x.max():  # nothing silently ignored: a profile no wheel reaches is said so
        warnings.warn(f"the profile spans {lo:.6g} to {hi:.6g} m, and the wheels run from {x.min():.6g} to "
                      f"{x.max():.6g} m: no wheel meets it, and the run is that of a smooth rail; start the "
                      "wheels before it or run longer", RuntimeWarning, stacklevel=4)
    return r
