"""One loop for every simulation: a system, a stepper, loads, state blocks, contacts and probes, over arrays.

:func:`simulate` integrates ``M a + C v + K u = f(t) + f_contacts - f_states`` from an initial
state at a constant step, and returns a :class:`~.response.TimeResponse` with named channels.
What it needs is given as arrays, known before the loop: loads as point sets with an amplitude
per step (a pulse, a moving load, a wheel's weight), contacts with their irregularity per step,
probes as point sets (fixed or moving). Nothing is called back inside the loop, so the loop can
be compiled (:mod:`semitrack.dynamics.compiled`, numba) and the NumPy loop
(:mod:`semitrack.dynamics.loop`) is its reference; the two agree to round-off (tested: 1e-12,
and 2e-11 through repeated losses of contact, whose impacts amplify their different summation
orders).

The compiled loop needs a banded Cholesky factor (a real symmetric positive definite effective
stiffness in band order, which every track model with its wheels and ends has), wheels that
touch the track by their contacts only, the track being the largest part of the system
(:func:`compiled_contacts_hold`), and numba; else, or with ``compiled=False``, the NumPy loop
runs.

Limits, checked before any work (:func:`check_limits`, which the time-domain entry points call
before they allocate a step's arrays): steps times DOFs and a fixed cost per step
:data:`MAX_STEP_DOFS`, values held per step :data:`MAX_RECORDED`.
"""

from __future__ import annotations

import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import splu

from ..base.checks import as_real_array, check_flag, check_int_at_least, check_work
from ..base.errors import InputError, InputTypeError
from ..base.threads import serial_blas
from .contact import HertzContacts
from .convolved import convolved_steps, one_contact_steps
from .factor import BandCholesky, factorise
from .loop import Outputs, StepArrays, add_loads, run_numpy
from .newmark import Newmark
from .points import PointSet
from .response import TimeResponse
from .states import TrapezoidalStates
from .system import SecondOrderSystem

__all__ = ["MAX_STEP_DOFS", "MAX_RECORDED", "simulate", "compiled_available", "compiled_contacts_hold",
           "check_limits", "convolved_loop", "Continued", "continue_run", "stepping_of"]

#: Most steps x (DOFs + :data:`STEP_OVERHEAD`) of one integration (compiled ~12 ns per DOF, NumPy
#: ~100 ns: 5e9 ~ 1-8 min).
MAX_STEP_DOFS = 5_000_000_000
#: The fixed cost of one step, in DOFs: the contact solve, the states, the loads and the recording
#: of a step cost what ~1000 DOFs of the matrix solve cost (a 33-DOF model's step costs ~30 times
#: its DOFs' share: by steps x DOFs alone, 1e8 steps of it passed the limit and allocated 763 MiB).
STEP_OVERHEAD = 1_000
#: Most values held per run for every step: (n_steps + 1) x (outputs + per-step inputs + the time),
#: 8 bytes each: 5e7 ~ 400 MB, so that a run stays well under 1 GB.
MAX_RECORDED = 50_000_000


def compiled_available() -> bool:
    """Whether numba is installed, so that the compiled loop can run."""
    try:
        from . import compiled  # noqa: F401  (imports numba: deferred to the first simulation)
    except ImportError:
        return False
    return True


def convolved_loop(compiled: bool | None, one_contact: bool = False):
    """The step loop of contacts against a convolution (:func:`semitrack.dynamics.convolved.convolved_steps`).

    Parameters
    ----------
    compiled : bool or None
        True: compiled (an error without numba); False: as Python with NumPy's dot products;
        None: compiled where numba is installed.
    one_contact : bool
        One contact on a one-DOF vehicle: the Python loop is then
        :func:`~semitrack.dynamics.convolved.one_contact_steps` (the same equations in floats).

    Returns
    -------
    callable
        The loop, with :func:`~semitrack.dynamics.convolved.convolved_steps`'s arguments.
    """
    python = one_contact_steps if one_contact else convolved_steps
    compiled = _compiled_choice(compiled)
    if compiled is False:
        return python
    if compiled is None and not compiled_available():
        return python
    if not compiled_available():
        raise InputError("compiled=True needs numba (pip install numba); compiled=None falls back to NumPy")
    from .compiled import run_convolved  # imports numba: deferred to the first run

    return run_convolved


