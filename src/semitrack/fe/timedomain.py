"""Time integration of the FE track models: Newmark's average-acceleration scheme and two loads.

:func:`newmark` integrates ``M a + C v + K u = F(t)`` with the unconditionally stable,
non-dissipative average-acceleration rule (gamma = 1/2, beta = 1/4) at a constant step; the
effective stiffness ``K + 2/dt C + 4/dt^2 M`` is factorised once (a banded Cholesky,
:mod:`semitrack.dynamics.factor`); the loop is :func:`semitrack.dynamics.simulate.simulate`.
Its period error is about ``(omega dt)^2 / 12``: 0.3 % at 1.5 kHz with the default dt = 20 us.

The matrices come from :meth:`semitrack.fe.models.FETrack.matrices`: rail, pads and ballast
with viscous damping equal to their loss factors at reference frequencies (by default
:meth:`semitrack.Track.reference_frequencies`), the equivalent systems with their
own viscous dampers. The paper fitted those systems to the hysteretically damped track; in the
time domain only viscous damping is available, so the truncated model with equivalent ends and
the long reference track (same viscous model) differ slightly in damping from the hysteretic
track that the systems were fitted to.

Loads (:func:`pulse_response`, :func:`moving_load_response`):

* a Hann (raised-cosine, ``sin^2``) force pulse of duration ``2 / f_max`` at the central
  cross-section; its amplitude spectrum is down 3 dB at ``0.36 f_max``, 20 dB at ``0.82 f_max``
  and has its first zero at ``f_max`` (default 1.5 kHz), falling as ``f^-3`` beyond;
* a constant force moving along the rail at constant speed (default 300 km/h), applied through
  work-equivalent (consistent) nodal loads: the force P at a point of an element gives the nodal
  forces and moments ``P N_w(xi)`` with the element's exact static shape functions, so the load
  and its moment arm follow the load smoothly across nodes and supports. Its magnitude rises
  with a raised-cosine ramp over ``ramp`` seconds to avoid an impulsive start.

:func:`relative_l2_error` is the error norm used to compare a truncated model with the long
reference: ``||u - u_ref||_2 / ||u_ref||_2`` over the time window, per output
(:func:`semitrack.fe.truncation.truncation_errors` runs that comparison).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from numpy.typing import ArrayLike

from ..base.checks import check_int_at_least, check_positive, check_real, check_steps, check_work
from ..base.deprecation import renamed_keywords
from ..base.errors import InputError, InputTypeError
from ..dynamics.newmark import Newmark
from ..dynamics.points import PointSet
from ..dynamics.signals import hann_pulse, sin2_ramp
from ..dynamics.simulate import MAX_RECORDED, MAX_STEP_DOFS, check_limits, simulate
from ..dynamics.states import StateBlock
from ..dynamics.system import SecondOrderSystem
from .models import FETrack, require_model

__all__ = [
    "TimeHistory",
    "newmark",
    "pulse_response",
    "moving_load_response",
    "relative_l2_error",
    "SPEED_300_KMH",
    "MAX_STEP_DOFS",
    "MAX_RECORDED",
]

#: 300 km/h in m/s.
SPEED_300_KMH = 300.0 / 3.6


@dataclass(frozen=True)
class TimeHistory:
    """Output of :func:`newmark`, :func:`pulse_response` and :func:`moving_load_response`.

    Attributes
    ----------
    t : ndarray, shape (n_steps + 1,)
        Times (s), starting at 0.
    u : ndarray, shape (n_steps + 1, n_out)
        The recorded outputs (displacements in m, rotations in rad).
    labels : tuple of str
        A label per output column.
    elapsed : float
        Wall time of the step loop (s): the factorisation and the set-up before it not counted.
    """

    t: np.ndarray
    u: np.ndarray
    labels: tuple = ()
    elapsed: float = 0.0


def _load_points(load, n: int, n_steps: int, t: np.ndarray) -> tuple[PointSet, np.ndarray]:
    """The (points, amplitudes) of :func:`newmark`'s load forms, sampled at the step times."""
    if callable(load):
        check_work((n_steps + 1) * n, MAX_RECORDED, f"a load callable sampled at {n_steps + 1} steps x {n} DOFs",
                   "give the load as (B, g) with few columns")
        samples = np.empty((n_steps + 1, n))
        for k, tk in enumerate(t):
            f = np.asarray(load(tk), dtype=float)
            if f.shape != (n,):
                raise InputError(f"load(t) must return shape ({n},), got {f.shape}")
            samples[k] = f
        return PointSet.on_dofs(np.arange(n)), samples
    if not (isinstance(load, tuple) and len(load) == 2):
        raise InputTypeError(f"load must be a callable load(t) or a tuple (B, g), got {type(load).__name__}")
    B, g = load
    B = sp.csc_matrix(B) if sp.issparse(B) else np.asarray(B, dtype=float)
    if B.ndim != 2 or B.shape[0] != n:
        raise InputError(f"load matrix B must have shape ({n}, n_in), got {B.shape}")
    n_in = B.shape[1]
    if callable(g):
        g = np.array([np.asarray(g(tk), dtype=float).reshape(n_in) for tk in t])
    g = np.asarray(g, dtype=float)
    if g.ndim == 1 and n_in == 1:
        g = g[:, None]
    if g.shape != (n_steps + 1, n_in):
        raise InputError(f"load history g must have shape ({n_steps + 1}, {n_in}), got {g.shape}")
    return PointSet.from_matrix(B), g


