"""The exact method: periodic-structure (Bloch-wave) theory on the transfer matrix of one period.

Cut the infinite periodic track at a cross-section x_c. The transfer matrix T of one period,
from x_c to x_c + L, maps the state s = (w, psi, Q, M) across the period. Its four eigenvalues
come in pairs (lambda, 1/lambda): the two with |lambda| < 1 are the Bloch waves that decay to the
right (Mead's periodic-structure theory). On the semi-infinite track x > x_c only these exist, so
with V the matrix of their eigenvectors, split in displacement rows V_u and force rows V_f,

    (w, psi) = V_u c,  (Q, M) = V_f c   =>   K_R = V_f V_u^{-1}

is the 2x2 dynamic stiffness of the right semi-infinite track at its end, and alpha = K_R^{-1}.
The growing waves do the same for the left part (K_L = -V_f V_u^{-1}, the sign because the loads
applied to the left part are -Q, -M). Nothing is truncated: no wavenumber range, no finite
differences, no sum over j.

Where damping is zero a pair of eigenvalues lies on the unit circle; the wave travelling to the
right is then the one that carries power to the right (the limit of vanishing damping).
"""

from __future__ import annotations

import numpy as np

from ..base.checks import check_real
from ..model.timoshenko import field_transfer, point_transfer, state_scaling
from ..model.tracks import PeriodicCell

# |log|lambda|| below this is treated as a propagating (undamped) wave.
_UNIT_CIRCLE_TOL = 1e-9


def period_transfer(cell: PeriodicCell, omega: np.ndarray, x_cut: float) -> np.ndarray:
    """Transfer matrix of one period starting at ``x_cut``: s(x_cut + L) = T s(x_cut).

    Parameters
    ----------
    cell : PeriodicCell
        The period (supports must not be coupled through the foundation).
    omega : ndarray
        Circular frequencies (rad/s), shape ``(n,)``.
    x_cut : float
        Start of the period (m). A support exactly at ``x_cut`` counts as lying just to its
        left, i.e. it is the last support of the period.

    Returns
    -------
    ndarray, shape (n, 4, 4)
    """
    f = omega / (2 * np.pi)
    if not cell.has_uncoupled_supports(f):
        raise NotImplementedError(
            "the transfer method needs supports that are not coupled through the foundation "
            "(G_rs diagonal); use method='wavenumber' for a coupled slab"
        )
    track, period = cell.track, cell.period
    ks = cell.support_stiffness_matrix(f)
    # Supports met when walking from x_cut (exclusive) to x_cut + L (inclusive).
    offsets = sorted(((x - x_cut) % period or period, i) for i, x in enumerate(cell.positions))
    t = np.broadcast_to(np.eye(4, dtype=complex), (omega.size, 4, 4)).copy()
    here = 0.0
    for dist, i in offsets:
        t = field_transfer(track, omega, dist - here) @ t
        t = point_transfer(ks[:, 2 * i : 2 * i + 2, 2 * i : 2 * i + 2]) @ t
        here = dist
    return field_transfer(track, omega, period - here) @ t


def bloch_waves(cell: PeriodicCell, omega: np.ndarray, x_cut: float) -> tuple[np.ndarray, ...]:
    """Bloch waves of the period starting at ``x_cut``, split into right- and left-decaying.

    Returns
    -------
    lam_right, vec_right, lam_left, vec_left : ndarray
        Eigenvalues (shape ``(n, 2)``) and state eigenvectors (shape ``(n, 4, 2)``, rows
        w, psi, Q, M in SI units) of the two waves that decay towards +x and of the two that
        decay towards -x.
    """
    t = period_transfer(cell, omega, x_cut)
    scale = state_scaling(cell.track)
    t_scaled = scale[:, None] * t / scale[None, :]
    lam, vec = np.linalg.eig(t_scaled)
    vec = vec / scale[None, :, None]  # back to SI rows
    order = np.argsort(_decay_key(lam, vec, omega), axis=-1)
    lam = np.take_along_axis(lam, order, axis=-1)
    vec = np.take_along_axis(vec, order[:, None, :], axis=-1)
    return lam[:, :2], vec[:, :, :2], lam[:, 2:], vec[:, :, 2:]


def _decay_key(lam, vec, omega):
    """Sort key: negative for waves that decay (or carry power) towards +x."""
    log_mod = np.log(np.abs(lam))
    # Time-averaged power through the cross-section towards +x: 0.5 Re(Q conj(v) + M conj(dpsi/dt)).
    w, psi, q, m = vec[:, 0], vec[:, 1], vec[:, 2], vec[:, 3]
    v_w = 1j * omega[:, None] * w
    v_psi = 1j * omega[:, None] * psi
    power = 0.5 * np.real(q * np.conj(v_w) + m * np.conj(v_psi))
    propagating = np.abs(log_mod) < _UNIT_CIRCLE_TOL
    return np.where(propagating, -0.5 * _UNIT_CIRCLE_TOL * np.sign(power), log_mod)


def end_stiffness(cell: PeriodicCell, omega: np.ndarray, x_cut: float) -> tuple[np.ndarray, np.ndarray]:
    """Dynamic stiffness of the two semi-infinite tracks on either side of a cut at ``x_cut``.

    Returns
    -------
    k_right, k_left : ndarray, shape (n, 2, 2)
        ``k_right`` maps (w, psi) at the end of the track x > x_cut to the loads (Q, M) applied
        to it there; ``k_left`` likewise for the track x < x_cut (loads applied to that part).
        Units: N/m, N/rad, N m/m, N m/rad.
    """
    check_real("x_cut", x_cut)
    _, v_r, _, v_l = bloch_waves(cell, omega, x_cut)
    k_right = np.linalg.solve(np.swapaxes(v_r[:, :2, :], 1, 2), np.swapaxes(v_r[:, 2:, :], 1, 2))
    k_left = -np.linalg.solve(np.swapaxes(v_l[:, :2, :], 1, 2), np.swapaxes(v_l[:, 2:, :], 1, 2))
    # solve(Vu^T, Vf^T) = (Vf Vu^{-1})^T; transpose back.
    return np.swapaxes(k_right, 1, 2), np.swapaxes(k_left, 1, 2)


def infinite_receptance(cell: PeriodicCell, omega: np.ndarray, x: float) -> np.ndarray:
    """2x2 receptance of the infinite track at ``x`` (response (w, psi) to load (F, M) at x).

    Shape ``(n, 2, 2)``; the displacement is continuous at x and the load splits between the
    two semi-infinite parts, so H = (K_R + K_L)^{-1}.
    """
    k_right, k_left = end_stiffness(cell, omega, x)
    return np.linalg.inv(k_right + k_left)
