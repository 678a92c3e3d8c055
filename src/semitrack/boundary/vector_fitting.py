"""Relaxed vector fitting with common poles (Gustavsen & Semlyen 1999; Gustavsen 2006).

Fits several frequency responses ``g_j(s)``, sampled at ``s = i omega``, by one set of poles:

    g_j(s) ~ sum_m c_jm phi_m(s),

with a real-valued basis ``phi_m``: ``1/(s - a)`` for a real pole ``a`` and, for a complex pair
``a, conj(a)``, the two functions ``1/(s - a) + 1/(s - conj a)`` and ``i/(s - a) - i/(s - conj a)``,
so that real coefficients give a response that is real for real ``s`` (a real system). A complex
pair is stored once, by its member with positive imaginary part.

Each iteration relocates the poles: it fits ``sigma(s) g_j(s)`` and ``sigma(s)`` with
``sigma = d + sum_m c~_m phi_m`` (``d`` free: the relaxed form, with one normalisation row that
keeps ``sigma`` from the trivial zero), and the zeros of ``sigma`` become the new poles. Poles that
land in the right half-plane are reflected into the left one (stability). The per-response least
squares blocks are reduced by QR before they are stacked (the "fast" variant), so the cost grows
linearly with the number of responses. No constant or proportional term is fitted: the responses
this package fits are strictly proper by construction (the known limits are subtracted first).
"""

from __future__ import annotations

import numpy as np
from scipy.linalg import eigvals

__all__ = ["pole_basis", "pole_states", "starting_poles", "relocate_poles", "fit_coefficients",
           "vector_fit", "n_real_coefficients"]

# Poles with |Im a| below this fraction of |a| are treated as real.
_REAL_POLE_TOL = 1e-9


def n_real_coefficients(poles: np.ndarray) -> int:
    """Number of real basis functions (and states per response) of a pole set: 1 per real pole, 2 per pair."""
    poles = np.asarray(poles)
    return int(np.sum(np.where(poles.imag == 0, 1, 2)))


def pole_basis(s: np.ndarray, poles: np.ndarray) -> np.ndarray:
    """The real-coefficient basis ``phi_m(s)``, shape ``(n_s, n_real_coefficients(poles))``.

    Parameters
    ----------
    s : ndarray
        Complex frequencies (rad/s), shape ``(n_s,)``.
    poles : ndarray
        Poles (rad/s): real ones with zero imaginary part, one member (Im > 0) per complex pair.
    """
    cols = []
    for a in np.asarray(poles):
        if a.imag == 0:
            cols.append(1.0 / (s - a.real))
        else:
            p, q = 1.0 / (s - a), 1.0 / (s - np.conj(a))
            cols.extend((p + q, 1j * (p - q)))
    return np.stack(cols, axis=1)


