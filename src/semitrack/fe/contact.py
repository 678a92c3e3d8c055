"""Wheels on an FE track in time: Hertzian contacts, roughness input, loss of contact.

Each wheel (:class:`semitrack.Wheel`: unsprung mass m, optional primary suspension k1, c1 to a
bogie held still, preload P0) becomes one more DOF of the FE track's equations of motion, and
they meet only through the contact forces F, the compressions of the Hertzian springs (one
wheel written out):

    track:  M a + C v + K u = N^T F            (N: shape weights of w at the contact point)
    wheel:  m a_W + c1 v_W + k1 w_W = P(t) - F
    F = C_H max(delta, 0)^(3/2),   delta = w_W - N u - r(t)

with displacements downward and r the rail surface's downward displacement (r > 0 a dip), the
convention of :func:`semitrack.wheel_rail_force`. All are integrated together by Newmark's
average acceleration with a broadband boundary's states by the trapezoidal rule
(:func:`semitrack.dynamics.simulate.simulate`). Each step is linear in the forces: with
``b_i = [N_i^T; -1]`` the new state is ``u = u_free + sum_i K_eff^-1 b_i F_i`` and the approaches
``delta = a - G F`` with the step's compliance ``G_ij = b_i^T K_eff^-1 b_j``; the forces solve
``F = C_H max(a - G F, 0)^(3/2)`` (:mod:`semitrack.dynamics.contact`): zero where ``a <= 0``
(loss of contact: a force is never negative), else by Newton's method from the upper bound
``delta = a``. For one wheel the equation is scalar, convex and increasing, and the iterates fall
monotonically to the root within ``[0, a]``.

The start is quiet: the run starts at rest in the static equilibrium under the preload (track
deflected, contact compressed by ``(P0 / C_H)^(2/3)``, the contact force P0 included in the
initial acceleration, which is then zero), and the roughness fades in as ``sin^2`` over
``[0, ramp]``. A preload ramped in from zero instead sets off the wheel's bounce on the track
(64 Hz with 1.1 % damping on the viscous slab track, a decay time of 0.22 s; measured: +-6 % of
P0 still 0.15 s after a 20 ms ramp), which would stand beside the roughness's response. With a
primary suspension the load on the wheel is ``P0 + k1 w0`` (w0 the wheel's static deflection at
the start), so that the suspension carries none of the preload there.

Two excitations (:func:`wheel_rail_response`): (a) a stationary wheel over which a roughness
passes at its speed (the moving-irregularity model, ``speed=0``), (b) a wheel rolling along the
model at ``speed``, its contact weights changing every step (the support-passing excitation at
``speed / spacing``), on a smooth or rough rail. :func:`contact_transfer` takes the force per
unit roughness from case (a) on the roughness's lines and in one-third-octave bands, beside the
linear frequency-domain theory ``-1 / (alpha_W + alpha_C + alpha_R)``.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from ..base.checks import check_int_at_least, check_nonnegative, check_positive, check_steps
from ..base.errors import InputError, InputTypeError
from ..dynamics.contact import MAX_NEWTON, HertzContacts, solve_hertz
from ..dynamics.factor import factorise
from ..dynamics.newmark import Newmark
from ..dynamics.points import PointSet
from ..dynamics.simulate import check_limits, simulate
from ..dynamics.system import union
from ..methods.infinite import InfiniteTrack
from ..methods.wheelrail import wheel_rail_force
from ..model.irregularity import Irregularity
from ..model.tracks import Track
from ..model.vehicle import Vehicle, as_vehicle
from ..model.wheel import Wheel
from .gaps import GapResponse, SleeperGaps, sleeper_gaps, static_with_gaps
from .models import FETrack, require_model
from .roughness import Roughness, third_octave_bands
from .timedomain import sin2_ramp
from .trackforces import TrackForces, track_forces, watched_dofs

__all__ = ["ContactResponse", "ContactTransfer", "wheel_rail_response", "contact_transfer", "hertz_contact_force",
           "profile_along"]

def hertz_contact_force(c_h: float, a: float, beta: float) -> float:
    """The force F >= 0 (N) with ``F = c_h max(a - beta F, 0)^(3/2)``: one wheel's contact equation in a step.

    The one-wheel case of :func:`semitrack.dynamics.contact.solve_hertz`.

    Parameters
    ----------
    c_h : float
        Hertz constant (N/m^1.5), positive.
    a : float
        The approach the step would have without contact force (m).
    beta : float
        The compliance that the contact force sees within the step (m/N), positive: the approach
        is ``a - beta F``.

    Returns
    -------
    float
        The contact force (N): 0 when ``a <= 0`` (loss of contact).

    Examples
    --------
    >>> f = hertz_contact_force(9.3e10, 1e-4, 1e-9)
    >>> bool(abs(f - 9.3e10 * (1e-4 - 1e-9 * f) ** 1.5) < 1e-6 * f)
    True
    """
    force = np.zeros(1)
    if solve_hertz(np.array([float(c_h)]), np.array([float(a)]), np.array([[float(beta)]]), force,
                   np.zeros((1, 6))) > MAX_NEWTON:
        raise RuntimeError(f"the contact force did not converge in {MAX_NEWTON} Newton steps")
    return float(force[0])


@dataclass(frozen=True, eq=False)
class ContactResponse:
    """Output of :func:`wheel_rail_response`.

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
        The wheel's speed along the model (m/s); 0 for a stationary wheel.
    ramp : float
        Duration of the roughness's fade-in (s).
    period : float or None
        The roughness's period (s); None without roughness.
    n_dof : int
        DOFs integrated: the FE model's and the wheels' (boundary states not counted).
    elapsed : float
        Wall time of the time integration (s).
    wheels : tuple of Wheel
        Every wheel (``wheel`` is the first); with several, the histories have a column each.
    vehicle : Vehicle
        The vehicle the wheels belong to (a :class:`semitrack.Bogie`, or the wheels on their own
        suspensions).
    infinite : InfiniteTrack
        The exact infinite track with the model's changes (the linear theory's rail).
    track_forces : TrackForces or None
        Rail-seat and ballast forces at the watched supports and the rail's bending moment
        (``watch_supports``, ``bending_at``); None when none were asked for.
    gaps : GapResponse or None
        The hanging sleepers' ballast forces, gap openings and times in contact
        (``ballast_gaps``); None without.
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
    wheels: tuple = ()
    vehicle: Vehicle | None = None
    infinite: InfiniteTrack | None = None
    track_forces: TrackForces | None = None
    gaps: GapResponse | None = None

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
        late = self.t >= after
        if np.count_nonzero(late) < 2:
            raise InputError(f"after={after!r} s leaves fewer than two samples of a {self.t[-1]:.6g} s record")
        force = self.force[late] - self.force[late].mean(axis=0)
        window = np.hanning(force.shape[0]).reshape((-1,) + (1,) * (force.ndim - 1))
        amplitude = np.abs(np.fft.rfft(force * window, axis=0)) * 4 / force.shape[0]
        return np.fft.rfftfreq(force.shape[0], self.dt), amplitude

    @property
    def x_from_support(self) -> np.ndarray:
        """The contact position measured from a support (m), in ``[0, period)``, as
        :func:`semitrack.wheel_rail_force` takes it.

        The model's x = 0 is a mid-span, the first support at ``d/2``; on a flexible slab x = 0 is
        a slab joint and the period is the slab's (its S supports), so the position is taken
        modulo the period, not one bay: where the wheel sits on the slab matters."""
        d = self.track.spacing
        return np.mod(self.x - 0.5 * d, self.track.cell().period)


