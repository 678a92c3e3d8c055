"""The periodic track in time without truncation: moving Green's functions beside the truncated model.

The computations of the book's chapter "Beyond the paper: the periodic track in time without
truncation" and of ``benchmarks/bench_moving.py``; each returns runs or a table
(:class:`pandas.DataFrame`) that the chapter shows.

* :func:`rolling_roughness`: the rough rail of the comparisons, the ISO 3095 limit over the
  wavelengths that a wheel at the speed meets between 40 Hz and 3 kHz (period 0.1 s).
* :func:`compare_runs`: one vehicle at one speed on one track, by moving Green's functions
  (:func:`semitrack.moving_green_response`) and by the truncated FE model with broadband ends that
  holds the whole path (:func:`semitrack.wheel_rail_response`), the same mesh, time step, start
  and roughness; with the set-up's cost, its cost read back from the cache, and the steps' costs.
* :func:`compare_cases`: :func:`compare_runs` for several cases side by side on the machine's cores.
* :func:`tail_run`: a comparison's run again with the kernels' tails in low rank.
* :func:`force_agreement`: the two contact forces' agreement: the rms of the difference over the
  rms of the reference's fluctuation, and the one-third-octave band levels 50 Hz - 2.5 kHz of the
  forces (their level difference, dB) and of the difference (its level under the reference's, dB).
* :func:`moving_table`: one row per comparison.
* :func:`finer_mesh_run`: a comparison's case on a finer mesh, by the truncated model.
* :func:`contact_table`: one wheel by both routes on a rail that makes it leave the rail and on a
  smooth one: its time out of contact and the support-passing line.
"""

from __future__ import annotations

import tempfile
import time
from collections.abc import Callable, Mapping
from concurrent.futures import Future
from dataclasses import dataclass

import numpy as np
import pandas as pd

from ..base.bands import third_octave_bands
from ..base.checks import check_in_range, check_int_at_least
from ..base.errors import InputError, InputTypeError
from ..base.parallel import one_thread, thread_map
from ..base.threads import serial_blas
from ..boundary.fitting import BroadbandBoundary
from ..dynamics.factor import factorise
from ..fe.ends import PINNED, BoundaryEnd
from ..fe.kernelcache import clear_kernel_memo
from ..fe.kernels import MovingKernels
from ..fe.models import TruncatedTrack
from ..interaction.fe_model import wheel_rail_response
from ..interaction.moving_green import moving_green_kernels, moving_green_response
from ..interaction.response import ContactResponse
from ..model.roughness import ISO3095_ROUGHNESS_LIMIT, Roughness, roughness_from_spectrum
from ..model.tracks import Track
from ..model.vehicle import as_vehicle
from ..model.wheel import Wheel

__all__ = ["MARGIN_BAYS", "TABLE_FORMATS", "TAIL_FORMATS", "rolling_roughness", "Comparison", "compare_runs",
           "compare_cases", "force_agreement", "moving_table", "impulse_run_step", "contact_table", "finer_mesh_run",
           "tail_run", "tail_table"]

#: How :func:`moving_table`'s columns read best (for :func:`semitrack.paper.tables.styled`).
TABLE_FORMATS = {"rms difference (%)": "{:.4f}", "worst band difference (dB)": "{:.1e}",
                 "worst band error level (dB)": "{:.1f}", "set-up (s)": "{:.1f}", "from cache (s)": "{:.2f}",
                 "step, compiled (us)": "{:.2f}", "step, Python (us)": "{:.1f}", "run, compiled (s)": "{:.2f}",
                 "km/h": "{:.0f}"}

#: Bays of the truncated reference beyond the path at each end: its broadband ends' reflections
#: then return at 1e-5 to 1e-4 of the force's fluctuation on the default meshes (measured; on a
#: coarse mesh of 8 elements per bay 3e-4, 1e-3 with 20 bays and 3e-6 with 120).
MARGIN_BAYS = 40


