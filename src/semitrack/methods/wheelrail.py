"""The linear wheel-rail force per unit roughness: the classical frequency-domain result.

A roughness r(x) on the running surfaces, passed at speed v, excites wheel and rail at
f = v / wavelength. Wheel, contact and rail act in series: with the receptances alpha_W of the
wheel (:meth:`semitrack.Wheel.receptance`), alpha_C = 1 / k_H of the contact linearised at the
preload and alpha_R(x) of the infinite rail at the contact point (:func:`point_receptance`,
exact), the dynamic contact force is

    F / r = -1 / (alpha_W + alpha_C + alpha_R(x)).

Sign convention: r is the rail surface's displacement, downward like w, so r > 0 is a dip that
relieves the contact; F is the compression, positive when wheel and rail press together. The
rail's receptance is that of a stationary load at x (the moving-irregularity model): the
wheel's speed is small beside the track's wave speeds.

Several wheels (a list, or a vehicle such as :class:`semitrack.Bogie`) at positions x_i couple
through the rail and through the vehicle: with the rail's transfer receptances
``A_R[i, j] = w(x_i) / F(x_j)`` (:class:`semitrack.InfiniteTrack`, exact, local changes too), the
vehicle's receptance matrix at its wheels ``A_W`` and the contacts' ``A_C = diag(1 / k_H)``,

    F = H r,   H = -(A_W + A_C + A_R)^-1,

``H[i, j]`` the force at wheel i per unit roughness under wheel j; one wheel gives the line above.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike

from ..base.checks import as_frequencies, as_real_array, check_real
from ..model.tracks import PeriodicCell, Track, require_track
from ..model.vehicle import Vehicle, as_vehicle
from ..model.wheel import Wheel
from .infinite import InfiniteTrack
from .receptance import point_receptance, position_origin


def wheel_rail_force(track: Track | PeriodicCell | InfiniteTrack, f: ArrayLike,
                     wheel: Wheel | Vehicle | Sequence[Wheel], x: float | ArrayLike = 0.0, *,
                     origin: str | None = None) -> np.ndarray:
    """Dynamic wheel-rail contact force per unit roughness, linear (N/m).

    Parameters
    ----------
    track : Track, PeriodicCell or InfiniteTrack
        The infinite periodic track, or an :class:`semitrack.InfiniteTrack` with local changes
        (several wheels always take that route).
    f : array_like
        Frequencies (Hz), positive and finite.
    wheel : Wheel, sequence of Wheel, or Vehicle
        One wheel (unsprung mass, primary suspension to a bogie held still, preload and Hertz
        constant); several such wheels; or a vehicle (:class:`semitrack.Bogie`), whose own
        receptance matrix couples its wheels.
    x : float or array_like
        The contact positions (m, from ``origin``). One per wheel; for a vehicle also a single
        position, that of its first wheel, the others at the vehicle's offsets.
    origin : {"midspan", "support"}
        Where ``x`` is measured from: the central mid-span (the package's one origin, as
        :class:`semitrack.InfiniteTrack` and the FE models take it), or support 0 (the paper's
        Sec. 4 origin; a support is at ``d / 2`` from the mid-span). Until 0.2 ``x`` was measured
        from a support on a Track; on a Track or a PeriodicCell, left out, it is measured from a
        mid-span with a :class:`FutureWarning` (until 0.3); on an InfiniteTrack it defaults to
        ``"midspan"``, as it always was.

    Returns
    -------
    ndarray of complex
        One wheel at one position on a Track: the shape of ``f``, F / r = -1 / (alpha_W +
        alpha_C + alpha_R(x)). Otherwise ``f.shape + (k, k)``: ``[..., i, j]`` the compression
        at wheel i per unit roughness under wheel j (r positive downward, a dip).

    Examples
    --------
    >>> import semitrack as st
    >>> force = st.wheel_rail_force(st.slab_track(), [100.0, 1000.0], st.Wheel(), origin="midspan")
    >>> force.shape
    (2,)
    >>> st.wheel_rail_force(st.slab_track(), [100.0, 1000.0], st.Bogie(), x=0.0, origin="midspan").shape
    (2, 2, 2)
    """
    f = as_frequencies(f)
    vehicle = as_vehicle(wheel)  # refuses what is no wheel or vehicle before anything else
    origin = "midspan" if origin is None and isinstance(track, InfiniteTrack) else position_origin(
        origin, "wheel_rail_force")
    if isinstance(wheel, Wheel) and as_real_array(x, "x", finite=False).ndim == 0 and \
            not isinstance(track, InfiniteTrack):
        alpha_r = point_receptance(track, f, check_real("x", x), origin=origin)[..., 0, 0]
        # -1 / (1/z_W + alpha_C + alpha_R) written with the wheel's dynamic stiffness z_W, which is 0
        # (not its receptance infinite) at an undamped primary suspension's resonance: the force is 0 there
        z_w = wheel.dynamic_stiffness(f)
        return -z_w / (1.0 + z_w * (1.0 / wheel.contact_stiffness + alpha_r))
    infinite, xs = _rail_and_positions(track, vehicle, x, origin)
    k = xs.size
    ff = np.atleast_1d(f)
    A = vehicle.receptance(ff) + np.diag([1.0 / w.contact_stiffness for w in vehicle.wheels])[None]
    for j in range(k):
        A[:, :, j] += infinite.receptance(ff, xs[j], xs)[:, :, 0, 0]
    return (-np.linalg.inv(A)).reshape(f.shape + (k, k))


def _rail_and_positions(track, vehicle: Vehicle, x, origin: str) -> tuple[InfiniteTrack, np.ndarray]:
    """The exact infinite track and the contacts in its coordinates (m from the central mid-span)."""
    if isinstance(track, InfiniteTrack):
        infinite = track
    else:
        infinite = InfiniteTrack(track.track if isinstance(track, PeriodicCell) else require_track(track))
    shift = 0.5 * infinite.track.spacing if origin == "support" else 0.0  # support 0 sits at d/2
    return infinite, vehicle.positions(x) + shift