def _initial_acceleration(M: sp.spmatrix, r0: np.ndarray) -> np.ndarray:
    """``M^-1 r0``: the acceleration at t = 0 from the initial residual force ``r0``."""
    if not np.any(r0 != 0):
        return np.zeros(r0.size)
    try:
        return splu(sp.csc_matrix(M)).solve(r0)
    except RuntimeError:
        raise InputError("M is singular: the initial acceleration is undefined for a non-zero initial "
                         "force; start from rest with zero load at t = 0") from None


def check_limits(n_steps: int, n_dof: int, n_out: int, n_in: int = 1, request: str | None = None) -> None:
    """Refuse, before any work or allocation, a run beyond :data:`MAX_STEP_DOFS` or :data:`MAX_RECORDED`.

    The time is ``n_steps x (n_dof + STEP_OVERHEAD)`` (:data:`STEP_OVERHEAD`: the fixed cost of a
    step); the memory ``(n_steps + 1) x (n_out + n_in + 1)`` values (outputs, per-step inputs
    such as loads, moving points and roughness, and the time).

    Parameters
    ----------
    n_steps, n_dof, n_out : int
        Steps, DOFs and recorded outputs of the run.
    n_in : int
        Values per step of the inputs (a load history's columns, a moving point's DOFs and
        weights, a roughness sample per wheel).
    request : str, optional
        What gave ``n_steps``, naming the parameters (e.g. ``"duration=1 s / dt=1e-09 s"``).
    """
    asked = f"n_steps = {n_steps} steps" if request is None else f"{request} gives n_steps = {n_steps} steps"
    check_work(n_steps * (n_dof + STEP_OVERHEAD), MAX_STEP_DOFS,
               f"{asked} x {n_dof} DOFs (+ {STEP_OVERHEAD} per step) give {n_steps * (n_dof + STEP_OVERHEAD):.3g} "
               "step-DOFs", "use a larger dt, a shorter duration or a smaller model")
    per_step = n_out + n_in + 1
    check_work((n_steps + 1) * per_step, MAX_RECORDED, f"{asked} x {n_out} outputs (+ {n_in + 1} input values per "
               f"step) give {(n_steps + 1) * per_step:.3g} values held",
               "record fewer outputs (outputs=...) or take fewer steps")


def _check_points(name: str, points, n: int, rows: int) -> None:
    if not isinstance(points, PointSet):
        raise InputTypeError(f"{name} must be a PointSet, got {type(points).__name__}")
    if points.moving and points.dofs.shape[0] != rows:
        raise InputError(f"{name} moves: it needs {rows} rows (one per step), got {points.dofs.shape[0]}")
    if points.dofs.size and points.dofs.max() >= n:
        raise InputError(f"{name} reaches DOF {points.dofs.max()} of a system of {n}")


def _check_loads(loads, n: int, rows: int) -> list:
    out = []
    for i, item in enumerate(loads):
        try:
            points, amplitude = item
        except (TypeError, ValueError):
            raise InputTypeError(f"loads[{i}] must be a pair (PointSet, amplitudes), "
                                 f"got {type(item).__name__}") from None
        _check_points(f"loads[{i}]", points, n, rows)
        amplitude = np.asarray(amplitude, dtype=float)
        if amplitude.ndim == 1 and points.n_points == 1:
            amplitude = amplitude[:, None]
        if amplitude.shape != (rows, points.n_points):
            raise InputError(f"loads[{i}] amplitudes must have shape ({rows}, {points.n_points}), "
                             f"got {amplitude.shape}")
        out.append((points, amplitude))
    return out


