"""The page on which time-domain route to take: each entry run on one case, its cost and its agreement measured.

Every time-domain entry of the package is run here on the same track (the slab track with viscous
damping), the same wheel and time step, for a short run, and timed on this machine as the book
is built: the set-up (what is paid once: a model and its factorisation, kernels, impulse
responses) and the cost of a step. Each is checked against an independent route where one
exists:

* a wheel rolling at constant speed: the FE model with broadband ends that holds the whole path
  (``wheel_rail_response``) against the moving Green's functions (``moving_green_response``),
  each the other's reference (the same mesh, step, start and roughness);
* a stationary wheel under a passing roughness: the 10-bay FE model with broadband ends against
  the exact infinite track by convolution (``convolution_response``), at two time steps: the FE
  route's Newmark rule shifts a frequency f to ``tan(pi f dt) / (pi dt)`` while the convolution's
  kernels are the continuous track's, so their difference falls as ``dt^2``;
* loads given in advance: a Hann pulse and a moving load on the 10-bay model with broadband ends
  (``fe.timedomain.pulse_response``, ``moving_load_response``) against a long pinned model that
  holds them within its reflection-free time, and ``fe.timedomain.newmark`` on the same model's
  matrices against ``pulse_response``.

The chapters that go with each route measure the same at scale (longer runs, bogies, both
tracks): this page measures what a user choosing a route needs, on one case, in the build.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import pandas as pd

from ..boundary.fitting import BroadbandBoundary
from ..dynamics.signals import hann_pulse
from ..fe.ends import PINNED, BoundaryEnd
from ..fe.models import TruncatedTrack
from ..fe.timedomain import moving_load_response, newmark, pulse_response, relative_l2_error
from ..interaction.fe_model import wheel_rail_response
from ..interaction.infinite_convolution import convolution_response
from ..interaction.moving_green import moving_green_kernels, moving_green_response
from ..interaction.response import ContactResponse
from ..model.tracks import Track
from ..model.wheel import Wheel
from .moving_study import MARGIN_BAYS, force_agreement, rolling_roughness

__all__ = ["RouteRun", "route_runs", "route_table", "ROUTE_FORMATS"]

#: How the page's table prints its columns.
ROUTE_FORMATS = {"set-up (s)": "{:.2f}", "step (us)": "{:.1f}", "difference (%)": "{:.4f}"}


@dataclass(frozen=True)
class RouteRun:
    """One route's run: what it cost and how far it is from its reference.

    Attributes
    ----------
    entry : str
        The function called.
    case : str
        What was run.
    setup : float
        Wall time paid once before the steps (s).
    step : float
        Wall time per step of the loop (s).
    n_dof : int
        DOFs stepped (the vehicle's alone where the rail is a convolution).
    difference : float
        The rms difference from the reference over the reference's rms fluctuation (-).
    reference : str
        What it was compared with.
    """

    entry: str
    case: str
    setup: float
    step: float
    n_dof: int
    difference: float
    reference: str


def _timed(make: Callable):
    start = time.perf_counter()
    out = make()
    return out, time.perf_counter() - start


def _difference(a: np.ndarray, b: np.ndarray) -> float:
    """rms of ``a - b`` over the rms fluctuation of ``b`` about its mean."""
    return float(np.sqrt(np.mean((a - b) ** 2) / np.mean((b - b.mean()) ** 2)))


def _rolling(track: Track, boundary: BroadbandBoundary, wheel: Wheel, speed: float, dt: float, duration: float):
    """A wheel rolling along the rail: the moving Green's functions and the FE model that holds its path."""
    x0 = -round(0.5 * speed * duration / track.spacing) * track.spacing
    kernels, kernel_time = _timed(lambda: moving_green_kernels(track, speed, dt, x=x0))
    rough = rolling_roughness(kernels.grid.speed)
    run = {"x": x0, "speed": speed, "dt": dt, "kernels": kernels}
    moving_green_response(track, wheel, rough, duration=0.03, **run)  # the loop compiled outside the timing
    green = moving_green_response(track, wheel, rough, duration=duration, **run)
    bays = int(np.ceil((abs(x0) + speed * duration + track.spacing) / track.spacing)) + MARGIN_BAYS
    model, model_time = _timed(lambda: TruncatedTrack(track, bays, BoundaryEnd.name, system=boundary,
                                                      elements_per_bay=kernels.elements_per_bay))
    truncated, run_time = _timed(lambda: wheel_rail_response(model, wheel, rough, x=x0, speed=green.speed, dt=dt,
                                                             duration=duration))
    rms = force_agreement(green, truncated, after=0.5 * duration)["rms"]
    case = f"one wheel rolling at {3.6 * speed:.0f} km/h, {duration:g} s, dt = {1e6 * dt:g} us"
    return [RouteRun("wheel_rail_response", case + f" (a {2 * bays}-bay model holds the path)", model_time
                     + run_time - truncated.elapsed, _per_step(truncated), truncated.n_dof, rms,
                     "moving_green_response"),
            RouteRun("moving_green_response", case, kernel_time, _per_step(green), green.n_dof, rms,
                     "wheel_rail_response")]


def _per_step(run: ContactResponse) -> float:
    return run.elapsed / (run.t.size - 1)


def _stationary(track: Track, boundary: BroadbandBoundary, wheel: Wheel, speed: float, dt: float, duration: float):
    """A stationary wheel under a passing roughness: the 10-bay FE model and the exact track by convolution."""
    rough = rolling_roughness(speed)
    model, model_time = _timed(lambda: TruncatedTrack(track, 10, BoundaryEnd.name, system=boundary))
    fe, fe_time = _timed(lambda: wheel_rail_response(model, wheel, rough, dt=dt, duration=duration))
    exact, exact_time = _timed(lambda: convolution_response(track, wheel, rough, dt=dt, duration=duration,
                                                            memory=0.2))  # the slab's responses die within it
    late = fe.t > 0.5 * duration
    rms = _difference(fe.force[late], exact.force[late])
    case = f"one wheel standing, a roughness passing at {3.6 * speed:.0f} km/h, {duration:g} s, dt = {1e6 * dt:g} us"
    return [RouteRun("wheel_rail_response", case + " (10 bays each side, broadband ends)",
                     model_time + fe_time - fe.elapsed, _per_step(fe), fe.n_dof, rms, "convolution_response"),
            RouteRun("convolution_response", case, exact_time - exact.elapsed, _per_step(exact), exact.n_dof, rms,
                     "wheel_rail_response")]


def _given_loads(track: Track, boundary: BroadbandBoundary, dt: float):
    """Loads given in advance on the 10-bay model: a pulse, a moving load and the matrices' own integration."""
    short, short_time = _timed(lambda: TruncatedTrack(track, 10, BoundaryEnd.name, system=boundary,
                                                      elements_per_bay=16))
    long = TruncatedTrack(track, 60, PINNED.name, elements_per_bay=16)  # its reflections return after the window
    x, duration = (0.0, 3 * track.spacing), 0.02
    pulse, pulse_time = _timed(lambda: pulse_response(short, x, f_max=3000.0, dt=dt, duration=duration))
    reference = pulse_response(long, x, f_max=3000.0, dt=dt, duration=duration)
    n_steps = pulse.t.size - 1
    moving, moving_time = _timed(lambda: moving_load_response(short, (0.0,), x_start=-2.0, x_end=2.0, dt=dt))
    moving_ref = moving_load_response(long, (0.0,), x_start=-2.0, x_end=2.0, dt=dt)
    M, C, K = short.matrices()
    load = np.zeros(short.n_dof)
    load[short.dof(0.0)] = 1.0
    g = hann_pulse(dt * np.arange(n_steps + 1), 2.0 / 3000.0)[:, None]
    own, own_time = _timed(lambda: newmark(M, C, K, (load[:, None], g), dt, n_steps,
                                           outputs=short.output_matrix(x), attachments=short.boundary_states()))
    cases = (("pulse_response", f"a Hann pulse (to 3 kHz) at the centre, {duration:g} s, 10 bays, broadband ends",
              pulse_time, pulse, relative_l2_error(pulse.u, reference.u).max(), "the 120-bay pinned model"),
             ("moving_load_response", "a constant load moving 4 m at 300 km/h, 10 bays, broadband ends", moving_time,
              moving, relative_l2_error(moving.u, moving_ref.u).max(), "the 120-bay pinned model"),
             ("newmark", "the same pulse on the 10-bay model's M, C, K and boundary states", own_time, own,
              relative_l2_error(own.u, pulse.u).max(), "pulse_response"))
    # set-up: the model's assembly and, inside the call, the factorisation and the loads before the loop
    return [RouteRun(entry, case, short_time + wall - run.elapsed, run.elapsed / (run.t.size - 1), short.n_dof,
                     float(err), ref) for entry, case, wall, run, err, ref in cases]


def route_runs(track: Track, boundary: BroadbandBoundary, *, dt: float = 4e-5, kmh: float = 300.0,
               duration: float = 0.1, wheel: Wheel | None = None) -> list[RouteRun]:
    """Every time-domain entry on one case (see the module docstring).

    Parameters
    ----------
    track : Track
        A periodic track with viscous damping (every route takes it).
    boundary : BroadbandBoundary
        Its broadband end.
    dt : float
        Time step (s); the stationary case runs at ``dt / 2`` too.
    kmh : float
        The rolling wheel's speed, and the passing roughness's (km/h).
    duration : float
        The vehicle runs' length (s).
    wheel : Wheel, optional
        The wheel (default ``Wheel()``).

    Returns
    -------
    list of RouteRun
    """
    wheel = Wheel() if wheel is None else wheel
    speed = kmh / 3.6
    small = TruncatedTrack(track, 2, elements_per_bay=4)  # the compiled loops loaded outside the timings
    wheel_rail_response(small, wheel, dt=dt, duration=0.03)
    wheel_rail_response(small, wheel, dt=dt, duration=0.03, speed=1.0)
    pulse_response(small, (0.0,), dt=dt, duration=0.001)
    return (_rolling(track, boundary, wheel, speed, dt, duration)
            + [run for step in (dt, dt / 2) for run in _stationary(track, boundary, wheel, speed, step, duration)]
            + _given_loads(track, boundary, dt))


def route_table(runs: list[RouteRun]) -> pd.DataFrame:
    """The runs as the page's table.

    Parameters
    ----------
    runs : list of RouteRun
        From :func:`route_runs`.

    Returns
    -------
    pandas.DataFrame
        A row per run: the entry, the case, set-up (s), step (us), DOFs stepped, the difference
        from the reference (%) and the reference.
    """
    return pd.DataFrame([{"entry": r.entry, "case": r.case, "set-up (s)": r.setup, "step (us)": 1e6 * r.step,
                          "DOFs stepped": r.n_dof, "difference (%)": 100 * r.difference, "against": r.reference}
                         for r in runs])