def _check_inputs(model, vehicle, roughness, x_contact, speed, dt, duration, ramp):
    """The checked scalars of :func:`wheel_rail_response`, and the contacts' paths along the rail."""
    require_model(model)
    if roughness is not None and not isinstance(roughness, Roughness):
        raise InputTypeError(f"roughness must be None (a smooth rail) or a Roughness (roughness_from_spectrum, "
                             f"corrugation), got {type(roughness).__name__}")
    x0 = vehicle.positions(x_contact, "x_contact")
    speed = check_nonnegative("speed", speed)
    dt, duration, ramp = check_positive("dt", dt), check_positive("duration", duration), check_positive("ramp", ramp)
    if not duration > ramp:
        raise InputError(f"duration must exceed ramp = {ramp!r} s (the roughness's fade-in), got {duration!r}")
    if roughness is not None and speed > 0 and not math.isclose(roughness.speed, speed, rel_tol=1e-9):
        raise InputError(f"a rolling wheel passes the roughness at its own speed: roughness.speed must equal "
                         f"speed={speed!r} m/s, got {roughness.speed!r}")
    n_steps = check_steps(dt, duration)
    k = len(vehicle.wheels)  # per step and wheel: 3 outputs, a moving point (4 DOFs, 4 weights), roughness, load, x
    check_limits(n_steps, model.n_dof + k, 3 * k, 11 * k, f"duration={duration!r} s / dt={dt!r} s")
    x = x0[None, :] + speed * dt * np.arange(n_steps + 1)[:, None]
    for name, value in (("x_contact", x[0]), ("x_contact + speed * duration", x[-1])):
        off = (value < model.x[0]) | (value > model.x[-1])
        if np.any(off):
            raise InputError(f"{name} must lie on the rail, {model.x[0]:.6g} <= x <= {model.x[-1]:.6g} m, "
                             f"got {value[off][0]!r}")
    return dt, ramp, n_steps, x


