"""Cell 0's field of a force at each grid point, with the force's phase: the moving kernels' near operand.

The cell's DOFs per unit force on each loaded DOF, ``Z[f, i, s]`` (one band solve per
frequency, :meth:`semitrack.fe.bloch.BlochCell.waves`), give the field of a force at grid point p
through the shape weights of its element's four DOFs, and the set-up of
:mod:`semitrack.fe.kernels` wants it with the force's phase ``exp(-i omega_f p dt)``:

    F[i, f, p] = phase[f, p] * sum_c W[p, c] Z[f, i, s[p, c]]

in the layout its products read, DOF first: an element's rows are then one contiguous block.
Four multiply-adds per value, so forming it is all memory traffic: NumPy's gathers, phase and
transposes took 150 ms a block of 128 frequencies on the made-up ballasted track (312 grid points,
123 DOFs), the compiled pass (:mod:`semitrack.fe.compiled`, numba) 30 ms. Without numba the NumPy
reference runs; the tests compare the two.
"""

from __future__ import annotations

import numpy as np

__all__ = ["phased_point_field", "phased_point_field_numpy"]


def phased_point_field_numpy(Z: np.ndarray, sidx: np.ndarray, weights: np.ndarray, phase: np.ndarray) -> np.ndarray:
    """The reference in NumPy (see the module docstring).

    Parameters
    ----------
    Z : ndarray of complex, shape (n_f, n, n_s)
        The cell's DOFs per unit force on each loaded DOF (m/N...).
    sidx : ndarray of int, shape (P, 4)
        The loaded DOFs (indices into Z's last axis) a force at each grid point acts on.
    weights : ndarray, shape (P, 4)
        Their shares of a unit force at each grid point.
    phase : ndarray of complex, shape (n_f, P)
        The force's phase at each frequency and grid point.

    Returns
    -------
    ndarray of complex, shape (n, n_f, P)
    """
    field = sum(weights[:, c] * Z[:, :, sidx[:, c]] for c in range(sidx.shape[1]))  # (n_f, n, P)
    return np.ascontiguousarray((field * phase[:, None, :]).transpose(1, 0, 2))


def phased_point_field(Z: np.ndarray, sidx: np.ndarray, weights: np.ndarray, phase: np.ndarray) -> np.ndarray:
    """:func:`phased_point_field_numpy`'s result, compiled where numba is installed (same arguments)."""
    try:
        from .compiled import point_field_into  # imports numba: deferred to the first set-up
    except ImportError:
        return phased_point_field_numpy(Z, sidx, weights, phase)
    out = np.empty((Z.shape[1], Z.shape[0], sidx.shape[0]), dtype=complex)
    point_field_into(np.ascontiguousarray(Z), np.ascontiguousarray(sidx, dtype=np.int64),
                     np.ascontiguousarray(weights, dtype=float), np.ascontiguousarray(phase), out)
    return out