def _prepare(system, stepper, n_steps, loads, contacts, probes, record, u0, v0, a0=None, x0=None,
             stepping=None) -> StepArrays:
    """The loop's inputs in the system's numbering, the initial acceleration included.

    ``a0`` and ``x0`` (the states' values) continue a run where another left off (the travelling
    window, :mod:`semitrack.interaction.window_model`): ``a0`` then replaces the acceleration the
    equation of motion gives at rest. ``stepping`` is the states and the factorisation when
    the caller holds it (the same matrices, step and states).

    The loop integrates the motion about the initial displacement, ``u = u0 + u~``: under a
    preload ``u0`` is the static deflection (a millimetre under a wheel), thousands of times the
    motion, and integrating ``u`` itself would carry its round-off into every approach of the
    contact. The constant load ``-K u0`` and the contacts' irregularity shifted by their initial
    approach make the equations of ``u~`` the same equations; the outputs add ``u0`` back.
    """
    n = system.n_dof
    states, factor = stepping_of(system, stepper) if stepping is None else stepping
    u_ref = np.zeros(n) if u0 is None else _vector("u0", u0, n)
    v = np.zeros(n) if v0 is None else _vector("v0", v0, n)
    if a0 is None:
        r0 = -(system.C @ v) - system.K @ u_ref
        add_loads(r0, loads, 0)
        if contacts is not None:
            r0 += contacts.load_vectors(n, 0) @ contacts.forces(u_ref, 0)
    if contacts is not None:
        initial = u_ref[contacts.wheel_dofs] - _on_points(contacts.points, u_ref, n_steps + 1)
        contacts = replace(contacts, irregularity=contacts.irregularity - initial)
    MC = sp.hstack([system.M, system.C]).tocsr()
    offset = -(system.K @ u_ref) if np.any(u_ref != 0) else np.zeros(0)
    a = _initial_acceleration(system.M, r0) if a0 is None else _vector("a0", a0, n)
    n_states = states.n_states if states is not None else 0
    x = np.zeros(n_states) if x0 is None else _vector("x0", x0, n_states)
    return StepArrays(stepper, n_steps, MC, factor, loads, states, contacts, dict(probes), record, np.zeros(n), v,
                      a, offset, u_ref, x)


def _on_points(points: PointSet, u: np.ndarray, rows: int) -> np.ndarray:
    """The values of ``u`` at the points at every step, ``(rows, n_points)``."""
    values = np.einsum("kpw,kpw->kp", points.weights, u[points.dofs])
    return np.broadcast_to(values, (rows, points.n_points))


def _vector(name, x, n):
    x = as_real_array(x, name)
    if x.shape != (n,):
        raise InputError(f"{name} must have shape ({n},), got {x.shape}")
    return x.copy()


def simulate(system: SecondOrderSystem, stepper: Newmark, n_steps: int, *,
             loads: Sequence[tuple[PointSet, np.ndarray]] = (), contacts: HertzContacts | None = None,
             probes: Mapping[str, PointSet] | None = None, record: Sequence[int] | None = (),
             u0: np.ndarray | None = None, v0: np.ndarray | None = None,
             compiled: bool | None = None) -> TimeResponse:
    """Integrate a system in time from an initial state.

    Parameters
    ----------
    system : SecondOrderSystem
        ``M, C, K`` and the state blocks.
    stepper : Newmark
        The scheme and its step ``dt`` (s).
    n_steps : int
        Steps to take; the channels hold ``n_steps + 1`` rows from t = 0. Steps times DOFs may
        not exceed :data:`MAX_STEP_DOFS`, nor recorded values :data:`MAX_RECORDED`.
    loads : sequence of (PointSet, ndarray)
        External forces: at each point, ``amplitude[k, p] * weights`` on its DOFs at step k
        (N, N m); amplitudes of shape ``(n_steps + 1, n_points)``.
    contacts : HertzContacts, optional
        Wheels in Hertzian contact, solved every step; their forces enter the initial
        acceleration from the initial state.
    probes : mapping of str to PointSet, optional
        Responses recorded at points, one channel per name.
    record : sequence of int or None
        DOFs recorded in the channel ``"dofs"``; None records all.
    u0, v0 : array_like, optional
        Initial displacement and velocity (default 0). The initial acceleration follows from
        the equation of motion (``M`` must be non-singular unless the initial force is zero).
    compiled : bool, optional
        True: the compiled loop (an error if it cannot run); False: the NumPy loop; None (the
        default): the compiled loop where it can run.

    Returns
    -------
    TimeResponse
        Channels ``"dofs"``, one per probe set, and with contacts ``"contact force"`` (N),
        ``"wheel"`` and ``"rail"`` (m, at the contacts).

    Examples
    --------
    An undamped oscillator released from u = 1 m, a quarter period later:

    >>> s = SecondOrderSystem([[10.0]], [[0.0]], [[4.0e6]])
    >>> r = simulate(s, Newmark(1e-5), 248, record=None, u0=[1.0])  # 2.48 ms
    >>> bool(abs(r["dofs"][-1, 0]) < 0.01)
    True
    """
    _check_types(system, stepper, contacts)
    n = system.n_dof
    n_steps = check_int_at_least("n_steps", n_steps, 1)
    record = _record(record, n)
    probes = dict(probes or {})
    n_out = record.size + sum(p.n_points for p in probes.values()) + 3 * (contacts.n_contacts if contacts else 0)
    check_limits(n_steps, n, n_out)
    loads = _check_loads(loads, n, n_steps + 1)
    for name, points in probes.items():
        _check_points(f"probes[{name!r}]", points, n, n_steps + 1)
    if contacts is not None:
        _check_points("contacts.points", contacts.points, n, n_steps + 1)
        if contacts.irregularity.shape[0] != n_steps + 1 or contacts.wheel_dofs.max() >= n:
            raise InputError(f"the contacts' irregularity needs {n_steps + 1} rows and their wheels DOFs of a system "
                             f"of {n}, got {contacts.irregularity.shape[0]} rows and DOFs "
                             f"{contacts.wheel_dofs.tolist()}")
    arrays = _prepare(system, stepper, n_steps, loads, contacts, probes, record, u0, v0)
    return _run(arrays, compiled, probes, contacts)


