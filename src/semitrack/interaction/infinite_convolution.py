"""The convolution route: stationary wheels on the exact infinite track in time, nothing truncated.

The reference of the stationary time-domain cases: the rail's displacement under the contacts is
the convolution of the contact forces with the rail's impulse responses between the contact
points, computed from the exact infinite track (:class:`semitrack.InfiniteTrack`, local changes
included), so no model is truncated and no mesh is involved:

    w_i(t) = w_i,static + sum_j integral h_ij(tau) (F_j(t - tau) - P0_j) dtau

The forces are piecewise linear between the steps, so the kernel is the rail's response to a hat
function of force, ``h = irfft(H sinc^2(f dt)) / dt`` on the grid of the run's step and memory
(``memory`` long: the rail's response must have died away within it; a warning says when it is
still above :data:`WRAP_TOLERANCE` of its peak over the memory's second half), and
``w_n = w_static + dt sum_m h_m (F_(n-m) - P0)``. The vehicle (:class:`semitrack.Bogie`, or wheels
on their suspensions) is integrated by Newmark's average acceleration, and each step's Hertzian
contacts are solved with the step's compliance of the vehicle and the current step's share of
the convolution (:func:`semitrack.dynamics.contact.solve_hertz`). The start is the static one of
:func:`semitrack.wheel_rail_response`, the roughness faded in the same way, so that
:func:`semitrack.contact_transfer` takes the result as it takes an FE run's.

Given ``speed``, the wheels turn at it while the rail passes under them (the moving-irregularity
model): a roughness passes at that speed and each wheel's defects come round once per
revolution. Limits: stationary wheels only (a rolling wheel's kernel changes with its position: the moving
Green's functions of a periodic track); the cost per step grows with the memory (a dot product
over it per wheel pair).
"""

from __future__ import annotations

import functools
import threading
import weakref
from collections.abc import Sequence

import numpy as np

from ..base.checks import MAX_FREQUENCIES, check_nonnegative, check_positive, check_work
from ..base.deprecation import renamed_keywords
from ..base.notices import warn_user
from ..methods.infinite import InfiniteTrack
from ..model.roughness import Roughness
from ..model.tracks import Track
from ..model.vehicle import Vehicle
from ..model.wheel import Wheel
from .convolved_run import convolved_run
from .excitation import rail_input
from .inputs import DEFAULT_DT, check_roughness_speed, check_run
from .response import ContactResponse, contact_response

__all__ = ["WRAP_TOLERANCE", "rail_impulse_responses", "convolution_response"]

#: The largest impulse response over the memory's second half, relative to its peak, that is accepted
#: without a warning.
WRAP_TOLERANCE = 1e-3


#: The rail's impulse responses already computed, per exact track while it lives, by contact
#: points, step and memory: a study of many runs on one track (speeds, defects, wheels that stand
#: in the same places) transforms its receptance once, not once a run (~1 s each).
_IMPULSE_CACHE: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()
_CACHE_LOCK = threading.Lock()
#: The most sets of responses kept for one track (the oldest goes first).
_CACHE_PER_TRACK = 4


