"""The step loop compiled with numba: the same steps as :func:`semitrack.dynamics.loop.run_numpy`.

Everything runs in the band order of the effective stiffness (:class:`~.factor.BandOrder`), so the
solve needs no permutation: the banded Cholesky factor, rewritten as ``L D L^T`` with a unit
``L``, is applied by two chains along the band (:func:`_forward`, :func:`_backward`), one
multiply-add per DOF on each chain. The wheels' contact forces are found between the two sweeps
(:func:`_step_contacts`), so that a step costs one solve whatever the number of wheels. ``M``
and ``C`` are in the same band, stored by diagonals so that their products vectorise; the state
blocks are CSR loops; loads, probes and contacts are gathers and scatters over their few DOFs.
Index arrays are unsigned, so that no gather pays a wraparound check. Measured: 11-12 ns per DOF
and step from 10 to 240 bays, against ~100 ns for the same step in NumPy, whose cost is mostly
per-call overhead (``benchmarks/bench_wheelrail.py``).

The kernel is compiled on first use (about 5 s on a 2-core machine: numba's typing and lowering
of a dozen functions) and cached on disk beside this file (numba's ``cache=True``), so later
processes load it in about 0.2 s. Importing this module imports numba (0.2-0.6 s) and starts its
typing contexts (:func:`_start`, 0.15-0.25 s); :mod:`semitrack.dynamics.simulate` does so only when a
compiled loop is asked for.
"""

from __future__ import annotations

import contextlib
import hashlib
import types
from pathlib import Path

import numba
import numpy as np

from .contact import HELPERS, MAX_NEWTON, solve_hertz
from .convolved import convolved_steps
from .loop import FLUSH

__all__ = ["run_compiled"]

_jit = numba.njit(cache=True, nogil=True, error_model="numpy")  # no division checks on the solve's chains


def _with_compiled_helpers(func, helpers=(), **compiled):
    """``func`` with the helpers it calls bound to their compiled twins (``compiled``: already compiled ones by name).

    numba resolves the names a function calls among its globals when it compiles it; the plain
    helpers of the one source would not compile there, their compiled twins do. A compiled
    function passed as an argument instead would make numba's cache key hold a weak reference to
    it, which a later process cannot resolve ("underlying object has vanished").
    """
    env = dict(func.__globals__, **{h.__name__: _jit(h) for h in helpers}, **compiled)
    twin = types.FunctionType(func.__code__, env, func.__name__, func.__defaults__, func.__closure__)
    twin.__qualname__ = func.__qualname__
    return twin


_hertz = _jit(_with_compiled_helpers(solve_hertz, HELPERS))
_convolved = _jit(_with_compiled_helpers(convolved_steps, solve_hertz=_hertz))


def run_convolved(*arrays) -> int:
    """The convolution loop of :mod:`semitrack.dynamics.convolved`, compiled, with the compiled contact solve."""
    return _convolved(*arrays)


@_jit
def _csr_product(indptr, indices, data, x, out, sign):
    """``out += sign * (A @ x)`` for the CSR matrix ``A``."""
    for i in range(indptr.size - 1):
        s = 0.0
        for p in range(indptr[i], indptr[i + 1]):
            s += data[p] * x[indices[p]]
        out[i] += sign * s


@_jit
def _band_product(mb, cb, y, rhs):
    """``rhs += M y1 + C y2`` with ``y = (y1, y2)`` and ``M, C`` in row band storage ``mb[t, i] = M[i, i + t - w]``.

    Diagonal by diagonal over slices, so that the inner loop runs along contiguous memory with
    non-negative indices and vectorises (indexing ``y[i + off]`` directly costs a wraparound
    check per entry: measured 4x slower).
    """
    n, w = rhs.size, (mb.shape[0] - 1) // 2
    for t in range(2 * w + 1):
        off = t - w
        lo, hi = max(0, -off), min(n, n - off)
        r, m, c = rhs[lo:hi], mb[t, lo:hi], cb[t, lo:hi]
        y1, y2 = y[lo + off:hi + off], y[n + lo + off:n + hi + off]
        for j in range(hi - lo):
            r[j] += m[j] * y1[j] + c[j] * y2[j]


@_jit
def _forward(unit, b, start):
    """``b <- L^-1 b`` in place for the unit lower band factor ``unit[j, t] = L[j + t, j]``, where
    ``b`` is zero before index ``start`` (so is the result: the sweep starts there).

    The sweep is a chain along the band, one step per DOF; with a unit diagonal each step is a
    single multiply-add on the chain.
    """
    n, w = unit.shape[0], unit.shape[1] - 1
    for j in range(start + 1, n):
        s = b[j]
        for t in range(min(w, j - start), 0, -1):
            s -= unit[j - t, t] * b[j - t]
        b[j] = s


