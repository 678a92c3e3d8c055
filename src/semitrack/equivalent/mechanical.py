"""The general mechanical system of an end: symmetric ``M, C, K`` with the two port DOFs first.

Every end that a finite-element code attaches as matrices is one of these: the paper's
multi-rigid-body systems (:class:`~.systems.EquivalentSystem`, Tables 4 and 7 and the fitted
N = 5 systems) and the broadband boundary in second-order form
(:meth:`semitrack.BroadbandBoundary.matrix_system`, a :class:`MatrixSystem`). Their DOFs are the
rail's ``(w, psi)`` at the cut (the ports: w downward in m, psi the clockwise rotation of the
cross-section in rad), then internal DOFs. Each describes the semi-infinite track to the right of
the cut; ``(Q, M)`` is the load applied to its ports (the force on the user's end node is
``-(Q, M)``); a left end takes ``P = diag(1, -1)`` on the ports. :class:`MechanicalSystem` holds
what follows from the matrices alone: dynamic stiffness, port receptance, passivity, natural
frequencies and the static condensation; :class:`MatrixSystem` is the system given by its
matrices.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np
from numpy.typing import ArrayLike

from ..base.checks import as_frequencies, as_real_array, brief, check_nonnegative
from ..base.errors import InputError, InputTypeError
from .assembly import IllConditionedError, dynamic_stiffness, end_loads, scaled_solve

__all__ = ["MechanicalSystem", "MatrixSystem", "PassivityReport", "undamped_natural_frequencies", "PORT_DOFS",
           "PSD_RTOL", "SYMMETRY_RTOL"]

#: The port DOFs of every end system, in matrix order: the rail's deflection and rotation at the cut.
PORT_DOFS = ("w", "psi")

# A dynamic stiffness matrix whose condition number, after symmetric diagonal scaling, exceeds
# this is treated as singular: about 1e4 * machine epsilon of relative accuracy is left at most.
_COND_LIMIT = 1e12

# A mass-matrix eigenvalue below this fraction of the largest counts as zero: that direction
# carries no inertia (a massless bar, as in the paper's Table 4) and follows the others statically.
# Rounding of the assembly leaves ~1e-16 of the largest; a genuinely light part is kept.
_MASSLESS_RTOL = 1e-12

#: Relative asymmetry ``max |X - X^T| / max |X|`` accepted in a matrix: rounding of its assembly.
SYMMETRY_RTOL = 1e-12

#: Smallest eigenvalue accepted in M, C and K, as a fraction of the largest: rounding, not activity.
PSD_RTOL = 1e-10


def undamped_natural_frequencies(M: np.ndarray, K: np.ndarray, massless_rtol: float = _MASSLESS_RTOL) -> np.ndarray:
    """Natural frequencies (Hz) of ``K v = omega^2 M v`` for symmetric ``M`` >= 0 and ``K`` >= 0.

    Directions of M without inertia (eigenvalues of M below ``massless_rtol`` of its largest)
    are condensed statically, ``K_c = K_aa - K_an K_nn^+ K_na`` (pseudo-inverse: a massless part
    that is also free, e.g. a bar with zero mass and zero springs, adds nothing). They are
    the infinite eigenvalues of the pencil: an explicit integrator must condense them too, as
    they cannot be stepped, so they set no time step.

    Parameters
    ----------
    M, K : ndarray, shape (n, n)
        Symmetric mass and stiffness matrices (SI units, consistent DOFs).
    massless_rtol : float
        Relative threshold of a zero mass eigenvalue (-).

    Returns
    -------
    ndarray
        Ascending natural frequencies (Hz) of the directions with inertia; rigid-body modes
        give 0. Empty when M is zero.
    """
    lam, V = np.linalg.eigh(M)
    big = np.max(np.abs(lam)) if lam.size else 0.0
    massive = lam > massless_rtol * big
    if big <= 0 or not np.any(massive):
        return np.zeros(0)
    Kt = V.T @ K @ V
    a, n = massive, ~massive
    K_c = Kt[np.ix_(a, a)]
    if np.any(n):
        K_c = K_c - Kt[np.ix_(a, n)] @ np.linalg.pinv(Kt[np.ix_(n, n)], hermitian=True) @ Kt[np.ix_(n, a)]
    scale = 1.0 / np.sqrt(lam[a])
    omega2 = np.linalg.eigvalsh(0.5 * (K_c + K_c.T) * scale[:, None] * scale[None, :])
    return np.sqrt(np.clip(omega2, 0.0, None)) / (2 * np.pi)


@dataclass(frozen=True)
class PassivityReport:
    """Outcome of :meth:`EquivalentSystem.is_passive`; truthy when the system is passive.

    Attributes
    ----------
    passive : bool
        All checks passed.
    min_eig_M, min_eig_C, min_eig_K : float
        Smallest eigenvalue of M, C and K divided by their largest absolute eigenvalue (-).
    min_eig_mobility : ndarray
        Per frequency, the smallest eigenvalue of the Hermitian part of the end mobility
        ``i omega alpha`` divided by the spectral norm of the mobility (-).
    frequencies : ndarray
        The frequencies checked (Hz).
    worst_frequency : float
        Frequency of the smallest ``min_eig_mobility`` (Hz).
    tol : float
        A relative eigenvalue counts as non-negative when it is >= ``-tol``.
    """

    passive: bool
    min_eig_M: float
    min_eig_C: float
    min_eig_K: float
    min_eig_mobility: np.ndarray
    frequencies: np.ndarray
    worst_frequency: float
    tol: float

    def __bool__(self) -> bool:
        return bool(self.passive)


def _relative_min_eig(X: np.ndarray) -> float:
    ev = np.linalg.eigvalsh(X)
    big = np.max(np.abs(ev))
    return float(ev[0] / big) if big > 0 else 0.0



class MechanicalSystem:
    """Base of the end systems: symmetric ``M, C, K``, the ports ``(w, psi)`` first (module docstring).

    Subclasses provide ``_mck`` (the three matrices, read-only) and :meth:`dof_names`.
    """

    #: How messages call the system.
    kind: ClassVar[str] = "mechanical"
    #: The port DOFs, the first two of the matrices.
    port_dofs: ClassVar[tuple[str, str]] = PORT_DOFS
    #: Condition number (after diagonal scaling) above which the dynamic stiffness counts as singular.
    cond_limit: ClassVar[float] = _COND_LIMIT

    @property
    def n_dof(self) -> int:
        """Number of degrees of freedom, the two ports included."""
        return int(self._mck[0].shape[0])

    @property
    def n_internal(self) -> int:
        """Number of internal DOFs (all but the two ports)."""
        return self.n_dof - 2

    def dof_names(self) -> list[str]:
        """Names of the degrees of freedom with units, in the order of :meth:`matrices`."""
        raise NotImplementedError

    def matrices(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Mass, damping and stiffness matrices ``(M, C, K)`` (SI units, DOFs of :meth:`dof_names`, the ports first).

        Rows are generalised forces (N for a displacement DOF, N m for a rotation), columns
        are accelerations, velocities or displacements of the DOFs. Real, symmetric, copies.
        """
        return tuple(np.array(X) for X in self._mck)

    def dynamic_stiffness(self, f: ArrayLike) -> np.ndarray:
        """The dynamic stiffness ``Z = K + i omega C - omega^2 M``.

        Parameters
        ----------
        f : float or array_like
            Frequencies (Hz), positive and finite; scalar or 1-D.

        Returns
        -------
        ndarray of complex, shape (n_f, n_dof, n_dof)
            Rows are generalised forces (N or N m) per displacement (m) or rotation (rad).
        """
        M, C, K = self._mck
        return dynamic_stiffness(M, C, K, 2 * np.pi * self._frequencies(f))

    @staticmethod
    def _frequencies(f) -> np.ndarray:
        f_arr = as_frequencies(f)
        if f_arr.ndim > 1:
            raise InputError(f"f must be a scalar or a 1-D array of frequencies (Hz), got shape {f_arr.shape}")
        return np.atleast_1d(f_arr)

    def _solve(self, f_arr: np.ndarray, rhs: np.ndarray) -> np.ndarray:
        """Solve ``Z(f) x = rhs`` for every frequency (:func:`.assembly.scaled_solve`).

        Raises ValueError when Z is singular or too ill-conditioned at some frequency.
        """
        try:
            return scaled_solve(self.dynamic_stiffness(f_arr), rhs, cond_limit=self.cond_limit)
        except IllConditionedError as exc:
            raise InputError(
                f"the dynamic stiffness of this {self.kind} system is singular (condition number "
                f"{exc.cond:.3g} > {self.cond_limit:.0e} after scaling) at f = {f_arr[exc.index]!r} Hz "
                f"({exc.n_bad} of {f_arr.size} frequencies); the receptance is undefined there "
                "(e.g. all-zero parameters, a free rigid-body motion, or an undamped resonance)"
            ) from None

    # --- end receptance ------------------------------------------------------------------------
    def receptance(self, f: ArrayLike) -> np.ndarray:
        """Receptance at the ports, the first two DOFs (for the paper's systems the left end of bar 1, Eq. 22).

        Parameters
        ----------
        f : float or array_like
            Frequencies (Hz), positive and finite; scalar or 1-D.

        Returns
        -------
        alpha : ndarray of complex, shape (n_f, 2, 2), or (2, 2) for a scalar ``f``
            ``[[w1/Q (m/N), w1/M (1/N)], [phi_1/Q (1/N), phi_1/M (rad/(N m))]]``, with Q a
            downward force and M a clockwise moment applied at the ports (the left end of bar 1).

        Raises
        ------
        ValueError
            For bad frequencies, or where the dynamic stiffness is singular.
        """
        f_arr = self._frequencies(f)
        alpha = self._solve(f_arr, end_loads(self.n_dof))[:, :2, :]
        return alpha[0] if np.ndim(f) == 0 else alpha

    def end_stiffness(self, f: ArrayLike) -> np.ndarray:
        """Dynamic stiffness condensed to ``(w1, phi_1)``: the inverse of :meth:`receptance`.

        Parameters
        ----------
        f : float or array_like
            Frequencies (Hz), positive and finite; scalar or 1-D.

        Returns
        -------
        ndarray of complex, shape (n_f, 2, 2) or (2, 2)
            Units ``[[N/m, N], [N, N m/rad]]``.
        """
        return np.linalg.inv(self.receptance(f))

    def mirrored_receptance(self, f: ArrayLike) -> np.ndarray:
        """Receptance at the junction of this system and its mirror image (paper Sec. 5.3).

        The second copy is this system turned 180 deg about a vertical axis through the left
        end of bar 1, so it extends to the left; the two are joined rigidly at that end (shared
        ``w1`` and ``phi_1``), as the two halves of a complete track meet at the central cross
        section. Mirroring keeps downward displacements and forces but reverses clockwise
        rotations and moments, so the end dynamic stiffness of the left copy is
        ``T K_R T`` with ``T = diag(1, -1)`` and ``K_R`` = :meth:`end_stiffness`. The junction
        receptance is ``inv(K_R + T K_R T) = diag(1 / (2 K_R[0,0]), 1 / (2 K_R[1,1]))``; its
        off-diagonal terms vanish by symmetry.

        Parameters
        ----------
        f : float or array_like
            Frequencies (Hz), positive and finite; scalar or 1-D.

        Returns
        -------
        ndarray of complex, shape (n_f, 2, 2) or (2, 2)
            ``[0, 0]`` (m/N) is the vertical point receptance compared with the complete track
            in the paper's Fig. 16; ``[1, 1]`` (rad/(N m)) is the rotational one.
        """
        K_R = self.end_stiffness(f)
        T = np.diag([1.0, -1.0])
        return np.linalg.inv(K_R + T @ K_R @ T)

    # --- passivity -------------------------------------------------------------------------------
    def is_passive(self, f: ArrayLike, tol: float = 1e-9) -> PassivityReport:
        """Check passivity: M, C, K positive semi-definite and the Hermitian part of the end
        mobility ``i omega alpha`` positive semi-definite at every frequency.

        Eigenvalues are compared relative to the largest one of each matrix (for the mobility,
        to its spectral norm).

        Parameters
        ----------
        f : float or array_like
            Frequencies (Hz) at which the mobility is checked, positive and finite.
        tol : float
            Relative eigenvalues >= ``-tol`` (-) count as non-negative; absorbs rounding.

        Returns
        -------
        PassivityReport
            Truthy when passive.
        """
        tol = check_nonnegative("tol", tol)
        f_arr = self._frequencies(f)
        M, C, K = self._mck
        eM, eC, eK = (_relative_min_eig(X) for X in (M, C, K))
        Y = 1j * (2 * np.pi * f_arr)[:, None, None] * self.receptance(f_arr)
        H = 0.5 * (Y + np.conj(np.swapaxes(Y, 1, 2)))
        ev = np.linalg.eigvalsh(H)[:, 0]
        norm = np.linalg.norm(Y, ord=2, axis=(1, 2))
        rel = np.where(norm > 0, ev / np.where(norm > 0, norm, 1.0), 0.0)
        passive = bool(min(eM, eC, eK) >= -tol and np.all(rel >= -tol))
        return PassivityReport(
            passive=passive, min_eig_M=eM, min_eig_C=eC, min_eig_K=eK,
            min_eig_mobility=rel, frequencies=f_arr, worst_frequency=float(f_arr[np.argmin(rel)]),
            tol=float(tol),
        )

    # --- natural frequencies -----------------------------------------------------------------------
    def natural_frequencies(self) -> np.ndarray:
        """Undamped natural frequencies (Hz) of the free system, ``K v = omega^2 M v``, ascending.

        The system is unconstrained at its attachment DOFs. Massless directions (bars with
        zero mass and inertia, as in the paper's Table 4) are condensed statically and give no
        frequency: see :func:`undamped_natural_frequencies`. A light but not massless part keeps
        its (high) frequency.

        Returns
        -------
        ndarray
            At most :attr:`n_dof` frequencies (Hz).
        """
        M, _, K = self._mck
        return undamped_natural_frequencies(M, K)

    def highest_natural_frequency(self) -> float:
        """The highest undamped natural frequency (Hz) of :meth:`natural_frequencies` (0 if none).

        It sets the time step of an explicit integrator: see :meth:`central_difference_time_step`.

        Examples
        --------
        A single bar with ``J = m L^2 / 4`` bounces and pitches at ``sqrt(2 k / m) / (2 pi)``:

        >>> import math
        >>> import semitrack as st
        >>> bar = st.SlabEquivalent(m=10.0, J=0.9, L=0.6, k=1e7, c_l=0.0, c_r=0.0, k_phi=[], c_phi=[])
        >>> round(bar.highest_natural_frequency(), 6) == round(math.sqrt(2 * 1e7 / 10.0) / (2 * math.pi), 6)
        True
        """
        f = self.natural_frequencies()
        return float(f[-1]) if f.size else 0.0

    def central_difference_time_step(self) -> float:
        """Largest stable step (s) of the undamped central-difference scheme, ``2 / omega_max``.

        ``omega_max = 2 pi`` :meth:`highest_natural_frequency`; damping lowers the limit a
        little. ``inf`` for a system without inertia. Massless DOFs are condensed statically
        here; where they carry dashpots (the broadband end's Maxwell DOFs,
        :meth:`semitrack.BroadbandBoundary.matrix_system`) no explicit scheme steps them at all:
        integrate such a system implicitly.
        """
        f_max = self.highest_natural_frequency()
        return 2.0 / (2 * np.pi * f_max) if f_max > 0 else math.inf


    # --- static condensation -----------------------------------------------------------------------
    def static_internal(self, u: ArrayLike) -> np.ndarray:
        """Internal DOFs at rest under the port displacement ``u``: every internal element unloaded.

        ``q = -K_ii^+ K_ip u`` (pseudo-inverse: internal DOFs without a spring path to the ground,
        such as the broadband end's massless Maxwell DOFs, take the least-norm position). This is the
        initial state of the internal DOFs after a static or preload step (see
        :meth:`static_stiffness`).

        Parameters
        ----------
        u : array_like, shape (2,)
            Port displacement ``(w, psi)`` (m, rad).

        Returns
        -------
        ndarray, shape (n_internal,)
            Internal DOFs in the units of :meth:`dof_names`.
        """
        u = as_real_array(u, "u")
        if u.shape != (2,) or not np.all(np.isfinite(u)):
            raise InputError(f"u must be two finite numbers (w in m, psi in rad), got {u.tolist()!r}")
        return self._static_map() @ u

    def static_stiffness(self) -> np.ndarray:
        """The 2x2 static stiffness at the ports, ``K_pp - K_pi K_ii^+ K_ip`` (N/m, N/rad, N m/rad).

        For the broadband end in second-order form it equals the boundary's ``K0``: a static or
        preload step may close the cut with this 2x2 spring instead of the whole system.
        """
        K = self._mck[2]
        Kc = K[:2, :2] + K[:2, 2:] @ self._static_map()
        return 0.5 * (Kc + Kc.T)

    def _static_map(self) -> np.ndarray:
        """``-K_ii^+ K_ip`` after Jacobi scaling (the internal DOFs' units differ by orders of magnitude).

        ``K_ii`` is singular on the DOFs without a spring path to the ground (a Maxwell dashpot's),
        and ``K_ip`` is zero there (K is PSD), so every solution of ``K_ii u = -K_ip`` gives the same
        condensed stiffness. The null space found by ``eigh`` is shifted to 1 and the rest solved
        directly: a pseudo-inverse instead inverts the smallest kept eigenvalue (7.7e-5 of the
        largest on the viscous slab fit) with its eigenvector's round-off, which left 5e-8 of ``K0``
        on one machine; this way 2e-11.
        """
        K = self._mck[2]
        d = np.diag(K)[2:].copy()
        d = 1.0 / np.sqrt(np.where(d > 0, d, 1.0))
        scaled = d[:, None] * K[2:, 2:] * d[None, :]
        lam, V = np.linalg.eigh(scaled)
        null = V[:, np.abs(lam) <= scaled.shape[0] * np.finfo(float).eps * np.abs(lam).max(initial=0.0)]
        return -d[:, None] * np.linalg.solve(scaled + null @ null.T, d[:, None] * K[2:, :2])


