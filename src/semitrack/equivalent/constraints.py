"""Constraint relations that tie the equivalent systems to the track's characteristic frequencies.

Slab layout (paper Sec. 4.4): each bar on its two end springs has its bouncing and pitching
frequencies both equal to ``f_n`` when (Eq. 19, 20)::

    k_j = m_j omega_n^2 / 2,        J_j = m_j L_j^2 / 4.

Ballasted layout (paper Sec. 5.2): the support mass on its upper and lower springs (upper end
held) resonates at the anti-resonance ``f_anti`` (Eq. 23), and each unit cell (paper Fig. 13)
has its two symmetric and two antisymmetric frequencies pairwise equal to ``f_n1`` and ``f_n2``
(Eq. 28-30)::

    mu_j = (k_j + s_j) / omega_anti^2,
    J_j  = m_j L_j^2 / 4,
    k_j  = m_j (omega_n1^2 + omega_n2^2 - omega_anti^2) / 2,
    s_j  = omega_n1^2 omega_n2^2 k_j / ((omega_n1^2 + omega_n2^2 - omega_anti^2) omega_anti^2
                                        - omega_n1^2 omega_n2^2).

The denominator of Eq. (30) equals ``(omega_anti^2 - omega_n1^2)(omega_n2^2 - omega_anti^2)``,
so a positive ``s_j`` needs ``f_n1 < f_anti < f_n2``. Frequencies are in Hz at this API.

:func:`unit_cell_frequencies` computes the natural frequencies of one cell by an eigenvalue
solution with its own set of coordinates (centre displacement and rotation of the bar), so that
the relations above can be checked numerically.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg
from numpy.typing import ArrayLike

from ..base.checks import as_frequencies, check_positive
from ..base.errors import InputError, InputTypeError
from .systems import (
    PARAMETER_RANGE,
    BallastedEquivalent,
    EquivalentSystem,
    SlabEquivalent,
    parameter_array,
    within_parameter_range,
)

__all__ = [
    "slab_constraints",
    "ballasted_constraints",
    "slab_from_free",
    "ballasted_from_free",
    "unit_cell_frequencies",
    "cell_frequencies",
    "support_mass_frequency",
]

_TWO_PI = 2 * np.pi


# --- The paper's relations, one function per equation ----------------------------------------
# Unchecked, broadcasting and complex-safe: the validated builders below, the fit (batched,
# complex arrays) and the consistency check of the printed tables all evaluate these.
def _omega2(f):
    return (_TWO_PI * f) ** 2


def inertia_relation(m, L):
    """J = m L^2 / 4 (Eq. 20 and 28), kg m^2."""
    return 0.25 * m * L**2


def slab_spring_relation(m, f_n):
    """k = m omega_n^2 / 2 (Eq. 19), N/m."""
    return 0.5 * m * _omega2(f_n)


def upper_spring_relation(m, f_n1, f_n2, f_anti):
    """k = m (omega_n1^2 + omega_n2^2 - omega_anti^2) / 2 (Eq. 29), N/m."""
    return 0.5 * m * (_omega2(f_n1) + _omega2(f_n2) - _omega2(f_anti))


def lower_spring_relation(k, f_n1, f_n2, f_anti):
    """s = w1 w2 k / ((w1 + w2 - wa) wa - w1 w2) with w = omega^2 (Eq. 30), N/m."""
    w1, w2, wa = _omega2(f_n1), _omega2(f_n2), _omega2(f_anti)
    return w1 * w2 * k / ((w1 + w2 - wa) * wa - w1 * w2)


def support_mass_relation(k, s, f_anti):
    """mu = (k + s) / omega_anti^2 (Eq. 23), kg."""
    return (k + s) / _omega2(f_anti)


def slab_constraints(m: ArrayLike, L: ArrayLike, f_n: float) -> dict[str, np.ndarray]:
    """Spring stiffness and inertia of the slab layout from Eq. (19) and (20).

    Parameters
    ----------
    m, L : array_like, shape (N,)
        Bar masses (kg) and lengths (m).
    f_n : float
        The repeated natural frequency of every bar on its end springs (Hz).

    Returns
    -------
    dict
        ``{"k": k (N/m), "J": J (kg m^2)}``.
    """
    m = parameter_array("m", m)
    L = parameter_array("L", L, positive=True)
    _same_length(m=m, L=L)
    f_n = check_positive("f_n", f_n)
    return _derived({"k": slab_spring_relation(m, f_n), "J": inertia_relation(m, L)}, "m, L and f_n")


def ballasted_constraints(m: ArrayLike, L: ArrayLike, f_n1: float, f_n2: float, f_anti: float) -> dict[str, np.ndarray]:
    """Stiffnesses, inertia and support masses of the ballasted layout, Eq. (23), (28)-(30).

    Parameters
    ----------
    m, L : array_like, shape (N,)
        Bar masses (kg) and lengths (m).
    f_n1, f_n2 : float
        The two repeated natural frequencies of each unit cell (Hz).
    f_anti : float
        Natural frequency of a support mass on its upper and lower springs (Hz); must lie
        strictly between ``f_n1`` and ``f_n2`` for ``s`` to be positive.

    Returns
    -------
    dict
        ``{"k": (N/m), "J": (kg m^2), "s": (N/m), "mu": (kg)}``.
    """
    m = parameter_array("m", m)
    L = parameter_array("L", L, positive=True)
    _same_length(m=m, L=L)
    for name, value in (("f_n1", f_n1), ("f_n2", f_n2), ("f_anti", f_anti)):
        check_positive(name, value)
    if not (f_n1 < f_anti < f_n2):
        raise InputError(
            f"f_anti must lie strictly between f_n1 and f_n2 (Eq. 30 gives s > 0 only then), "
            f"got f_n1={f_n1!r}, f_anti={f_anti!r}, f_n2={f_n2!r} Hz"
        )
    k = upper_spring_relation(m, f_n1, f_n2, f_anti)  # > 0 because f_n2 > f_anti
    s = lower_spring_relation(k, f_n1, f_n2, f_anti)
    return _derived({"k": k, "J": inertia_relation(m, L), "s": s, "mu": support_mass_relation(k, s, f_anti)},
                    "m, L, f_n1, f_n2 and f_anti")


def _derived(values: dict[str, np.ndarray], inputs: str) -> dict[str, np.ndarray]:
    """The derived parameters, refused (naming the ``inputs`` that gave them) where a system could not hold them."""
    lo, hi = PARAMETER_RANGE
    for name, arr in values.items():
        bad = np.flatnonzero(~within_parameter_range(arr))
        if bad.size:
            i = int(bad[0])
            raise InputError(f"{inputs} give {name}[{i}] = {float(arr[i])!r}, outside {lo:g} to {hi:g} (SI units: "
                             "beyond, the assembled matrices over- or underflow)")
    return values


def _frequency(name: str, value: object) -> float:
    """One characteristic frequency (Hz): a real number, positive, at most the package's highest."""
    return float(as_frequencies(check_positive(name, value), name))


