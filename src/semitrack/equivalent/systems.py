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
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np
from numpy.typing import ArrayLike

from ..base.errors import InputError, InputTypeError
from .assembly import Layout, assembly, end_loads
from .mechanical import SYMMETRY_RTOL, MechanicalSystem, PassivityReport, undamped_natural_frequencies

__all__ = [
    "EquivalentSystem",
    "SlabEquivalent",
    "BallastedEquivalent",
    "PassivityReport",
    "undamped_natural_frequencies",
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


#: The magnitudes a bar's parameter may have (SI units, zero aside): far around every fitted system
#: (masses of 1-1e3 kg, stiffnesses of 1e5-1e10 N/m, dampers of 1e2-1e6 N s/m); at 1e308 the
#: assembled matrices' eigen-solves failed, and m omega^2 overflowed into the derived springs.
PARAMETER_RANGE = (1e-12, 1e18)


def within_parameter_range(value: ArrayLike) -> np.ndarray:
    """Where ``value`` is finite and zero or of a magnitude within :data:`PARAMETER_RANGE` (elementwise)."""
    a = np.abs(np.asarray(value, dtype=float))
    return np.isfinite(a) & ((a == 0) | ((a >= PARAMETER_RANGE[0]) & (a <= PARAMETER_RANGE[1])))


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
        if not within_parameter_range(v):
            raise InputError(f"{name}[{i}] must be from {PARAMETER_RANGE[0]:g} to {PARAMETER_RANGE[1]:g} (SI units: "
                             f"beyond, the assembled matrices over- or underflow), got {float(v)!r}")
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
    if asym > SYMMETRY_RTOL * max(scale, np.finfo(float).tiny):
        raise RuntimeError(f"assembled {name} matrix is not symmetric: max |{name} - {name}^T| = {asym:.3e}")
    S = 0.5 * (X + X.T)
    S.setflags(write=False)
    return S


def _format_value(x: float) -> str:
    """A parameter value in a short form: 4 significant digits, 0 as 0."""
    return "0" if x == 0 else f"{x:.4g}"


@dataclass(frozen=True, eq=False)
class EquivalentSystem(MechanicalSystem):
    """Common base of the two layouts; not meant to be instantiated itself.

    A :class:`~.mechanical.MechanicalSystem`: its receptance, passivity and natural frequencies
    follow from :meth:`matrices`, DOFs ``(w1, phi_1, ...)``, the ports first.

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

    @property
    def kind(self) -> str:
        """How messages call the system: its layout."""
        return self.layout

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
