"""Time integration of the FE track models: Newmark's average-acceleration scheme and two loads.

:func:`newmark` integrates ``M a + C v + K u = F(t)`` with the unconditionally stable,
non-dissipative average-acceleration rule (gamma = 1/2, beta = 1/4) at a constant step; the
effective stiffness ``K + 2/dt C + 4/dt^2 M`` is factorised once (``scipy.sparse.linalg.splu``).
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
from scipy.linalg import block_diag, lapack
from scipy.sparse.linalg import splu

from ..base.checks import check_int_at_least, check_positive, check_real, check_work
from ..base.threads import serial_blas
from .assembly import band_order
from .element import shear_parameter, timoshenko_shape_functions
from .models import BoundaryAttachment, FETrack

__all__ = [
    "TimeHistory",
    "newmark",
    "hann_pulse",
    "pulse_response",
    "moving_load_response",
    "relative_l2_error",
    "SPEED_300_KMH",
]

#: Most steps x DOFs of one integration (~50 ns each: 5e9 ~ 4 min).
MAX_STEP_DOFS = 5_000_000_000
#: Most recorded values, (n_steps + 1) x outputs (8 bytes each: 2e8 ~ 1.6 GB).
MAX_RECORDED = 200_000_000
#: 300 km/h in m/s.
SPEED_300_KMH = 300.0 / 3.6


@dataclass(frozen=True)
class TimeHistory:
    """Output of :func:`newmark`.

    Attributes
    ----------
    t : ndarray, shape (n_steps + 1,)
        Times (s), starting at 0.
    u : ndarray, shape (n_steps + 1, n_out)
        The recorded outputs (displacements in m, rotations in rad).
    labels : tuple of str
        A label per output column.
    """

    t: np.ndarray
    u: np.ndarray
    labels: tuple = ()


def _as_operator(name, X, n=None):
    if not sp.issparse(X):
        try:
            X = np.asarray(X, dtype=float)
        except (TypeError, ValueError):
            raise TypeError(f"{name} must be a real matrix (dense or scipy.sparse), got {type(X).__name__}") from None
        X = sp.csc_matrix(X)
    if np.iscomplexobj(X.data):
        raise TypeError(f"{name} must be real, got a complex matrix")
    if X.ndim != 2 or X.shape[0] != X.shape[1]:
        raise ValueError(f"{name} must be square, got shape {X.shape}")
    if n is not None and X.shape[0] != n:
        raise ValueError(f"{name} must have shape ({n}, {n}) like M, got {X.shape}")
    return sp.csc_matrix(X, dtype=float)


def newmark(M: ArrayLike | sp.spmatrix, C: ArrayLike | sp.spmatrix, K: ArrayLike | sp.spmatrix,
            load: Callable | tuple, dt: float, n_steps: int,
            outputs: Sequence[int] | ArrayLike | sp.spmatrix | Callable | None = None,
            u0: ArrayLike | None = None, v0: ArrayLike | None = None,
            gamma: float = 0.5, beta: float = 0.25,
            attachments: Sequence[BoundaryAttachment] = (),
            correction: Callable | None = None) -> TimeHistory:
    """Integrate ``M a + C v + K u = F(t)`` with Newmark's method (default: average acceleration).

    Parameters
    ----------
    M, C, K : (n, n) sparse or dense real matrices
        Mass (kg...), damping (N s/m...) and stiffness (N/m...) matrices.
    load : callable or tuple
        Either ``load(t) -> (n,)`` array of generalised forces (N, N m) at time t (s), or
        ``(B, g)`` with ``B`` an ``(n, n_in)`` matrix and ``g`` either a callable
        ``g(t) -> (n_in,)`` or an array of shape ``(n_steps + 1, n_in)`` with the input values
        at the time steps; then ``F(t_k) = B g_k``.
    dt : float
        Constant time step (s).
    n_steps : int
        Number of steps; the histories hold ``n_steps + 1`` times including t = 0. ``n_steps``
        times the number of DOFs may not exceed :data:`MAX_STEP_DOFS` (5e9), nor ``n_steps + 1``
        times the number of outputs :data:`MAX_RECORDED` (2e8).
    outputs : None, sequence of int, matrix or callable
        What to record: ``None`` all DOFs; DOF indices; an ``(n_out, n)`` matrix (e.g.
        :meth:`FETrack.output_matrix`); or ``outputs(t, u) -> (n_out,)`` for outputs that move
        (e.g. the rail under a moving load).
    u0, v0 : array_like, optional
        Initial displacement and velocity (default 0). The initial acceleration is solved from
        the equation of motion (``M`` must then be non-singular unless the initial residual
        force is zero).
    gamma, beta : float
        Newmark parameters; 1/2 and 1/4 (average acceleration, unconditionally stable, no
        numerical damping). Require gamma >= 1/2 and beta >= (gamma + 1/2)^2 / 4.
    attachments : sequence of BoundaryAttachment
        First-order boundary states coupled at end DOFs (:meth:`FETrack.boundary_states`),
        integrated with the trapezoidal rule, which is the same discretisation as average
        acceleration (so these need ``gamma = 1/2, beta = 1/4``). Each adds only a 2x2 block
        to the effective stiffness at its end DOFs; see :class:`_StateCoupling`.
    correction : callable, optional
        ``correction(k, u_free, solve) -> u``: a force that depends on the new state (a wheel's
        contact, :mod:`semitrack.fe.contact`). Each step's new displacement is linear in such a
        force ``F`` along a load vector ``b``: ``u = u_free + solve(b) F``, where ``u_free`` is
        the step's solution without it and ``solve`` applies the inverse of the constant
        effective stiffness; ``correction`` finds ``F`` at step ``k`` and returns ``u``.

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
    M = _as_operator("M", M)
    n = M.shape[0]
    C = _as_operator("C", C, n)
    K = _as_operator("K", K, n)
    dt = check_positive("dt", dt)
    n_steps = check_int_at_least("n_steps", n_steps, 1)
    check_work(n_steps * n, MAX_STEP_DOFS, f"n_steps = {n_steps} steps x {n} DOFs give {n_steps * n} step-DOFs",
               "use a larger dt, a shorter duration or a smaller model")
    gamma = check_real("gamma", gamma)
    beta = check_real("beta", beta)
    if gamma < 0.5 or beta < 0.25 * (gamma + 0.5) ** 2 - 1e-15:
        raise ValueError(
            "gamma and beta must satisfy gamma >= 1/2 and beta >= (gamma + 1/2)^2 / 4 (unconditional "
            f"stability), got gamma={gamma!r}, beta={beta!r}"
        )
    if attachments and (gamma != 0.5 or beta != 0.25):
        raise ValueError("boundary attachments need the average-acceleration rule (gamma=1/2, beta=1/4), "
                         f"got gamma={gamma!r}, beta={beta!r}")
    coupling = _StateCoupling(attachments, dt, n) if attachments else None
    t = dt * np.arange(n_steps + 1)
    force = _load_function(load, n, n_steps, t)
    record, n_out, labels = _recorder(outputs, n)
    check_work((n_steps + 1) * n_out, MAX_RECORDED, f"n_steps = {n_steps} steps x {n_out} outputs give "
               f"{(n_steps + 1) * n_out} recorded values", "record fewer outputs (outputs=...) or fewer steps")

    u = np.zeros(n) if u0 is None else _vector("u0", u0, n)
    v = np.zeros(n) if v0 is None else _vector("v0", v0, n)
    a = _initial_acceleration(M, force(0, t[0]) - C @ v - K @ u)

    a0, a1 = 1.0 / (beta * dt * dt), gamma / (beta * dt)
    a2, a3 = 1.0 / (beta * dt), 1.0 / (2 * beta) - 1.0
    a4, a5 = gamma / beta - 1.0, dt * (gamma / (2 * beta) - 1.0)
    K_eff = K + a1 * C + a0 * M
    lu = _factor(sp.csc_matrix(K_eff if coupling is None else K_eff + coupling.stiffness))
    # M y1 + C y2 as one product of [M C] with (y1, y2): one sparse product a step instead of two
    MC, y = sp.hstack([M, C]).tocsr(), np.empty(2 * n)

    out = np.empty((n_steps + 1, n_out))
    out[0] = record(t[0], u)
    with serial_blas():  # thousands of small triangular solves: threads only contend
        for k in range(1, n_steps + 1):
            np.multiply(a0, u, out=y[:n])
            y[:n] += a2 * v + a3 * a
            np.multiply(a1, u, out=y[n:])
            y[n:] += a4 * v + a5 * a
            rhs = force(k, t[k]) + MC @ y
            if coupling is not None:
                coupling.add_history(rhs, u)
            u_new = lu.solve(rhs)
            if correction is not None:
                u_new = correction(k, u_new, lu.solve)
            if coupling is not None:
                coupling.advance(u, u_new)
            a_new = a0 * (u_new - u) - a2 * v - a3 * a
            v = v + dt * ((1 - gamma) * a + gamma * a_new)
            u, a = u_new, a_new
            out[k] = record(t[k], u)
    return TimeHistory(t=t, u=out, labels=labels)