def _square_matrix(name: str, X: ArrayLike, n: int | None) -> np.ndarray:
    """A finite, real, square, symmetric matrix (symmetrised exactly), read-only copy."""
    try:
        X = np.array(X, dtype=float)
    except (TypeError, ValueError):
        raise InputTypeError(f"{name} must be a real matrix, got {type(X).__name__}") from None
    if X.ndim != 2 or X.shape[0] != X.shape[1] or X.shape[0] < 2 or (n is not None and X.shape[0] != n):
        raise InputError(f"{name} must be a square matrix of the same size as M (>= 2: the ports), got shape {X.shape}")
    if not np.all(np.isfinite(X)):
        raise InputError(f"{name} must be finite")
    scale = np.max(np.abs(X))
    if np.max(np.abs(X - X.T)) > SYMMETRY_RTOL * max(scale, np.finfo(float).tiny):
        raise InputError(f"{name} must be symmetric (a reciprocal system): max |{name} - {name}^T| = "
                         f"{np.max(np.abs(X - X.T)):.3e} of max |{name}| = {scale:.3e}")
    X = 0.5 * (X + X.T)
    lam = np.linalg.eigvalsh(X)
    if lam[0] < -PSD_RTOL * max(abs(lam[-1]), abs(lam[0])):
        raise InputError(f"{name} must be positive semi-definite (a passive system): smallest eigenvalue "
                         f"{lam[0]:.6e}, largest {lam[-1]:.6e}")
    X.setflags(write=False)
    return X