def _check_types(system, stepper, contacts) -> None:
    """The system, stepper and contacts of a run are what their names say (before any is read)."""
    if not isinstance(system, SecondOrderSystem):
        raise InputTypeError(f"system must be a SecondOrderSystem, got {type(system).__name__}")
    if not isinstance(stepper, Newmark):
        raise InputTypeError(f"stepper must be a Newmark stepper, got {type(stepper).__name__}")
    if contacts is not None and not isinstance(contacts, HertzContacts):
        raise InputTypeError(f"contacts must be HertzContacts or None, got {type(contacts).__name__}")


def _record(record, n: int) -> np.ndarray:
    """The recorded DOFs' indices (None: all), each in [0, n)."""
    if record is None:
        return np.arange(n)
    raw = as_real_array(record, "record").ravel()
    if raw.size and (np.any(raw != np.round(raw)) or raw.min() < 0 or raw.max() >= n):
        raise InputError(f"record must hold DOF indices in [0, {n}), got {raw.tolist()[:5]}")
    return raw.astype(np.int64)


def _run(arrays: StepArrays, compiled: bool | None, probes, contacts) -> TimeResponse:
    use_compiled = _choose(compiled, arrays)
    start = time.perf_counter()
    with serial_blas():  # thousands of small solves: threads only contend
        out = _run_compiled(arrays) if use_compiled else run_numpy(arrays)
    elapsed = time.perf_counter() - start
    return _response(arrays, out, probes, contacts, arrays.stepper.dt, elapsed, use_compiled)


@dataclass(frozen=True, eq=False)
class Continued:
    """A run continued from a given state: its channels and the state it ended in.

    Attributes
    ----------
    response : TimeResponse
        The channels, row 0 the given state.
    u, v, a : ndarray
        The final displacement (m, rad), velocity and acceleration of every DOF.
    x : ndarray
        The final values of the state blocks' states.
    """

    response: TimeResponse
    u: np.ndarray
    v: np.ndarray
    a: np.ndarray
    x: np.ndarray


