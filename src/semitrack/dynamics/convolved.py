"""Contacts on a medium known by its impulse responses: a vehicle by Newmark, the rail by convolution.

The rail's displacement under k contacts is linear in the contact forces' history, with
coefficients that depend on the lag and, for contacts that move over a periodic medium, on where
in the period each force acted (the moving Green's functions of :mod:`semitrack.fe.kernels`):

    w_i(n) = sum_j [ P0_j e_ij[n] + sum_{m=1..L-1} K_ij[q_j(n), m] F_j(n - m) ] + sum_j K_ij[q_j(n), 0] F_j(n)

with ``q_j(n) = (q_j(0) + n) mod P`` contact j's phase at step n, ``K_ij = kernels[pair[i, j]]``
arranged so that each step reads one contiguous row, ``K[q, m] = h[(q - m) mod P, m]``, and
``e_ij`` the release of the preloads that stood at the start (the static start). The last sum
is the current step's share: with the vehicle's own compliance within the step and each
contact's local flexibility it is the step's compliance ``G`` of the Hertzian contacts, solved by
:func:`semitrack.dynamics.contact.solve_hertz`; the vehicle (M, C, K, the contacts' wheels first)
is stepped by Newmark's average acceleration with its effective stiffness inverted once.

:func:`convolved_steps` is one source: run as Python (the reference, NumPy's dot product over
the memory) and compiled by numba (:mod:`semitrack.dynamics.compiled`).
"""

from __future__ import annotations

import numpy as np

from .contact import MAX_NEWTON, solve_hertz

__all__ = ["convolved_steps", "one_contact_steps"]


def convolved_steps(kernels, pair, release, preload, phase0, flexibility, c_h, r, inverse, M, C, coef, loads,
                    u, force, w_wheel, w_rail, history, work, first, last):  # noqa: PLR0913, PLR0915
    """Run the steps ``first..last`` of the contacts against the convolution, in place (see the module docstring).

    A run may be taken in pieces (``1..a``, ``a+1..b``, ...) with the same arrays: every step starts from
    what the arrays hold, so the pieces give the one run's numbers bit for bit. Between them the
    caller may add to ``r`` what the kernels here do not hold (a long memory's tail,
    :mod:`semitrack.fe.kerneltail`).

    Parameters
    ----------
    kernels : ndarray, shape (n_kernels, P, L)
        ``K[q, m]`` (m/N) for each distinct kernel, rows by the loading contact's phase at the step.
    pair : ndarray of int64, shape (k, k)
        Which kernel gives w at contact i per force at contact j.
    release : ndarray, shape (k, k, R)
        ``e_ij[n]`` (m/N): w at contact i, n steps after the preload of contact j that stood at
        its start was taken off; 0 from step R on (R = L for moving contacts, whose release has
        gone by then; a stationary one's is the kernel's cut-off tail for good).
    preload : ndarray, shape (k,)
        The standing forces of the start (N).
    phase0 : ndarray of int64, shape (k,)
        Each contact's phase at step 0.
    flexibility : ndarray, shape (P,)
        Local compliance in series with a contact at each phase (m/N).
    c_h : ndarray, shape (k,)
        Hertz constants (N/m^1.5).
    r : ndarray, shape (n_steps + 1, k)
        Roughness under each contact (m, downward).
    inverse, M, C : ndarray, shape (n_v, n_v)
        The vehicle's effective stiffness inverted, mass and damping (the contacts' wheels first).
    coef : ndarray, shape (6,)
        Newmark's coefficients (:attr:`semitrack.dynamics.newmark.Newmark.coefficients`).
    loads : ndarray, shape (n_v,)
        The vehicle's constant loads (N).
    u : ndarray, shape (3, n_v)
        The vehicle's displacement, velocity and acceleration at the start; updated.
    force, w_wheel, w_rail : ndarray, shape (n_steps + 1, k)
        Filled from row 1 (row 0 is the start's).
    history : ndarray, shape (k, n_steps + L)
        Zero; holds each contact's forces from step 1, newest first (``F_j(n)`` at ``n_steps - n``).
    work : ndarray, shape (k, k + 5)
        Workspace of the contact solve.
    first, last : int
        The steps to run, ``1 <= first <= last <= n_steps``.

    Returns
    -------
    int
        0, or the first step whose contact forces did not converge.
    """
    n_kernels, P, L = kernels.shape
    k, n_v = pair.shape[0], M.shape[0]
    n_steps = force.shape[0] - 1
    R = release.shape[2]
    a0, a1, a2, a3, a4, a5 = coef[0], coef[1], coef[2], coef[3], coef[4], coef[5]
    G = np.zeros((k, k))
    a = np.zeros(k)
    hist = np.zeros(k)
    rhs = np.zeros(n_v)
    free = np.zeros(n_v)
    f_now = np.zeros(k)
    for n in range(first, last + 1):
        base = n_steps - n
        for i in range(k):
            s = 0.0
            for j in range(k):
                q = (phase0[j] + n) % P
                row = kernels[pair[i, j], q]
                if n < R:
                    s += preload[j] * release[i, j, n]
                s += np.dot(row[1:], history[j, base + 1: base + L])
                G[i, j] = row[0] + inverse[i, j]
            G[i, i] += flexibility[(phase0[i] + n) % P]
            hist[i] = s
        for i in range(n_v):  # the vehicle's step without contact forces
            s = loads[i]
            for j in range(n_v):
                s += M[i, j] * (a0 * u[0, j] + a2 * u[1, j] + a3 * u[2, j]) + C[i, j] * (
                    a1 * u[0, j] + a4 * u[1, j] + a5 * u[2, j])
            rhs[i] = s
        for i in range(n_v):
            s = 0.0
            for j in range(n_v):
                s += inverse[i, j] * rhs[j]
            free[i] = s
        for i in range(k):
            a[i] = free[i] - hist[i] - r[n, i]
        if solve_hertz(c_h, a, G, f_now, work) > MAX_NEWTON:
            return n
        for i in range(n_v):
            s = free[i]
            for j in range(k):
                s -= inverse[i, j] * f_now[j]
            new = s
            acc = a0 * (new - u[0, i]) - a2 * u[1, i] - a3 * u[2, i]
            u[1, i] += (u[2, i] + acc) / a1  # average acceleration: v += dt/2 (a + a_new), a1 = 2/dt
            u[0, i], u[2, i] = new, acc
        for i in range(k):
            history[i, base] = f_now[i]
            force[n, i] = f_now[i]
            w_wheel[n, i] = u[0, i]
            s = hist[i] + flexibility[(phase0[i] + n) % P] * f_now[i]
            for j in range(k):
                s += kernels[pair[i, j], (phase0[j] + n) % P, 0] * f_now[j]
            w_rail[n, i] = s
    return 0