def rolling_roughness(speed: float, f_low: float = 40.0, f_high: float = 3000.0, period: float = 0.1,
                      seed: int = 1) -> Roughness:
    """The ISO 3095 limit spectrum over the wavelengths a wheel at ``speed`` passes between ``f_low`` and ``f_high``.

    Parameters
    ----------
    speed : float
        Speed (m/s).
    f_low, f_high : float
        The frequencies the wavelengths are kept between (Hz).
    period : float
        The roughness's period (s).
    seed : int
        Seed of the random phases.

    Returns
    -------
    Roughness
    """
    kept = {lam: level for lam, level in ISO3095_ROUGHNESS_LIMIT.items() if f_low <= speed / lam <= f_high}
    return roughness_from_spectrum(speed, list(kept), list(kept.values()), period=period, seed=seed)


@dataclass(frozen=True, eq=False)
class Comparison:
    """One vehicle at one speed by moving Green's functions and by the truncated model.

    Attributes
    ----------
    label : str
        Track and vehicle.
    kmh : float
        The speed asked (km/h); the runs' is the rounded ``green.speed``.
    green, truncated : ContactResponse
        The two runs.
    kernels : MovingKernels
        The kernels used.
    setup : float
        CPU time of the kernels' set-up (s; on one thread, BLAS and the set-up's parts too).
    from_cache : float
        CPU time to read them back from a cache folder in a fresh process memory (s).
    step_compiled : float
        Wall time of a step of the compiled loop (us; the loop alone, ``green.elapsed``, on a core of
        its own while it runs).
    step_numpy : float
        Wall time of a step of the Python loop (us), timed alone after the other runs.
    truncated_dofs : int
        DOFs of the truncated model.
    truncated_time : float
        CPU time of the truncated model's run (s; one thread).
    green_time : float
        CPU time of the compiled run on the kernels (s; one thread).
    track : Track
        The track.
    start : float
        The vehicle's start as both runs were given it (m; the first wheel's position).
    roughness : Roughness
        The rail's roughness of both runs (:func:`rolling_roughness`).
    """

    label: str
    kmh: float
    green: ContactResponse
    truncated: ContactResponse
    kernels: MovingKernels
    setup: float
    from_cache: float
    step_compiled: float
    step_numpy: float
    truncated_dofs: int
    truncated_time: float
    green_time: float
    track: Track
    start: float
    roughness: Roughness


def compare_runs(label: str, track: Track, boundary: BroadbandBoundary, vehicle, kmh: float, dt: float,
                 duration: float, numpy_duration: float = 0.05, kernels: MovingKernels | None = None) -> Comparison:
    """One vehicle on a rough rail by both routes (see the module docstring).

    Parameters
    ----------
    label : str
        The case's name.
    track : Track
        A periodic track (viscous damping).
    boundary : BroadbandBoundary
        Its broadband end, for the truncated model.
    vehicle : Wheel, Bogie or sequence of Wheel
        The vehicle.
    kmh : float
        Speed (km/h).
    dt, duration : float
        Time step and duration (s).
    numpy_duration : float
        Duration of the Python loop's timed run (s).
    kernels : MovingKernels, optional
        Kernels already computed for this track, speed, step and start whose offsets hold this
        vehicle's (a bogie's for one of its wheels): used as they are, and the set-up and the cache's
        read are not timed (NaN).

    Returns
    -------
    Comparison
    """
    return _timed_python_step(_both_routes(label, track, boundary, vehicle, kmh, dt, duration, kernels),
                              numpy_duration)


