"""The FE model route of a vehicle's run: wheels on an FE track in time, Hertzian contacts, loss of contact.

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
linear frequency-domain theory ``-1 / (alpha_W + alpha_C + alpha_R)``
(:mod:`semitrack.interaction.transfer`).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence

import numpy as np

from ..base.deprecation import renamed_keywords
from ..base.errors import InputError
from ..dynamics.newmark import Newmark
from ..dynamics.points import PointSet
from ..dynamics.simulate import check_limits, simulate
from ..dynamics.system import union
from ..fe.gaps import sleeper_gaps
from ..fe.models import FETrack, require_model
from ..fe.trackforces import track_forces, watched_dofs
from ..fe.window import WindowTrack
from ..model.irregularity import Irregularity
from ..model.roughness import Roughness
from ..model.vehicle import Vehicle
from ..model.wheel import Wheel
from .excitation import rail_input
from .fe_wheels import all_contacts, contact_points, gap_response, static_start
from .inputs import DEFAULT_DT, RunInputs, check_run
from .response import ContactResponse, contact_response
from .window_model import window_response

__all__ = ["wheel_rail_response"]


def _on_rail(model: FETrack, run: RunInputs) -> np.ndarray:
    """The wheels' paths, checked on the model's rail from start to end, after the work is known to be bounded."""
    k = run.k  # per step and wheel: 3 outputs, a moving point (4 DOFs, 4 weights), roughness, load, x
    check_limits(run.n_steps, model.n_dof + k, 3 * k, 11 * k, f"duration={run.duration!r} s / dt={run.dt!r} s")
    x = run.path()
    for name, value in (("x", x[0]), ("x + speed * duration", x[-1])):  # speed(t): its integral
        off = (value < model.x[0]) | (value > model.x[-1])
        if np.any(off):
            raise InputError(f"{name} must lie on the rail, {model.x[0]:.6g} <= x <= {model.x[-1]:.6g} m, "
                             f"got {value[off][0]!r}")
    return x


@renamed_keywords({"model": "track", "x_contact": "x"})
def wheel_rail_response(track: FETrack, wheel: Wheel | Vehicle | Sequence[Wheel], roughness: Roughness | None = None,
                        *, x: float | Sequence[float] = 0.0, speed: float | Callable[[float], float] = 0.0,
                        dt: float = DEFAULT_DT,
                        duration: float = 0.1, ramp: float = 0.02, f_ref: float | dict | None = None,
                        compiled: bool | None = None, element_flexibility: bool = True,
                        profile: Irregularity | None = None, watch_supports: Sequence[int] = (),
                        bending_at: Sequence[float] = (), ballast_gaps: Mapping[int, float] | None = None
                        ) -> ContactResponse:
    """Wheels on an FE track in time: nonlinear Hertzian contacts driven by roughness or by rolling.

    Parameters
    ----------
    track : FETrack or WindowTrack
        The FE model the wheels run on (e.g. :class:`semitrack.TruncatedTrack` with
        ``"boundary"``, ``"pinned"`` or ``"equivalent"`` ends; not ``"exact"``), or a
        :class:`semitrack.WindowTrack`, whose window travels with the vehicle over an infinite
        track with changes (:mod:`semitrack.interaction.window_model`). Until 0.3 also
        ``model=``.
    wheel : Wheel, sequence of Wheel, or Vehicle
        Unsprung mass, primary suspension (to a bogie held still), preload and Hertz constant; a
        list for several wheels, each on its own suspension, coupled through the rail; or a
        vehicle (:class:`semitrack.Bogie`, :class:`semitrack.WheelGroup`).
    roughness : Roughness, optional
        The roughness along the rail (:func:`semitrack.roughness_from_spectrum`,
        :func:`semitrack.corrugation`) as the first wheel sees it, faded in over ``ramp``; None
        for a smooth rail. A wheel a distance ``s`` ahead of the first sees it ``s / v`` earlier
        (:meth:`Roughness.shifted`). With rolling wheels its speed must be theirs.
    x : float or sequence of float
        The contact positions (m from the central mid-span), one per wheel or a vehicle's first
        wheel's; rolling wheels' starts. Until 0.3 also ``x=``.
    speed : float or callable
        The wheels' speed along the model (m/s), >= 0; 0 holds them still while the roughness
        passes (moving-irregularity model). Or a function ``speed(t)`` (m/s, t in s) for a
        braking or accelerating vehicle: the wheels' positions are its integral (trapezoidal
        rule, :attr:`ContactResponse.speeds` the values at the steps); the rail's roughness is
        then a profile along it (``profile=roughness.along_rail(...)``), and a ``Roughness``, a
        signal at one speed, is refused. The contacts must stay on the rail.
    dt : float
        Time step (s). The average-acceleration rule shifts a frequency f to
        ``tan(pi f dt) / (pi dt)``: +0.8 % at 2.5 kHz with the default 20 us (every route's,
        :data:`semitrack.interaction.inputs.DEFAULT_DT`; 10 us until 0.2: +0.2 %).
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
    if isinstance(track, WindowTrack):  # the same run on a window that travels with the vehicle
        return window_response(track, wheel, roughness, x=x, speed=speed, dt=dt, duration=duration, ramp=ramp,
                               f_ref=f_ref, compiled=compiled, element_flexibility=element_flexibility,
                               profile=profile, watch_supports=watch_supports, bending_at=bending_at,
                               ballast_gaps=ballast_gaps)
    model = require_model(track, "track")
    run = check_run(wheel, roughness, x, speed, dt, duration, ramp, varying=True)
    vehicle, wheels, k = run.vehicle, run.vehicle.wheels, run.k
    dt, n_steps = run.dt, run.n_steps
    path = _on_rail(model, run)
    rail = model.time_domain_system(f_ref)
    system = union({"track": rail, "vehicle": vehicle.system()})
    points = contact_points(model, path, run.moving)
    flexibility = model.local_flexibility(path if run.moving else path[:1]) * bool(element_flexibility)
    gaps = sleeper_gaps(model, ballast_gaps) if ballast_gaps else None
    r = rail_input(roughness, path, dt, run.ramp, profile, wheels)
    u0, vehicle_loads = static_start(model, vehicle, rail.K, points, flexibility[0], gaps, r[0])
    watch = watched_dofs(model, watch_supports, bending_at)
    vehicle_dofs = model.n_dof + np.arange(vehicle_loads.size)
    contacts = all_contacts(vehicle_dofs[:k], points, wheels, r, flexibility, gaps)
    loads = [(PointSet.on_dofs(vehicle_dofs), np.tile(vehicle_loads, (n_steps + 1, 1)))]
    res = simulate(system, Newmark(dt), n_steps, loads=loads, contacts=contacts, u0=u0, compiled=compiled,
                   record=watch.dofs)
    forces = track_forces(model, watch, res["dofs"], dt, f_ref) if watch.dofs.size else None
    if forces is not None and gaps is not None and forces.ballast is not None:
        for j, k_gap in enumerate(gaps.supports):  # a hanging sleeper's ballast is its gap's contact
            forces.ballast[:, forces.supports == k_gap] = res["contact force"][:, [k + j]]
    return contact_response(route="fe model", t=run.t, force=res["contact force"], w_wheel=res["wheel"],
                            w_rail=res["rail"], roughness=r, x=path, track=model.track, vehicle=vehicle,
                            speed=run.speed, ramp=run.ramp, period=None if roughness is None else roughness.period,
                            n_dof=model.n_dof + vehicle_loads.size, elapsed=res.elapsed,
                            infinite=model.infinite_track(), track_forces=forces,
                            gaps=None if gaps is None else gap_response(res, gaps, k, dt), speeds=run.speeds)