def _initial_acceleration(M: sp.spmatrix, r0: np.ndarray) -> np.ndarray:
    """``M^-1 r0``: the acceleration at t = 0 from the initial residual force ``r0``."""
    if not np.any(r0 != 0):
        return np.zeros(r0.size)
    try:
        return splu(sp.csc_matrix(M)).solve(r0)
    except RuntimeError:
        raise ValueError("M is singular: the initial acceleration is undefined for a non-zero initial "
                         "force; start from rest with zero load at t = 0") from None


class _BandLU:
    """LU of a real band matrix in a given order (LAPACK ``gbtrf``), solved by ``gbtrs``."""

    def __init__(self, A: sp.csc_matrix, perm: np.ndarray, where: np.ndarray, width: int):
        coo = A.tocoo()
        r, c = where[coo.row], where[coo.col]
        ab = np.zeros((3 * width + 1, A.shape[0]))  # LAPACK's storage: width extra rows for the pivots
        np.add.at(ab, (2 * width + r - c, c), coo.data)
        self.lu, self.piv, info = lapack.dgbtrf(ab, width, width, overwrite_ab=True)
        if info > 0:
            raise RuntimeError("Factor is exactly singular")
        self.perm, self.where, self.width = perm, where, width

    def solve(self, b: np.ndarray) -> np.ndarray:
        x, _ = lapack.dgbtrs(self.lu, self.width, self.width, b[self.perm][:, None], self.piv, overwrite_b=True)
        return x[self.where, 0]