def compare_cases(cases: Mapping[str, tuple], duration: float, shares: Mapping[str, str] | None = None,
                  numpy_duration: float = 0.05) -> dict[str, Comparison]:
    """:func:`compare_runs` for several cases, side by side on this machine's cores.

    The cases' set-ups and runs go on threads (:func:`semitrack.base.parallel.thread_map`): the
    compiled loops and the set-up's matrix products release the GIL, so on two cores two cases take
    about the time of one, and every force is the one :func:`compare_runs` gives alone, bit for bit
    (one BLAS thread in both). The set-up, the cache's read and both runs are costed by their
    thread's CPU time, which another case on the other core does not inflate (two hardware threads
    of one core would); a step of the compiled loop by the loop's own wall time; the Python loop's
    steps, which the GIL would slow, are timed after, alone, as wall time.

    Parameters
    ----------
    cases : mapping of str to tuple
        ``{label: (track, boundary, vehicle, kmh, dt)}`` as :func:`compare_runs` takes them.
    duration : float
        Duration of every run (s).
    shares : mapping of str to str, optional
        ``{label: other label}``: the case reads the other's kernels (a bogie's for one of its
        wheels, on the same track, speed and step), which are computed first.
    numpy_duration : float
        Duration of each Python loop's timed run (s).

    Returns
    -------
    dict of str to Comparison
        In the order of ``cases``.
    """
    shares = dict(shares or {})
    for label, source in shares.items():
        if label not in cases or source not in cases or source in shares:
            raise InputError(f"shares must map a case to another case that computes its own kernels, got "
                             f"{label!r}: {source!r} for the cases {list(cases)}")
    kernels_of = {label: Future() for label in cases if label not in shares}

    def one(label: str) -> _Routes:
        """A case; one that reads another's kernels waits for them, from an item that started before it."""
        if label in shares:
            return _both_routes(label, *cases[label], duration, kernels_of[shares[label]].result())
        found = kernels_of[label]
        try:  # its readers may start as soon as the kernels are there, not after this case's runs
            return _both_routes(label, *cases[label], duration, on_kernels=found.set_result)
        except BaseException as err:
            if not found.done():
                found.set_exception(err)  # its readers raise it too, not wait for ever
            raise

    # The cases that compute kernels first: the items start in this order (and a reader on a thread that is
    # free waits only for kernels under way), so the readers fill the threads that finish first.
    order = list(kernels_of) + list(shares)
    done = dict(zip(order, thread_map(one, order)))
    return {label: _timed_python_step(done[label], numpy_duration) for label in cases}


@dataclass(frozen=True, eq=False)
class _Routes:
    """Both routes' runs of a case and their costs, before the Python loop is timed."""

    label: str
    kmh: float
    track: Track
    green: ContactResponse
    truncated: ContactResponse
    kernels: MovingKernels
    setup: float
    from_cache: float
    rough: Roughness
    run: dict
    vehicle: object
    truncated_dofs: int
    truncated_time: float
    green_time: float


def _both_routes(label: str, track: Track, boundary: BroadbandBoundary, vehicle, kmh: float, dt: float,
                 duration: float, kernels: MovingKernels | None = None,
                 on_kernels: Callable[[MovingKernels], object] | None = None) -> _Routes:
    """The kernels (timed from an empty cache and read back, unless given; handed to ``on_kernels`` once
    there), the compiled run on them and the truncated model's run, each cost its thread's CPU time: all
    of it on this thread (one BLAS thread, and the set-up's parts in turn)."""
    vehicle = as_vehicle(vehicle)
    speed = kmh / 3.6
    path = speed * duration
    x0 = -round(0.5 * path / track.spacing) * track.spacing  # the path centred on the model, from a mid-span
    setup = from_cache = float("nan")
    with serial_blas(), one_thread():
        if kernels is None:
            with tempfile.TemporaryDirectory() as folder:
                clear_kernel_memo()  # timed from nothing: this process keeps no kernels from before
                start = time.thread_time()
                kernels = moving_green_kernels(track, speed, dt, vehicle.offsets, x=x0, cache=folder)
                setup = time.thread_time() - start
                clear_kernel_memo(kernels)  # read back as a fresh process would
                start = time.thread_time()
                moving_green_kernels(track, speed, dt, vehicle.offsets, x=x0, cache=folder)
                from_cache = time.thread_time() - start
        if on_kernels is not None:
            on_kernels(kernels)
        rough = rolling_roughness(kernels.grid.speed)
        run = {"x": x0, "speed": speed, "dt": dt, "kernels": kernels}
        moving_green_response(track, vehicle, rough, duration=0.03, **run)  # compile outside the timing
        start = time.thread_time()
        green = moving_green_response(track, vehicle, rough, duration=duration, **run)
        green_time = time.thread_time() - start
        model = _holding_the_path(track, boundary, green, kernels.elements_per_bay)
        start = time.thread_time()
        truncated = wheel_rail_response(model, green.vehicle, rough, x=x0, speed=green.speed, dt=dt,
                                        duration=duration)  # the vehicle as run: its offsets on the grid
        spent = time.thread_time() - start
    return _Routes(label, kmh, track, green, truncated, kernels, setup, from_cache, rough, run, vehicle, model.n_dof,
                   spent, green_time)


