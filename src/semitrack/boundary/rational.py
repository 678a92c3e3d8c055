"""A rational model of the 2x2 end dynamic stiffness of a semi-infinite track.

The model is written in impedance form (force per end velocity), which makes its physics and its
passivity explicit:

    K(s) = K0 + s Z(s),    Z(s) = D + sum_m C_m phi_m(s) = D + C (sI - A)^-1 B,

with ``s = i omega``, ``K0`` the static stiffness (a spring), ``D`` the dashpot of a semi-infinite
Timoshenko beam end (the high-frequency limit, ``diag(sqrt(kappa A G rho A), sqrt(E I rho I))``)
and a strictly proper part with common stable poles and symmetric 2x2 coefficient matrices (one
per real basis function of :mod:`.vector_fitting`). ``K(0) = K0`` and ``K ~ i omega D`` hold
exactly whatever the fitted coefficients, so fitting and passivity enforcement can never move
them. The end force and moment follow from the end displacement ``u = (w, psi)`` through the
first-order states ``x``:

    (Q, M) = K0 u + D du/dt + C x,    dx/dt = A x + B du/dt,

which is how a time integrator couples the model to a finite-element rail (see ``state_space``).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from ..base.checks import as_frequencies
from ..base.errors import InputError
from .vector_fitting import n_real_coefficients, pole_basis, pole_states

__all__ = ["RationalEndStiffness", "BoundaryStateSpace", "SYMMETRIC_ELEMENTS"]

#: The three independent elements of a symmetric 2x2 matrix, in coefficient-column order.
SYMMETRIC_ELEMENTS = ((0, 0), (0, 1), (1, 1))


def symmetric_from_columns(values: np.ndarray) -> np.ndarray:
    """Symmetric 2x2 matrices from their (11, 12, 22) elements on the last axis."""
    values = np.asarray(values)
    out = np.empty(values.shape[:-1] + (2, 2), dtype=values.dtype)
    for j, (i, k) in enumerate(SYMMETRIC_ELEMENTS):
        out[..., i, k] = out[..., k, i] = values[..., j]
    return out


@dataclass(frozen=True)
class BoundaryStateSpace:
    """Real state-space form of a rational end model, input the end velocity.

    ``(Q, M) = K0 u + D du/dt + C x`` and ``dx/dt = A x + B du/dt``, with ``u = (w, psi)`` the
    end displacement and rotation (the paper's signs: w downward, psi clockwise). Unpacks as
    ``A, B, C, D = bnd.state_space()``.

    Attributes
    ----------
    A : ndarray, shape (n, n)
        State matrix (1/s), stable.
    B : ndarray, shape (n, 2)
        Input matrix: states per end velocity.
    C : ndarray, shape (2, n)
        Output matrix: end force (N) and moment (N m) per state.
    D : ndarray, shape (2, 2)
        Dashpot (N s/m, N m s/rad on the diagonal).
    K0 : ndarray, shape (2, 2)
        Static stiffness ([[N/m, N/rad], [N m/m, N m/rad]]).
    dofs : tuple of str
        The end degrees of freedom, ``("w", "psi")``.
    units : dict
        Units of the inputs, outputs and matrices.
    """

    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    D: np.ndarray
    K0: np.ndarray
    dofs: tuple[str, str] = ("w", "psi")
    units: dict = field(default_factory=lambda: {
        "input": "end velocity (m/s, rad/s)", "output": "end force and moment (N, N m)",
        "A": "1/s", "D": "N s/m, N m s/rad", "K0": "N/m, N/rad, N m/rad", "time": "s"})

    def __iter__(self):
        return iter((self.A, self.B, self.C, self.D))

    @property
    def n_states(self) -> int:
        """Number of first-order states."""
        return self.A.shape[0]


@dataclass(frozen=True, eq=False)
class RationalEndStiffness:
    """``K(s) = K0 + s (D + sum_m C_m phi_m(s))``: the end stiffness as a rational function.

    Parameters
    ----------
    poles : array_like of complex
        Stable poles (rad/s); one member (Im > 0) per complex pair.
    coefficients : array_like, shape (n_coef, 3)
        Real coefficients of each basis function for the (11, 12, 22) elements.
    K0 : array_like, shape (2, 2)
        Static stiffness, real symmetric.
    D : array_like, shape (2, 2)
        High-frequency dashpot, real symmetric positive definite.
    """

    poles: np.ndarray
    coefficients: np.ndarray
    K0: np.ndarray
    D: np.ndarray

    def __post_init__(self):
        poles = np.array(self.poles, dtype=complex).ravel()  # copies: the model is immutable
        coef = np.array(self.coefficients, dtype=float)
        K0 = np.array(self.K0, dtype=float)
        D = np.array(self.D, dtype=float)
        for name, value in (("poles", poles), ("coefficients", coef), ("K0", K0), ("D", D)):
            if not np.all(np.isfinite(value)):
                raise InputError(f"{name} must be finite")
        if poles.size == 0:
            raise InputError("poles must hold at least one pole")
        if np.any(poles.imag < 0):
            raise InputError("poles must list one member of each complex pair, the one with Im > 0, "
                             f"got {poles[poles.imag < 0][0]!r}")
        if coef.shape != (n_real_coefficients(poles), 3):
            raise InputError(f"coefficients must have shape ({n_real_coefficients(poles)}, 3) for "
                             f"{poles.size} poles, got {coef.shape}")
        for name, value in (("K0", K0), ("D", D)):
            if value.shape != (2, 2) or not np.allclose(value, value.T, rtol=1e-12, atol=0):
                raise InputError(f"{name} must be a symmetric 2x2 matrix, got {value.tolist()}")
        if np.linalg.eigvalsh(D)[0] <= 0:
            raise InputError(f"D (the high-frequency dashpot) must be positive definite, got {D.tolist()}")
        for name, value in (("poles", poles), ("coefficients", coef), ("K0", K0), ("D", D)):
            value.setflags(write=False)
            object.__setattr__(self, name, value)

    @property
    def n_poles(self) -> int:
        """Number of poles, counting both members of a complex pair."""
        return n_real_coefficients(self.poles)

    def impedance(self, s: np.ndarray) -> np.ndarray:
        """``Z(s)`` without the spring term (``D`` plus the strictly proper part), ``(n, 2, 2)``.

        Parameters
        ----------
        s : ndarray
            Complex frequencies (rad/s).
        """
        s = np.atleast_1d(np.asarray(s, dtype=complex))
        return self.D + symmetric_from_columns(pole_basis(s, self.poles) @ self.coefficients)

    def dynamic_stiffness(self, f: ArrayLike) -> np.ndarray:
        """End dynamic stiffness ``K = alpha^-1`` at frequencies ``f`` (Hz), shape ``(n, 2, 2)``.

        Parameters
        ----------
        f : array_like
            Positive frequencies (Hz), any range.
        """
        s = 2j * np.pi * as_frequencies(f).ravel()
        return self.K0 + s[:, None, None] * self.impedance(s)

    def receptance(self, f: ArrayLike) -> np.ndarray:
        """End receptance ``alpha = K^-1`` at frequencies ``f`` (Hz), shape ``(n, 2, 2)``.

        Parameters
        ----------
        f : array_like
            Positive frequencies (Hz), any range.
        """
        return np.linalg.inv(self.dynamic_stiffness(f))

    def state_space(self) -> BoundaryStateSpace:
        """Real state-space form (input: end velocity); see :class:`BoundaryStateSpace`."""
        a, b = pole_states(self.poles)
        eye = np.eye(2)
        C = np.concatenate(symmetric_from_columns(self.coefficients), axis=1)  # (2, 2 n)
        return BoundaryStateSpace(A=np.kron(a, eye), B=np.kron(b[:, None], eye), C=C,
                                  D=self.D.copy(), K0=self.K0.copy())