def _factor(A: sp.csc_matrix):
    """LU of the constant effective stiffness of a step: a band LU when it is a narrow band in
    reverse Cuthill-McKee order (a track is a chain: each step's solve then costs O(n), measured
    4-5 times faster than SuperLU's), else SuperLU."""
    coo = A.tocoo()
    order = band_order(coo.row, coo.col, A.shape[0]) if A.shape[0] > 0 else None
    return splu(A) if order is None else _BandLU(A, *order)


class _StateCoupling:
    """Trapezoidal integration of the boundaries' states, eliminated into the Newmark step.

    With ``y = P L u`` an end's motion (``L`` picks the end DOFs, ``P`` the mirror), its states
    obey ``dx/dt = A x + B dy/dt`` and load the rail by ``-L^T P C x``. The trapezoidal rule with
    average acceleration's ``dt/2 (v_n + v_n+1) = u_n+1 - u_n`` gives

        x_n+1 = E x_n + Phi (y_n+1 - y_n),   E = (I - dt/2 A)^-1 (I + dt/2 A),  Phi = (I - dt/2 A)^-1 B,

    so ``-L^T P C x_n+1`` splits into a constant 2x2 stiffness ``L^T P C Phi P L`` at the end
    DOFs (added to the effective stiffness once) and a history load from ``x_n`` and ``u_n``.

    All ends are merged into one block-diagonal state vector and the products ``P C E`` and
    ``P C Phi P`` are formed once: a step then costs two small matrix-vector products, where one
    object per end with the products taken each step cost ~25 us a step (measured), more than the
    banded solve of a 10-bay model.
    """

    def __init__(self, attachments, dt: float, n: int):
        E, Phi_P, P_C = [], [], []
        for att in attachments:
            m = att.A.shape[0]
            lhs = np.eye(m) - 0.5 * dt * att.A
            E.append(np.linalg.solve(lhs, np.eye(m) + 0.5 * dt * att.A))
            Phi_P.append(np.linalg.solve(lhs, att.B) @ att.mirror)
            P_C.append(att.mirror @ att.C)
        self.dofs = np.concatenate([np.asarray(att.dofs) for att in attachments]).astype(int)
        if np.unique(self.dofs).size != self.dofs.size:
            raise ValueError(f"boundary attachments must act on distinct DOFs, got {self.dofs.tolist()}")
        self.E, self.Phi_P = block_diag(*E), block_diag(*Phi_P)
        P_C = block_diag(*P_C)
        self.history_x = P_C @ self.E  # history load per state
        block = P_C @ self.Phi_P  # the constant end stiffness (per end motion, u at the end DOFs)
        rows, cols = np.meshgrid(self.dofs, self.dofs, indexing="ij")
        self.stiffness = sp.csc_matrix((block.ravel(), (rows.ravel(), cols.ravel())), shape=(n, n))
        self.stiffness.eliminate_zeros()  # no coupling between the ends: keep the step's band narrow
        self.block = block
        self.x = np.zeros(self.E.shape[0])

    def add_history(self, rhs: np.ndarray, u: np.ndarray) -> None:
        """Move the known part of ``-L^T P C x_n+1`` to the right-hand side."""
        rhs[self.dofs] -= self.history_x @ self.x - self.block @ u[self.dofs]

    def advance(self, u: np.ndarray, u_new: np.ndarray) -> None:
        """The states at the new step."""
        self.x = self.E @ self.x + self.Phi_P @ (u_new[self.dofs] - u[self.dofs])


