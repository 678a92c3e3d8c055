"""Refining the coefficients of a rational end model on the error that matters: alpha's.

Vector fitting minimises a weighted error of the fitted function (here the impedance); what a
user judges is the element-wise relative error of the receptance ``alpha = K^-1``. With the poles
fixed, ``K`` is linear in the coefficients and ``d alpha = -alpha dK alpha``, so a Gauss-Newton
(Levenberg-Marquardt) solve on the relative errors of ``alpha11, alpha12, alpha22`` is cheap and
has an analytic Jacobian. Its weights are then re-balanced a few times (iteratively re-weighted
least squares: each weight grows with the square root of its error over the median), which trades
a little of the median error for a lower maximum: the paper's hysteretic damping cannot be matched
by any causal model, and without re-weighting the whole misfit piles up at the band's low end.
"""

from __future__ import annotations

import numpy as np

from .levenberg import levenberg_marquardt
from .rational import SYMMETRIC_ELEMENTS, RationalEndStiffness
from .vector_fitting import pole_basis

__all__ = ["relative_alpha_residuals", "refine_coefficients"]


def _alpha_columns(alpha: np.ndarray) -> np.ndarray:
    return np.stack([alpha[:, i, k] for i, k in SYMMETRIC_ELEMENTS], axis=1)


class _AlphaProblem:
    """Weighted relative residuals of alpha and their Jacobian, for fixed poles."""

    def __init__(self, model: RationalEndStiffness, f: np.ndarray, alpha: np.ndarray, weights: np.ndarray):
        self.model, self.s = model, 2j * np.pi * f
        self.target = _alpha_columns(alpha)
        self.scale = weights / np.abs(self.target)
        self.phi_s = pole_basis(self.s, model.poles) * self.s[:, None]

    def alpha(self, c: np.ndarray) -> np.ndarray:
        m = RationalEndStiffness(self.model.poles, c.reshape(-1, 3), self.model.K0, self.model.D)
        return np.linalg.inv(m.K0 + self.s[:, None, None] * m.impedance(self.s))

    def fun(self, c: np.ndarray) -> np.ndarray:
        r = (_alpha_columns(self.alpha(c)) - self.target) * self.scale
        return np.concatenate([r.real.ravel(), r.imag.ravel()])

    def jac(self, c: np.ndarray) -> np.ndarray:
        a = self.alpha(c)
        # d alpha_ik / d K_pq for a symmetric perturbation of the (p, q) element.
        v = np.empty((a.shape[0], 3, 3), dtype=complex)
        for e, (i, k) in enumerate(SYMMETRIC_ELEMENTS):
            for j, (p, q) in enumerate(SYMMETRIC_ELEMENTS):
                v[:, e, j] = a[:, i, p] * a[:, q, k] + (a[:, i, q] * a[:, p, k] if p != q else 0.0)
        J = -(v * self.scale[:, :, None])[:, :, None, :] * self.phi_s[:, None, :, None]
        J = J.reshape(a.shape[0] * 3, -1)
        return np.vstack([J.real, J.imag])


def relative_alpha_residuals(model: RationalEndStiffness, f: np.ndarray, alpha: np.ndarray,
                             weights: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Residual vector and Jacobian (w.r.t. the flattened coefficients) of the weighted relative
    errors of alpha11, alpha12, alpha22.

    Parameters
    ----------
    model : RationalEndStiffness
        The model (its coefficients are the point of evaluation).
    f : ndarray
        Frequencies (Hz).
    alpha : ndarray, shape (n, 2, 2)
        Reference receptance.
    weights : ndarray, shape (n, 3), optional
        Extra weights per sample and element (ones if omitted).
    """
    w = np.ones((f.size, 3)) if weights is None else weights
    problem = _AlphaProblem(model, f, alpha, w)
    c = model.coefficients.ravel()
    return problem.fun(c), problem.jac(c)


def refine_coefficients(model: RationalEndStiffness, f: np.ndarray, alpha: np.ndarray, n_balance: int = 3,
                        max_nfev: int = 40, guard: np.ndarray | None = None,
                        guard_weight: float = 0.3) -> tuple[RationalEndStiffness, np.ndarray]:
    """Least-squares refinement of the coefficients on alpha's relative error, re-weighted.

    Parameters
    ----------
    model : RationalEndStiffness
        Starting model (poles, ``K0`` and ``D`` are kept).
    f : ndarray
        Frequencies (Hz) of the reference.
    alpha : ndarray, shape (n, 2, 2)
        Reference receptance.
    n_balance : int
        Re-weighting rounds after the first, unweighted solve.
    max_nfev : int
        Evaluations per solve.
    guard : ndarray of bool, optional
        Samples outside the band that only keep the model sane there: they get the fixed
        weight ``guard_weight`` and are never re-balanced.
    guard_weight : float
        Weight of the guard samples.

    Returns
    -------
    model : RationalEndStiffness
        The refined model.
    weights : ndarray, shape (n, 3)
        The final weights (to build the passivity-enforcement metric on the same error).
    """
    guard = np.zeros(f.size, bool) if guard is None else guard
    weights = np.where(guard[:, None], guard_weight, 1.0) * np.ones((f.size, 3))
    c = model.coefficients.ravel()
    for round_ in range(n_balance + 1):
        problem = _AlphaProblem(model, f, alpha, weights)
        c = levenberg_marquardt(problem.fun, problem.jac, c, max_nfev=max_nfev).x
        if round_ < n_balance:
            err = np.abs(_alpha_columns(problem.alpha(c)) - problem.target) / np.abs(problem.target)
            inside = weights[~guard] * np.sqrt(err[~guard] / np.median(err[~guard]))
            weights[~guard] = inside / inside.mean()
    return RationalEndStiffness(model.poles, c.reshape(-1, 3), model.K0, model.D), weights