def _static_start(model: FETrack, vehicle: Vehicle, K: sp.csc_matrix, contacts: PointSet,
                  flexibility: np.ndarray, gaps: SleeperGaps | None) -> tuple[np.ndarray, np.ndarray]:
    """The static equilibrium under the preloads with the contacts at their first positions.

    ``flexibility`` is the rail elements' own deflection under each contact at the start (m/N);
    hanging sleepers rest on their ballast where the preloads close their gaps.
    Returns the state ``u0`` (model DOFs, then the vehicle's) and the constant loads on the
    vehicle's DOFs (:meth:`semitrack.model.vehicle.Vehicle.static_loads`: each contact at its
    wheel's preload, a suspension to a still bogie carrying none of it).
    """
    n, wheels = model.n_dof, vehicle.wheels
    preload = np.array([w.preload for w in wheels])
    load = contacts.matrix(n, 0).T @ preload
    u_track = factorise(K).solve(load) if gaps is None else static_with_gaps(K, load, gaps)
    w0 = contacts.values(u_track, 0) + flexibility * preload + np.array([w.static_approach for w in wheels])
    u_vehicle = vehicle.static_state(w0)
    return np.concatenate([u_track, u_vehicle]), vehicle.static_loads(u_vehicle)


def _all_contacts(wheel_dofs: np.ndarray, points: PointSet, wheels: tuple[Wheel, ...], r: np.ndarray,
                  flexibility: np.ndarray, gaps: SleeperGaps | None) -> HertzContacts:
    """The wheels' Hertzian contacts, then each hanging sleeper's unilateral ballast (:mod:`.gaps`)."""
    c_h = [w.hertz_constant for w in wheels]
    if gaps is None:
        return HertzContacts(wheel_dofs, points, c_h, r, compliance=flexibility)
    rows = points.dofs.shape[0]
    return HertzContacts(np.concatenate([wheel_dofs, gaps.dofs]), PointSet.stacked([points, gaps.points(rows)]),
                         np.concatenate([c_h, gaps.stiffness]), np.hstack([r, np.tile(gaps.gaps, (r.shape[0], 1))]),
                         labels=tuple(f"wheel {i}" for i in range(len(wheels))) + tuple(
                             f"ballast under support {k}" for k in gaps.supports),
                         compliance=np.hstack([flexibility, np.zeros((rows, gaps.n))]),
                         linear=np.r_[np.zeros(len(wheels), bool), np.ones(gaps.n, bool)])