def continue_run(system: SecondOrderSystem, stepper: Newmark, n_steps: int, *, u: np.ndarray, v: np.ndarray,
                 a: np.ndarray | None, x: np.ndarray, loads: Sequence[tuple[PointSet, np.ndarray]] = (),
                 contacts: HertzContacts | None = None, record: Sequence[int] = (), stepping=None,
                 compiled: bool | None = None) -> Continued:
    """Steps from a whole given state, as :func:`simulate` takes them from rest or a static state.

    For a model whose matrices change between stretches of a run (the travelling window of
    :mod:`semitrack.interaction.window_model`): the state ``(u, v, a, x)`` carried over from the
    last stretch, the acceleration not recomputed. The run's size is bounded as :func:`simulate`
    bounds it and the state's shapes are checked; the loads and contacts are the caller's, as
    :func:`simulate` takes them, not checked again.

    Parameters
    ----------
    system, stepper, n_steps, loads, contacts, record, compiled
        As :func:`simulate`.
    u, v, a : ndarray, shape (n,)
        The state at row 0 (m, m/s, m/s^2, and rad for rotations); ``a=None`` takes the
        acceleration from the equation of motion, as :func:`simulate` does.
    x : ndarray
        The state blocks' values at row 0 (in :class:`~.states.TrapezoidalStates`'s order).
    stepping : tuple, optional
        The discretised states and the factorisation (:func:`stepping_of`), when the caller keeps
        them across stretches with the same matrices and step.

    Returns
    -------
    Continued
    """
    _check_types(system, stepper, contacts)
    n_steps = check_int_at_least("n_steps", n_steps, 1)
    record = _record(record, system.n_dof)
    k = contacts.n_contacts if contacts is not None else 0
    check_limits(n_steps, system.n_dof, record.size + 3 * k)
    n = system.n_dof
    u, v = _vector("u", u, n), _vector("v", v, n)
    a = None if a is None else _vector("a", a, n)
    x = _vector("x", x, sum(blk.n_states for blk in system.states))
    arrays = _prepare(system, stepper, n_steps, list(loads), contacts, {}, record, u, v, a0=a, x0=x, stepping=stepping)
    response = _run(arrays, compiled, {}, contacts)
    return Continued(response, arrays.u + arrays.u_ref, arrays.v.copy(), arrays.a.copy(), arrays.x.copy())


def stepping_of(system: SecondOrderSystem, stepper: Newmark, states: TrapezoidalStates | None = None
                ) -> tuple[TrapezoidalStates | None, object]:
    """``(states, factor)``: the system's state blocks discretised and the effective stiffness factorised.

    Parameters
    ----------
    system : SecondOrderSystem
        The system.
    stepper : Newmark
        The scheme and its step.
    states : TrapezoidalStates, optional
        The discretised states when the caller holds them (the same blocks on the same DOFs).

    Returns
    -------
    tuple
        What :func:`simulate` steps with, for :func:`continue_run` to take again.
    """
    if states is None and system.states:
        states = TrapezoidalStates(system.states, stepper.dt, system.n_dof)
    if states is not None and not stepper.is_average_acceleration:
        raise InputError("state blocks need the average-acceleration rule (gamma=1/2, beta=1/4), got "
                         f"gamma={stepper.gamma!r}, beta={stepper.beta!r}")
    K_eff = stepper.effective_stiffness(system.M, system.C, system.K)
    return states, factorise(K_eff if states is None else K_eff + states.stiffness, system.order)


def compiled_contacts_hold(factor, contacts: HertzContacts | None) -> bool:
    """Whether the compiled loop's contact solve applies: each wheel after its contact's rail DOFs
    in the band order, and not coupled to them (in another connected part of the effective
    stiffness: a wheel on its own suspension, or a vehicle that touches the track only through
    its contacts). The NumPy loop has no such condition."""
    if contacts is None:
        return True
    order = factor.order
    dofs, weights = contacts.points.dofs, contacts.points.weights
    wheel = contacts.wheel_dofs[None, :, None]
    touched = weights != 0
    apart = order.part[dofs] != order.part[wheel]
    after = order.where[dofs] < order.where[wheel]
    return bool(np.all(apart[touched] & after[touched]))


def _compiled_choice(compiled: object) -> bool | None:
    """``compiled=`` as given: None (where it can run) or a flag, never read by its truth value."""
    return None if compiled is None else check_flag("compiled", compiled)