@_jit
def _backward(unit, dinv, b):
    """``b <- L^-T D^-1 b`` in place: the second half of a solve with ``L D L^T``."""
    n, w = unit.shape[0], unit.shape[1] - 1
    for j in range(n):
        b[j] *= dinv[j]
    for jj in range(1, n):
        j = n - 1 - jj
        s = b[j]
        f = unit[j]
        for t in range(min(w, n - 1 - j), 0, -1):
            s -= f[t] * b[j + t]
        b[j] = s


@_jit
def _interpolate(dofs, weights, u, out):
    """``out[p] = weights[p] @ u[dofs[p]]`` for every point."""
    for p in range(dofs.shape[0]):
        s = 0.0
        for q in range(dofs.shape[1]):
            s += weights[p, q] * u[dofs[p, q]]
        out[p] = s


@_jit
def _scatter(dofs, weights, amplitude, rhs):
    """``rhs[dofs[p]] += amplitude[p] weights[p]`` for every point."""
    for p in range(dofs.shape[0]):
        for q in range(dofs.shape[1]):
            rhs[dofs[p, q]] += amplitude[p] * weights[p, q]


#: Entries of ``L^-1 b`` below this fraction of its largest are dropped: ``L^-1`` of a chain decays
#: geometrically away from the load, and its far tail, far below double precision in every sum it
#: enters, would otherwise reach subnormal numbers, whose arithmetic is a hundred times slower
#: (measured: a stationary wheel's step 70 % dearer on a 120-bay model).
NEGLIGIBLE = 1e-20


@_jit
def _forward_local(unit, p, start, end):
    """``L^-1 b`` for a ``b`` whose entries in ``[start, end)`` are its only ones there, swept from
    ``start`` until it has decayed (``width`` entries in a row below :data:`NEGLIGIBLE` of the
    largest) or reached ``end``; returns where it stopped (entries beyond are left as they are)."""
    w = unit.shape[1] - 1
    largest, quiet = abs(p[start]), 0
    for j in range(start + 1, end):
        s = p[j]
        for t in range(min(w, j - start), 0, -1):
            s -= unit[j - t, t] * p[j - t]
        p[j] = s
        largest = max(largest, abs(s))
        quiet = quiet + 1 if abs(s) <= NEGLIGIBLE * largest else 0
        if quiet > w:
            return j + 1
    return end


@_jit
def _contact_vectors(unit, dinv, wheels, dofs, weights, P, support, count, G, p, dense):
    """The contacts' load vectors through the factor's first half, ``p_i = L^-1 b_i``, kept where they
    matter (``P[i, :count[i]]`` at the DOFs ``support[i, :count[i]]``), and the step's compliance
    ``G_ij = b_i^T K_eff^-1 b_j = p_i^T D^-1 p_j``.

    It needs every wheel after its contact's rail DOFs in the band order and not coupled to them
    in the effective stiffness (:func:`semitrack.dynamics.simulate.compiled_contacts_hold`
    checks it: the track comes first, the wheels last): the rail part of ``b_i`` is swept from
    its first DOF until it decays (a few bays: ``L^-1`` of a chain decays geometrically), the
    wheel part from the wheel's DOF. A contact point with no weight (a pinned end node) has no
    rail part. ``p`` (n) and ``dense`` (k, n) are zeroed workspaces, left zeroed.
    """
    k, n = P.shape
    for i in range(k):
        first, wheel = n, np.int64(wheels[i])  # signed: unsigned and signed integers mix into floats
        for q in range(dofs.shape[1]):
            if weights[i, q] != 0.0:
                first = min(first, np.int64(dofs[i, q]))
                p[dofs[i, q]] += weights[i, q]
        stop = _forward_local(unit, p, first, wheel) if first < wheel else wheel  # no rail part: none to sweep
        p[wheel] -= 1.0
        end = _forward_local(unit, p, wheel, n)
        lo = min(first, wheel)
        largest = 0.0
        for j in range(lo, end):
            largest = max(largest, abs(p[j]))
        m = 0
        for j in range(lo, end):
            if abs(p[j]) > NEGLIGIBLE * largest and (j < stop or j >= wheel):
                support[i, m], P[i, m], dense[i, j] = j, p[j], p[j]
                m += 1
            p[j] = 0.0
        count[i] = m
    for i in range(k):
        for j in range(k):
            s = 0.0
            for m in range(count[i]):
                l = support[i, m]
                s += P[i, m] * dinv[l] * dense[j, l]
            G[i, j] = s
    for i in range(k):
        for m in range(count[i]):
            dense[i, support[i, m]] = 0.0


