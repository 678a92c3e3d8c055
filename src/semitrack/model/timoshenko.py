"""The rail as a Timoshenko beam: wavenumber operator, internal forces and field transfer matrix.

Sign convention of the paper: w downward, psi clockwise, time factor exp(i omega t). The internal
forces at a cross-section x are those that the rail on the left of x exerts on the rail on the
right of x (paper Eq. 15-16):

    Q(x) = -kappa A G (dw/dx - psi)      (downward positive)
    M(x) = -E I dpsi/dx                  (clockwise positive)

With these, a point force F and moment M0 applied at x make Q and M jump by +F and +M0, and the
end loads applied to a semi-infinite rail x > x_c are simply (Q(x_c+), M(x_c+)).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike
from scipy.linalg import expm

from .tracks import Track


def operator_inverse(track: Track, omega: ArrayLike, beta: ArrayLike) -> tuple[np.ndarray, ...]:
    """Closed-form inverse of the paper's operator D(beta, omega) (Eq. 6), element-wise.

    D = -omega^2 M + K0 + i beta K1 + beta^2 K2, with the matrices of Eq. (4):

        D = [[-omega^2 rho A + kAG beta^2,          i beta kAG            ],
             [        -i beta kAG,       -omega^2 rho I + kAG + EI beta^2]]

    Parameters
    ----------
    track : Track
        Rail properties (complex moduli include the rail damping, see ``Track.rail_moduli``).
    omega, beta : array_like
        Circular frequency (rad/s) and wavenumber (rad/m), broadcast together.

    Returns
    -------
    d11, d12, d21, d22 : ndarray of complex
        Entries of D^{-1} (d11 in m/N, d22 in rad/(N m), d12, d21 in 1/N), broadcast shape.
    """
    ei, kag = track.rail_moduli(np.abs(np.asarray(omega)) / (2 * np.pi))
    omega2 = np.asarray(omega) ** 2
    beta = np.asarray(beta)
    beta2 = beta * beta
    a = kag * beta2 - omega2 * track.mass_per_length
    b = ei * beta2 + (kag - omega2 * track.rotary_inertia)
    c = 1j * kag * beta  # D12 = c, D21 = -c
    det = a * b + c * c  # a b - (c)(-c)
    inv_det = 1.0 / det
    return b * inv_det, -c * inv_det, c * inv_det, a * inv_det


def state_matrix(track: Track, omega: ArrayLike) -> np.ndarray:
    """Matrix A(omega) of the first-order field equation ds/dx = A s, shape ``(n, 4, 4)``.

    The state is s = (w, psi, Q, M). From the homogeneous Eq. (1)-(2) with Eq. (15)-(16):

        w'   = psi - Q / kAG
        psi' = -M / EI
        Q'   = omega^2 rho A w
        M'   = omega^2 rho I psi - Q
    """
    omega = np.atleast_1d(np.asarray(omega, dtype=float))
    ei, kag = track.rail_moduli(omega / (2 * np.pi))
    a = np.zeros((omega.size, 4, 4), dtype=complex)
    a[:, 0, 1] = 1.0
    a[:, 0, 2] = -1.0 / kag
    a[:, 1, 3] = -1.0 / ei
    a[:, 2, 0] = omega**2 * track.mass_per_length
    a[:, 3, 1] = omega**2 * track.rotary_inertia
    a[:, 3, 2] = -1.0
    return a


def field_transfer(track: Track, omega: ArrayLike, length: float) -> np.ndarray:
    """Transfer matrix of a free rail segment: s(x + length) = F s(x), shape ``(n, 4, 4)``.

    Computed as the matrix exponential of ``A(omega) * length`` (batched over frequency).
    """
    if length == 0:
        omega = np.atleast_1d(omega)
        return np.broadcast_to(np.eye(4, dtype=complex), (omega.size, 4, 4)).copy()
    return expm(state_matrix(track, omega) * length)


def point_transfer(support_stiffness: np.ndarray) -> np.ndarray:
    """Transfer matrix across a support with 2x2 dynamic stiffness K_s (rows w, psi).

    The support pushes on the rail with (-K_s (w, psi)), so (Q, M) jump by that amount while
    (w, psi) are continuous: P = [[I, 0], [-K_s, I]]. ``support_stiffness`` has shape
    ``(n, 2, 2)``; the result ``(n, 4, 4)``.
    """
    ks = np.asarray(support_stiffness)
    p = np.broadcast_to(np.eye(4, dtype=complex), ks.shape[:-2] + (4, 4)).copy()
    p[..., 2:, :2] = -ks
    return p


def state_scaling(track: Track) -> np.ndarray:
    """Diagonal scaling that makes the state (w, psi, Q, M) dimensionless, shape ``(4,)``.

    w / d, psi, Q d^2 / EI, M d / EI with d the support spacing; used to keep the eigenvalue
    problems of the transfer method well balanced.
    """
    d, ei = track.spacing, abs(track.EI)
    return np.array([1.0 / d, 1.0, d**2 / ei, d / ei])
