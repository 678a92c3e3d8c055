"""The paper's least-squares residuals and their analytic Jacobian.

At the fit frequencies the residuals are ``Re(alpha_E - alpha)/|alpha|`` and
``Im(alpha_E - alpha)/|alpha|`` of alpha11, alpha12 and alpha22 (paper Sec. 4.4, 5.2), with
``alpha_E`` the end receptance of the equivalent system of ``theta``
(:class:`~.parametrisation.FitParametrisation`) and ``alpha`` the target.

**Speed.** Residuals and the Jacobian are vectorised over frequency: one batched
``numpy.linalg.solve`` of the dynamic stiffness ``Z = K + i omega C - omega^2 M`` with symmetric
diagonal scaling (:func:`~.assembly.scaled_solve`), shared by both for a given ``theta``. The
Jacobian is analytic, ``d alpha = -X^T dZ X`` with ``X = Z^-1 E``, evaluated through the
spring-elongation maps ``P`` (``Z`` is a sum of ``P^T diag(v) P`` terms,
:meth:`~.assembly.Assembly.stacked_sensitivities`) in O(n_f N n_theta) operations; the
derivatives of the values ``v`` through the constraints come from a complex-step
differentiation (exact to rounding).
"""

from __future__ import annotations

import numpy as np

from ..base.conventions import ELEMENTS
from .assembly import dynamic_stiffness, end_loads, scaled_solve
from .parametrisation import FitParametrisation

__all__ = ["Residuals"]

# (row, column) of the compared receptance elements alpha11, alpha12, alpha22.
_PAIRS = tuple(ELEMENTS.values())

# Stand-in for a residual that is not finite (an exactly singular Z): large, so the solver
# steps back, yet finite, so it can.
_NONFINITE_RESIDUAL = 1e6


class Residuals:
    """Residuals ``[Re, Im] (alpha_E - alpha) / |alpha|`` and their Jacobian at frequencies ``f``.

    Parameters
    ----------
    model : FitParametrisation
        The unknowns and their map to the system.
    f : ndarray, shape (n_f,)
        Fit frequencies (Hz).
    alpha : ndarray of complex, shape (n_f, 2, 2)
        The target receptance at ``f``; alpha11, alpha12, alpha22 must be non-zero.
    """

    def __init__(self, model: FitParametrisation, f: np.ndarray, alpha: np.ndarray):
        self.model = model
        self.f = np.asarray(f, float)
        self.omega = 2 * np.pi * self.f
        self.target = np.stack([alpha[:, i, j] for i, j in _PAIRS], axis=1)  # (n_f, 3)
        self.scale = 1.0 / np.abs(self.target)  # (n_f, 3)
        self._key = None
        self._loads = end_loads(model.n_dof)

    def _solve(self, theta: np.ndarray) -> np.ndarray:
        """``X = Z^-1 E`` (n_f, n_dof, 2) for ``theta``; the last one is kept for the Jacobian."""
        key = theta.tobytes()
        if key != self._key:
            M, C, K = (X[0] for X in self.model.matrices(theta[None, :]))
            try:
                X = scaled_solve(dynamic_stiffness(M, C, K, self.omega), self._loads)
            except np.linalg.LinAlgError:  # exactly singular: residuals become large (see fun)
                X = np.full((self.f.size, self.model.n_dof, 2), np.nan + 0j)
            self._key, self._X = key, X
        return self._X

    def alpha(self, theta: np.ndarray) -> np.ndarray:
        """alpha11, alpha12, alpha22 of the system of ``theta``, shape (n_f, 3)."""
        X = self._solve(theta)
        return np.stack([X[:, i, j] for i, j in _PAIRS], axis=1)

    def fun(self, theta: np.ndarray) -> np.ndarray:
        """The residuals: real parts, then imaginary parts, each (n_f, 3) flattened."""
        d = (self.alpha(theta) - self.target) * self.scale
        r = np.concatenate([d.real.ravel(), d.imag.ravel()])
        if not np.all(np.isfinite(r)):
            r = np.where(np.isfinite(r), r, _NONFINITE_RESIDUAL)
        return r

    def jac(self, theta: np.ndarray) -> np.ndarray:
        """Analytic Jacobian of :meth:`fun`, shape (2 n_f 3, n_theta).

        The receptance sensitivities to every value and length
        (:meth:`~.assembly.Assembly.stacked_sensitivities`) chained with ``d p / d theta``
        (complex step through the constraints; ``d L / d theta_L = L``).
        """
        model = self.model
        X = self._solve(theta)
        p = {k: np.real(v[0]) for k, v in model.params(theta[None, :]).items()}
        dp = model.param_derivatives(theta)  # {value: (n_theta, rows)}
        d_rows, d_lengths = model.assembly.stacked_sensitivities(X, p, self.omega, _PAIRS)
        # d p_r / d theta for every stacked row: the rows of each term are those of its family.
        D = np.concatenate([dp[term.value] for term in model.assembly.terms], axis=1).T  # (rows, n_theta)
        # d alpha / d theta, scaled like the residuals; D is real, so the real and imaginary
        # rows of J are two real products, (n_f * n_elements, rows) @ (rows, n_theta).
        n_rows = d_rows.shape[-1]
        Q = (d_rows * self.scale[:, :, None]).reshape(-1, n_rows)
        lengths = (d_lengths * (self.scale[:, :, None] * p["L"][None, None, :])).reshape(-1, model.N)
        J = np.empty((2 * Q.shape[0], model.n_theta))
        for part, rows in ((np.real, slice(0, Q.shape[0])), (np.imag, slice(Q.shape[0], None))):
            J[rows] = part(Q) @ D
            J[rows, model.slices["L"]] += part(lengths)
        return np.where(np.isfinite(J), J, 0.0)