def tail_run(comparison: Comparison, tail_rank: int = 4, tail_start: float | None = None) -> ContactResponse:
    """The comparison's moving Green's functions run again, its kernels' tails in low rank.

    Parameters
    ----------
    comparison : Comparison
        From :func:`compare_runs` or :func:`compare_cases`: its track, kernels, vehicle, start, speed,
        step, duration and roughness.
    tail_rank : int
        The rank of the kernels past ``tail_start`` (:func:`semitrack.moving_green_response`).
    tail_start : float, optional
        Where the tail starts (s); default :data:`semitrack.interaction.moving_green.DEFAULT_TAIL_START`.

    Returns
    -------
    ContactResponse
        The run as the comparison's was made, on the same kernels.
    """
    if not isinstance(comparison, Comparison):
        raise InputTypeError(f"comparison must be a Comparison (compare_runs, compare_cases), got "
                             f"{type(comparison).__name__}")
    green = comparison.green
    return moving_green_response(comparison.track, green.vehicle, comparison.roughness, x=comparison.start,
                                 speed=green.speed, dt=comparison.kernels.grid.dt, duration=float(green.t[-1]),
                                 kernels=comparison.kernels, tail_rank=tail_rank, tail_start=tail_start)


def tail_table(comparisons: Mapping[str, Comparison], labels, tail_rank: int = 4,
               tail_start: float | None = None) -> pd.DataFrame:
    """Each comparison's run again with the kernels' tails in low rank (:func:`tail_run`), against both of its runs.

    Parameters
    ----------
    comparisons : mapping of str to Comparison
        From :func:`compare_cases`.
    labels : sequence of str
        Which of them.
    tail_rank : int
        The tails' rank.
    tail_start : float, optional
        Where the tails start (s).

    Returns
    -------
    pandas.DataFrame
        By case, each the largest over the wheels: the rms difference from the whole kernels' run (%),
        the worst band level difference from it (dB), the rms difference from the truncated model's
        run (%); and the step on the whole kernels and with the tail (us, wall time; the tail's FFTs
        included; the loop the comparison ran, compiled where numba is installed).
    """
    rows = {}
    for label in labels:
        c = comparisons[label]
        run = tail_run(c, tail_rank, tail_start)
        wheels = range(len(c.green.wheels))  # the vehicle's: shared kernels may hold more offsets
        whole = [force_agreement(run, c.green, wheel=i) for i in wheels]
        truncated = [force_agreement(run, c.truncated, wheel=i) for i in wheels]
        rows[label] = {"rms from the whole kernels (%)": 100 * max(a["rms"] for a in whole),
                       "worst band from the whole kernels (dB)": max(a["worst_level_difference"] for a in whole),
                       "rms from the truncated model (%)": 100 * max(a["rms"] for a in truncated),
                       "step, whole kernels (us)": c.step_compiled,
                       "step, low-rank tail (us)": 1e6 * run.elapsed / (run.t.size - 1)}
    return pd.DataFrame(rows).T.rename_axis("case")


