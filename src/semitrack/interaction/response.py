"""The one result of a vehicle's run on the rail, whatever the route: :class:`ContactResponse`.

Each route hands its histories, one column per contact, to :func:`contact_response`, which
keeps the wheels' columns (an FE run's contacts include the hanging sleepers after them) and
makes a one-wheel run's histories 1-D.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..base.checks import check_real
from ..base.errors import InputError
from ..base.fields import check_fields, check_rows
from ..fe.gaps import GapResponse
from ..fe.trackforces import TrackForces
from ..methods.infinite import InfiniteTrack
from ..model.tracks import Track
from ..model.vehicle import Vehicle
from ..model.wheel import Wheel
from .summary import run_summary

__all__ = ["ContactResponse", "ROUTES", "contact_response"]

#: The routes of a vehicle's run, as :attr:`ContactResponse.route` names them.
ROUTES = ("fe model", "window", "convolution", "moving green")


@dataclass(frozen=True, eq=False)
class ContactResponse:
    """A vehicle's run on the rail, by any route: the one result of the package's time-domain contact runs.

    :func:`semitrack.wheel_rail_response` (an FE model), :func:`semitrack.convolution_response`
    (the exact infinite track by convolution) and :func:`semitrack.moving_green_response` (the
    periodic FE track by moving Green's functions) fill every field alike; :attr:`route` says which
    ran. With one wheel the histories are 1-D, with k wheels ``(n_steps + 1, k)``.

    Attributes
    ----------
    t : ndarray, shape (n_steps + 1,)
        Times (s), from 0.
    force : ndarray
        Contact force F (N), the compression, >= 0.
    w_wheel : ndarray
        Wheel displacement (m, downward).
    w_rail : ndarray
        Rail displacement at the contact point (m, downward).
    roughness : ndarray
        Roughness r at the contact (m, downward), faded in as applied.
    x : ndarray
        Contact position (m, model coordinates: 0 is the central mid-span).
    track : Track
        The model's track.
    wheel : Wheel
        The wheel.
    speed : float
        The wheel's speed along the model (m/s); 0 for a stationary wheel; its first when it
        varies.
    ramp : float
        Duration of the roughness's fade-in (s).
    period : float or None
        The roughness's period (s); None without roughness.
    n_dof : int
        DOFs stepped by Newmark's rule: the FE model's (0 where the rail is a convolution) and the
        vehicle's; boundary states not counted.
    elapsed : float
        Wall time of the time integration (s).
    wheels : tuple of Wheel
        Every wheel (``wheel`` is the first); with several, the histories have a column each.
    vehicle : Vehicle
        The vehicle the wheels belong to (a :class:`semitrack.Bogie`, or the wheels on their own
        suspensions).
    infinite : InfiniteTrack or None
        The exact infinite track with the model's changes (the linear theory's rail); None on a
        flexible slab, which InfiniteTrack does not hold.
    track_forces : TrackForces or None
        Rail-seat and ballast forces at the watched supports and the rail's bending moment
        (``watch_supports``, ``bending_at``); None when none were asked for.
    gaps : GapResponse or None
        The hanging sleepers' ballast forces, gap openings and times in contact
        (``ballast_gaps``); None without.
    route : str
        The route that ran: ``"fe model"``, ``"window"``, ``"convolution"`` or ``"moving green"``.
    speeds : ndarray or None
        The speed at each step (m/s) when it varied (``speed=speed(t)``); None at a constant speed.
    """

    t: np.ndarray
    force: np.ndarray
    w_wheel: np.ndarray
    w_rail: np.ndarray
    roughness: np.ndarray
    x: np.ndarray
    track: Track
    wheel: Wheel
    speed: float
    ramp: float
    period: float | None
    n_dof: int
    elapsed: float
    wheels: tuple[Wheel, ...] = ()
    vehicle: Vehicle | None = None
    infinite: InfiniteTrack | None = None
    track_forces: TrackForces | None = None
    gaps: GapResponse | None = None
    route: str = "fe model"
    speeds: np.ndarray | None = None

    def __post_init__(self):
        check_fields(self)  # a record built by hand is refused here, not in a method
        check_rows(self, ("t",))
        check_rows(self, ("t", "force", "w_wheel", "w_rail", "roughness", "x"), ndims=(1, 2))

    @property
    def dt(self) -> float:
        """The time step (s)."""
        return float(self.t[1] - self.t[0])

    @property
    def t_full(self) -> float:
        """``ramp``: from then on the roughness acts in full (s)."""
        return self.ramp

    @property
    def approach(self) -> np.ndarray:
        """delta = w_wheel - w_rail - r (m), positive in contact."""
        return self.w_wheel - self.w_rail - self.roughness

    @property
    def in_contact(self) -> np.ndarray:
        """True where the contact carries a force (F > 0)."""
        return self.force > 0

    @property
    def lost_contact(self) -> bool:
        """Whether contact was lost at any time."""
        return bool(np.any(~self.in_contact))

    def force_spectrum(self, after: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
        """One-sided amplitude spectrum of the force's fluctuation from time ``after`` on.

        The record from ``after`` (s) has its mean removed and a Hann window applied (amplitudes
        corrected for the window's coherent gain of 1/2), so a line of amplitude A reads about A.

        Parameters
        ----------
        after : float
            Start of the analysed record (s), e.g. past a start-up transient.

        Returns
        -------
        f : ndarray
            Frequencies (Hz), spaced 1 / (analysed duration).
        amplitude : ndarray
            Force amplitude at each frequency (N); a column per wheel for several wheels.
        """
        late = self.t >= check_real("after", after)
        if np.count_nonzero(late) < 2:
            raise InputError(f"after={after!r} s leaves fewer than two samples of a {self.t[-1]:.6g} s record")
        force = self.force[late] - self.force[late].mean(axis=0)
        window = np.hanning(force.shape[0]).reshape((-1,) + (1,) * (force.ndim - 1))
        amplitude = np.abs(np.fft.rfft(force * window, axis=0)) * 4 / force.shape[0]
        return np.fft.rfftfreq(force.shape[0], self.dt), amplitude

    def summary(self, reference: ContactResponse | None = None, after: float | None = None):
        """The run's figures engineers read, beside a reference run's (:func:`~.summary.run_summary`).

        Parameters
        ----------
        reference : ContactResponse, optional
            A run to compare with (the same vehicle on the perfect track, say): its values and
            the ratios join the table.
        after : float, optional
            Statistics from this time on (s); by default from the end of the fade-in (``ramp``).

        Returns
        -------
        pandas.DataFrame
            Indexed by ``(item, quantity)``: per wheel (as the vehicle names them) the peak,
            minimum, rms and static contact force (kN), peak over static and time out of
            contact (ms), from ``after``; per watched support the peak rail-seat and ballast force (kN); the
            rail's peak sagging moment; per hanging sleeper its peak ballast force and time on
            the ballast (that time over the whole run). Columns ``value`` (and ``reference``, ``ratio``).

        Examples
        --------
        >>> import semitrack as st
        >>> model = st.TruncatedTrack(st.slab_track(damping="viscous"), 2, elements_per_bay=4)
        >>> res = st.wheel_rail_response(model, st.Wheel(), dt=1e-4, duration=0.02, ramp=0.005)
        >>> round(float(res.summary().loc[("wheel", "peak / static (-)"), "value"]), 3)
        1.0
        """
        return run_summary(self, reference, after)

    @property
    def x_from_support(self) -> np.ndarray:
        """The contact position measured from a support (m), in ``[0, period)``, as
        :func:`semitrack.wheel_rail_force` takes it.

        The model's x = 0 is a mid-span, the first support at ``d/2``; on a flexible slab x = 0 is
        a slab joint and the period is the slab's (its S supports), so the position is taken
        modulo the period, not one bay: where the wheel sits on the slab matters."""
        d = self.track.spacing
        return np.mod(self.x - 0.5 * d, self.track.cell().period)


def contact_response(*, route: str, t: np.ndarray, force: np.ndarray, w_wheel: np.ndarray, w_rail: np.ndarray,
                     roughness: np.ndarray, x: np.ndarray, track: Track, vehicle: Vehicle, speed: float, ramp: float,
                     period: float | None, n_dof: int, elapsed: float, infinite: InfiniteTrack | None,
                     track_forces: TrackForces | None = None, gaps: GapResponse | None = None,
                     speeds: np.ndarray | None = None) -> ContactResponse:
    """A route's run as a :class:`ContactResponse`: the wheels' columns of its ``(n_steps + 1, >= k)`` histories.

    Parameters
    ----------
    route : str
        One of :data:`ROUTES`.
    t, force, w_wheel, w_rail, roughness, x : ndarray
        Times (s) and, a column per contact (the k wheels first), the histories of
        :class:`ContactResponse` (N, m).
    track, vehicle, speed, ramp, period, n_dof, elapsed, infinite, track_forces, gaps, speeds
        As :class:`ContactResponse` holds them.

    Returns
    -------
    ContactResponse
    """
    if route not in ROUTES:
        raise InputError(f"route must be one of {ROUTES}, got {route!r}")
    k = len(vehicle.wheels)
    wheels: Callable[[np.ndarray], np.ndarray] = (lambda a: a[:, 0]) if k == 1 else (lambda a: a[:, :k])
    return ContactResponse(t=t, force=wheels(force), w_wheel=wheels(w_wheel), w_rail=wheels(w_rail),
                           roughness=wheels(roughness), x=wheels(x), track=track, wheel=vehicle.wheels[0],
                           speed=float(speed), ramp=ramp, period=period, n_dof=int(n_dof), elapsed=elapsed,
                           wheels=vehicle.wheels, vehicle=vehicle, infinite=infinite, track_forces=track_forces,
                           gaps=gaps, route=route, speeds=speeds)
