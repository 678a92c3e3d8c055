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

from .beam import beam_scaling, beam_state_matrix, wave_dynamic_stiffness
from .tracks import Track


def operator_inverse(track: Track, omega: ArrayLike, beta: ArrayLike,
                     work: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Closed-form inverse of the paper's operator D(beta, omega) (Eq. 6), element-wise.

    D = -omega^2 M + K0 + i beta K1 + beta^2 K2, with the matrices of Eq. (4):

        D = [[-omega^2 rho A + kAG beta^2,          i beta kAG            ],
             [        -i beta kAG,       -omega^2 rho I + kAG + EI beta^2]]

    Its inverse has d21 = -d12, so only d11, d12 and d22 are returned.

    Parameters
    ----------
    track : Track
        Rail properties (complex moduli include the rail damping, see ``Track.rail_moduli``).
    omega, beta : array_like
        Circular frequency (rad/s) and wavenumber (rad/m), broadcast together.
    work : ndarray of complex, optional
        Workspace of shape ``(4, *broadcast shape)``; the results are views of it. The
        wavenumber method reuses one across its ~1e5-entry blocks: there a fresh array per
        operation (page faults of large allocations) cost 4-5x the arithmetic.

    Returns
    -------
    d11, d12, d22 : ndarray of complex
        Entries of D^{-1} (d11 in m/N, d22 in rad/(N m), d12 = -d21 in 1/N), broadcast shape.
    """
    ei, kag = track.rail_moduli(np.abs(np.asarray(omega)) / (2 * np.pi))
    omega2 = np.asarray(omega) ** 2
    beta = np.asarray(beta)
    if work is None:
        work = np.empty((4, *np.broadcast_shapes(np.shape(omega), beta.shape)), dtype=complex)
    d11, d12, d22, t = work
    # Every operation writes into the workspace: no temporaries of the broadcast shape.
    beta2 = t.real
    np.multiply(beta, beta, out=beta2)
    np.multiply(kag, beta2, out=d22)
    d22 -= omega2 * track.mass_per_length  # a = D11
    np.multiply(ei, beta2, out=d11)
    d11 += kag - omega2 * track.rotary_inertia  # b = D22
    np.multiply(kag * kag, beta2, out=d12)  # D12 D21 = kAG^2 beta^2
    np.multiply(d22, d11, out=t)
    t -= d12  # det D = a b - D12 D21
    np.reciprocal(t, out=t)
    d11 *= t  # b / det
    d22 *= t  # a / det
    np.multiply(-1j * kag, beta, out=d12)
    d12 *= t  # -D12 / det
    return d11, d12, d22


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
    return beam_state_matrix(omega, ei, 1.0 / kag, track.mass_per_length, track.rotary_inertia)


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
    return beam_scaling(track.spacing, abs(track.EI))


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
    return wave_dynamic_stiffness(state_matrix(track, omega, extra_loss), state_scaling(track), lengths)