def _recorded(outputs, n: int) -> tuple[np.ndarray | None, dict, tuple]:
    """DOFs to record, or a probe matrix, for :func:`newmark`'s output forms."""
    if outputs is None:
        return None, {}, tuple(f"dof {i}" for i in range(n))
    if sp.issparse(outputs) or (isinstance(outputs, np.ndarray) and outputs.ndim == 2):
        O = sp.csr_matrix(outputs)
        if O.shape[1] != n:
            raise InputError(f"outputs matrix must have {n} columns, got shape {O.shape}")
        labels = tuple(f"output {i}" for i in range(O.shape[0]))
        return np.zeros(0, np.int64), {"out": PointSet.from_matrix(O.T)}, labels
    idx = np.asarray(outputs)
    if idx.ndim != 1 or idx.dtype.kind not in "iu" or np.any((idx < 0) | (idx >= n)):
        raise InputError(f"outputs must be None, DOF indices in [0, {n}) or a matrix, got {outputs!r}")
    return idx, {}, tuple(f"dof {i}" for i in idx)


def newmark(M: ArrayLike | sp.spmatrix, C: ArrayLike | sp.spmatrix, K: ArrayLike | sp.spmatrix,
            load: Callable | tuple, dt: float, n_steps: int,
            outputs: Sequence[int] | ArrayLike | sp.spmatrix | None = None,
            u0: ArrayLike | None = None, v0: ArrayLike | None = None,
            gamma: float = 0.5, beta: float = 0.25, attachments: Sequence[StateBlock] = ()) -> TimeHistory:
    """Integrate ``M a + C v + K u = F(t)`` with Newmark's method (default: average acceleration).

    A convenience over :func:`semitrack.dynamics.simulate.simulate` for matrices and a load in
    one of two forms.

    Parameters
    ----------
    M, C, K : (n, n) sparse or dense real matrices
        Mass (kg...), damping (N s/m...) and stiffness (N/m...) matrices.
    load : callable or tuple
        Either ``load(t) -> (n,)`` array of generalised forces (N, N m) at time t (s), sampled
        at the step times before the loop, or ``(B, g)`` with ``B`` an ``(n, n_in)`` matrix and
        ``g`` either a callable ``g(t) -> (n_in,)`` or an array of shape ``(n_steps + 1, n_in)``
        with the input values at the time steps; then ``F(t_k) = B g_k``.
    dt : float
        Constant time step (s).
    n_steps : int
        Number of steps; the histories hold ``n_steps + 1`` times including t = 0. ``n_steps``
        times (the number of DOFs + a fixed cost per step) may not exceed :data:`MAX_STEP_DOFS`
        (5e9), nor ``n_steps + 1`` times the values held per step :data:`MAX_RECORDED` (5e7).
    outputs : None, sequence of int or matrix
        What to record: ``None`` all DOFs; DOF indices; or an ``(n_out, n)`` matrix (e.g.
        :meth:`FETrack.output_matrix`).
    u0, v0 : array_like, optional
        Initial displacement and velocity (default 0). The initial acceleration is solved from
        the equation of motion (``M`` must then be non-singular unless the initial residual
        force is zero).
    gamma, beta : float
        Newmark parameters; 1/2 and 1/4 (average acceleration, unconditionally stable, no
        numerical damping). Require gamma >= 1/2 and beta >= (gamma + 1/2)^2 / 4.
    attachments : sequence of StateBlock
        First-order states coupled at DOFs (:meth:`FETrack.boundary_states`), integrated with the
        trapezoidal rule, the same discretisation as average acceleration (so these need
        ``gamma = 1/2, beta = 1/4``); see :mod:`semitrack.dynamics.states`.

    Returns
    -------
    TimeHistory

    Examples
    --------
    An undamped oscillator released from u = 1 m, a quarter period later:

    >>> k, m = 4.0e6, 10.0
    >>> h = newmark([[m]], [[0.0]], [[k]], lambda t: np.zeros(1), 1e-5, 248, u0=[1.0])  # 2.48 ms
    >>> bool(abs(h.u[-1, 0]) < 0.01)
    True
    """
    system = SecondOrderSystem(M, C, K, states=tuple(attachments))
    n = system.n_dof
    stepper = Newmark(dt, gamma, beta)
    n_steps = check_int_at_least("n_steps", n_steps, 1)
    record, probes, labels = _recorded(outputs, n)
    # before a load callable is sampled: the same limits as simulate's
    check_limits(n_steps, n, n if record is None else record.size + sum(p.n_points for p in probes.values()))
    t = stepper.dt * np.arange(n_steps + 1)
    res = simulate(system, stepper, n_steps, loads=[_load_points(load, n, n_steps, t)], probes=probes,
                   record=record, u0=u0, v0=v0)
    return TimeHistory(t=res.t, u=res["out"] if probes else res["dofs"], labels=labels, elapsed=res.elapsed)