#: How :func:`tail_table`'s columns are shown.
TAIL_FORMATS = {"rms from the whole kernels (%)": "{:.5f}", "worst band from the whole kernels (dB)": "{:.1e}",
                "rms from the truncated model (%)": "{:.4f}", "step, whole kernels (us)": "{:.2f}",
                "step, low-rank tail (us)": "{:.2f}"}


def _holding_the_path(track: Track, boundary: BroadbandBoundary, run: ContactResponse,
                      elements_per_bay: int) -> TruncatedTrack:
    """The truncated model with broadband ends that holds the path of ``run``'s wheels, and
    :data:`MARGIN_BAYS` beyond it at each end."""
    # run.x holds every wheel; the offsets once more are the margin the comparisons were measured with
    reach = np.abs(run.x).max() + np.abs(run.vehicle.offsets).max() + track.spacing
    return TruncatedTrack(track, int(np.ceil(reach / track.spacing)) + MARGIN_BAYS, BoundaryEnd.name,
                          system=boundary, elements_per_bay=int(elements_per_bay))


def finer_mesh_run(comparison: Comparison, boundary: BroadbandBoundary, factor: int = 2) -> ContactResponse:
    """The comparison's case on a mesh ``factor`` times finer, by the truncated model (the reference route).

    The two routes agree on one mesh far closer than either moves with the mesh, so either measures
    the mesh's effect; the truncated model's finer run costs less than new kernels (measured on the
    slab track's wheel at 300 km/h and 40 us: 3.8 s against 8.9 s, one thread).

    Parameters
    ----------
    comparison : Comparison
        From :func:`compare_runs` or :func:`compare_cases`: its track, vehicle, start, speed, step,
        duration and roughness.
    boundary : BroadbandBoundary
        The track's broadband end (on the finer mesh the same fit: it is the track's, not the mesh's).
    factor : int
        How many times finer than the comparison's mesh (elements per bay), 2 to 8.

    Returns
    -------
    ContactResponse
        The run as the comparison's truncated run was made (the vehicle as run, its offsets on the grid),
        on the finer mesh.
    """
    if not isinstance(comparison, Comparison):
        raise InputTypeError(f"comparison must be a Comparison (compare_runs, compare_cases), got "
                             f"{type(comparison).__name__}")
    factor = int(check_in_range("factor", check_int_at_least("factor", factor, 2), (2, 8), "times the mesh"))
    green, dt = comparison.green, comparison.kernels.grid.dt
    model = _holding_the_path(comparison.track, boundary, green, factor * comparison.kernels.elements_per_bay)
    return wheel_rail_response(model, green.vehicle, comparison.roughness, x=comparison.start, speed=green.speed,
                               dt=dt, duration=float(green.t[-1]))


def _timed_python_step(routes: _Routes, numpy_duration: float) -> Comparison:
    """The case's :class:`Comparison`, with a step of the Python loop timed on the same kernels (us)."""
    green = routes.green
    numpy = moving_green_response(routes.track, routes.vehicle, routes.rough, duration=numpy_duration, compiled=False,
                                  **routes.run)
    return Comparison(routes.label, routes.kmh, green, routes.truncated, routes.kernels, routes.setup,
                      routes.from_cache, 1e6 * green.elapsed / (green.t.size - 1),
                      1e6 * numpy.elapsed / (numpy.t.size - 1), routes.truncated_dofs, routes.truncated_time,
                      routes.green_time, routes.track, routes.run["x"], routes.rough)