def _gap_response(res, gaps: SleeperGaps, k: int, dt: float) -> GapResponse:
    """The hanging sleepers' columns of a run's contact channels (after the k wheels')."""
    force, w = res["contact force"][:, k:], res["wheel"][:, k:]
    return GapResponse(supports=gaps.supports, gaps=gaps.gaps, force=force, opening=gaps.gaps - w,
                       contact_time=dt * np.count_nonzero(force[1:] > 0, axis=0))  # a step per sample after the start


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
    return r


def _contact_points(model: FETrack, x: np.ndarray, moving: bool) -> PointSet:
    """The wheels' contact points: fixed at ``x[0]``, or along their paths ``x`` (steps, wheels)."""
    if not moving:
        return model.points(x[0], name="x_contact")
    return PointSet.stacked(model.points(x[:, i], moving=True, name="x_contact") for i in range(x.shape[1]))


def wheel_rail_response(model: FETrack, wheel: Wheel | Sequence[Wheel], roughness: Roughness | None = None, *,
                        x_contact: float | Sequence[float] = 0.0, speed: float = 0.0, dt: float = 1e-5,
                        duration: float = 0.1, ramp: float = 0.02, f_ref: float | dict | None = None,
                        compiled: bool | None = None, element_flexibility: bool = True,
                        profile: Irregularity | None = None, watch_supports: Sequence[int] = (),
                        bending_at: Sequence[float] = (), ballast_gaps: Mapping[int, float] | None = None
                        ) -> ContactResponse:
    """Wheels on an FE track in time: nonlinear Hertzian contacts driven by roughness or by rolling.

    Parameters
    ----------
    model : FETrack
        The track model (e.g. :class:`semitrack.TruncatedTrack` with ``"boundary"``, ``"pinned"``
        or ``"equivalent"`` ends; not ``"exact"``).
    wheel : Wheel or sequence of Wheel
        Unsprung mass, primary suspension (to a bogie held still), preload and Hertz constant; a
        list for several wheels, each on its own suspension, coupled through the rail.
    roughness : Roughness, optional
        The roughness along the rail (:func:`semitrack.roughness_from_spectrum`,
        :func:`semitrack.corrugation`) as the first wheel sees it, faded in over ``ramp``; None
        for a smooth rail. A wheel a distance ``s`` ahead of the first sees it ``s / v`` earlier
        (:meth:`Roughness.shifted`). With rolling wheels its speed must be theirs.
    x_contact : float or sequence of float
        The contact positions (m, model coordinates: 0 is the central mid-span), one per wheel,
        or rolling wheels' starts.
    speed : float
        The wheels' speed along the model (m/s), >= 0; 0 holds them still while the roughness
        passes (moving-irregularity model). The contacts must stay on the rail.
    dt : float
        Time step (s). The average-acceleration rule shifts a frequency f to
        ``tan(pi f dt) / (pi dt)``: +0.2 % at 2.5 kHz with the default 10 us.
    duration : float
        Simulated time (s), more than ``ramp``. Steps times DOFs are limited as in
        :func:`semitrack.dynamics.simulate.simulate`.
    ramp : float
        Duration (s) of the roughness's ``sin^2`` fade-in.
    f_ref : None, float or dict
        Reference frequencies of the track's viscous damping (Hz), see :meth:`FETrack.matrices`.
    compiled : bool, optional
        The step loop: compiled (True), NumPy (False) or compiled where it can run (None);
        see :func:`semitrack.dynamics.simulate.simulate`.
    profile : Irregularity, optional
        A geometric irregularity fixed on the rail (:class:`semitrack.DippedWeld`,
        :class:`semitrack.RailProfile`), met by each wheel where it is, ``r(x_i(t))``, on top of
        the roughness (not faded in: the wheels must start off it).
    ballast_gaps : mapping of int to float, optional
        ``{k: g}``: support k's sleeper hangs over a gap of g m and rests on the track's ballast
        only once it has closed it (:mod:`semitrack.fe.gaps`; build the model with
        ``changes={k: {"kb": 0.0}}``). What the sleepers did is :attr:`ContactResponse.gaps`.
    watch_supports : sequence of int
        Supports (indices k) whose rail-seat and ballast forces are recorded
        (:attr:`ContactResponse.track_forces`, :mod:`semitrack.fe.trackforces`).
    bending_at : sequence of float
        Positions (m) where the rail's bending moment is recorded.
    element_flexibility : bool
        Add each rail element's own deflection under its contact force in series with the
        contact (:meth:`FETrack.local_flexibility`; default). False reads the rail under a wheel
        from the mesh's interpolation alone, as the engine did before: a contact between nodes is
        then too stiff by up to 2 % of the Hertzian compliance, the two-wheel bands 0.3 dB off at
        1.6 kHz on the slab track (0.1 dB with it), and a rolling wheel sees a mesh line at
        ``speed / element length``.

    Returns
    -------
    ContactResponse
        With one wheel its histories are 1-D; with k wheels each is ``(n_steps + 1, k)``.

    Examples
    --------
    A stationary wheel on a 2-bay pinned slab track settles on its preload:

    >>> import semitrack as st
    >>> model = st.TruncatedTrack(st.slab_track(), 2, elements_per_bay=4)
    >>> res = st.wheel_rail_response(model, st.Wheel(), dt=5e-5, duration=0.06)
    >>> bool(abs(res.force[-1] / 1e5 - 1) < 0.01), res.lost_contact
    (True, False)
    """
    vehicle = as_vehicle(wheel)
    wheels = vehicle.wheels
    dt, ramp, n_steps, x = _check_inputs(model, vehicle, roughness, x_contact, speed, dt, duration, ramp)
    k = len(wheels)
    track = model.time_domain_system(f_ref)
    system = union({"track": track, "vehicle": vehicle.system()})
    t = dt * np.arange(n_steps + 1)
    points = _contact_points(model, x, speed > 0)
    flexibility = model.local_flexibility(x if speed > 0 else x[:1], name="x_contact") * bool(element_flexibility)
    gaps = sleeper_gaps(model, ballast_gaps) if ballast_gaps else None
    u0, vehicle_loads = _static_start(model, vehicle, track.K, points, flexibility[0], gaps)
    fade = sin2_ramp(t, ramp)
    r = np.zeros((t.size, k)) if roughness is None else np.column_stack(
        [roughness.shifted(x[0, i] - x[0, 0]).sampled(dt, t.size) * fade for i in range(k)])
    if profile is not None:
        r = r + profile_along(profile, x)
    watch = watched_dofs(model, watch_supports, bending_at)
    vehicle_dofs = model.n_dof + np.arange(vehicle_loads.size)
    contacts = _all_contacts(vehicle_dofs[:k], points, wheels, r, flexibility, gaps)
    loads = [(PointSet.on_dofs(vehicle_dofs), np.tile(vehicle_loads, (t.size, 1)))]
    res = simulate(system, Newmark(dt), n_steps, loads=loads, contacts=contacts, u0=u0, compiled=compiled,
                   record=watch.dofs)
    forces = track_forces(model, watch, res["dofs"], dt, f_ref) if watch.dofs.size else None
    if forces is not None and gaps is not None and forces.ballast is not None:
        for j, k_gap in enumerate(gaps.supports):  # a hanging sleeper's ballast is its gap's contact
            forces.ballast[:, forces.supports == k_gap] = res["contact force"][:, [k + j]]
    one = (lambda a: a[:, 0]) if k == 1 else (lambda a: a[:, :k])
    return ContactResponse(t=t, force=one(res["contact force"]), w_wheel=one(res["wheel"]), w_rail=one(res["rail"]),
                           roughness=one(r), x=one(x), track=model.track, wheel=wheels[0], speed=float(speed),
                           ramp=ramp, period=None if roughness is None else roughness.period,
                           n_dof=model.n_dof + vehicle_loads.size, elapsed=res.elapsed, wheels=wheels,
                           vehicle=vehicle, infinite=model.infinite_track(), track_forces=forces,
                           gaps=None if gaps is None else _gap_response(res, gaps, k, dt))


