"""Uniform beams on an elastic (Winkler) foundation: state matrix and exact segment dynamic stiffness.

The kernel shared by the rail (:mod:`semitrack.model.timoshenko`, no foundation) and the slab
(:mod:`semitrack.model.slab`, on its resilient layer). The state is s = (w, psi, Q, M) with the
paper's sign convention (w downward, psi clockwise, Q(x) and M(x) the loads that the beam left of
x exerts on the beam right of x); the time factor is exp(i omega t).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike


def beam_state_matrix(omega: np.ndarray, ei: ArrayLike, shear_compliance: ArrayLike, mass_per_length: float,
                      rotary_inertia: float, foundation: ArrayLike = 0.0) -> np.ndarray:
    """State matrix of any Timoshenko (or Euler-Bernoulli) beam on a Winkler foundation, ``(n, 4, 4)``.

    The rail's :func:`semitrack.model.timoshenko.state_matrix` and the slab of :mod:`semitrack.model.slab` are both this
    beam; the foundation only shifts the inertia term, Q' = (omega^2 m - k_f) w.

    Parameters
    ----------
    omega : ndarray
        Circular frequencies (rad/s), shape ``(n,)``.
    ei : array_like
        Complex bending stiffness (N m^2), scalar or ``(n,)``.
    shear_compliance : array_like
        1 / (kappa A G) (1/N), scalar or ``(n,)``; zero for an Euler-Bernoulli beam.
    mass_per_length, rotary_inertia : float
        rho A (kg/m) and rho I (kg m); zero rotary inertia for an Euler-Bernoulli beam.
    foundation : array_like
        Complex Winkler stiffness per unit length (N/m^2), scalar or ``(n,)``.
    """
    a = np.zeros((omega.size, 4, 4), dtype=complex)
    a[:, 0, 1] = 1.0
    a[:, 0, 2] = -shear_compliance
    a[:, 1, 3] = -1.0 / ei
    a[:, 2, 0] = omega**2 * mass_per_length - foundation
    a[:, 3, 1] = omega**2 * rotary_inertia
    a[:, 3, 2] = -1.0
    return a


def beam_scaling(length: float, ei: float) -> np.ndarray:
    """Diagonal scaling (w / l, psi, Q l^2 / EI, M l / EI) that makes a beam's state dimensionless.

    Parameters
    ----------
    length : float
        Length scale l (m), e.g. the support spacing.
    ei : float
        Bending stiffness (N m^2), real.

    Returns
    -------
    ndarray, shape (4,)
    """
    return np.array([1.0 / length, 1.0, length**2 / ei, length / ei])


def wave_dynamic_stiffness(a: np.ndarray, scale: np.ndarray, lengths: ArrayLike) -> np.ndarray:
    """Exact dynamic stiffness of uniform beam segments from their state matrix ``a``.

    The kernel of :func:`segment_dynamic_stiffness`, shared with the slab: each of the four waves
    exp(kappa x) of ds/dx = A s is referred to the end it decays away from.

    Parameters
    ----------
    a : ndarray, shape (n, 4, 4)
        State matrix of (w, psi, Q, M) per frequency (:func:`beam_state_matrix`).
    scale : ndarray, shape (4,)
        Diagonal scaling that makes the state dimensionless (:func:`state_scaling`).
    lengths : array_like
        Segment lengths (m), shape ``(m,)``, positive.

    Returns
    -------
    ndarray, shape (m, n, 4, 4)
        As :func:`segment_dynamic_stiffness`.
    """
    lengths = np.atleast_1d(np.asarray(lengths, dtype=float))
    kappa, phi = np.linalg.eig(scale[:, None] * a / scale[None, :])
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