def slab_from_free(m: ArrayLike, L: ArrayLike, c_l: ArrayLike, c_r: ArrayLike, k_phi: ArrayLike,
                   c_phi: ArrayLike, f_n: float) -> SlabEquivalent:
    """A :class:`SlabEquivalent` whose ``k`` and ``J`` follow Eq. (19)-(20) at ``f_n``.

    The free parameters are the 6N - 2 of the paper's fit.

    Parameters
    ----------
    m : array_like, shape (N,)
        Bar masses (kg).
    L : array_like, shape (N,)
        Bar lengths (m), positive.
    c_l, c_r : array_like, shape (N,)
        Dampers to the ground under the left and right end of each bar (N s/m).
    k_phi : array_like, shape (N-1,)
        Rotational stiffness between bars j and j+1 (N m/rad).
    c_phi : array_like, shape (N-1,)
        Rotational damping between bars j and j+1 (N m s/rad).
    f_n : float
        The repeated natural frequency of every bar on its end springs (Hz).

    Returns
    -------
    SlabEquivalent
        With ``k = m omega_n^2 / 2`` (N/m) and ``J = m L^2 / 4`` (kg m^2).

    Examples
    --------
    >>> import semitrack as st
    >>> bar = st.slab_from_free(m=[10.0], L=[0.5], c_l=[0.0], c_r=[0.0], k_phi=[], c_phi=[], f_n=100.0)
    >>> st.cell_frequencies(bar).round(6)
    array([[100., 100.]])
    """
    f_n = _frequency("f_n", f_n)
    derived = slab_constraints(m, L, f_n)
    return SlabEquivalent(m=m, J=derived["J"], L=L, k=derived["k"], c_l=c_l, c_r=c_r,
                          k_phi=k_phi, c_phi=c_phi)