@dataclass(frozen=True, eq=False)
class ContactTransfer:
    """The contact force per unit roughness of a stationary wheel, time domain beside linear theory.

    Attributes
    ----------
    f : ndarray
        The roughness's lines in the analysed bands (Hz).
    H : ndarray of complex
        ``H1 = S_rF / S_rr`` on those lines (N/m): the time-domain force per unit roughness.
    linear : ndarray of complex
        :func:`semitrack.wheel_rail_force` on those lines (N/m), for the infinite track at the
        contact point.
    r_amplitude : ndarray
        Roughness amplitude of each line (m), the weights of the band levels.
    centres : ndarray
        Centres of the one-third-octave bands that hold at least one line (Hz).
    level, linear_level : ndarray
        Band levels of the force per unit roughness (dB re 1 N/m):
        ``10 log10(sum |H R|^2 / sum |R|^2)`` over the band's lines, time domain and linear.
    """

    f: np.ndarray
    H: np.ndarray
    linear: np.ndarray
    r_amplitude: np.ndarray
    centres: np.ndarray
    level: np.ndarray
    linear_level: np.ndarray

    @property
    def error_db(self) -> np.ndarray:
        """``level - linear_level`` per band (dB)."""
        return self.level - self.linear_level


def _band_levels(H: np.ndarray, r: np.ndarray, band_of_line: np.ndarray, n_bands: int) -> np.ndarray:
    power = np.bincount(band_of_line, np.abs(H * r) ** 2, n_bands)
    return 10 * np.log10(power / np.bincount(band_of_line, r**2, n_bands))


