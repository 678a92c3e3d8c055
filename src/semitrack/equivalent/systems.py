"""Multi-rigid-body systems equivalent to a semi-infinite track (paper Sec. 4.4, 5.2, App. A, B).

Two layouts, both a train of ``N`` rigid bars hinged together, bar ``j`` having mass ``m_j``,
moment of inertia ``J_j`` about its centre of mass (taken at mid-length) and length ``L_j``;
neighbouring bars ``j`` and ``j+1`` are joined by a rotational spring ``k_phi_j`` and damper
``c_phi_j``:

* :class:`SlabEquivalent` (paper Fig. 7): each bar end rests on a vertical spring ``k_j`` to the
  ground, with dampers ``c_l_j`` (left end) and ``c_r_j`` (right end). Degrees of freedom
  (Eq. 21): ``q = (w1, phi_1, ..., phi_N)``, N + 1 in all.
* :class:`BallastedEquivalent` (paper Fig. 12): each bar end rests on a spring ``k_j`` (damper
  ``c_l_j``/``c_r_j``) on a support mass ``mu_j``, which rests on a spring ``s_j`` (damper
  ``d_l_j``/``d_r_j``) to the ground. Degrees of freedom (Eq. 31):
  ``q = (w1, phi_1..phi_N, w_l1..w_lN, w_r1..w_rN)``, 3N + 1 in all.

``w1`` is the downward displacement of the left end of bar 1, ``phi_j`` the clockwise rotation
of bar ``j``; the harmonic time factor is ``exp(i omega t)``. The receptance at the left end of
bar 1 is ordered ``[[w/Q, w/M], [phi_1/Q, phi_1/M]]`` like the track receptance of the paper.

The matrices follow Appendix A (Eq. A.16, A.18, A.24) and Appendix B (Eq. B.15, B.20, B.26),
written as sums of ``P^T diag(v) P`` terms, one per family of springs or dampers, where ``P``
maps ``q`` to the elongation of each spring of the family; :mod:`.assembly` holds those maps,
the term tables and the scaled solve, shared with the fit.
"""

from __future__ import annotations

import dataclasses
import functools
import math
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np
from numpy.typing import ArrayLike

from ..base.checks import as_frequencies
from ..base.errors import InputError, InputTypeError
from .assembly import IllConditionedError, Layout, assembly, dynamic_stiffness, end_loads, scaled_solve

__all__ = [
    "EquivalentSystem",
    "SlabEquivalent",
    "BallastedEquivalent",
    "PassivityReport",
    "PARAMETER_UNITS",
]

#: SI unit of every parameter of the two layouts.
PARAMETER_UNITS: dict[str, str] = {
    "m": "kg",
    "J": "kg m^2",
    "L": "m",
    "k": "N/m",
    "c_l": "N s/m",
    "c_r": "N s/m",
    "k_phi": "N m/rad",
    "c_phi": "N m s/rad",
    "mu": "kg",
    "s": "N/m",
    "d_l": "N s/m",
    "d_r": "N s/m",
}

# A dynamic stiffness matrix whose condition number, after symmetric diagonal scaling, exceeds
# this is treated as singular: about 1e4 * machine epsilon of relative accuracy is left at most.
_COND_LIMIT = 1e12

# A mass-matrix eigenvalue below this fraction of the largest counts as zero: that direction
# carries no inertia (a massless bar, as in the paper's Table 4) and follows the others statically.
# Rounding of the assembly leaves ~1e-16 of the largest; a genuinely light part is kept.
_MASSLESS_RTOL = 1e-12

# Relative asymmetry tolerated in an assembled matrix before it counts as an assembly bug: the
# P^T diag(v) P products are symmetric up to a few roundings of the largest entry.
_SYMMETRY_RTOL = 1e-12