def ballasted_from_free(m: ArrayLike, L: ArrayLike, c_l: ArrayLike, c_r: ArrayLike, k_phi: ArrayLike,
                        c_phi: ArrayLike, d_l: ArrayLike, d_r: ArrayLike,
                        f_n1: float, f_n2: float, f_anti: float) -> BallastedEquivalent:
    """A :class:`BallastedEquivalent` whose ``k, J, s, mu`` follow Eq. (23), (28)-(30).

    The free parameters are the 8N - 2 of the paper's fit.

    Parameters
    ----------
    m : array_like, shape (N,)
        Bar masses (kg).
    L : array_like, shape (N,)
        Bar lengths (m), positive.
    c_l, c_r : array_like, shape (N,)
        Upper dampers at the left and right end of each bar (N s/m).
    k_phi : array_like, shape (N-1,)
        Rotational stiffness between bars j and j+1 (N m/rad).
    c_phi : array_like, shape (N-1,)
        Rotational damping between bars j and j+1 (N m s/rad).
    d_l, d_r : array_like, shape (N,)
        Lower dampers under the left and right support masses (N s/m).
    f_n1, f_n2 : float
        The two repeated natural frequencies of each unit cell (Hz).
    f_anti : float
        Natural frequency of a support mass between its springs (Hz), strictly between
        ``f_n1`` and ``f_n2``.

    Returns
    -------
    BallastedEquivalent
        With ``k`` (N/m), ``J`` (kg m^2), ``s`` (N/m) and ``mu`` (kg) from
        :func:`ballasted_constraints`.

    Examples
    --------
    >>> import semitrack as st
    >>> bar = st.ballasted_from_free([20.0], [0.4], [0.0], [0.0], [], [], [0.0], [0.0],
    ...                              f_n1=117.0, f_n2=465.0, f_anti=243.0)
    >>> st.cell_frequencies(bar).round(6)
    array([[117., 117., 465., 465.]])
    """
    f_n1, f_n2, f_anti = (_frequency(name, v) for name, v in (("f_n1", f_n1), ("f_n2", f_n2), ("f_anti", f_anti)))
    derived = ballasted_constraints(m, L, f_n1, f_n2, f_anti)
    return BallastedEquivalent(m=m, J=derived["J"], L=L, k=derived["k"], c_l=c_l, c_r=c_r,
                               k_phi=k_phi, c_phi=c_phi, mu=derived["mu"], s=derived["s"],
                               d_l=d_l, d_r=d_r)


def support_mass_frequency(k: ArrayLike, s: ArrayLike, mu: ArrayLike) -> np.ndarray:
    """Natural frequency ``sqrt((k + s) / mu) / (2 pi)`` of a support mass with the upper end held.

    Eq. (23) sets it to ``f_anti``.

    Parameters
    ----------
    k : array_like, shape (N,)
        Upper springs (N/m).
    s : array_like, shape (N,)
        Lower springs (N/m).
    mu : array_like, shape (N,)
        Support masses (kg), positive.

    Returns
    -------
    ndarray, shape (N,)
        Frequencies (Hz).
    """
    k = parameter_array("k", k)
    s = parameter_array("s", s)
    mu = parameter_array("mu", mu, positive=True)
    return np.sqrt((k + s) / mu) / _TWO_PI


def _in_range(name: str, value: float) -> float:
    """A bar's parameter within :data:`PARAMETER_RANGE` (SI units): beyond it the eigenproblem over- or underflows."""
    if not within_parameter_range(value):  # the bars' one predicate (positive values only reach here)
        lo, hi = PARAMETER_RANGE
        raise InputError(f"{name} must be from {lo:g} to {hi:g} (SI units, a bar of an equivalent system), "
                         f"got {value!r}")
    return value