def contact_transfer(response: ContactResponse, band: tuple[float, float] = (50.0, 2500.0),
                     periods: int = 1, wheel: int | None = None) -> ContactTransfer:
    """Force per unit roughness from the last whole roughness periods of a stationary wheel's run.

    A periodic roughness (:class:`semitrack.Roughness`) has all its power on lines ``j / period``;
    over whole periods the discrete Fourier transforms of r and F hold them without leakage, and
    ``H1 = sum_p conj(R_p) F_p / sum_p |R_p|^2`` (over the ``periods`` analysed) is the force per
    unit roughness on each line. The window must start after the fade-in (``response.t_full``),
    and the fade-in's transient must have decayed by then: on the viscous slab track the wheel's
    bounce (64 Hz, 1.1 % damping) leaves 1.6 dB in the 50 Hz band 0.3 s after the fade-in and
    0.26 dB after 0.7 s; on the ballasted track (5.5 %) 0.02 dB after 0.3 s (measured). The
    time domain's damping is viscous (:meth:`FETrack.matrices`): compare a track with
    ``damping="viscous"``, whose frequency domain has the same dampers.

    Parameters
    ----------
    response : ContactResponse
        A stationary wheel's run (``speed=0``) with a roughness whose period is a whole
        number of time steps.
    band : tuple of float
        The lowest and highest one-third-octave band centres (Hz) analysed (nominal values
        name their band).
    periods : int
        Number of whole roughness periods at the end of the record to analyse (>= 1).
    wheel : int, optional
        With several wheels, whose force: the transfer is then the force at that wheel per unit
        roughness under the first wheel, ``sum_j H_ij R_j / R_1`` in the linear theory (the
        roughness reaching wheel j earlier or later, :func:`semitrack.wheel_rail_force`'s matrix
        ``H`` on the model's exact infinite track). Required with several wheels.

    Returns
    -------
    ContactTransfer
    """
    if not isinstance(response, ContactResponse):
        raise InputTypeError(f"response must be a ContactResponse (wheel_rail_response), got {type(response).__name__}")
    n_wheels = 1 if response.force.ndim == 1 else response.force.shape[1]
    if wheel is None and n_wheels > 1:
        raise InputError(f"contact_transfer of a run with {n_wheels} wheels needs wheel=i (0 <= i < {n_wheels}): "
                         "the force at wheel i per unit roughness under the first wheel")
    wheel = check_int_at_least("wheel", 0 if wheel is None else wheel, 0)
    if wheel >= n_wheels:
        raise InputError(f"wheel must be below the number of wheels, {n_wheels}, got {wheel}")
    if response.period is None or response.speed != 0:
        raise InputError("contact_transfer needs a stationary wheel (speed=0) driven by a roughness, got "
                         f"speed={response.speed!r} m/s and period={response.period!r}")
    try:
        lo, hi = band
    except (TypeError, ValueError):
        raise InputTypeError(f"band must be a pair (lowest, highest) of band centres in Hz, got {band!r}") from None
    periods = check_int_at_least("periods", periods, 1)
    dt, n_per = response.dt, response.period / response.dt
    if abs(n_per - round(n_per)) > 1e-6 * n_per:
        raise InputError(f"the roughness period {response.period!r} s must be a whole number of time steps "
                         f"dt={dt!r} s for a transfer without leakage")
    n_per = int(round(n_per))
    start = response.t.size - periods * n_per
    if start < 0 or response.t[start] < response.t_full - 1e-12:
        raise InputError(f"periods={periods} roughness periods of {response.period:.6g} s must fit after the fade-in "
                         f"(t >= {response.t_full:.6g} s) in a record of {response.t[-1]:.6g} s; simulate longer")
    column = (lambda a: a) if n_wheels == 1 else (lambda a: a[:, wheel])  # noqa: E731
    rough = response.roughness.reshape(response.t.size, -1)
    R_all = np.fft.rfft(rough[start:].T.reshape(n_wheels, periods, n_per), axis=2)  # every wheel's roughness
    R, F = R_all[0], np.fft.rfft(column(response.force)[start:].reshape(periods, n_per), axis=1)
    try:
        centres, lower, upper = third_octave_bands(lo, hi)
    except (TypeError, ValueError) as err:
        raise type(err)(f"band: {err}") from None
    j = np.arange(R.shape[1])
    f = j / response.period
    power = np.sum(np.abs(R) ** 2, axis=0)
    keep = (power > 1e-12 * power.max()) & (f >= lower[0]) & (f < upper[-1]) & (j > 0)
    if not np.any(keep):
        raise InputError(f"band={band!r} Hz holds none of the roughness's lines ({1 / response.period:.4g} Hz "
                         "apart); choose bands the roughness covers")
    f, H = f[keep], (np.sum(np.conj(R) * F, axis=0) / np.where(power > 0, power, 1.0))[keep]
    r_amp = 2 * np.sqrt(power[keep] / periods) / n_per
    band_of_line = np.searchsorted(upper, f, side="right")
    used = np.unique(band_of_line)
    band_of_line = np.searchsorted(used, band_of_line)
    linear = _linear_transfer(response, f, R_all[:, :, keep], wheel)
    return ContactTransfer(f=f, H=H, linear=linear, r_amplitude=r_amp, centres=centres[used],
                           level=_band_levels(H, r_amp, band_of_line, used.size),
                           linear_level=_band_levels(linear, r_amp, band_of_line, used.size))


def _linear_transfer(response: ContactResponse, f: np.ndarray, R: np.ndarray, wheel: int) -> np.ndarray:
    """The linear theory's force at ``wheel`` per unit roughness under the first, on the lines ``f``.

    ``R`` holds every wheel's roughness spectrum on those lines, (wheels, periods, lines): the
    roughness reaches each wheel with its own phase, ``R_j / R_1`` read from the run itself.
    """
    x0 = response.x if response.x.ndim == 1 else response.x[0]
    if response.infinite is None:  # a flexible slab (no InfiniteTrack), or a response made by hand
        if len(response.wheels) > 1:
            raise InputError("the linear theory of several wheels needs the exact InfiniteTrack of the model, which "
                             "a flexible slab does not have: analyse one wheel at a time")
        return wheel_rail_force(response.track, f, response.wheel, float(response.x_from_support[0]))
    H = wheel_rail_force(response.infinite, f, response.vehicle, x=np.atleast_1d(x0)[: len(response.wheels)])
    ratio = R[:, 0, :] / R[0, 0, :]  # (wheels, lines)
    return np.einsum("fj,jf->f", H[:, wheel, :], ratio)