def rail_impulse_responses(infinite: InfiniteTrack, x: np.ndarray, dt: float, memory: float
                           ) -> tuple[np.ndarray, np.ndarray, float]:
    """The rail's impulse responses between the contact points, and its static receptance.

    Kept for the track object (read-only arrays): a later call with the same points, step and
    memory on the same ``InfiniteTrack`` returns them without recomputing, so an InfiniteTrack is
    taken to be unchanged once built (its constructor checks what it holds; nothing alters it).

    Parameters
    ----------
    infinite : InfiniteTrack
        The exact infinite track.
    x : ndarray, shape (k,)
        Contact positions (m, its coordinates).
    dt : float
        Time step (s).
    memory : float
        Length of the responses kept (s).

    Returns
    -------
    h : ndarray, shape (n_memory, k, k)
        ``h[m, i, j]``: w at contact i after m steps per unit force at contact j, the force a hat
        function of one step's half-width (m/(N s)): ``w_n = dt sum_m h[m] F_(n-m)``.
    static : ndarray, shape (k, k)
        The static receptance (m/N).
    wrap : float
        The largest |h| over the memory's second half over the largest |h|: what is left to cut off.
    """
    key = (np.asarray(x, dtype=float).tobytes(), float(dt), float(memory))
    held = _IMPULSE_CACHE.setdefault(infinite, {})
    found = held.get(key)  # one read: a run on another thread may drop it between a test and a read
    if found is not None:
        return found
    lags = memory / dt  # guarded before the grid is allocated (1e9 lags asked for 24 GB here)
    check_work(lags + 1, MAX_FREQUENCIES, f"memory={memory!r} s at dt={dt!r} s takes {lags + 1:.3g} frequencies",
               "give a shorter memory or a larger dt")
    n = 2 * int(np.ceil(lags))  # twice the memory: the kept first half is free of the wrap-around
    f = np.fft.rfftfreq(n, dt)
    f[0] = 1e-3 * f[1]  # quasi-static: the receptance's limit at 0 Hz
    k = x.size
    H = np.empty((f.size, k, k), dtype=complex)
    for j in range(k):
        H[:, :, j] = infinite.receptance(f, x[j], x)[:, :, 0, 0]
    # the force piecewise linear between the steps (hat functions, spectrum dt sinc^2(f dt)): the
    # kernel of that force is causal, and the taper removes the ringing of the spectrum cut at Nyquist
    h = np.fft.irfft(H * (np.sinc(f * dt) ** 2)[:, None, None], n=n, axis=0) / dt
    kept = h[: n // 2]  # lags up to the memory (the transform's second half: later lags and the ringing before t = 0)
    tail = np.abs(kept[n // 4:]).max() / np.abs(kept).max()  # what is left over the memory's second half
    kept, static = kept.copy(), H[0].real.copy()  # a copy: the transform's second half is not kept alive
    kept.setflags(write=False)
    static.setflags(write=False)
    found = (kept, static, float(tail))
    with _CACHE_LOCK:  # runs on threads share it: the oldest out and this one in, as one step
        if len(held) >= _CACHE_PER_TRACK:
            held.pop(next(iter(held)))
        held[key] = found
    return found


@renamed_keywords({"x_contact": "x"})
def convolution_response(track: Track | InfiniteTrack, wheel: Wheel | Vehicle | Sequence[Wheel],
                         roughness: Roughness | None = None, *, x: float | Sequence[float] = 0.0,
                         dt: float = DEFAULT_DT, duration: float = 0.1, ramp: float = 0.02,
                         memory: float = 0.4, speed: float = 0.0) -> ContactResponse:
    """Stationary wheels or a vehicle on the exact infinite track, in time (see the module docstring).

    Parameters
    ----------
    track : Track or InfiniteTrack
        The track (its coordinates: m from the central mid-span; support k at ``(k + 1/2) d``).
    wheel : Wheel, sequence of Wheel, or Vehicle
        As :func:`semitrack.wheel_rail_response` takes it.
    roughness : Roughness, optional
        The roughness passing under the first wheel (faded in over ``ramp``); None: a smooth rail.
    x : float or sequence of float
        The contact positions (m), one per wheel (or a vehicle's first wheel's); until 0.3 also
        ``x=``.
    dt, duration, ramp : float
        Time step, duration and fade-in (s).
    memory : float
        How long the rail's impulse responses are kept (s): longer than they take to die away, or
        than the run (a run within the memory uses every lag it has).
    speed : float
        The speed the wheels turn at (m/s), >= 0: the rail passes under them at it, so that their
        defects (:class:`semitrack.WheelFlat`, ...) come round once per revolution and a roughness
        passes at it (its ``speed`` must be this one). The wheels stay where they are on the track
        (the moving-irregularity model). 0 (default): wheels that do not turn.

    Returns
    -------
    ContactResponse
        As an FE run's (``speed = 0``); ``n_dof`` the vehicle's DOFs.
    """
    infinite = track if isinstance(track, InfiniteTrack) else _periodic(track)
    run = check_run(wheel, roughness, x, 0.0, dt, duration, ramp)
    turning = check_nonnegative("speed", speed)
    check_roughness_speed(roughness, turning)
    if turning == 0 and any(w.defects for w in run.vehicle.wheels):
        warn_user("speed=0: the wheels do not turn, and each stays on the point of its tread it starts on; give "
                  "speed= for their defects to come round", RuntimeWarning)
    memory = check_positive("memory", memory)
    h, static, wrap = rail_impulse_responses(infinite, run.x0, run.dt, memory)
    if wrap > WRAP_TOLERANCE and run.t.size > h.shape[0]:  # a run within the memory uses no lag it cut
        warn_user(f"memory={memory!r} s keeps the rail's impulse responses while they are still {wrap:.1e} of "
                  "their peak over its second half: the convolution cuts off their tail; give a longer memory",
                  RuntimeWarning)
    path = run.path()
    r = rail_input(roughness, path, run.dt, run.ramp, wheels=run.vehicle.wheels,
                   rolled=np.repeat(turning * run.t[:, None], run.k, axis=1))
    force, w_wheel, w_rail, elapsed = convolved_run(run.vehicle, *_loop_arrays(h, static, run.dt, r.shape[0]),
                                                    np.zeros(run.k, dtype=np.int64), np.zeros(1), r, run.dt, None)
    return contact_response(route="convolution", t=run.t, force=force, w_wheel=w_wheel, w_rail=w_rail, roughness=r,
                            x=path, track=infinite.track, vehicle=run.vehicle, speed=0.0, ramp=run.ramp,
                            period=None if roughness is None else roughness.period,
                            n_dof=run.vehicle.matrices()[0].shape[0], elapsed=elapsed, infinite=infinite)


def _periodic(track: Track) -> InfiniteTrack:
    """The periodic exact track of ``track``, one object per equal track: runs on the same Track
    share it, and with it the impulse responses kept for it (a track that cannot be hashed gets
    its own)."""
    try:
        return _periodic_of(track)
    except TypeError:  # unhashable: a field the dataclass cannot hash
        return InfiniteTrack(track)


@functools.lru_cache(maxsize=4)
def _periodic_of(track: Track) -> InfiniteTrack:
    return InfiniteTrack(track)


def _loop_arrays(h: np.ndarray, static: np.ndarray, dt: float, rows: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The loop's kernels, pairs and release for stationary wheels (one phase).

    The kernel is ``dt h`` and the release of the standing preloads ``static - dt sum_(k<min(n, L))
    h[k]`` over the whole run, so that ``w_n = static P0 + dt sum_m h_m (F_(n-m) - P0)`` as the
    module docstring writes it (a constant preload gives the static deflection, the memory's tail
    included).
    """
    k, L = static.shape[0], h.shape[0]
    kernels = np.ascontiguousarray((dt * h).transpose(1, 2, 0).reshape(k * k, 1, L))  # one phase per pair
    pair = np.arange(k * k, dtype=np.int64).reshape(k, k)
    taken = np.cumsum(dt * h, axis=0).transpose(1, 2, 0)  # (k, k, L): sum over k <= n of dt h
    held = np.concatenate([np.zeros((k, k, 1)), taken, np.repeat(taken[:, :, -1:], max(rows - L - 1, 0), axis=2)],
                          axis=2)[:, :, :rows]  # sum over k < min(n, L): the memory's cut-off tail stays
    return kernels, pair, static[:, :, None] - held