def _vector(name, x, n):
    x = np.asarray(x, dtype=float)
    if x.shape != (n,):
        raise ValueError(f"{name} must have shape ({n},), got {x.shape}")
    return x.copy()


def _load_function(load, n, n_steps, t):
    if callable(load):
        def force(k, tk):
            f = np.asarray(load(tk), dtype=float)
            if f.shape != (n,):
                raise ValueError(f"load(t) must return shape ({n},), got {f.shape}")
            return f
        return force
    if not (isinstance(load, tuple) and len(load) == 2):
        raise TypeError(f"load must be a callable load(t) or a tuple (B, g), got {type(load).__name__}")
    B, g = load
    B = sp.csr_matrix(B) if sp.issparse(B) else np.asarray(B, dtype=float)
    if sp.issparse(B) and B.shape[0] * B.shape[1] <= 1_000_000:
        B = B.toarray()  # a few columns: a dense product skips sparse dispatch (~10 us a step)
    if B.ndim != 2 or B.shape[0] != n:
        raise ValueError(f"load matrix B must have shape ({n}, n_in), got {B.shape}")
    n_in = B.shape[1]
    if callable(g):
        return lambda k, tk: np.asarray(B @ np.asarray(g(tk), dtype=float)).ravel()
    g = np.asarray(g, dtype=float)
    if g.ndim == 1 and n_in == 1:
        g = g[:, None]
    if g.shape != (n_steps + 1, n_in):
        raise ValueError(f"load history g must have shape ({n_steps + 1}, {n_in}), got {g.shape}")
    return lambda k, tk: np.asarray(B @ g[k]).ravel()