def parameter_array(name: str, value: ArrayLike, *, positive: bool = False) -> np.ndarray:
    """One per-bar (or per-hinge) parameter as a checked, read-only 1-D float array.

    Shared by the systems and the constraint builders of this subpackage.

    Parameters
    ----------
    name : str
        The parameter's name, quoted in error messages.
    value : array_like
        Real numbers; a scalar counts as one bar.
    positive : bool
        Require entries > 0 (lengths) instead of >= 0.

    Returns
    -------
    ndarray, shape (n,)
        A private, read-only copy.

    Raises
    ------
    TypeError
        For non-numeric (or bool, complex) input.
    ValueError
        Naming the first offending entry: not finite, negative (or zero with ``positive``), or
        not one-dimensional.
    """
    try:
        arr = np.atleast_1d(np.asarray(value))
    except (TypeError, ValueError):
        raise InputTypeError(f"{name} must be an array of real numbers, got {value!r}") from None
    if arr.size and arr.dtype.kind not in "iuf":  # bool, complex, str and object are refused
        raise InputTypeError(f"{name} must be an array of real numbers, got {value!r} (dtype {arr.dtype})")
    arr = np.array(arr, dtype=float)  # a private copy
    if arr.ndim != 1:
        raise InputError(f"{name} must be one-dimensional (one value per bar), got shape {arr.shape}")
    rule = "positive and finite" if positive else "non-negative and finite"
    for i, v in enumerate(arr):
        ok = np.isfinite(v) and (v > 0 if positive else v >= 0)
        if not ok:
            raise InputError(f"{name}[{i}] must be {rule}, got {float(v)!r}")
    arr.setflags(write=False)
    return arr


def readonly_state(obj: object, state: dict) -> None:
    """``__setstate__`` of the package's frozen records: restore ``state``, arrays read-only again.

    Pickling does not keep the writeable flag of an array; the records that promise read-only
    arrays (the systems, :class:`~.fitting.FitResult`) set it again when unpickled.
    """
    obj.__dict__.update(state)
    for value in state.values():
        for item in value if isinstance(value, tuple) else (value,):
            if isinstance(item, np.ndarray):
                item.setflags(write=False)


def _symmetrised(name: str, X: np.ndarray) -> np.ndarray:
    """Check that an assembled matrix is symmetric to rounding, then return it exactly symmetric."""
    scale = np.max(np.abs(X)) if X.size else 0.0
    asym = np.max(np.abs(X - X.T)) if X.size else 0.0
    if asym > _SYMMETRY_RTOL * max(scale, np.finfo(float).tiny):
        raise RuntimeError(f"assembled {name} matrix is not symmetric: max |{name} - {name}^T| = {asym:.3e}")
    S = 0.5 * (X + X.T)
    S.setflags(write=False)
    return S


def _format_value(x: float) -> str:
    """A parameter value in a short form: 4 significant digits, 0 as 0."""
    return "0" if x == 0 else f"{x:.4g}"


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