@_jit
def _step_contacts(k, y, c_wheels, c_dofs, c_w, c_h, c_r, c_g, c_lin, unit, dinv, P, support, count, G, a_c, force,
                   hertz_work, p, dense):
    """The contact forces of step ``k`` from the forward-swept load ``y = L^-1 rhs``, added to it.

    The approaches need the free step's motion at the contacts, ``b_i^T u_free = p_i^T D^-1 y``:
    no backward sweep is needed before the forces are known, and after them one sweep of
    ``y + sum_i p_i F_i`` gives the step's displacements (one solve a step, not one per wheel).
    """
    row = k if c_dofs.shape[0] > 1 else 0
    if k == 1 or c_dofs.shape[0] > 1:
        _contact_vectors(unit, dinv, c_wheels, c_dofs[row], c_w[row], P, support, count, G, p, dense)
        for i in range(c_wheels.size):
            G[i, i] += c_g[row, i]  # the local compliance in series with each contact
    for i in range(c_wheels.size):
        s = 0.0
        for m in range(count[i]):
            l = support[i, m]
            s += P[i, m] * dinv[l] * y[l]
        a_c[i] = -s - c_r[k, i]
    if _hertz(c_h, a_c, G, force, hertz_work, c_lin) > MAX_NEWTON:
        raise RuntimeError("the contact forces did not converge")
    for i in range(c_wheels.size):
        if force[i] > 0.0:
            for m in range(count[i]):
                y[support[i, m]] += P[i, m] * force[i]


@_jit
def _record(k, u, rec, out_rec, pf_dofs, pf_w, out_pf, pm_dofs, pm_w, out_pm):
    for i in range(rec.size):
        out_rec[k, i] = u[rec[i]]
    _interpolate(pf_dofs[0], pf_w[0], u, out_pf[k])
    if pm_dofs.shape[0] > 1:
        _interpolate(pm_dofs[k], pm_w[k], u, out_pm[k])