def _choose(compiled: bool | None, arrays: StepArrays) -> bool:
    compiled = _compiled_choice(compiled)
    cholesky = isinstance(arrays.factor, BandCholesky)
    holds = cholesky and compiled_contacts_hold(arrays.factor, arrays.contacts)
    if compiled is None:
        return holds and compiled_available()
    if compiled and not cholesky:
        raise InputError("compiled=True needs a real symmetric positive definite effective stiffness with a narrow "
                         f"band (a chain); this one was factorised as {type(arrays.factor).__name__}: "
                         "use compiled=None")
    if compiled and not holds:
        raise InputError("compiled=True needs each wheel apart from the track (coupled to it by its contact only) "
                         "and after it in the band order (the track the largest part of the system); use "
                         "compiled=None, which runs the NumPy loop")
    if compiled and not compiled_available():
        raise InputError("compiled=True needs numba, which is not installed (pip install numba); use compiled=None")
    return bool(compiled)


def _response(arrays, out: Outputs, probes, contacts, dt, elapsed, use_compiled) -> TimeResponse:
    """The channels, ``u0`` added back (see :func:`_prepare`)."""
    u_ref, rows = arrays.u_ref, arrays.n_steps + 1
    channels = {"dofs": out.dofs + u_ref[arrays.record],
                **{name: out.probes[name] + _on_points(p, u_ref, rows) for name, p in probes.items()}}
    labels = {"dofs": tuple(f"dof {i}" for i in arrays.record), **{k: p.labels for k, p in probes.items()}}
    if contacts is not None:
        channels.update({"contact force": out.force, "wheel": out.wheel + u_ref[contacts.wheel_dofs],
                         "rail": out.rail + _on_points(contacts.points, u_ref, rows)})
        labels.update(dict.fromkeys(("contact force", "wheel", "rail"), contacts.labels))
    t = dt * np.arange(rows)
    return TimeResponse(t=t, channels=channels, labels=labels, elapsed=elapsed, compiled=use_compiled)


# ------------------------------------------------------------------------------------------------
# The compiled loop's arrays: everything in the band order of the factor
# ------------------------------------------------------------------------------------------------
def _stack(points: Sequence[PointSet], amplitudes: Sequence[np.ndarray] | None, moving: bool, rows: int, where):
    """Fixed (or moving) point sets stacked into one ``(rows or 1, P, W)`` pair, renumbered, padded."""
    chosen = [i for i, p in enumerate(points) if p.moving == moving]
    width = max([points[i].dofs.shape[2] for i in chosen], default=1)
    n_rows = rows if moving and chosen else 1
    total = sum(points[i].n_points for i in chosen)
    dofs, weights = np.zeros((n_rows, total, width), np.uint64), np.zeros((n_rows, total, width))
    amp = np.zeros((rows, total))
    p0 = 0
    for i in chosen:
        p = points[i]
        dofs[:, p0:p0 + p.n_points, :p.dofs.shape[2]] = where[p.dofs]
        weights[:, p0:p0 + p.n_points, :p.dofs.shape[2]] = p.weights
        if amplitudes is not None:
            amp[:, p0:p0 + p.n_points] = amplitudes[i]
        p0 += p.n_points
    return dofs, weights, amp


def _csr(X):
    """CSR arrays with unsigned indices (no wraparound checks in the compiled gathers)."""
    X = sp.csr_matrix(X)
    return X.indptr.astype(np.uint64), X.indices.astype(np.uint64), X.data.astype(float)


def _run_compiled(arrays: StepArrays) -> Outputs:
    from .compiled import run_compiled  # numba's import (0.3-0.6 s) only for a compiled run

    order, rows = arrays.factor.order, arrays.n_steps + 1
    where, perm, n = order.where, order.perm, order.n
    mc = tuple(_band_rows(X, order) for X in (arrays.MC[:, :n], arrays.MC[:, n:]))
    lower = arrays.factor.lower
    ldl = (np.ascontiguousarray(lower / lower[:, :1]), 1.0 / lower[:, 0] ** 2)  # L D L^T, L with a unit diagonal
    load_points = [p for p, _ in arrays.loads]
    load_amp = [a for _, a in arrays.loads]
    lf, lm = (_stack(load_points, load_amp, moving, rows, where) for moving in (False, True))
    st = _state_arrays(arrays.states, where, arrays.x)
    ct = _contact_arrays(arrays.contacts, where)
    probe_list = list(arrays.probes.values())
    pf, pm = (_stack(probe_list, None, moving, rows, where)[:2] for moving in (False, True))
    u, v, a = (np.ascontiguousarray(x[perm]) for x in (arrays.u, arrays.v, arrays.a))
    out = Outputs.empty(arrays)
    k_c = ct[0].size
    o_pf, o_pm = np.zeros((rows, pf[0].shape[1])), np.zeros((rows, pm[0].shape[1]))
    outs = (out.dofs, o_pf, o_pm, out.force, out.wheel, out.rail)
    rec = where[arrays.record].astype(np.uint64)
    _first_row(arrays, out, o_pf, o_pm, pf, pm, u, rec, k_c)
    s = arrays.stepper
    offset = np.ascontiguousarray(arrays.offset[perm]) if arrays.offset.size else arrays.offset
    run_compiled(arrays.n_steps, s.coefficients, s.dt, s.gamma, mc, ldl, offset, u, v, a,
                 lf, lm, st, ct, (pf[0], pf[1], pm[0], pm[1]), rec, outs)
    _split_probes(arrays.probes, out, o_pf, o_pm)
    arrays.u[perm], arrays.v[perm], arrays.a[perm] = u, v, a
    return out