def _recorder(outputs, n):
    if outputs is None:
        return (lambda tk, u: u), n, tuple(f"dof {i}" for i in range(n))
    if callable(outputs):
        probe = np.atleast_1d(np.asarray(outputs(0.0, np.zeros(n)), dtype=float))
        return (lambda tk, u: outputs(tk, u)), probe.size, tuple(f"output {i}" for i in range(probe.size))
    if sp.issparse(outputs) or (isinstance(outputs, np.ndarray) and outputs.ndim == 2):
        O = sp.csr_matrix(outputs)
        if O.shape[1] != n:
            raise ValueError(f"outputs matrix must have {n} columns, got shape {O.shape}")
        return (lambda tk, u: O @ u), O.shape[0], tuple(f"output {i}" for i in range(O.shape[0]))
    idx = np.asarray(outputs)
    if idx.ndim != 1 or idx.dtype.kind not in "iu" or np.any((idx < 0) | (idx >= n)):
        raise ValueError(f"outputs must be None, DOF indices in [0, {n}), a matrix or a callable, got {outputs!r}")
    return (lambda tk, u: u[idx]), idx.size, tuple(f"dof {i}" for i in idx)


# ------------------------------------------------------------------------------------------------
# Loads on an FE track
# ------------------------------------------------------------------------------------------------
def hann_pulse(t: ArrayLike, duration: float) -> np.ndarray:
    """Unit Hann (raised-cosine) pulse ``sin^2(pi t / duration)`` on ``0 <= t <= duration``, else 0.

    Its amplitude spectrum is ``duration / 2 |sinc(f T) / (1 - (f T)^2)|`` (T = duration) with
    the first zero at ``f = 2 / T``; choose ``T = 2 / f_max`` for content up to ``f_max``.

    Parameters
    ----------
    t : array_like
        Times (s).
    duration : float
        Length T of the pulse (s), positive.

    Returns
    -------
    ndarray
        The pulse at ``t`` (-), same shape.

    Examples
    --------
    >>> hann_pulse([0.0, 0.5e-3, 1e-3, 2e-3], 1e-3).round(12).tolist()
    [0.0, 1.0, 0.0, 0.0]
    """
    duration = check_positive("duration", duration)
    t = np.asarray(t, dtype=float)
    return np.where((t >= 0) & (t <= duration), np.sin(np.pi * t / duration) ** 2, 0.0)


def _check_model(model):
    if not isinstance(model, FETrack):
        raise TypeError(f"model must be an FETrack (e.g. TruncatedTrack), got {type(model).__name__}")


def pulse_response(model: FETrack, positions: ArrayLike = (0.0, 1.95), *, amplitude: float = 1.0,
                   f_max: float = 1500.0, dt: float = 2e-5, t_end: float = 0.03,
                   f_ref: float | dict | None = None) -> TimeHistory:
    """Rail displacement after a Hann force pulse at the central cross-section (x = 0).

    Parameters
    ----------
    model : FETrack
        The track model (not with ``"exact"`` ends).
    positions : array_like
        Where to record the rail's vertical displacement (m from the centre).
    amplitude : float
        Peak force (N), downward.
    f_max : float
        The pulse lasts ``2 / f_max`` s; its spectrum's first zero is at ``f_max`` (Hz).
    dt, t_end : float
        Time step and window length (s).
    f_ref : None, float or dict
        Reference frequencies of the viscous damping model (Hz), see :meth:`FETrack.matrices`.

    Returns
    -------
    TimeHistory
        ``u`` has one column per position (m); labels "w(x=...)".
    """
    _check_model(model)
    positions = np.atleast_1d(np.asarray(positions, dtype=float))
    check_real("amplitude", amplitude)
    duration = 2.0 / check_positive("f_max", f_max)
    n_steps = int(round(check_positive("t_end", t_end) / check_positive("dt", dt)))
    M, C, K = model.matrices(f_ref)
    b = np.zeros((model.n_dof, 1))
    b[model.dof(0.0, "w"), 0] = amplitude
    g = hann_pulse(dt * np.arange(n_steps + 1), duration)[:, None]
    hist = newmark(M, C, K, (b, g), dt, n_steps, outputs=model.output_matrix(positions),
                   attachments=model.boundary_states())
    return TimeHistory(hist.t, hist.u, tuple(f"w(x={x:g} m)" for x in positions))