@_jit
def _run(n_steps, coef, dt, gamma, mc, ldl, offset, u, v, a, lf, lm, st, ct, pr, rec, out):  # noqa: C901, PLR0915
    """Long by design: one loop over the steps, so that numba compiles it as one function.

    ``ldl`` is the factor (unit, dinv) of :func:`_forward` and :func:`_backward`, ``offset`` a constant load (empty
    for none). The tuples group the arrays: ``mc`` the band storage of M and C
    (:func:`_band_product`); ``lf``/``lm`` fixed and moving loads
    (dofs, weights, amplitudes); ``st`` the states (dofs, E, Phi_P, history_x as CSR triples,
    block, and their values x, which end as the final ones); ``ct`` the contacts; ``pr`` fixed
    and moving probes; ``out`` the outputs.
    """
    a0, a1, a2, a3, a4, a5 = coef
    n = u.size
    s_dofs, e_p, e_i, e_d, f_p, f_i, f_d, h_p, h_i, h_d, block, x = st
    c_wheels, c_dofs, c_w, c_h, c_r, c_g, c_lin = ct
    pf_dofs, pf_w, pm_dofs, pm_w = pr
    out_rec, out_pf, out_pm, out_f, out_ww, out_wr = out
    nb, k_c = s_dofs.size, c_wheels.size
    y, rhs, u_new = np.empty(2 * n), np.empty(n), np.empty(n)
    x_new, ub, du = np.zeros(e_p.size - 1), np.empty(nb), np.empty(nb)
    P, G = np.zeros((k_c, n)), np.zeros((k_c, k_c))
    support, count = np.zeros((k_c, n), np.int64), np.zeros(k_c, np.int64)
    p_work, dense = np.zeros(n if k_c else 0), np.zeros((k_c, n))
    a_c, force = np.empty(k_c), np.empty(k_c)
    hertz_work = np.zeros((k_c, k_c + 5))
    for k in range(1, n_steps + 1):
        for i in range(n):
            y[i] = a0 * u[i] + a2 * v[i] + a3 * a[i]
            y[n + i] = a1 * u[i] + a4 * v[i] + a5 * a[i]
        for i in range(n):
            rhs[i] = 0.0
        _band_product(mc[0], mc[1], y, rhs)
        if offset.size:
            rhs += offset
        _scatter(lf[0][0], lf[1][0], lf[2][k], rhs)
        if lm[0].shape[0] > 1:
            _scatter(lm[0][k], lm[1][k], lm[2][k], rhs)
        if nb:
            for i in range(nb):
                ub[i] = u[s_dofs[i]]
            for i in range(nb):
                du[i] = 0.0
            _csr_product(h_p, h_i, h_d, x, du, 1.0)
            for i in range(nb):
                s = du[i]
                for j in range(nb):
                    s -= block[i, j] * ub[j]
                rhs[s_dofs[i]] -= s
        _forward(ldl[0], rhs, 0)
        if k_c:
            _step_contacts(k, rhs, c_wheels, c_dofs, c_w, c_h, c_r, c_g, c_lin, ldl[0], ldl[1], P, support, count,
                           G, a_c, force, hertz_work, p_work, dense)
        _backward(ldl[0], ldl[1], rhs)
        for i in range(n):
            u_new[i] = rhs[i]
        if k_c:
            row = k if c_dofs.shape[0] > 1 else 0
            for i in range(k_c):
                out_f[k, i], out_ww[k, i] = force[i], u_new[c_wheels[i]]
            _interpolate(c_dofs[row], c_w[row], u_new, out_wr[k])
            for i in range(k_c):
                out_wr[k, i] += c_g[row, i] * force[i]
        if nb:
            for i in range(nb):
                du[i] = u_new[s_dofs[i]] - ub[i]
            for i in range(x.size):
                x_new[i] = 0.0
            _csr_product(e_p, e_i, e_d, x, x_new, 1.0)
            _csr_product(f_p, f_i, f_d, du, x_new, 1.0)
            for i in range(x.size):
                x[i] = x_new[i]
        for i in range(n):
            a_new = a0 * (u_new[i] - u[i]) - a2 * v[i] - a3 * a[i]
            v_new = v[i] + dt * ((1.0 - gamma) * a[i] + gamma * a_new)
            u_i = u_new[i]
            if abs(u_i) < FLUSH and abs(v_new) < FLUSH and abs(a_new) < FLUSH:
                u_i = v_new = a_new = 0.0
            a[i], u[i], v[i] = a_new, u_i, v_new
        _record(k, u, rec, out_rec, pf_dofs, pf_w, out_pf, pm_dofs, pm_w, out_pm)


def run_compiled(n_steps, coef, dt, gamma, mc, ldl, offset, u, v, a, lf, lm, st, ct, pr, rec, out) -> None:
    """Run the compiled loop (arguments as :func:`_run`; the state ``u, v, a`` ends as the final one)."""
    _run(n_steps, coef, dt, gamma, mc, ldl, offset, u, v, a, lf, lm, st, ct, pr, rec, out)


def _forget_stale_kernels() -> None:
    """Delete this module's cached kernels when a module they compile in has changed.

    numba keys a function's on-disk cache on its own file only, but the cached loop holds the
    compiled code of what it calls: :func:`semitrack.dynamics.contact.solve_hertz` and the
    constants of :mod:`semitrack.dynamics.loop`. A digest of those sources, kept beside the
    cache, says when the kernels must be compiled again. Where the cache cannot be written,
    numba does not cache either, and nothing is done.
    """
    here = Path(__file__).resolve().parent
    digest = hashlib.sha256(b"".join((here / name).read_bytes() for name in ("contact.py", "loop.py",
                                                                                    "convolved.py"))).hexdigest()
    with contextlib.suppress(AttributeError, OSError):
        folder = Path(_run._cache._cache_path)
        stamp = folder / "compiled.dependencies.sha256"
        if stamp.is_file() and stamp.read_text() == digest:
            return
        for cached in folder.glob("compiled.*.nb[ic]"):
            cached.unlink(missing_ok=True)
        folder.mkdir(parents=True, exist_ok=True)
        stamp.write_text(digest)


_forget_stale_kernels()


@_jit
def _ready(x):
    """Nothing: its first call starts numba's typing and target contexts (see :func:`_start`)."""
    return x + 1.0


def _start() -> None:
    """Start numba's typing and target contexts now, at import, not inside the first run's timed loop.

    The first call of any compiled function in a process builds them, 0.15-0.25 s on a 2-core machine
    (measured), whatever the on-disk cache holds. Inside a run it read as that run's step cost (the made-up
    ballasted bogie's first 0.3-s run in a fresh process: 23.7 us a step instead of 8.2); it belongs to
    starting numba, with the import.
    """
    _ready(0.0)


_start()