def impulse_run_step(track: Track, bays: int, dt: float, positions: int, elements_per_bay: int | None = None,
                     repeat: int = 3) -> tuple[int, float]:
    """The cost of one step of the alternative source of the kernels: an FE impulse run with a load per position.

    The kernels could also come from Newmark run on a long FE model with one right-hand side per
    position a contact takes within a spacing; each step then solves the step's factorised
    effective stiffness for all of them and forms the mass and damping products.

    Parameters
    ----------
    track : Track
        The track.
    bays : int
        Bays of the model each side of its centre (margins for its ends' reflections and the memory's reach).
    dt : float
        Time step (s).
    positions : int
        Right-hand sides (the positions per spacing).
    elements_per_bay : int, optional
        The mesh (default: the default mesh for 3 kHz).
    repeat : int
        Steps timed (the mean is returned).

    Returns
    -------
    n_dof : int
        The model's DOFs.
    seconds : float
        Wall time of one step (s).
    """
    model = TruncatedTrack(track, bays, PINNED.name, elements_per_bay=elements_per_bay)
    M, C, K = model.matrices()
    factor = factorise(K + 2 / dt * C + 4 / dt**2 * M, model.dofs.along_track(model.mesh))
    rhs = np.random.default_rng(0).random((model.n_dof, positions))
    start = time.perf_counter()
    for _ in range(repeat):
        factor.solve(M @ rhs + C @ rhs)
    return model.n_dof, (time.perf_counter() - start) / repeat


def force_agreement(green: ContactResponse, truncated: ContactResponse, wheel: int = 0, after: float = 0.1,
                    band: tuple[float, float] = (50.0, 2500.0)) -> dict:
    """How closely two runs' contact forces agree, from time ``after`` on.

    Parameters
    ----------
    green, truncated : ContactResponse
        The run and its reference, on the same time steps.
    wheel : int
        Which wheel's force.
    after : float
        Start of the compared record (s).
    band : (float, float)
        Lowest and highest one-third-octave band centres (Hz).

    Returns
    -------
    dict
        ``rms`` (the difference's rms over the reference's fluctuation's, -), ``centres`` (Hz),
        ``level_difference`` (dB, per band), ``error_level`` (dB, the difference's band level
        under the reference's), their largest magnitudes ``worst_level_difference`` and
        ``worst_error_level``. A band that holds no frequency of the record (a record shorter than
        about the inverse of the band's width: 0.09 s for the 50-Hz band) is left out of all of them:
        ``centres`` lists the bands kept.
    """
    column = (lambda a: a) if green.force.ndim == 1 else (lambda a: a[:, wheel])  # noqa: E731
    late = green.t >= after
    if np.count_nonzero(late) < 2:
        raise InputError(f"after={after!r} s leaves fewer than two steps of the {green.t[-1]:g}-s runs to compare")
    F, R = column(green.force)[late], column(truncated.force)[late]
    fluct = R - R.mean()
    rms = float(np.sqrt(np.mean((F - R) ** 2)) / np.sqrt(np.mean(fluct**2)))
    f = np.fft.rfftfreq(F.size, green.dt)
    spec_f, spec_r = np.abs(np.fft.rfft(F - F.mean())) ** 2, np.abs(np.fft.rfft(fluct)) ** 2
    spec_e = np.abs(np.fft.rfft(F - R - (F - R).mean())) ** 2
    centres, lower, upper = third_octave_bands(*band)
    held = np.array([np.any((f >= lo) & (f < hi)) for lo, hi in zip(lower, upper)])
    if not held.any():
        raise InputError(f"the {F.size * green.dt:.3g}-s record after after={after!r} s holds no frequency of the "
                         f"bands {band} Hz: compare a longer record")
    centres, lower, upper = centres[held], lower[held], upper[held]
    level_f, level_r, level_e = (np.array([s[(f >= lo) & (f < hi)].sum() for lo, hi in zip(lower, upper)])
                                 for s in (spec_f, spec_r, spec_e))
    difference = 10 * np.log10(level_f / level_r)
    error = 10 * np.log10(level_e / level_r)
    return {"rms": rms, "centres": centres, "level_difference": difference, "error_level": error,
            "worst_level_difference": float(np.abs(difference).max()), "worst_error_level": float(error.max())}


