"""The rail as a Timoshenko beam: wavenumber operator, field transfer matrix, segment dynamic stiffness.

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


def state_matrix(track: Track, omega: ArrayLike, extra_loss: float = 0.0) -> np.ndarray:
    """Matrix A(omega) of the first-order field equation ds/dx = A s, shape ``(n, 4, 4)``.

    ``extra_loss`` multiplies EI and kappa A G by (1 + i extra_loss) on top of the track's own
    damping (the exact method's stand-in for vanishing damping on an undamped rail).

    The state is s = (w, psi, Q, M). From the homogeneous Eq. (1)-(2) with Eq. (15)-(16):

        w'   = psi - Q / kAG
        psi' = -M / EI
        Q'   = omega^2 rho A w
        M'   = omega^2 rho I psi - Q
    """
    omega = np.atleast_1d(np.asarray(omega, dtype=float))
    ei, kag = (modulus * (1 + 1j * extra_loss) for modulus in track.rail_moduli(omega / (2 * np.pi)))
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


def state_scaling(track: Track) -> np.ndarray:
    """Diagonal scaling that makes the state (w, psi, Q, M) dimensionless, shape ``(4,)``.

    w / d, psi, Q d^2 / EI, M d / EI with d the support spacing; used to keep the eigenvalue
    problems of the transfer method well balanced.
    """
    d, ei = track.spacing, abs(track.EI)
    return np.array([1.0 / d, 1.0, d**2 / ei, d / ei])


def segment_dynamic_stiffness(track: Track, omega: ArrayLike, lengths: ArrayLike,
                              extra_loss: float = 0.0) -> np.ndarray:
    """Exact dynamic stiffness of free rail segments between their two end cross-sections.

    Unlike :func:`field_transfer`, this stays accurate however long the segment and however high
    the frequency: each of the four waves of the field equation is referred to the end it decays
    away from, so no exponential in the formula exceeds 1 in modulus (a transfer matrix holds
    e^{kL} and e^{-kL} side by side and loses the small one once e^{kL} approaches 1e16).

    Parameters
    ----------
    track : Track
        Rail properties (complex moduli include the rail damping).
    omega : array_like
        Circular frequencies (rad/s), shape ``(n,)``, positive.
    lengths : array_like
        Segment lengths (m), shape ``(m,)``, positive.
    extra_loss : float
        Loss factor added to the rail's (-), see :func:`state_matrix`.

    Returns
    -------
    ndarray, shape (m, n, 4, 4)
        Maps the end displacements (w_a, psi_a, w_b, psi_b) (m, rad) to the loads applied to the
        segment at its ends (Q_a, M_a, Q_b, M_b) (N, N m); symmetric (reciprocity).
    """
    omega = np.atleast_1d(np.asarray(omega, dtype=float))
    lengths = np.atleast_1d(np.asarray(lengths, dtype=float))
    scale = state_scaling(track)  # a balanced, dimensionless state
    kappa, phi = np.linalg.eig(scale[:, None] * state_matrix(track, omega, extra_loss) / scale[None, :])
    order = np.argsort(kappa.real, axis=-1, kind="stable")  # two decaying towards +x first
    kappa = np.take_along_axis(kappa, order, axis=-1)
    phi = np.take_along_axis(phi, order[:, None, :], axis=-1)
    # s(x) = phi_1 e^{kappa_1 x} a + phi_2 e^{kappa_2 (x - l)} b, with Re kappa_1 <= Re kappa_2.
    decay = np.exp(np.concatenate([kappa[None, :, :2], -kappa[None, :, 2:]], axis=-1)
                   * lengths[:, None, None])  # (m, n, 4): e^{kappa_1 l}, e^{-kappa_2 l}
    start = phi * np.where(np.arange(4) < 2, 1.0 + 0j, decay)[..., None, :]  # s(0) per wave
    end = phi * np.where(np.arange(4) < 2, decay, 1.0 + 0j)[..., None, :]  # s(l) per wave
    disp = np.concatenate([start[..., :2, :], end[..., :2, :]], axis=-2)
    load = np.concatenate([start[..., 2:, :], -end[..., 2:, :]], axis=-2)  # loads ON the segment
    d_scaled = np.swapaxes(np.linalg.solve(np.swapaxes(disp, -1, -2), np.swapaxes(load, -1, -2)), -1, -2)
    # Back to SI: the scaled loads are scale[2:] * (Q, M), the scaled displacements scale[:2] * (w, psi).
    s_u, s_f = np.tile(scale[:2], 2), np.tile(scale[2:], 2)
    return d_scaled * s_u[None, :] / s_f[:, None]