def pole_states(poles: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Real state matrix ``A`` and input vector ``b`` with ``phi(s) = (sI - A)^-1 b`` row-wise.

    A real pole ``a`` gives the 1x1 block ``a`` with ``b = 1``; a pair ``sigma +- i omega`` gives
    ``[[sigma, omega], [-omega, sigma]]`` with ``b = (2, 0)``, so that ``c^T (sI - A)^-1 b`` equals
    ``sum_m c_m phi_m(s)`` for the basis of :func:`pole_basis`.

    Parameters
    ----------
    poles : ndarray
        Poles (rad/s), one member (Im > 0) per complex pair.
    """
    n = n_real_coefficients(poles)
    A, b = np.zeros((n, n)), np.zeros(n)
    i = 0
    for a in np.asarray(poles):
        if a.imag == 0:
            A[i, i], b[i] = a.real, 1.0
            i += 1
        else:
            A[i:i + 2, i:i + 2] = [[a.real, a.imag], [-a.imag, a.real]]
            b[i] = 2.0
            i += 2
    return A, b


def starting_poles(f_lo: float, f_hi: float, n_pairs: int, n_real: int) -> np.ndarray:
    """Starting poles: complex pairs spread log-uniformly over the band, lightly damped
    (``-omega/100 + i omega``), and real poles spread log-uniformly from a decade below to a
    decade above it (they carry the smooth, damping-like part of a response).

    Parameters
    ----------
    f_lo, f_hi : float
        The band (Hz).
    n_pairs, n_real : int
        Number of complex pairs and of real poles.
    """
    w = 2 * np.pi * np.geomspace(f_lo, f_hi, n_pairs) if n_pairs else np.empty(0)
    r = -2 * np.pi * np.geomspace(f_lo / 10, f_hi * 10, n_real) if n_real else np.empty(0)
    return _sorted_poles(np.concatenate([-w / 100 + 1j * w, r + 0j]))


def _sorted_poles(poles: np.ndarray) -> np.ndarray:
    """Stable poles, one member (Im > 0) per pair, real ones exactly real, sorted by |a|."""
    p = np.asarray(poles, dtype=complex)
    p = np.where(p.real > 0, -p.real + 1j * p.imag, p)  # reflect unstable poles
    is_real = np.abs(p.imag) <= _REAL_POLE_TOL * np.abs(p)
    keep = np.concatenate([p[is_real].real + 0j, p[~is_real & (p.imag > 0)]])
    return keep[np.argsort(np.abs(keep), kind="stable")]


def relocate_poles(s: np.ndarray, data: np.ndarray, weights: np.ndarray, poles: np.ndarray) -> np.ndarray:
    """One relaxed pole-relocation step of vector fitting.

    Parameters
    ----------
    s : ndarray
        Complex frequencies (rad/s), shape ``(n_s,)``.
    data : ndarray
        Responses, shape ``(n_s, n_resp)``.
    weights : ndarray
        Least-squares weights of each sample of each response, shape ``(n_s, n_resp)``.
    poles : ndarray
        Current poles.

    Returns
    -------
    ndarray
        The new poles (stable, sorted).
    """
    phi = pole_basis(s, poles)
    n = phi.shape[1]
    blocks = []
    for j in range(data.shape[1]):
        w, g = weights[:, j:j + 1], data[:, j:j + 1]
        rows = np.hstack([w * phi, -(w * g) * phi, -(w * g)])
        rows = np.vstack([rows.real, rows.imag])
        scale = np.linalg.norm(rows, axis=0)
        scale[scale == 0] = 1.0
        r = np.linalg.qr(rows / scale, mode="r")
        blocks.append(r[n:, n:] * scale[n:])  # the part that involves sigma only
    system = np.vstack(blocks)
    # Relaxation: Re sum_k sigma(s_k) = n_s, weighted like an average row of the system.
    relax = np.concatenate([phi.sum(axis=0).real, [s.size]]) / s.size
    weight = np.linalg.norm(system) / system.shape[0]
    x = np.linalg.lstsq(np.vstack([system, weight * relax]), np.r_[np.zeros(system.shape[0]), weight],
                        rcond=None)[0]
    c_sigma, d_sigma = x[:n], x[n]
    if abs(d_sigma) < 1e-8:  # sigma with a vanishing constant: keep the zeros finite
        d_sigma = np.copysign(1e-8, d_sigma)
    A, b = pole_states(poles)
    return _sorted_poles(eigvals(A - np.outer(b, c_sigma) / d_sigma))


def fit_coefficients(s: np.ndarray, data: np.ndarray, weights: np.ndarray, poles: np.ndarray) -> np.ndarray:
    """Weighted least-squares coefficients of each response for fixed poles.

    Parameters
    ----------
    s, data, weights, poles
        As in :func:`relocate_poles`.

    Returns
    -------
    ndarray
        Real coefficients, shape ``(n_real_coefficients(poles), n_resp)``.
    """
    phi = pole_basis(s, poles)
    out = np.empty((phi.shape[1], data.shape[1]))
    for j in range(data.shape[1]):
        m = weights[:, j:j + 1] * phi
        y = weights[:, j] * data[:, j]
        out[:, j] = np.linalg.lstsq(np.vstack([m.real, m.imag]), np.r_[y.real, y.imag], rcond=None)[0]
    return out


def vector_fit(s: np.ndarray, data: np.ndarray, weights: np.ndarray, poles: np.ndarray,
               n_iter: int = 20) -> tuple[np.ndarray, np.ndarray]:
    """Relocate the poles ``n_iter`` times, then fit the coefficients.

    Parameters
    ----------
    s, data, weights, poles
        As in :func:`relocate_poles`; ``poles`` are the starting poles.
    n_iter : int
        Number of relocation steps.

    Returns
    -------
    poles : ndarray
    coefficients : ndarray, shape ``(n_real_coefficients(poles), n_resp)``
    """
    for _ in range(n_iter):
        poles = relocate_poles(s, data, weights, poles)
    return poles, fit_coefficients(s, data, weights, poles)