def unit_cell_frequencies(m: float, J: float, L: float, k: float,
                          mu: float | None = None, s: float | None = None) -> np.ndarray:
    """Undamped natural frequencies of one unit cell (paper Fig. 13).

    The cell is one rigid bar with a spring under each end. Without ``mu``/``s`` the springs
    go to the ground (slab layout, 2 frequencies); with them, each spring rests on a support
    mass on a lower spring (ballasted layout, 4 frequencies). Coordinates are the centre
    displacement and rotation of the bar (and the two support masses), not the end
    coordinates of Eq. (21)/(31), so that the constraint relations are checked independently.

    Parameters
    ----------
    m : float
        Bar mass (kg), positive.
    J : float
        Moment of inertia of the bar about its centre (kg m^2), positive.
    L : float
        Bar length (m), positive.
    k : float
        Spring under each end of the bar (N/m), positive.
    mu : float, optional
        Support mass under each end (kg), positive; goes with ``s``.
    s : float, optional
        Lower spring under each support mass (N/m), positive; goes with ``mu``.

    Returns
    -------
    ndarray, shape (2,) or (4,)
        Natural frequencies (Hz), ascending.

    Examples
    --------
    A bar on two springs: bounce ``sqrt(2 k / m)`` and pitch ``sqrt(k L^2 / (2 J))`` rad/s.

    >>> import semitrack as st
    >>> st.unit_cell_frequencies(m=10.0, J=0.1, L=0.4, k=1e7).round(2)
    array([225.08, 450.16])
    """
    m, J, L, k = (_in_range(name, check_positive(name, v)) for name, v in (("m", m), ("J", J), ("L", L), ("k", k)))
    h = 0.5 * L
    if (mu is None) != (s is None):
        raise InputError(f"mu and s go together (ballasted cell) or are both omitted, got mu={mu!r}, s={s!r}")
    if mu is None:
        M = np.diag([m, J])
        ends = np.array([[1.0, -h], [1.0, h]])  # left and right end displacements
        K = k * ends.T @ ends
    else:
        mu, s = _in_range("mu", check_positive("mu", mu)), _in_range("s", check_positive("s", s))
        M = np.diag([m, J, mu, mu])
        upper = np.array([[1.0, -h, -1.0, 0.0], [1.0, h, 0.0, -1.0]])  # end minus support mass
        lower = np.array([[0.0, 0.0, 1.0, 0.0], [0.0, 0.0, 0.0, 1.0]])
        K = k * upper.T @ upper + s * lower.T @ lower
    lam = scipy.linalg.eigh(K, M, eigvals_only=True)
    return np.sqrt(np.clip(lam, 0.0, None)) / _TWO_PI


def cell_frequencies(system: EquivalentSystem) -> np.ndarray:
    """Natural frequencies of every unit cell of a system (:func:`unit_cell_frequencies`).

    Parameters
    ----------
    system : SlabEquivalent or BallastedEquivalent
        The system; cell j is bar j with its springs (and support masses).

    Returns
    -------
    ndarray, shape (N, 2) slab or (N, 4) ballasted
        Frequencies (Hz), ascending per row; rows of bars whose cell is degenerate (a zero
        mass, inertia, spring or support mass, such as the massless bars of Table 4) are NaN.
    """
    if not isinstance(system, EquivalentSystem):
        raise InputTypeError(f"system must be an EquivalentSystem, got {type(system).__name__}")
    ballasted = isinstance(system, BallastedEquivalent)
    out = np.full((system.n_bars, 4 if ballasted else 2), np.nan)
    for j in range(system.n_bars):
        args = [system.m[j], system.J[j], system.L[j], system.k[j]]
        if ballasted:
            args += [system.mu[j], system.s[j]]
        if min(args) > 0:
            out[j] = unit_cell_frequencies(*args)
    return out


def _same_length(**arrays: np.ndarray) -> None:
    sizes = {name: a.size for name, a in arrays.items()}
    if len(set(sizes.values())) > 1:
        raise InputError(f"per-bar parameters must have the same length, got lengths {sizes}")