@dataclass(frozen=True, eq=False)
class EquivalentSystem:
    """Common base of the two layouts; not meant to be instantiated itself.

    Parameters
    ----------
    m : array_like, shape (N,)
        Bar masses (kg).
    J : array_like, shape (N,)
        Moments of inertia of the bars about their centres (kg m^2).
    L : array_like, shape (N,)
        Bar lengths (m); must be positive.
    k : array_like, shape (N,)
        Stiffness of the vertical spring at each end of a bar (N/m).
    c_l, c_r : array_like, shape (N,)
        Damping coefficients of the left and right end dampers of each bar (N s/m).
    k_phi : array_like, shape (N-1,)
        Rotational stiffness between bars j and j+1 (N m/rad).
    c_phi : array_like, shape (N-1,)
        Rotational damping between bars j and j+1 (N m s/rad).

    All entries must be finite and >= 0. The arrays are stored read-only.
    """

    layout: ClassVar[str] = ""
    _per_bar: ClassVar[tuple[str, ...]] = ("m", "J", "L", "k", "c_l", "c_r")
    _per_hinge: ClassVar[tuple[str, ...]] = ("k_phi", "c_phi")

    m: np.ndarray
    J: np.ndarray
    L: np.ndarray
    k: np.ndarray
    c_l: np.ndarray
    c_r: np.ndarray
    k_phi: np.ndarray
    c_phi: np.ndarray

    def __post_init__(self):
        if type(self) is EquivalentSystem:
            raise InputTypeError("EquivalentSystem is abstract: use SlabEquivalent or BallastedEquivalent")
        for name in self.parameter_names():
            object.__setattr__(self, name, parameter_array(name, getattr(self, name), positive=(name == "L")))
        N = self.m.size
        if N < 1:
            raise InputError("m must hold at least one bar, got an empty array")
        for name in self._per_bar:
            if getattr(self, name).size != N:
                raise InputError(
                    f"{name} must have one value per bar (length N = {N} as m), "
                    f"got length {getattr(self, name).size}"
                )
        for name in self._per_hinge:
            if getattr(self, name).size != N - 1:
                raise InputError(
                    f"{name} must have one value per hinge (length N - 1 = {N - 1}), "
                    f"got length {getattr(self, name).size}"
                )

    # --- bookkeeping ------------------------------------------------------------------------
    @classmethod
    def parameter_names(cls) -> tuple[str, ...]:
        """Names of the parameters in constructor order."""
        return tuple(f.name for f in dataclasses.fields(cls))

    @property
    def n_bars(self) -> int:
        """Number of bars N."""
        return int(self.m.size)

    @property
    def n_dof(self) -> int:
        """Number of degrees of freedom (N + 1 or 3N + 1)."""
        return assembly(self.layout, self.n_bars).n_dof

    def parameters(self) -> dict[str, np.ndarray]:
        """The parameters as a dict of name -> writable float array (copies); units in
        :data:`PARAMETER_UNITS`."""
        return {name: np.array(getattr(self, name)) for name in self.parameter_names()}

    @classmethod
    def from_parameters(cls, params: dict[str, Any]) -> EquivalentSystem:
        """Build a system from a dict of parameters (as returned by :meth:`parameters`).

        Parameters
        ----------
        params : dict
            Every parameter of the layout by name (units in :data:`PARAMETER_UNITS`), and
            optionally ``"layout"``. Called on :class:`EquivalentSystem` itself, the layout is
            taken from the ``"layout"`` key if present, otherwise it is ballasted when ``mu`` is
            given and slab otherwise.

        Returns
        -------
        SlabEquivalent or BallastedEquivalent

        Raises
        ------
        TypeError
            For a non-dict, unknown or missing parameters.
        ValueError
            For an unknown layout, or one that contradicts the class.

        Examples
        --------
        >>> import semitrack as st
        >>> p = {"m": [10.0], "J": [0.2], "L": [0.3], "k": [1e7], "c_l": [50.0], "c_r": [50.0],
        ...      "k_phi": [], "c_phi": []}
        >>> st.EquivalentSystem.from_parameters(p).layout
        'slab'
        """
        if not isinstance(params, dict):
            raise InputTypeError(f"params must be a dict of parameter arrays, got {type(params).__name__}")
        params = dict(params)
        layout = params.pop("layout", None)
        target = cls
        if cls is EquivalentSystem:
            if layout is None:
                layout = "ballasted" if "mu" in params else "slab"
            target = _LAYOUTS.get(layout)
            if target is None:
                raise InputError(f"layout must be one of {sorted(_LAYOUTS)}, got {layout!r}")
        elif layout is not None and layout != cls.layout:
            raise InputError(f"layout must be {cls.layout!r} for {cls.__name__}, got {layout!r}")
        names = target.parameter_names()
        unknown = sorted(set(params) - set(names))
        missing = [n for n in names if n not in params]
        if unknown:
            raise InputTypeError(f"unknown parameter(s) for the {target.layout} layout: {unknown}")
        if missing:
            raise InputTypeError(f"missing parameter(s) for the {target.layout} layout: {missing}")
        return target(**params)

    def replace(self, **changes: ArrayLike) -> EquivalentSystem:
        """A copy with some parameters changed (validated again).

        Parameters
        ----------
        **changes
            New values of parameters by name (units in :data:`PARAMETER_UNITS`).

        Returns
        -------
        EquivalentSystem
            Of the same layout.
        """
        return dataclasses.replace(self, **changes)

    def __eq__(self, other):
        if type(other) is not type(self):
            return NotImplemented
        return all(np.array_equal(getattr(self, n), getattr(other, n)) for n in self.parameter_names())

    def __hash__(self):
        return hash((type(self).__name__,) + tuple(getattr(self, n).tobytes() for n in self.parameter_names()))

    def __setstate__(self, state: dict) -> None:
        readonly_state(self, state)

    def to_frame(self):
        """Parameters as a pandas DataFrame: one row per parameter (with unit), one column per bar.

        The N - 1 hinge parameters ``k_phi``, ``c_phi`` sit in the columns of bars 1..N-1 (the
        hinge between bar j and bar j+1 is listed under bar j, as in the paper's tables).
        """
        import pandas as pd

        n = self.n_bars
        rows = {}
        for name, values in self.parameters().items():
            padded = np.full(n, np.nan)
            padded[: len(values)] = values
            rows[f"{name} ({PARAMETER_UNITS[name]})"] = padded
        return pd.DataFrame.from_dict(rows, orient="index", columns=[f"bar {j + 1}" for j in range(n)])

    def dof_names(self) -> list[str]:
        """Names of the degrees of freedom with units, in the order of :meth:`matrices`."""
        N = self.n_bars
        return ["w1 (m)"] + [f"phi_{j} (rad)" for j in range(1, N + 1)]

    # --- matrices ----------------------------------------------------------------------------
    @functools.cached_property
    def _mck(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        params = {name: getattr(self, name)[None] for name in self.parameter_names()}
        M, C, K = (X[0] for X in assembly(self.layout, self.n_bars).matrices(params))
        return _symmetrised("M", M), _symmetrised("C", C), _symmetrised("K", K)

    def matrices(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Mass, damping and stiffness matrices ``(M, C, K)`` (SI units, DOFs of :meth:`dof_names`).

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
            return scaled_solve(self.dynamic_stiffness(f_arr), rhs, cond_limit=_COND_LIMIT)
        except IllConditionedError as exc:
            raise InputError(
                f"the dynamic stiffness of this {self.layout} system is singular (condition number "
                f"{exc.cond:.3g} > {_COND_LIMIT:.0e} after scaling) at f = {f_arr[exc.index]!r} Hz "
                f"({exc.n_bad} of {f_arr.size} frequencies); the receptance is undefined there "
                "(e.g. all-zero parameters, a free rigid-body motion, or an undamped resonance)"
            ) from None

    # --- end receptance ------------------------------------------------------------------------
    def receptance(self, f: ArrayLike) -> np.ndarray:
        """Receptance at the left end of bar 1 (Eq. 22).

        Parameters
        ----------
        f : float or array_like
            Frequencies (Hz), positive and finite; scalar or 1-D.

        Returns
        -------
        alpha : ndarray of complex, shape (n_f, 2, 2), or (2, 2) for a scalar ``f``
            ``[[w1/Q (m/N), w1/M (1/N)], [phi_1/Q (1/N), phi_1/M (rad/(N m))]]``, with Q a
            downward force and M a clockwise moment at the left end of bar 1.

        Raises
        ------
        ValueError
            For bad frequencies, or where the dynamic stiffness is singular.
        """
        f_arr = self._frequencies(f)
        alpha = self._solve(f_arr, end_loads(self.n_dof))[:, :2, :]
        return alpha[0] if np.ndim(f) == 0 else alpha

    def bar_centre_motion(self, f: ArrayLike) -> np.ndarray:
        """Vertical displacement of each bar's centre relative to ``w1`` under an end force.

        Shows how far into the chain the end's motion reaches: a bar with a small ratio is
        barely moved by the rail it is attached to, whatever its mass.

        Parameters
        ----------
        f : float or array_like
            Frequencies (Hz), positive and finite; scalar or 1-D.

        Returns
        -------
        ndarray of complex, shape (n_f, N)
            ``w_centre_j / w1`` (-) for a vertical force at the left end of bar 1.
        """
        f_arr = self._frequencies(f)
        q = self._solve(f_arr, end_loads(self.n_dof))[:, :, 0]
        phi = q[:, 1 : self.n_bars + 1]
        left_end = q[:, :1] + np.cumsum(phi * self.L, axis=1) - phi * self.L
        return (left_end + 0.5 * self.L * phi) / q[:, :1]

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
        if not (isinstance(tol, (int, float)) and np.isfinite(tol) and tol >= 0):
            raise InputError(f"tol must be non-negative and finite, got {tol!r}")
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
        little. ``inf`` for a system without inertia.
        """
        f_max = self.highest_natural_frequency()
        return 2.0 / (2 * np.pi * f_max) if f_max > 0 else math.inf

    def __repr__(self) -> str:
        """The layout, size, each parameter on a line with its unit, and the highest natural frequency."""
        lines = [f"{type(self).__name__}: N = {self.n_bars} bars, {self.n_dof} DOFs "
                 f"({', '.join(self.dof_names()[:2])} at the attachment)"]
        for name, values in self.parameters().items():
            cells = "".join(f"{_format_value(v):>11}" for v in values)
            lines.append(f"  {name:<6} {'(' + PARAMETER_UNITS[name] + ')':<12}{cells}")
        f_max = self.highest_natural_frequency()
        f_text = f"{f_max:.0f}" if f_max >= 100 else f"{f_max:.3g}"
        lines.append(f"  highest natural frequency {f_text} Hz (central differences stable for "
                     f"dt < {1e6 * self.central_difference_time_step():.3g} µs)")
        return "\n".join(lines)


@dataclass(frozen=True, eq=False, repr=False)
class SlabEquivalent(EquivalentSystem):
    """Equivalent system of a semi-infinite slab track (paper Fig. 7, Appendix A).

    DOFs ``(w1, phi_1, ..., phi_N)`` (Eq. 21); matrices Eq. (A.16), (A.18), (A.24).

    Parameters
    ----------
    m : array_like, shape (N,)
        Bar masses (kg).
    J : array_like, shape (N,)
        Moments of inertia of the bars about their centres (kg m^2).
    L : array_like, shape (N,)
        Bar lengths (m); must be positive.
    k : array_like, shape (N,)
        Stiffness of the spring to the ground under each end of a bar (N/m).
    c_l, c_r : array_like, shape (N,)
        Dampers to the ground under the left and right end of each bar (N s/m).
    k_phi : array_like, shape (N-1,)
        Rotational stiffness between bars j and j+1 (N m/rad).
    c_phi : array_like, shape (N-1,)
        Rotational damping between bars j and j+1 (N m s/rad).

    All entries must be finite and >= 0. The arrays are stored read-only.

    Examples
    --------
    One bar on two springs: its end receptance at 100 Hz.

    >>> import semitrack as st
    >>> bar = st.SlabEquivalent(m=10.0, J=0.2, L=0.6, k=1e7, c_l=500.0, c_r=500.0, k_phi=[], c_phi=[])
    >>> bar.n_dof, bar.receptance(100.0).shape
    (2, (2, 2))
    """

    layout: ClassVar[Layout] = "slab"


@dataclass(frozen=True, eq=False, repr=False)
class BallastedEquivalent(EquivalentSystem):
    """Equivalent system of a semi-infinite ballasted track (paper Fig. 12, Appendix B).

    DOFs ``(w1, phi_1..phi_N, w_l1..w_lN, w_r1..w_rN)`` (Eq. 31); matrices Eq. (B.15),
    (B.20), (B.26).

    Parameters
    ----------
    m : array_like, shape (N,)
        Bar masses (kg).
    J : array_like, shape (N,)
        Moments of inertia of the bars about their centres (kg m^2).
    L : array_like, shape (N,)
        Bar lengths (m); must be positive.
    k : array_like, shape (N,)
        Upper spring between each bar end and its support mass (N/m).
    c_l, c_r : array_like, shape (N,)
        Upper dampers at the left and right end of each bar (N s/m).
    k_phi : array_like, shape (N-1,)
        Rotational stiffness between bars j and j+1 (N m/rad).
    c_phi : array_like, shape (N-1,)
        Rotational damping between bars j and j+1 (N m s/rad).
    mu : array_like, shape (N,)
        Support mass under each end of bar j (kg).
    s : array_like, shape (N,)
        Lower spring under each support mass (N/m).
    d_l, d_r : array_like, shape (N,)
        Lower dampers under the left and right support masses (N s/m).

    All entries must be finite and >= 0. The arrays are stored read-only.
    """

    layout: ClassVar[Layout] = "ballasted"
    _per_bar: ClassVar[tuple[str, ...]] = ("m", "J", "L", "k", "c_l", "c_r", "mu", "s", "d_l", "d_r")

    mu: np.ndarray
    s: np.ndarray
    d_l: np.ndarray
    d_r: np.ndarray

    def dof_names(self) -> list[str]:
        """Names of the degrees of freedom with units, in the order of :meth:`matrices`."""
        N = self.n_bars
        return (
            super().dof_names()
            + [f"w_l{j} (m)" for j in range(1, N + 1)]
            + [f"w_r{j} (m)" for j in range(1, N + 1)]
        )


_LAYOUTS: dict[str, type[EquivalentSystem]] = {
    SlabEquivalent.layout: SlabEquivalent,
    BallastedEquivalent.layout: BallastedEquivalent,
}