@dataclass(frozen=True, eq=False)
class MatrixSystem(MechanicalSystem):
    """An end system given by its matrices: symmetric positive semi-definite ``M, C, K``.

    The first two DOFs are the ports, the rail's ``(w, psi)`` at the cut (m, rad), the others
    internal. Each matrix is checked symmetric (to 1e-12 of its largest entry, then made exactly
    symmetric) and positive semi-definite (eigenvalues >= -1e-10 of the largest).

    Parameters
    ----------
    M : array_like, shape (n, n)
        Mass matrix (kg on w rows and columns, kg m on the w-psi ones, kg m^2 on psi; the internal
        DOFs in the units of ``dofs``).
    C : array_like, shape (n, n)
        Damping matrix (N s/m, N s, N m s/rad on the ports).
    K : array_like, shape (n, n)
        Stiffness matrix (N/m, N, N m/rad on the ports).
    dofs : tuple of str
        Names of the DOFs with units (default: ``w (m)``, ``psi (rad)``, ``q1``, ...).
    info : dict
        What the system is (e.g. the track and band it was fitted on, its origin), kept in exports.
    """

    kind: ClassVar[str] = "matrix"
    # A synthesised end's massless Maxwell DOFs creep at low frequency, where its full dynamic
    # stiffness reaches a condition of 1e12-1e13 while the port receptance stays exact to 1e-9
    # (measured); only a numerically singular matrix is refused.
    cond_limit: ClassVar[float] = 1e15

    M: np.ndarray
    C: np.ndarray
    K: np.ndarray
    dofs: tuple[str, ...] = ()
    info: dict = field(default_factory=dict)

    def __post_init__(self):
        M = _square_matrix("M", self.M, None)
        for name, X in (("M", M), ("C", _square_matrix("C", self.C, M.shape[0])),
                        ("K", _square_matrix("K", self.K, M.shape[0]))):
            object.__setattr__(self, name, X)
        n = M.shape[0]
        if isinstance(self.dofs, (str, bytes)) or not isinstance(self.dofs, (tuple, list)) or not all(
                isinstance(d, str) for d in self.dofs):
            raise InputTypeError(f"dofs must be a tuple of names (str), one per DOF, got {brief(self.dofs)}")
        dofs = tuple(self.dofs) or ("w (m)", "psi (rad)") + tuple(f"q{j}" for j in range(1, n - 1))
        if len(dofs) != n:
            raise InputError(f"dofs must name the {n} DOFs of the matrices, got {len(dofs)} names")
        if not isinstance(self.info, dict):
            raise InputTypeError(f"info must be a dict, got {type(self.info).__name__}")
        object.__setattr__(self, "dofs", dofs)
        object.__setattr__(self, "info", dict(self.info))

    @property
    def _mck(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        return self.M, self.C, self.K

    def dof_names(self) -> list[str]:
        """Names of the degrees of freedom with units, in the order of :meth:`matrices`."""
        return list(self.dofs)

    def __repr__(self) -> str:
        return (f"MatrixSystem: {self.n_dof} DOFs ({', '.join(self.dofs[:2])} the ports, {self.n_internal} internal), "
                f"{int(np.sum(np.linalg.eigvalsh(self.M) > _MASSLESS_RTOL * max(np.abs(self.M).max(), 1e-300)))} "
                f"with inertia; {self.info.get('origin', '')}".rstrip("; "))