# ------------------------------------------------------------------------------------------------
# Loads on an FE track
# ------------------------------------------------------------------------------------------------
@renamed_keywords({"model": "track", "positions": "x", "t_end": "duration"})
def pulse_response(track: FETrack, x: ArrayLike = (0.0, 1.95), *, amplitude: float = 1.0,
                   f_max: float = 1500.0, dt: float = 2e-5, duration: float = 0.03,
                   f_ref: float | dict | None = None) -> TimeHistory:
    """Rail displacement after a Hann force pulse at the central cross-section (x = 0).

    Parameters
    ----------
    track : FETrack
        The FE model (not with ``"exact"`` ends).
    x : array_like
        Where to record the rail's vertical displacement (m from the centre).
    amplitude : float
        Peak force (N), downward.
    f_max : float
        The pulse lasts ``2 / f_max`` s; its spectrum's first zero is at ``f_max`` (Hz).
    dt, duration : float
        Time step and the run's length (s).
    f_ref : None, float or dict
        Reference frequencies of the viscous damping model (Hz), see :meth:`FETrack.matrices`.

    Returns
    -------
    TimeHistory
        ``u`` has one column per position (m); labels "w(x=...)".
    """
    model = require_model(track, "track")
    xs = np.atleast_1d(np.asarray(x, dtype=float))
    amplitude = check_real("amplitude", amplitude)
    pulse_length = 2.0 / check_positive("f_max", f_max)
    stepper = Newmark(check_positive("dt", dt))
    n_steps = check_steps(stepper.dt, duration)
    check_limits(n_steps, model.n_dof, xs.size, 1, f"duration={duration!r} s / dt={dt!r} s")
    pulse = amplitude * hann_pulse(stepper.dt * np.arange(n_steps + 1), pulse_length)
    res = simulate(model.time_domain_system(f_ref), stepper, n_steps,
                   loads=[(PointSet.on_dofs([model.dof(0.0, "w")]), pulse)], probes={"w": model.points(xs)})
    return TimeHistory(res.t, res["w"], tuple(f"w(x={xi:g} m)" for xi in xs), res.elapsed)


