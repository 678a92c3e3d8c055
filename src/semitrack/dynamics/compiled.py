"""The step loop compiled with numba: the same steps as :func:`semitrack.dynamics.loop.run_numpy`.

Everything runs in the band order of the effective stiffness (:class:`~.factor.BandOrder`), so the
banded Cholesky solve needs no permutation: ``L y = b`` column by column, then ``L^T x = y`` by
dot products, over the ``width + 1`` entries of each column, multiplying by the stored reciprocal
of the diagonal. ``M`` and ``C`` are in the same band, stored by diagonals so that their products
vectorise; the state blocks are CSR loops; loads, probes and contacts are gathers and scatters
over their few DOFs. Per step the work is a few passes over the band: measured ~12 ns per DOF against 45-80 ns
for the same step in NumPy, whose cost is mostly per-call overhead.

The kernel is compiled on first use (about 2 s) and cached on disk beside this file (numba's
``cache=True``), so later processes load it in ~0.02 s. Importing this module imports numba
(0.3-0.6 s); :mod:`semitrack.dynamics.simulate` does so only when a compiled loop is asked for.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from ..base.errors import InputError
from .contact import MAX_NEWTON, solve_hertz

__all__ = ["run_compiled"]

_jit = numba.njit(cache=True, nogil=True, error_model="numpy")  # no division checks on the solve's chains
_hertz = _jit(solve_hertz)


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
def _ldl_solve(unit, dinv, b):
    """``b <- (L D L^T)^-1 b`` in place: ``unit[j, t] = L[j + t, j]`` (unit diagonal), ``dinv = 1 / D``.

    The solves are chains along the band, one step per DOF; with a unit diagonal each step is a
    single multiply-add on the chain, the scaling by ``1 / D`` a separate pass that vectorises
    (measured: 3.5 us against 4.1 us for the Cholesky form's division or product on the chain,
    482 DOFs, half-bandwidth 3).
    """
    n, w = unit.shape[0], unit.shape[1] - 1
    for j in range(1, n):
        s = b[j]
        for t in range(min(w, j), 0, -1):
            s -= unit[j - t, t] * b[j - t]
        b[j] = s
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


@_jit
def _contact_responses(unit, dinv, wheels, dofs, weights, g, G, work):
    """The load vectors' responses ``g[:, i] = K_eff^-1 b_i`` and the compliance ``G = B^T g``."""
    n, k = g.shape
    for i in range(k):
        for j in range(n):
            work[j] = 0.0
        for q in range(dofs.shape[1]):
            work[dofs[i, q]] += weights[i, q]
        work[wheels[i]] -= 1.0
        _ldl_solve(unit, dinv, work)
        for j in range(n):
            g[j, i] = work[j]
    for i in range(k):
        for j in range(k):
            s = -g[wheels[i], j]
            for q in range(dofs.shape[1]):
                s += weights[i, q] * g[dofs[i, q], j]
            G[i, j] = s


@_jit
def _step_contacts(k, u, c_wheels, c_dofs, c_w, c_h, c_r, unit, dinv, g, G, a_c, force, rail, work, hertz_work):
    """The contact forces of step ``k`` added to the free step ``u`` (in place)."""
    row = k if c_dofs.shape[0] > 1 else 0
    if k == 1 or c_dofs.shape[0] > 1:
        _contact_responses(unit, dinv, c_wheels, c_dofs[row], c_w[row], g, G, work)
    _interpolate(c_dofs[row], c_w[row], u, rail)
    for i in range(c_wheels.size):
        a_c[i] = u[c_wheels[i]] - rail[i] - c_r[k, i]
    if _hertz(c_h, a_c, G, force, hertz_work) > MAX_NEWTON:
        raise RuntimeError("the contact forces did not converge")
    for i in range(c_wheels.size):
        if force[i] > 0.0:
            for j in range(u.size):
                u[j] += g[j, i] * force[i]


@_jit
def _record(k, u, rec, out_rec, pf_dofs, pf_w, out_pf, pm_dofs, pm_w, out_pm):
    for i in range(rec.size):
        out_rec[k, i] = u[rec[i]]
    _interpolate(pf_dofs[0], pf_w[0], u, out_pf[k])
    if pm_dofs.shape[0] > 1:
        _interpolate(pm_dofs[k], pm_w[k], u, out_pm[k])


@_jit
def _run(n_steps, coef, dt, gamma, mc, ldl, offset, u, v, a, lf, lm, st, ct, pr, rec, out):  # noqa: C901
    """Long by design: one loop over the steps, so that numba compiles it as one function.

    ``ldl`` is the factor (unit, dinv) of :func:`_ldl_solve`, ``offset`` a constant load (empty
    for none). The tuples group the arrays: ``mc`` the band storage of M and C
    (:func:`_band_product`); ``lf``/``lm`` fixed and moving loads
    (dofs, weights, amplitudes); ``st`` the states (dofs, E, Phi_P, history_x as CSR triples,
    block); ``ct`` the contacts; ``pr`` fixed and moving probes; ``out`` the outputs.
    """
    a0, a1, a2, a3, a4, a5 = coef
    n = u.size
    s_dofs, e_p, e_i, e_d, f_p, f_i, f_d, h_p, h_i, h_d, block = st
    c_wheels, c_dofs, c_w, c_h, c_r = ct
    pf_dofs, pf_w, pm_dofs, pm_w = pr
    out_rec, out_pf, out_pm, out_f, out_ww, out_wr = out
    nb, k_c = s_dofs.size, c_wheels.size
    y, rhs, u_new = np.empty(2 * n), np.empty(n), np.empty(n)
    x, x_new, ub, du = np.zeros(e_p.size - 1), np.zeros(e_p.size - 1), np.empty(nb), np.empty(nb)
    g, G, work = np.zeros((n, k_c)), np.zeros((k_c, k_c)), np.empty(n)
    a_c, force, rail = np.empty(k_c), np.empty(k_c), np.empty(k_c)
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
        _ldl_solve(ldl[0], ldl[1], rhs)
        for i in range(n):
            u_new[i] = rhs[i]
        if k_c:
            _step_contacts(k, u_new, c_wheels, c_dofs, c_w, c_h, c_r, ldl[0], ldl[1], g, G, a_c, force, rail, work,
                           hertz_work)
            row = k if c_dofs.shape[0] > 1 else 0
            for i in range(k_c):
                out_f[k, i], out_ww[k, i] = force[i], u_new[c_wheels[i]]
            _interpolate(c_dofs[row], c_w[row], u_new, out_wr[k])
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
            v[i] += dt * ((1.0 - gamma) * a[i] + gamma * a_new)
            a[i], u[i] = a_new, u_new[i]
        _record(k, u, rec, out_rec, pf_dofs, pf_w, out_pf, pm_dofs, pm_w, out_pm)


def run_compiled(n_steps, coef, dt, gamma, mc, ldl, offset, u, v, a, lf, lm, st, ct, pr, rec, out) -> None:
    """Run the compiled loop (arguments as :func:`_run`; the state ``u, v, a`` ends as the final one)."""
    if not math.isfinite(dt):
        raise InputError(f"dt must be finite, got {dt!r}")
    _run(n_steps, coef, dt, gamma, mc, ldl, offset, u, v, a, lf, lm, st, ct, pr, rec, out)