def contact_table(track: Track, boundary: BroadbandBoundary, kernels: MovingKernels, rails: Mapping[str, object],
                  duration: float = 0.3, after: float = 0.1) -> pd.DataFrame:
    """One wheel from a mid-span on each rail by both routes: its time out of contact, the largest force
    difference and the support-passing line at ``v / d``.

    Parameters
    ----------
    track : Track
        A periodic track.
    boundary : BroadbandBoundary
        Its broadband end, for the truncated model.
    kernels : MovingKernels
        One wheel's kernels for this track, speed and step, starting at a mid-span (phase 0).
    rails : mapping of str to Roughness or None
        The rails: a roughness at the kernels' speed, or None for a smooth rail.
    duration : float
        Duration of each run (s).
    after : float
        Start of the force spectra (s).

    Returns
    -------
    pandas.DataFrame
        One row per rail; the out-of-contact times and the line's amplitudes in numbers, both routes'.
    """
    speed, dt, d = kernels.grid.speed, kernels.grid.dt, track.spacing

    def both(rough) -> tuple[ContactResponse, ContactResponse]:
        green = moving_green_response(track, Wheel(), rough, speed=speed, dt=dt, duration=duration, kernels=kernels)
        model = _holding_the_path(track, boundary, green, kernels.elements_per_bay)
        return green, wheel_rail_response(model, Wheel(), rough, speed=speed, dt=dt, duration=duration)

    rows = {}
    for label, (green, truncated) in zip(rails, thread_map(both, rails.values())):  # the rails side by side
        f, amp = green.force_spectrum(after=after)
        amp_ref = truncated.force_spectrum(after=after)[1]
        line = int(np.argmin(np.abs(f - speed / d)))
        rows[label] = {"out of contact, Green (ms)": 1e3 * dt * np.count_nonzero(~green.in_contact),
                       "out of contact, truncated (ms)": 1e3 * dt * np.count_nonzero(~truncated.in_contact),
                       "largest force difference (% of peak)":
                       100 * np.abs(green.force - truncated.force).max() / truncated.force.max(),
                       "line at v/d, Green (N)": amp[line], "line at v/d, truncated (N)": amp_ref[line],
                       "v/d (Hz)": speed / d, "smallest force (N)": min(green.force.min(), truncated.force.min())}
    return pd.DataFrame.from_dict(rows, orient="index").rename_axis("rail")


def moving_table(comparisons: Mapping[str, Comparison] | list[Comparison]) -> pd.DataFrame:
    """One row per comparison and wheel: agreement and costs.

    Parameters
    ----------
    comparisons : list of Comparison
        From :func:`compare_runs`.

    Returns
    -------
    pandas.DataFrame
    """
    rows = []
    for c in (comparisons.values() if isinstance(comparisons, Mapping) else comparisons):
        k = len(c.green.wheels)
        for i in range(k):
            a = force_agreement(c.green, c.truncated, wheel=i)
            rows.append({"case": c.label, "km/h": c.kmh, "wheel": i + 1 if k > 1 else "",
                         "rms difference (%)": 100 * a["rms"],
                         "worst band difference (dB)": a["worst_level_difference"],
                         "worst band error level (dB)": a["worst_error_level"],
                         "steps per spacing": c.kernels.grid.positions,
                         "set-up (s)": c.setup, "from cache (s)": c.from_cache,
                         "step, compiled (us)": c.step_compiled, "step, Python (us)": c.step_numpy,
                         "truncated model": f"{c.truncated_dofs} DOFs, {c.truncated_time:.1f} s",
                         "run, compiled (s)": c.green_time})
    return pd.DataFrame(rows).set_index(["case", "km/h", "wheel"])