def moving_load_response(model: FETrack, positions: ArrayLike = (0.0,), *, load: float = 1.0,
                         speed: float = SPEED_300_KMH, x_start: float = -2.0, x_end: float = 2.0,
                         ramp: float = 0.01, dt: float = 2e-5, f_ref: float | dict | None = None) -> TimeHistory:
    """Rail displacement under and near a constant vertical force moving along the rail.

    The force ``load`` (N, downward) moves from ``x_start`` to ``x_end`` (m, from the centre) at
    ``speed`` (m/s), applied as consistent nodal loads (shape functions of the element it is
    on); its magnitude rises as ``sin^2`` over the first ``ramp`` seconds.

    Parameters
    ----------
    model : FETrack
        The track model (not with ``"exact"`` ends).
    positions : array_like
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
        Column 0: the rail displacement under the load (m); then w at each of ``positions``.
    """
    _check_model(model)
    check_real("load", load)
    speed = check_positive("speed", speed)
    x_start, x_end = check_real("x_start", x_start), check_real("x_end", x_end)
    if not x_end > x_start:
        raise ValueError(f"x_end must be greater than x_start={x_start!r}, got {x_end!r}")
    for name, x in (("x_start", x_start), ("x_end", x_end)):
        if not model.x[0] <= x <= model.x[-1]:
            raise ValueError(f"{name} must lie on the rail, {model.x[0]:.6g} <= x <= {model.x[-1]:.6g} m, got {x!r}")
    ramp = check_positive("ramp", ramp)
    dt = check_positive("dt", dt)
    n_steps = int(np.ceil((x_end - x_start) / speed / dt))
    M, C, K = model.matrices(f_ref)
    n = model.n_dof
    positions = np.atleast_1d(np.asarray(positions, dtype=float))
    fixed = model.output_matrix(positions) if positions.size else None

    # The load's element DOFs and shape-function weights at every step, at once (the same numbers
    # as FETrack.shape_weights position by position).
    times = dt * np.arange(n_steps + 1)  # the step times of newmark
    step_dofs, step_weights = _shape_weights_along(model, np.minimum(x_start + speed * times, x_end))

    def weights(tk):
        k = int(round(tk / dt))
        return step_dofs[k], step_weights[k]

    def force(tk):
        idx, nw = weights(tk)
        amp = load * (np.sin(0.5 * np.pi * tk / ramp) ** 2 if tk < ramp else 1.0)
        f = np.zeros(n)
        ok = idx >= 0
        f[idx[ok]] = amp * nw[ok]
        return f

    def record(tk, u):
        idx, nw = weights(tk)
        ok = idx >= 0
        under = float(nw[ok] @ u[idx[ok]])
        if fixed is None:
            return np.array([under])
        return np.concatenate(([under], fixed @ u))

    hist = newmark(M, C, K, force, dt, n_steps, outputs=record, attachments=model.boundary_states())
    labels = ("w under the load",) + tuple(f"w(x={x:g} m)" for x in positions)
    return TimeHistory(hist.t, hist.u, labels)


def _shape_weights_along(model: FETrack, xs: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """:meth:`FETrack.shape_weights` (``w``) at every position of ``xs`` (on the rail), vectorised:
    DOFs and weights, each ``(xs.size, 4)``."""
    mesh, tr = model.mesh, model.track
    h = mesh.element_length
    e = np.clip(np.floor((xs - mesh.x[0]) / h).astype(np.int64), 0, mesh.n_elements - 1)
    xi = np.clip((xs - mesh.x[e]) / h, 0.0, 1.0)
    n_w, _ = timoshenko_shape_functions(xi, h, shear_parameter(tr.E * tr.I, tr.kappa * tr.A * tr.G, h))
    return model.dofs.index[2 * e[:, None] + np.arange(4)], n_w


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
        raise ValueError(f"u and u_ref must have the same shape, got {u.shape} and {u_ref.shape}")
    ref = np.linalg.norm(u_ref, axis=0)
    if np.any(ref == 0):
        raise ValueError("u_ref must not be identically zero in any column for a relative error")
    return np.linalg.norm(u - u_ref, axis=0) / ref
