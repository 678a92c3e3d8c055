"""Receptance at the end of a semi-infinite periodic track (paper Sec. 3, Eq. 13-18).

Public entry points: :func:`central_response`, :func:`semi_infinite_receptance` and
:func:`point_receptance`. Frequencies are in Hz; every result is vectorised over frequency.

The central responses are those of the infinite track at the central cross-section x0 (a
mid-span), just to the right of the load: for a unit force, w1 and the bending moment M1; for a
unit moment, psi2 and the shear force Q2. With them (Eq. 14)

    alpha = 1 / (0.25 - M1 Q2) [[0.5 w1, -w1 Q2], [-psi2 M1, 0.5 psi2]]

and det(alpha^-1) = (0.25 - M1 Q2) / (w1 psi2) (Eq. 18).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from typing import Literal, get_args

import numpy as np
from numpy.typing import ArrayLike

from ..base.checks import as_frequencies, check_choice, check_real, check_work
from ..base.errors import InputError, InputTypeError
from ..base.fields import check_fields
from ..model.tracks import PeriodicCell, Track, require_cell
from .transfer import end_stiffness, infinite_response, same_section, slab_cut_end_stiffness
from .wavenumber import WavenumberSettings, central_quantities

#: The two ways to compute the receptance: the exact periodic-structure method and the paper's.
Method = Literal["transfer", "wavenumber"]
METHODS: tuple[str, ...] = get_args(Method)


@dataclass(frozen=True)
class CentralResponse:
    """Responses of the infinite track at the central cross-section (paper Eq. 14-18).

    Attributes
    ----------
    f : ndarray
        Frequencies (Hz).
    w1 : ndarray
        Vertical displacement per unit vertical force (m/N).
    psi2 : ndarray
        Rotation per unit moment (rad/(N m)).
    Q2 : ndarray
        Shear force on the section just right of the load per unit moment (N/(N m)).
    M1 : ndarray
        Bending moment on that section per unit force (N m/N).
    method : {"transfer", "wavenumber"}
        The method that computed them.
    separable : bool
        False where a flexible slab runs through the central cross-section: the two halves then
        also meet through the slab, and Eq. (14) and (18), which presume they meet through the
        rail alone, do not hold (:attr:`alpha` and :attr:`det` refuse).

    Examples
    --------
    >>> import semitrack as st
    >>> r = st.central_response(st.slab_track(), [100.0, 200.0])
    >>> r.w1.shape, r.alpha.shape
    ((2,), (2, 2, 2))
    """

    f: np.ndarray
    w1: np.ndarray
    psi2: np.ndarray
    Q2: np.ndarray
    M1: np.ndarray
    method: str
    separable: bool = True

    def __post_init__(self):
        check_fields(self)  # a record built by hand is refused here, not in a method

    def _require_separable(self, what: str) -> None:
        if not self.separable:
            raise InputError(
                f"{what} presumes that the two halves of the track meet through the rail alone; a flexible "
                "slab runs through this cut (their Eq. 14 alpha is not even reciprocal). Use "
                "semi_infinite_receptance, which cuts the slab there too")

    @property
    def det(self) -> np.ndarray:
        """det(alpha^-1), Eq. (18) (N^2)."""
        self._require_separable("Eq. (18)")
        return (0.25 - self.M1 * self.Q2) / (self.w1 * self.psi2)

    @property
    def alpha(self) -> np.ndarray:
        """Receptance of the semi-infinite track by Eq. (14), shape ``(n, 2, 2)``."""
        self._require_separable("Eq. (14)")
        scale = 1.0 / (0.25 - self.M1 * self.Q2)
        a = np.empty(self.w1.shape + (2, 2), dtype=complex)
        a[..., 0, 0] = 0.5 * self.w1 * scale
        a[..., 0, 1] = -self.w1 * self.Q2 * scale
        a[..., 1, 0] = -self.psi2 * self.M1 * scale
        a[..., 1, 1] = 0.5 * self.psi2 * scale
        return a


def _settings(method: str, options: dict) -> WavenumberSettings | None:
    check_choice("method", method, METHODS)
    if method == "transfer":
        if options:
            raise InputTypeError(f"method='transfer' takes no discretisation settings, got {sorted(options)}")
        return None
    allowed = {"beta_max", "dbeta", "j_max", "dx", "settings"}
    unknown = sorted(set(options) - allowed)
    if unknown:
        raise InputTypeError(f"unknown wavenumber setting(s) {unknown}; allowed: {sorted(allowed)}")
    if "settings" in options:
        base = options.pop("settings")
        if not isinstance(base, WavenumberSettings):
            raise InputTypeError(f"settings must be a WavenumberSettings, got {type(base).__name__}")
        return WavenumberSettings(**{**base.__dict__, **options})
    return WavenumberSettings(**options)


#: Most frequencies x supports per period of one call: a flexible slab's S fasteners make each
#: frequency far dearer (measured 0.05-0.5 s per frequency for S = 200 on a busy 2-core machine,
#: 0.1 ms for one support: 3-3000 Hz at df = 0.015 Hz on 200 fasteners would take hours), so
#: 200 fasteners take 1000 frequencies (about a minute), one support the 200 000 of
#: :data:`~semitrack.base.checks.MAX_FREQUENCIES`.
MAX_FREQUENCY_SUPPORTS = 200_000
#: Memory of one block of frequencies evaluated at once (bytes); a frequency takes ~200 S^2 bytes
#: at least (measured: 1.6 GiB for 200 frequencies of a 200-fastener slab in one block, 845 MiB
#: for 37 at 3-300 Hz, 165 MiB in blocks of 12, this budget's).
BLOCK_BYTES = 100_000_000


def check_frequency_work(cell: PeriodicCell, n_frequencies: float, request: str = "f") -> int:
    """Refuse evaluating the exact method at more frequencies x supports than :data:`MAX_FREQUENCY_SUPPORTS`.

    Parameters
    ----------
    cell : PeriodicCell
        The track's period.
    n_frequencies : float
        Frequencies to evaluate (with any refinements counted).
    request : str
        What asked for them, naming the parameters (e.g. ``"f"`` or ``"band and df"``).

    Returns
    -------
    int
        The supports per period.
    """
    s = len(cell.positions)
    check_work(n_frequencies * s, MAX_FREQUENCY_SUPPORTS, f"{request} gives {n_frequencies:.0f} frequencies x {s} "
               f"supports per period = {n_frequencies * s:.0f}", "use fewer frequencies (a larger df, a narrower "
               "band) or a slab with fewer fasteners")
    return s


def frequency_blocks(cell: PeriodicCell, f: np.ndarray, name: str = "f") -> list[np.ndarray]:
    """The frequencies of one call in blocks that bound its memory, after the check of its work.

    Parameters
    ----------
    cell : PeriodicCell
        The track's period (its supports set the cost of a frequency).
    f : ndarray
        The frequencies (Hz), checked.
    name : str
        What gave them, for the message (:func:`check_frequency_work`).

    Returns
    -------
    list of ndarray
        Consecutive blocks of ``f.ravel()``; one block unless the cell has many supports.

    Raises
    ------
    InputError
        When frequencies x supports exceed :data:`MAX_FREQUENCY_SUPPORTS`.
    """
    s = check_frequency_work(cell, f.size, name)
    size = max(1, BLOCK_BYTES // (200 * s * s))
    flat = f.ravel()
    return [flat[i:i + size] for i in range(0, flat.size, size)]


def central_response(track: Track | PeriodicCell, f: ArrayLike, method: Method = "transfer",
                     **settings) -> CentralResponse:
    """Central responses w1, psi2, Q2, M1 of the infinite track (paper Eq. 14-16).

    Parameters
    ----------
    track : Track or PeriodicCell
        The track; a :class:`PeriodicCell` allows several supports per period.
    f : array_like
        Frequencies (Hz), positive and finite.
    method : {"transfer", "wavenumber"}
        "transfer" (default) is exact; "wavenumber" is the paper's Eq. (12) with the
        finite-difference slopes of Sec. 4.1.
    **settings
        For "wavenumber" only: ``beta_max`` (rad/m), ``dbeta`` (rad/m), ``j_max``, ``dx`` (m), or
        ``settings=WavenumberSettings(...)``. Defaults are the paper's.

    Returns
    -------
    CentralResponse
        Arrays of the same shape as ``f``.

    Examples
    --------
    The bouncing resonance of the slab track shows in w1 (m/N):

    >>> import semitrack as st
    >>> r = st.central_response(st.slab_track(), [100.0, 186.0, 300.0])
    >>> bool(abs(r.w1[1]) > abs(r.w1[0]) and abs(r.w1[1]) > abs(r.w1[2]))
    True
    """
    f = as_frequencies(f)
    cell = require_cell(track)
    blocks = frequency_blocks(cell, f)
    if len(blocks) > 1:
        parts = [central_response(cell, block, method, **settings) for block in blocks]
        joined = {name: np.concatenate([getattr(p, name) for p in parts]).reshape(f.shape)
                  for name in ("w1", "psi2", "Q2", "M1")}
        return CentralResponse(f=f, method=method, separable=parts[0].separable, **joined)
    ws = _settings(method, dict(settings))
    x0 = cell.central_section
    if not cell.is_symmetric_about(x0):
        # Eq. (14) uses psi1 = w2 = 0 and Q1 = M2 = 0.5 at the cut: true only at a mirror plane.
        raise InputError(
            f"the central responses and Eq. (14) need a cell that is symmetric about its central "
            f"cross-section x = {x0}; supports at {cell.positions} in a period of {cell.period} are not. "
            "semi_infinite_receptance(..., method='transfer') handles any cell without a coupled foundation"
        )
    omega = 2 * np.pi * f.ravel()
    if ws is None:
        h, loads = infinite_response(cell, omega, x0)  # loads on the right part per unit force, moment
        w1, psi2 = h[:, 0, 0], h[:, 1, 1]
        m1, q2 = loads[:, 1, 0], loads[:, 0, 1]
    else:
        w1, psi2, q2, m1 = central_quantities(cell, omega, ws)
    shape = f.shape
    return CentralResponse(f=f, w1=w1.reshape(shape), psi2=psi2.reshape(shape), Q2=q2.reshape(shape),
                           M1=m1.reshape(shape), method=method, separable=_separable(cell, f))


def _separable(cell: PeriodicCell, f: np.ndarray) -> bool:
    """True when the cut splits the track into two structures joined by the rail alone."""
    return cell.has_uncoupled_supports(f.ravel()[:1]) or same_section(cell.central_section, cell.joint, cell.period)


def semi_infinite_receptance(track: Track | PeriodicCell, f: ArrayLike, method: Method = "transfer",
                             **settings) -> np.ndarray:
    """2x2 receptance alpha at the end of the semi-infinite track (paper Eq. 13).

    The track is cut at a mid-span (the central cross-section; for a flexible slab, the slab joint
    or centre as ``slab.cut`` says). ``alpha[..., i, k]`` is response i (0: w, downward, m;
    1: psi, clockwise, rad) per end load k (0: force Q, downward, N; 1: moment M, clockwise, N m).

    Inside a flexible slab (``slab.cut`` not "joint") the slab is cut too: alpha is that of the
    semi-infinite track whose first slab starts, free, at the cut (exact method only; the
    paper's Eq. 14 presumes halves joined by the rail alone, so the wavenumber method refuses).

    Parameters
    ----------
    track : Track or PeriodicCell
        The track.
    f : array_like
        Frequencies (Hz), positive and finite.
    method : {"transfer", "wavenumber"}
        "transfer" (default): exact Bloch-wave method. "wavenumber": the paper's method, Eq. (14)
        from the central responses of Eq. (12).
    **settings
        Wavenumber settings, see :func:`central_response`.

    Returns
    -------
    ndarray of complex, shape ``f.shape + (2, 2)``
        Units :data:`semitrack.base.conventions.ELEMENT_UNITS`: [[m/N, 1/N], [1/N, rad/(N m)]].

    Examples
    --------
    >>> import semitrack as st
    >>> alpha = st.semi_infinite_receptance(st.slab_track(), [3.0, 183.0])
    >>> alpha.shape
    (2, 2, 2)
    >>> bool(np.allclose(alpha[:, 0, 1], alpha[:, 1, 0]))  # reciprocity: alpha12 = alpha21
    True
    """
    f = as_frequencies(f)
    cell = require_cell(track)
    check_choice("method", method, METHODS)  # before any comparison: an array is never one
    blocks = frequency_blocks(cell, f)
    if len(blocks) > 1:
        parts = [semi_infinite_receptance(cell, block, method, **settings) for block in blocks]
        return np.concatenate(parts).reshape(f.shape + (2, 2))
    omega = 2 * np.pi * f.ravel()
    if _separable(cell, f):
        if method == "wavenumber":
            return central_response(cell, f, method, **settings).alpha
        _settings(method, dict(settings))
        k_right, _ = end_stiffness(cell, omega, cell.central_section)
    elif cell.track.has_flexible_slab and cell.foundation is not None:
        if method != "transfer":
            raise InputError("inside a flexible slab alpha is that of the track with its slab cut at the cut, "
                             "which the paper's Eq. (14) cannot give: use method='transfer' or slab cut='joint'")
        _settings(method, dict(settings))
        k_right = slab_cut_end_stiffness(cell, omega)
    else:
        raise InputError(f"the foundation of this cell couples supports across its central cross-section "
                         f"x = {cell.central_section:g} m, so the track does not end there; cut at its joint "
                         f"x = {cell.joint:g} m (PeriodicCell(..., cut=...))")
    return np.linalg.inv(k_right).reshape(f.shape + (2, 2))


#: Where positions are measured from: the package's one origin, or the paper's Sec. 4 one (an explicit choice).
ORIGINS = ("midspan", "support")


def position_origin(origin: str | None, where: str) -> str:
    """``origin`` checked, or ``"midspan"`` with a :class:`FutureWarning` when it is left out (until 0.3).

    Parameters
    ----------
    origin : {"midspan", "support"} or None
        As given by the caller.
    where : str
        The function, for the messages.

    Returns
    -------
    str
    """
    if origin is None:
        warnings.warn(f"{where}: x is measured from a mid-span since semitrack 0.2, as everywhere in the package "
                      "(it was measured from a support before); pass origin='midspan' to say so, or "
                      "origin='support' for the paper's origin. The warning goes in 0.3", FutureWarning, stacklevel=3)
        return "midspan"
    return check_choice("origin", origin, ORIGINS)


def point_receptance(track: Track | PeriodicCell, f: ArrayLike, x: float = 0.0, *, origin: str | None = None
                     ) -> np.ndarray:
    """2x2 receptance of the infinite periodic track at position ``x`` (exact method).

    Parameters
    ----------
    track : Track or PeriodicCell
        The track.
    f : array_like
        Frequencies (Hz).
    x : float
        Position of load and response (m); any finite value within 1e9 periods of the origin, the
        track being periodic.
    origin : {"midspan", "support"}
        Where ``x`` is measured from. ``"midspan"``: the package's one origin, the central mid-span
        of the FE models and :class:`semitrack.InfiniteTrack` (supports at ``(k + 1/2) d``; on a
        flexible slab a slab joint). ``"support"``: the paper's Sec. 4 origin, over a support
        (``x = d / 2`` is then a mid-span). Until 0.2 ``x`` was measured from a support; left out,
        it is measured from a mid-span with a :class:`FutureWarning` (until 0.3) saying so.

    Returns
    -------
    ndarray of complex, shape ``f.shape + (2, 2)``
        Response (w, psi) per load (F, M) at the same point, units as for
        :func:`semi_infinite_receptance`.

    Examples
    --------
    Over a support the rail is stiffer than at mid-span (0.325 m on the slab track):

    >>> import semitrack as st
    >>> track = st.slab_track()
    >>> over, mid = (abs(st.point_receptance(track, 50.0, x, origin="midspan")[0, 0]) for x in (0.325, 0.0))
    >>> bool(over < mid)
    True
    """
    f = as_frequencies(f)
    cell = require_cell(track)
    x = check_real("x", x)
    # Beyond 1e9 periods a double cannot place x within the period to better than ~1e-7 of it.
    if not abs(x) <= 1e9 * cell.period:
        raise InputError(f"x must be finite and within 1e9 periods ({1e9 * cell.period:.3g} m) of the "
                         f"origin, got {x!r}: the track is periodic, give x modulo the period")
    # the cell's own frame has its first support at positions[0]; the mid-span origin is the joint before it
    x = (x + (cell.joint if position_origin(origin, "point_receptance") == "midspan" else 0.0)) % cell.period
    parts = [infinite_response(cell, 2 * np.pi * block, x)[0] for block in frequency_blocks(cell, f)]
    return np.concatenate(parts).reshape(f.shape + (2, 2))