@renamed_keywords({"model": "track", "positions": "x"})
def moving_load_response(track: FETrack, x: ArrayLike = (0.0,), *, load: float = 1.0,
                         speed: float = SPEED_300_KMH, x_start: float = -2.0, x_end: float = 2.0,
                         ramp: float = 0.01, dt: float = 2e-5, f_ref: float | dict | None = None) -> TimeHistory:
    """Rail displacement under and near a constant vertical force moving along the rail.

    The force ``load`` (N, downward) moves from ``x_start`` to ``x_end`` (m, from the centre) at
    ``speed`` (m/s), applied as consistent nodal loads (shape functions of the element it is
    on); its magnitude rises as ``sin^2`` over the first ``ramp`` seconds (:func:`sin2_ramp`).

    Parameters
    ----------
    track : FETrack
        The FE model (not with ``"exact"`` ends).
    x : array_like
        Fixed points where the rail's vertical displacement is also recorded (m from the
        centre); may be empty.
    load : float
        The force (N), downward.
    speed : float
        Its speed (m/s); default 300 km/h.
    x_start, x_end : float
        Where the force starts and stops (m from the centre), on the rail, ``x_start < x_end``.
    ramp : float
        Duration of the ``sin^2`` rise of the force (s).
    dt : float
        Time step (s); the window ends when the force reaches ``x_end``.
    f_ref : None, float or dict
        Reference frequencies of the viscous damping model (Hz), see :meth:`FETrack.matrices`.

    Returns
    -------
    TimeHistory
        Column 0: the rail displacement under the load (m); then w at each of ``x``.
    """
    model = require_model(track, "track")
    load = check_real("load", load)
    speed = check_positive("speed", speed)
    x_start, x_end = check_real("x_start", x_start), check_real("x_end", x_end)
    if not x_end > x_start:
        raise InputError(f"x_end must be greater than x_start={x_start!r}, got {x_end!r}")
    for name, end in (("x_start", x_start), ("x_end", x_end)):
        if not model.x[0] <= end <= model.x[-1]:
            raise InputError(f"{name} must lie on the rail, {model.x[0]:.6g} <= x <= {model.x[-1]:.6g} m, "
                             f"got {end!r}")
    ramp = check_positive("ramp", ramp)
    stepper = Newmark(check_positive("dt", dt))
    n_steps = check_steps(stepper.dt, (x_end - x_start) / speed, ("dt", "(x_end - x_start) / speed"), ceil=True)
    xs = np.atleast_1d(np.asarray(x, dtype=float))
    check_limits(n_steps, model.n_dof, 1 + xs.size, 9,
                 f"(x_end - x_start) / speed = {(x_end - x_start) / speed:.6g} s / dt={dt!r} s")
    t = stepper.dt * np.arange(n_steps + 1)
    path = model.points(np.minimum(x_start + speed * t, x_end), moving=True)
    probes = {"under": path, "fixed": model.points(xs)}
    res = simulate(model.time_domain_system(f_ref), stepper, n_steps, loads=[(path, load * sin2_ramp(t, ramp))],
                   probes=probes)
    labels = ("w under the load",) + tuple(f"w(x={xi:g} m)" for xi in xs)
    return TimeHistory(res.t, np.hstack([res["under"], res["fixed"]]), labels, res.elapsed)


def relative_l2_error(u: ArrayLike, u_ref: ArrayLike) -> np.ndarray:
    """``||u - u_ref||_2 / ||u_ref||_2`` over time, per column (-).

    Parameters
    ----------
    u : array_like, shape (n_t, n_out) or (n_t,)
        The history to judge.
    u_ref : array_like, same shape
        The reference history; no column may be identically zero.

    Returns
    -------
    ndarray, shape (n_out,) or ()
        Relative errors (fractions).

    Examples
    --------
    >>> float(relative_l2_error([1.0, 2.0, 2.0], [1.0, 2.0, 0.0]).round(6))
    0.894427
    """
    u, u_ref = np.asarray(u, dtype=float), np.asarray(u_ref, dtype=float)
    if u.shape != u_ref.shape:
        raise InputError(f"u and u_ref must have the same shape, got {u.shape} and {u_ref.shape}")
    ref = np.linalg.norm(u_ref, axis=0)
    if np.any(ref == 0):
        raise InputError("u_ref must not be identically zero in any column for a relative error")
    return np.linalg.norm(u - u_ref, axis=0) / ref