def one_contact_steps(kernels, pair, release, preload, phase0, flexibility, c_h, r, inverse, M, C, coef, loads,
                      u, force, w_wheel, w_rail, history, work, first, last):  # noqa: PLR0913
    """:func:`convolved_steps` for one contact on a one-DOF vehicle (a wheel on its primary suspension), in floats.

    The same equations with Python floats for the vehicle and the contact, so that the Python
    loop costs little more than its dot product over the memory (the general one indexes arrays
    element by element). The arguments are :func:`convolved_steps`'s.
    """
    rows = kernels[pair[0, 0]]
    P, L = rows.shape
    n_steps = force.shape[0] - 1
    a0, a1, a2, a3, a4, a5 = (float(c) for c in coef)
    m, c, g_w = float(M[0, 0]), float(C[0, 0]), float(inverse[0, 0])
    load, p0 = float(loads[0]), float(preload[0])
    e = release[0, 0].tolist()
    R = len(e)
    flex, rough = flexibility.tolist(), r[:, 0].tolist()
    hist_force = history[0]
    at_now = rows[:, 0].tolist()
    x, v, acc = float(u[0, 0]), float(u[1, 0]), float(u[2, 0])
    phase, dot = int(phase0[0]), np.dot
    count = last - first + 1
    f_out, w_out, r_out = [0.0] * count, [0.0] * count, [0.0] * count
    G, a, f_now = np.zeros((1, 1)), np.zeros(1), np.zeros(1)
    for n in range(first, last + 1):
        q = (phase + n) % P
        base = n_steps - n
        hist = float(dot(rows[q, 1:], hist_force[base + 1: base + L]))
        if n < R:
            hist += p0 * e[n]
        flex_n = flex[q]
        free = g_w * (load + m * (a0 * x + a2 * v + a3 * acc) + c * (a1 * x + a4 * v + a5 * acc))
        G[0, 0] = at_now[q] + g_w + flex_n
        a[0] = free - hist - rough[n]
        if solve_hertz(c_h, a, G, f_now, work) > MAX_NEWTON:
            return n
        f = float(f_now[0])
        new = free - g_w * f
        acc_new = a0 * (new - x) - a2 * v - a3 * acc
        v += (acc + acc_new) / a1
        x, acc = new, acc_new
        hist_force[base] = f
        f_out[n - first], w_out[n - first], r_out[n - first] = f, x, hist + (at_now[q] + flex_n) * f
    force[first:last + 1, 0], w_wheel[first:last + 1, 0], w_rail[first:last + 1, 0] = f_out, w_out, r_out
    u[0, 0], u[1, 0], u[2, 0] = x, v, acc
    return 0
