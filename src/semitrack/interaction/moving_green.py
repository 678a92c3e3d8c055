"""The moving Green's functions route: a vehicle on the periodic FE track in time without truncation.

For wheels rolling at constant speed along a perfectly periodic track, the fastest route
(WERAN-type codes) holds no model of the track in the loop: the rail under each wheel is the
convolution of the contact forces with the track's response at the moving contacts, computed once
for every position a contact takes within a support spacing (:mod:`semitrack.fe.kernels`, from
the infinite FE track of :mod:`semitrack.fe.bloch`: the same mesh and the same time steps as a
truncated FE model, without its ends). The vehicle (:class:`semitrack.Bogie`, or wheels on their
suspensions) is stepped by Newmark's average acceleration and each step's Hertzian contacts are
solved against it (:mod:`semitrack.dynamics.convolved`). The start is the one of
:func:`semitrack.wheel_rail_response`: at rest in the static equilibrium under the preloads, the
roughness faded in; so the two agree where both apply, the truncated model's ends aside.

Limits, where a user meets them:

* the track must be periodic: one support per spacing, no local change, transition or joint (a
  defect or a transition breaks the periodicity: the truncated model is the tool there); a
  flexible slab is not held (its period is a whole slab);
* constant speed, rounded so that a spacing is a whole number P of steps (by at most
  ``1 / (2P)`` of itself; :attr:`ContactResponse.speed` is the speed used), the first wheel's start
  rounded to the grid of steps ``h = speed dt`` and the wheels' offsets to whole steps;
* the kernels remember ``memory`` seconds: the rail's response to a force older than that is
  dropped (:attr:`MovingKernels.tail` says what is left at the end of the memory; a warning when
  over :data:`TAIL_TOLERANCE`);
* the kernels hold ``P x memory / dt`` values per wheel offset (29 MB for the ballasted track at
  300 km/h, 20 us and 0.2 s); their set-up is paid once per track, mesh, damping, speed, time
  step, offsets, memory and the start's position within a spacing, and can be kept on disk
  (``cache``, :mod:`semitrack.fe.kernelcache`).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from ..base.checks import (
    check_in_range,
    check_int_at_least,
    check_positive,
    check_real,
    check_rolling_speed,
    check_steps,
    check_work,
    shown,
)
from ..base.deprecation import renamed_keywords
from ..base.errors import InputError, InputTypeError
from ..base.notices import warn_user
from ..equivalent.cache import canonical
from ..fe.kernelcache import cached_kernels
from ..fe.kernels import ALIAS_FACTOR, MovingKernels, grid_of, track_key
from ..fe.kerneltail import KernelTail, kernel_tail
from ..fe.models import elements_per_bay_of
from ..methods.infinite import InfiniteTrack
from ..model.irregularity import Irregularity
from ..model.roughness import MAX_DISTANCE, Roughness
from ..model.tracks import Track, require_track
from ..model.vehicle import Bogie, Vehicle, WheelGroup
from ..model.wheel import Wheel
from .convolved_run import convolved_run
from .excitation import rail_input
from .inputs import DEFAULT_DT, check_roughness_speed, check_run
from .response import ContactResponse, contact_response

__all__ = ["TAIL_TOLERANCE", "MAX_LOOP_WORK", "DEFAULT_MEMORY", "DEFAULT_TAIL_START", "TAIL_RANK_TOLERANCE",
           "FFT_SAVING_STEPS",
           "moving_green_kernels", "moving_green_response", "vehicle_on_grid"]

#: The kernels' memory when none is given (s): on the paper's tracks at 300 km/h they have died to
#: 6e-5 (slab) and below (ballasted) of their peak by its last quarter (measured).
DEFAULT_MEMORY = 0.2

#: Most multiply-adds of a run's convolutions, steps x wheels^2 x memory (a 1-s bogie run on the ballasted
#: track at 20 us, 2e9, took 0.9 s compiled).
MAX_LOOP_WORK = 2e11

#: Where a low-rank tail starts when none is given (s): half the default memory. The paper's slab track loses the
#: load's phase slowest of its tracks: a bogie at 300 km/h and 40 us over 0.5 s, rank 4 past 0.1 s held the kernels
#: to 1.4e-6 of their peak and the forces to 0.0021 % rms of the whole kernels' (past 0.06 s: 2.4e-5 and 0.043 %).
#: On the ballasted track 0.06 s is enough: a wheel there 1.2e-6 and 0.0005 %, three wheels 2 m apart at 20 us
#: 0.0011 % (measured, ``benchmarks/bench_moving.py``).
DEFAULT_TAIL_START = 0.1

#: Fewest steps of a low-rank tail's start per unit of rank for its FFTs to cost less than what they save: a block of
#: M0 steps takes k^2 R FFTs of about the memory's length (some 3 L log2 L operations each) in place of
#: k^2 M0 (L - M0) multiply-adds, so the break-even is near M0 = 3 R log2 L, some 50 R at the memories of the book.
FFT_SAVING_STEPS = 50

#: The largest distance of a low-rank tail from the kernels, over their peak, accepted without a warning: at 1e-5 the
#: forces were 0.01-0.03 % rms from the whole kernels' (three wheels on the ballasted track, a bogie on the slab
#: track), at 8e-5 0.11 %.
TAIL_RANK_TOLERANCE = 1e-5

#: The largest magnitude of the kernels over the memory's last quarter, relative to their peak, accepted without a
#: warning.
TAIL_TOLERANCE = 1e-3


def _require_periodic(track: Track) -> Track:
    track = require_track(track)
    if track.has_flexible_slab:
        raise InputError("moving Green's functions need one support per period (rigid or ballasted supports); a "
                         "flexible slab's period is a whole slab: use its truncated FE model "
                         "(st.TruncatedTrack with st.wheel_rail_response)")
    return track


@renamed_keywords({"x_contact": "x"})
def moving_green_kernels(track: Track, speed: float, dt: float = DEFAULT_DT, offsets: Sequence[float] = (0.0,), *,
                         x: float = 0.0, memory: float = DEFAULT_MEMORY, elements_per_bay: int | None = None,
                         f_max: float | None = None, f_ref: float | dict | None = None,
                         cache: str | Path | None = None) -> MovingKernels:
    """The moving Green's functions of a periodic track for wheels at ``offsets`` rolling at ``speed``.

    Parameters
    ----------
    track : Track
        A periodic track (rigid or ballasted supports).
    speed : float
        Speed (m/s), > 0; rounded to a whole number of steps per support spacing.
    dt : float
        Time step (s).
    offsets : sequence of float
        The wheels' positions along +x from the first wheel (m), as :attr:`semitrack.Bogie.offsets`;
        rounded to whole steps ``speed dt``.
    x : float
        Where the vehicle starts (m; wheel i at ``x + offsets[i]``; until 0.3 also ``x=``): the kernels hold the
        release of the standing preloads for that start's position within a spacing (any start a
        whole number of spacings away shares them).
    memory : float
        How long the kernels remember a force (s).
    elements_per_bay : int, optional
        The FE mesh; default the fewest elements that keep the mesh's own error under 1 % up to
        ``f_max`` (:class:`semitrack.TruncatedTrack`'s default).
    f_max : float, optional
        The highest frequency of interest (Hz) for the default mesh (default 3 kHz).
    f_ref : None, float or dict
        Reference frequencies of the viscous damping (Hz), see :meth:`semitrack.FETrack.matrices`.
    cache : str or Path, optional
        A folder where the kernels are kept (one ``.npz`` file per key) and read back.

    Returns
    -------
    MovingKernels
    """
    kernels = _kernels_for(track, speed, dt, offsets, x, memory, elements_per_bay, f_max, f_ref, cache)
    _warn_short_memory(kernels)
    return kernels


def _kernels_for(track, speed, dt, offsets, x, memory, elements_per_bay, f_max, f_ref, cache) -> MovingKernels:
    """:func:`moving_green_kernels` without its warning (the response warns once, for kernels given or computed)."""
    track = _require_periodic(track)
    speed, dt, memory = check_rolling_speed("speed", speed), check_positive("dt", dt), check_positive("memory", memory)
    grid = grid_of(track, speed, dt, offsets)
    steps = check_steps(dt, memory, names=("dt", "memory"))
    x = check_in_range("x", check_real("x", x), (-MAX_DISTANCE, MAX_DISTANCE), "m along the rail")
    start = int(round(x / grid.step)) % grid.positions
    if elements_per_bay is not None:  # checked as every FE model checks it (never a string read as a number)
        elements_per_bay = elements_per_bay_of([track], elements_per_bay)
    return cached_kernels(track, elements_per_bay, f_max, grid, steps, f_ref, cache, start)


def _warn_short_memory(kernels: MovingKernels) -> None:
    """Warn (for the public function's caller) when the kernels have not died within their memory.

    A memory that cuts the kernels off costs twice: the forces older than it are dropped, and the
    inverse transform that gives the kernels (its length :data:`semitrack.fe.kernels.ALIAS_FACTOR`
    memories) folds the response beyond it back onto them (at a 0.03-s memory on the ballasted
    track at 300 km/h, 1e-3 of their peak was measured).
    """
    if kernels.tail > TAIL_TOLERANCE:
        L = kernels.memory
        warn_user(f"memory={L * kernels.grid.dt:.4g} s keeps the moving Green's functions while they are still "
                  f"{kernels.tail:.1e} of their peak over its last quarter: forces older than it are dropped, "
                  f"and the transform that gives the kernels folds their response after {ALIAS_FACTOR} memories "
                  "back onto them (aliasing); give a longer memory", RuntimeWarning)


def vehicle_on_grid(vehicle: Vehicle, kernels: MovingKernels) -> Vehicle:
    """The vehicle with its wheels' offsets rounded to the kernels' grid, as the route runs it.

    A :class:`semitrack.Bogie`'s wheelbase or a :class:`semitrack.WheelGroup`'s spacing becomes a
    whole number of grid steps ``speed dt``: the vehicle to give a truncated model that is to run
    exactly what the route ran.

    Parameters
    ----------
    vehicle : Vehicle
        The vehicle.
    kernels : MovingKernels
        Its kernels.

    Returns
    -------
    Vehicle
    """
    h = kernels.grid.step
    offsets = np.round(np.asarray(vehicle.offsets, dtype=float) / h) * h
    if isinstance(vehicle, Bogie):
        return dataclasses.replace(vehicle, wheelbase=float(-offsets[1]))
    if isinstance(vehicle, WheelGroup):
        return dataclasses.replace(vehicle, spacing=tuple(float(o) for o in offsets))
    return vehicle


def _start(kernels: MovingKernels, x: float, k: int) -> tuple[np.ndarray, np.ndarray]:
    """The wheels' grid indices and phases at the start (the first wheel's start rounded to the grid)."""
    grid = kernels.grid
    g = int(round(x / grid.step)) + np.array(grid.offsets[:k], dtype=np.int64)
    return g, np.mod(g, grid.positions).astype(np.int64)


def _loop_arrays(kernels: MovingKernels, g: np.ndarray, phase0: np.ndarray):
    """Which of the kernels' stack (in :attr:`KernelGrid.lags` order) each wheel pair reads, and the releases of the
    start: the stack itself is handed over as it is stored."""
    index = {lag: i for i, lag in enumerate(kernels.grid.lags)}
    k = g.size
    pair = np.array([[index[int(g[i] - g[j])] for j in range(k)] for i in range(k)], dtype=np.int64)
    release = np.stack([np.stack([kernels.release[int(g[i] - g[j]), int(phase0[j])] for j in range(k)])
                        for i in range(k)])
    return kernels.loop, pair, release


@renamed_keywords({"x_contact": "x"})
def moving_green_response(track: Track, wheel: Wheel | Vehicle | Sequence[Wheel], roughness: Roughness | None = None,
                          *, x: float = 0.0, speed: float, dt: float = DEFAULT_DT, duration: float = 0.1,
                          ramp: float = 0.02, memory: float | None = None, elements_per_bay: int | None = None,
                          f_max: float | None = None, f_ref: float | dict | None = None,
                          compiled: bool | None = None, cache: str | Path | None = None,
                          profile: Irregularity | None = None, kernels: MovingKernels | None = None,
                          tail_rank: int | None = None, tail_start: float | None = None) -> ContactResponse:
    """Wheels or a vehicle rolling along the periodic FE track, nothing truncated (see the module docstring).

    Parameters
    ----------
    track : Track
        A periodic track (rigid or ballasted supports; no changes). Its coordinates are the FE
        models': x = 0 a mid-span, supports at ``(k + 1/2) d``.
    wheel : Wheel, sequence of Wheel, or Vehicle
        As :func:`semitrack.wheel_rail_response` takes it.
    roughness : Roughness, optional
        The roughness under the first wheel, at the wheels' speed (re-sampled at the rounded
        speed, its wavelengths kept), faded in over ``ramp``; None: a smooth rail.
    x : float
        Where the vehicle starts (m; until 0.3 also ``x=``): wheel i at ``x + offsets[i]`` (the first wheel's
        start for a vehicle whose first offset is 0), rounded to the grid of steps ``speed dt``.
    speed : float
        The wheels' speed (m/s), > 0, rounded to a whole number of steps per spacing.
    dt, duration, ramp : float
        Time step, duration and fade-in (s).
    memory : float, optional
        How long the kernels remember a force (s; default :data:`DEFAULT_MEMORY`): longer than the
        rail's response takes to die away.
    elements_per_bay, f_max, f_ref
        The FE mesh and damping, as :class:`semitrack.TruncatedTrack` takes them. With ``kernels``,
        ``memory``, the mesh and ``f_ref`` are the kernels'; any of them given must agree with them.
    compiled : bool, optional
        The step loop compiled (True), in Python and NumPy (False) or compiled where numba is
        installed (None).
    cache : str or Path, optional
        A folder for the kernels (see :func:`moving_green_kernels`).
    profile : Irregularity, optional
        A geometric irregularity of the rail (:class:`semitrack.DippedWeld`, ...) met by each wheel
        where it is: the rail's shape, not the track's, so the track stays periodic.
    kernels : MovingKernels, optional
        Kernels already computed for this track, speed, step, vehicle (its offsets, or more) and
        start (its position within a spacing); any preload, roughness or vehicle dynamics may
        use them. Kernels of another track, step, speed, mesh, damping or memory are refused.
    tail_rank : int, optional
        Take the kernels past ``tail_start`` in this rank over the load's phase
        (:mod:`semitrack.fe.kerneltail`): the step then costs ``k^2`` times the steps up to
        ``tail_start`` instead of the whole memory, and the tail comes by FFT once a block. None
        (default): the whole kernels, exactly. The factors' distance from the kernels is warned of
        when it passes :data:`TAIL_RANK_TOLERANCE` of their peak. Measured, on the paper's ballasted
        track at 300 km/h and 20 us, three wheels 2 m apart over 0.4 s, rank 4 past 0.06 s: the forces
        0.0011 % rms from the whole kernels' and 0.0015 % from the truncated model's (0.0011 % with the
        whole kernels), band levels within 2e-4 dB; the step 11 us instead of 45 us
        (``benchmarks/bench_moving.py --cases ballasted-three-300 --duration 0.4 --tail-rank 4
        --tail-start 0.06``).
    tail_start : float, optional
        Where the tail starts (s; default :data:`DEFAULT_TAIL_START`), shorter than the memory;
        only with ``tail_rank``.

    Returns
    -------
    ContactResponse
        As :func:`semitrack.wheel_rail_response` gives it; ``n_dof`` is the vehicle's DOFs, ``speed``
        the rounded speed, ``x`` the contacts on the grid, ``vehicle`` the vehicle with its offsets
        rounded (:func:`vehicle_on_grid`), which a truncated model takes to run the same.
    """
    track = _require_periodic(track)
    x = check_real("x", x)  # the vehicle's origin: wheel i at x + offsets[i]
    # the roughness's speed is checked below, against the rounded one too
    run = check_run(wheel, roughness, x, check_rolling_speed("speed", speed), dt, duration, ramp, check_speed=False)
    vehicle, k, dt, n_steps = run.vehicle, run.k, run.dt, run.n_steps
    tail_rank, tail_start = _check_tail(tail_rank, tail_start)  # before a set-up that may take a minute
    settings = {"memory": memory, "elements_per_bay": elements_per_bay, "f_max": f_max, "f_ref": f_ref}
    if kernels is None:
        kernels = _kernels_for(track, run.speed, dt, vehicle.offsets, x, DEFAULT_MEMORY if memory is None else memory,
                               elements_per_bay, f_max, f_ref, cache)
    _check_kernels(kernels, track, run.speed, dt, vehicle, settings)
    v = kernels.grid.speed
    check_roughness_speed(roughness, run.speed, v)
    g, phase0 = _start(kernels, x, k)
    _check_start(kernels, g, vehicle)
    _check_work(kernels, n_steps, k, f"duration={duration!r} s / dt={dt!r} s with {k} wheel(s)")
    _warn_short_memory(kernels)
    path = (g[None, :] + np.arange(n_steps + 1)[:, None]) * kernels.grid.step
    r = rail_input(None if roughness is None else roughness.at_speed(v), path, dt, run.ramp, profile, vehicle.wheels)
    stack, pair, release = _loop_arrays(kernels, g, phase0)
    tail = _tail_of(kernels, tail_rank, tail_start)
    force, w_wheel, w_rail, elapsed = convolved_run(vehicle, stack if tail is None else tail.head, pair, release,
                                                    phase0, kernels.flexibility, r, dt, compiled, tail)
    vehicle = vehicle_on_grid(vehicle, kernels)
    return contact_response(route="moving green", t=run.t, force=force, w_wheel=w_wheel, w_rail=w_rail, roughness=r,
                            x=path, track=track, vehicle=vehicle, speed=v, ramp=run.ramp,
                            period=None if roughness is None else roughness.at_speed(v).period,
                            n_dof=vehicle.matrices()[0].shape[0], elapsed=elapsed, infinite=InfiniteTrack(track))


def _check_tail(rank, start) -> tuple[int | None, float | None]:
    """``tail_rank`` and ``tail_start`` as given, checked as far as they can be without the kernels."""
    if rank is None:
        if start is not None:
            raise InputError("tail_start is where the low-rank tail starts: give tail_rank with it")
        return None, None
    return check_int_at_least("tail_rank", rank, 1), None if start is None else check_positive("tail_start", start)


def _tail_of(kernels: MovingKernels, rank: int | None, start: float | None) -> KernelTail | None:
    """The kernels' tail in low rank a run asked for (None: the whole kernels), checked against them
    (``rank`` and ``start`` from :func:`_check_tail`)."""
    if rank is None:
        return None
    P, L, dt = kernels.grid.positions, kernels.memory, kernels.grid.dt
    if rank > P:
        raise InputError(f"tail_rank must be at most the {P} steps per spacing (the load's phases), got {rank}")
    given = start is not None
    start = start if given else DEFAULT_TAIL_START
    steps = int(round(start / dt))
    if not 1 <= steps < L:
        said = f"tail_start={start!r} s" if given else f"tail_start, by default {start!r} s,"
        raise InputError(f"{said} must lie within the kernels' memory ({L * dt:.6g} s) and be at least dt={dt!r} s: "
                         "give a tail_start within it")
    if steps < FFT_SAVING_STEPS * rank:
        warn_user(f"tail_start={start!r} s is {steps} steps: its FFTs, once a block of that many steps, cost more "
                  "than the dot products it saves; give a later start", RuntimeWarning)
    tail = kernel_tail(kernels, steps, rank)
    if tail.error > TAIL_RANK_TOLERANCE:
        warn_user(f"tail_rank={rank} past tail_start={start!r} s holds the kernels to {tail.error:.2g} of their "
                  "peak: give a higher rank or a later start", RuntimeWarning)
    return tail


def _check_kernels(kernels: MovingKernels, track: Track, speed: float, dt: float, vehicle: Vehicle,
                   settings: dict) -> None:
    """Kernels given by the caller must be those of this track, speed, step, vehicle and of the settings given."""
    if not isinstance(kernels, MovingKernels):
        raise InputTypeError(f"kernels must be MovingKernels (st.moving_green_kernels), got {type(kernels).__name__}")
    grid = grid_of(track, speed, dt, vehicle.offsets)
    theirs = kernels.grid
    differ = [text for same, text in (
        (grid.dt == theirs.dt, f"dt={shown(dt)} s (the kernels': {shown(theirs.dt)} s)"),
        (grid.positions == theirs.positions, f"speed={shown(speed)} m/s, {grid.positions} steps per spacing (the "
                                             f"kernels': {theirs.speed:.6g} m/s, {theirs.positions})"),
        (grid.offsets == theirs.offsets[:len(grid.offsets)], f"the vehicle's offsets {grid.offsets} steps (the "
                                                              f"kernels': {theirs.offsets})")) if not same]
    if differ:
        raise InputError("kernels do not fit this run: " + "; ".join(differ))
    if kernels.key.get("track") != track_key(track):
        raise InputError("the kernels were computed for another track")
    memory, ne, f_max, f_ref = (settings[name] for name in ("memory", "elements_per_bay", "f_max", "f_ref"))
    differ = []
    if memory is not None and check_steps(dt, check_positive("memory", memory), ("dt", "memory")) != kernels.memory:
        differ.append(f"memory={memory!r} s (the kernels': {kernels.memory * dt:.6g} s)")
    if (ne is not None or f_max is not None) and elements_per_bay_of([track], ne, f_max) != kernels.elements_per_bay:
        differ.append(f"elements_per_bay={ne!r}, f_max={f_max!r} (the kernels': {kernels.elements_per_bay} elements)")
    if f_ref is not None and canonical(f_ref) != kernels.key.get("f_ref"):
        differ.append(f"f_ref={f_ref!r}")
    if differ:
        raise InputError(f"the kernels were computed with other settings than {', '.join(differ)}: leave them out "
                         "to run with the kernels' own, or compute kernels for these")


def _check_start(kernels: MovingKernels, g: np.ndarray, vehicle: Vehicle) -> None:
    """The kernels' release must be for this start's position within a spacing."""
    start = int(g[0] - kernels.grid.offsets[0]) % kernels.grid.positions
    if start != kernels.start:
        x = kernels.start * kernels.grid.step
        raise InputError(f"the kernels hold the release of the preloads for a start at phase {kernels.start} of "
                         f"{kernels.grid.positions} (x = {x:.6g} m plus whole spacings); x is at phase "
                         f"{start}: compute kernels for this start (moving_green_kernels(..., x=))")


def _check_work(kernels: MovingKernels, n_steps: int, k: int, request: str) -> None:
    """A run's convolutions within reason (its records are :func:`~.inputs.check_run`'s)."""
    L = kernels.memory
    check_work(float(n_steps) * k * k * L, MAX_LOOP_WORK, f"{request} and a memory of {L} steps take "
               f"{float(n_steps) * k * k * L:.3g} multiply-adds", "simulate less or use a shorter memory")