def _band_rows(A, order) -> np.ndarray:
    """``A`` reordered into ``order``, by diagonals: ``out[t, i] = A[i, i + t - width]`` (zero outside).

    ``M`` and ``C`` lie within the effective stiffness's band, whose pattern holds theirs.
    """
    coo = sp.coo_matrix(A)
    keep = coo.data != 0  # the FE families share one pattern: explicit zeros outside the band
    coo = sp.coo_matrix((coo.data[keep], (coo.row[keep], coo.col[keep])), shape=coo.shape)
    r, c = order.where[coo.row], order.where[coo.col]
    w = order.width
    if coo.nnz and np.max(np.abs(r - c)) > w:
        raise InputError("M and C must lie within the band of the effective stiffness")
    out = np.zeros((2 * w + 1, order.n))
    np.add.at(out, (c - r + w, r), coo.data)
    return out


def _first_row(arrays, out, o_pf, o_pm, pf, pm, u, rec, k_c) -> None:
    """Row 0 (the initial state) of every output, in band order."""
    out.dofs[0] = u[rec]
    o_pf[0] = np.einsum("pw,pw->p", pf[1][0], u[pf[0][0]])
    o_pm[0] = np.einsum("pw,pw->p", pm[1][0], u[pm[0][0]])
    if k_c:
        c = arrays.contacts
        out.force[0] = c.forces(arrays.u, 0)
        out.wheel[0] = arrays.u[c.wheel_dofs]
        out.rail[0] = c.points.values(arrays.u, 0) + c.local_compliance(0) * out.force[0]


def _split_probes(probes, out: Outputs, o_pf, o_pm) -> None:
    i_f = i_m = 0
    for name, p in probes.items():
        if p.moving:
            out.probes[name][:] = o_pm[:, i_m:i_m + p.n_points]
            i_m += p.n_points
        else:
            out.probes[name][:] = o_pf[:, i_f:i_f + p.n_points]
            i_f += p.n_points


def _state_arrays(states: TrapezoidalStates | None, where, x: np.ndarray):
    """The states' arrays of the compiled loop; ``x`` (their values) is updated in place."""
    if states is None:
        empty = (np.zeros(1, np.uint64), np.zeros(0, np.uint64), np.zeros(0))
        return (np.zeros(0, np.uint64), *empty, *empty, *empty, np.zeros((0, 0)), x)
    return (where[states.dofs].astype(np.uint64), *_csr(states.E), *_csr(states.Phi_P), *_csr(states.history_x),
            np.ascontiguousarray(states.block), x)


def _contact_arrays(contacts: HertzContacts | None, where):
    if contacts is None:
        return (np.zeros(0, np.uint64), np.zeros((1, 0, 1), np.uint64), np.zeros((1, 0, 1)), np.zeros(0),
                np.zeros((1, 0)), np.zeros((1, 0)), np.zeros(0, dtype=np.bool_))
    c = contacts.renumbered(where)
    return (c.wheel_dofs.astype(np.uint64), c.points.dofs.astype(np.uint64), c.points.weights, c.hertz_constants,
            c.irregularity, c.compliance, c.linear)
