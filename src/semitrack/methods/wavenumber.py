"""The paper's method (Sec. 2.4 and 4.1): responses of the infinite periodic track by Eq. (12).

The rail displacement q = (w, psi) at a distance x' from a harmonic load p0 at x0 is

    q(x') = (1/2pi) int D(beta)^-1 e^{i beta x'} dbeta p0
            - sum_j (1/(2pi L)) e^{-i 2pi j (x'+x0)/L}
                    int D(beta_j)^-1 C(beta_j) A(beta)^-1 B(beta) D(beta)^-1 e^{i beta x'} dbeta p0

with beta_j = beta - 2 pi j / L, C, B of Eq. (7)-(8) and A(beta) of Eq. (10). As in the paper the
integrals are Riemann sums over beta in [-beta_max, beta_max) with step dbeta and the sum over j
is truncated at |j| <= j_max. The support receptance H_rs of Eq. (3) enters A as
``A^-1 = K (I + R K)^-1`` with K = H^-1 the support stiffness, which stays finite for kphi = 0.

The central responses of Eq. (14)-(16) need dpsi_1/dx and dw_2/dx at the load. The paper fits the
odd fields by a x + b x^3 through the samples at dx and 2 dx, giving the slope (8 y1 - y2)/(6 dx).
The fields have a kink in their slope at the load (Table 1), so this estimate is only first-order
accurate in dx; together with the truncated beta range this is what limits the accuracy of the
paper's numbers (see :mod:`semitrack.methods.transfer` for the exact method).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ..base.checks import check_in_range, check_int_at_least, check_positive, check_work
from ..base.errors import InputError

# The paper's settings (Sec. 4.1), kept importable from here as well.
from ..base.paper_values import PAPER_BETA_MAX, PAPER_DBETA, PAPER_DX, PAPER_J_MAX
from ..base.threads import serial_blas
from ..model.timoshenko import operator_inverse
from ..model.tracks import PeriodicCell

__all__ = ["PAPER_BETA_MAX", "PAPER_DBETA", "PAPER_DX", "PAPER_J_MAX", "WavenumberSettings", "central_quantities",
           "displacement_fields", "odd_slope"]


#: Most terms (2 j_max + 1) x (2 beta_max / dbeta) of Eq. (12) per frequency (the paper's settings
#: use 4.1e5). Memory is bounded by summing the wavenumbers in blocks; the limit is one of time:
#: ~1e-7 s per term with one support per period, ~1e-6 s with ten (a flexible slab), so 1e8 terms
#: take from 10 s to ~2 min per frequency.
MAX_TERMS_PER_FREQUENCY = 100_000_000
#: Most periods summed each side (the paper's 20; the work guard counts the terms they make).
MAX_J = 100_000
#: Largest step of the rail's fields (m), twice the paper's 0.04 m: from 0.1 m on the method's receptance of the
#: paper's tracks is no longer passive (Im alpha11 > 0 at 50-400 Hz, measured), whatever the other settings.
MAX_DX = 0.08
#: Smallest step (m): below it the finite-difference slope loses its digits to the fields' rounding (measured on the
#: slab track against the exact receptance: 4 % at 0.1 mm as at 1 mm, 25 % at 1 um, 100 % at 1 nm, NaN at 1e-308).
MIN_DX = 1e-4
#: Most terms per call, over all frequencies (~1.4e7 terms/s on one core: 1e10 ~ 12 min).
MAX_TERMS = 10_000_000_000
#: Most supports per period, squared: the method's per-frequency arrays grow with it, not with the
#: terms (summed in blocks of ~6 MB), measured at the paper's settings: 118 MiB for 10 fasteners
#: per slab, 594 MiB for 40 (0.37 MiB per support squared), so 50 stay under ~1 GB; 200
#: allocated GiBs. The refined settings (6e7 terms) on 10 fasteners run in ~15 s a frequency.
MAX_SUPPORTS_SQUARED = 2_500

@dataclass(frozen=True)
class WavenumberSettings:
    """Discretisation of Eq. (12); the defaults are the paper's (Sec. 4.1).

    The defaults are :data:`semitrack.base.paper_values.PAPER_BETA_MAX` (78.5 rad/m),
    ``PAPER_DBETA`` (2 pi x 0.0025 rad/m), ``PAPER_J_MAX`` (20) and ``PAPER_DX`` (0.04 m).

    Parameters
    ----------
    beta_max : float
        Half-width of the wavenumber range (rad/m); the grid is [-beta_max, beta_max).
    dbeta : float
        Wavenumber step (rad/m). Responses repeat with period 2 pi / dbeta in x.
    j_max : int
        The sum over j runs from -j_max to j_max.
    dx : float
        Step of the finite-difference slope (8 y1 - y2) / (6 dx) (m), from :data:`MIN_DX` (0.1 mm)
        to :data:`MAX_DX` (0.08 m).
    """

    beta_max: float = PAPER_BETA_MAX
    dbeta: float = PAPER_DBETA
    j_max: int = PAPER_J_MAX
    dx: float = PAPER_DX

    def __post_init__(self):
        # held as plain floats and an int: 2**64 given for beta_max must not stay a Python int numpy reads as an object
        object.__setattr__(self, "beta_max", check_positive("beta_max", self.beta_max))
        object.__setattr__(self, "dbeta", check_positive("dbeta", self.dbeta))
        j_max = check_int_at_least("j_max", self.j_max, 0)
        if j_max > MAX_J:
            raise InputError(f"j_max must be at most {MAX_J} (periods each side), got {j_max!r}")
        object.__setattr__(self, "j_max", j_max)
        dx = check_in_range("dx", check_positive("dx", self.dx), (MIN_DX, MAX_DX), "m, the step of the rail's fields")
        object.__setattr__(self, "dx", dx)
        if self.beta_max / self.dbeta > MAX_TERMS_PER_FREQUENCY:  # its grid could not be counted, let alone made
            raise InputError(f"beta_max/dbeta = {self.beta_max!r}/{self.dbeta!r} gives more than "
                             f"{MAX_TERMS_PER_FREQUENCY} wavenumbers: use a larger dbeta or a smaller beta_max")
        if self.dbeta >= self.beta_max:
            raise InputError(f"dbeta must be smaller than beta_max, got dbeta={self.dbeta}, beta_max={self.beta_max}")

    @property
    def n_beta(self) -> int:
        """The number of wavenumbers of the grid (counted, not allocated)."""
        return 2 * int(round(self.beta_max / self.dbeta))

    @property
    def beta(self) -> np.ndarray:
        """The wavenumber grid (rad/m)."""
        n_half = self.n_beta // 2
        return self.dbeta * np.arange(-n_half, n_half)


def displacement_fields(cell: PeriodicCell, omega: ArrayLike, x_rel: ArrayLike,
                        settings: WavenumberSettings | None = None, x0: float | None = None,
                        chunk_bytes: float = 6e6) -> np.ndarray:
    """Rail displacement of the infinite track due to a unit force and a unit moment, Eq. (12).

    Parameters
    ----------
    cell : PeriodicCell
        One period of the track.
    omega : array_like
        Circular frequencies (rad/s), shape ``(n,)``.
    x_rel : array_like
        Observation points x' = x - x0 relative to the load (m), shape ``(p,)``.
    settings : WavenumberSettings, optional
        Discretisation; the paper's by default.
    x0 : float, optional
        Load position (m); the cell's central cross-section by default.
    chunk_bytes : float
        Rough memory budget of one frequency chunk (bytes).

    The work is refused beyond :data:`MAX_TERMS_PER_FREQUENCY` terms per frequency or
    :data:`MAX_TERMS` in all (ValueError).

    Returns
    -------
    ndarray, shape (n, p, 2, 2)
        ``q[..., i, k]``: response i (0: w in m, 1: psi in rad) to load k (0: unit force in N,
        1: unit moment in N m).

    Raises
    ------
    ValueError
        For a track whose rail has no damping (``eta_rail = 0``): the method needs it.
    """
    if cell.track.eta_rail <= 0:
        # Without rail damping the free rail's travelling waves are poles of D(beta)^-1 on the
        # real beta axis that Eq. (12) integrates along: the sum is then meaningless (measured: a11
        # off by > 100 % at 500 Hz, a12 != a21, not passive). The paper's method needs damping.
        raise InputError(
            f"the wavenumber method needs a damped rail (eta_rail > 0), got eta_rail={cell.track.eta_rail!r} "
            f"for track {cell.track.name!r}: its integral over real wavenumbers runs through the free "
            "rail's poles; use method='transfer', which takes the limit of vanishing damping")
    settings = settings or WavenumberSettings()
    omega = np.atleast_1d(np.asarray(omega, dtype=float))
    x_rel = np.atleast_1d(np.asarray(x_rel, dtype=float))
    x0 = cell.central_section if x0 is None else float(x0)
    n_terms = (2 * settings.j_max + 1) * settings.n_beta  # terms of the sum over (j, beta), before any is made
    check_work(n_terms, MAX_TERMS_PER_FREQUENCY, f"beta_max/dbeta/j_max = {settings.beta_max!r}/{settings.dbeta!r}/"
               f"{settings.j_max!r} give {n_terms} terms per frequency", "use a larger dbeta or a smaller beta_max")
    check_work(n_terms * omega.size, MAX_TERMS, f"{omega.size} frequencies x {n_terms} terms give "
               f"{n_terms * omega.size} terms", "use fewer frequencies or coarser settings")
    s = len(cell.positions)
    check_work(s * s, MAX_SUPPORTS_SQUARED, f"{s} supports per period (squared: {s * s})",
               "use method='transfer' for a slab with many fasteners")
    grid = _Grid(cell, settings, x_rel, x0)
    # Three (J, N) component arrays of D(beta_j)^-1 per frequency, plus their temporaries: chunk
    # the frequencies, and where one frequency alone exceeds the budget, its wavenumbers.
    per_term = 16 * 8
    per_freq = per_term * grid.beta_j.size
    step = max(1, int(chunk_bytes // per_freq))
    beta_block = max(1, int(chunk_bytes // (per_term * grid.beta_j.shape[0])))
    out = np.empty((omega.size, x_rel.size, 2, 2), dtype=complex)
    # One (rows, J) x (J, N) product per frequency, a few MB each: threaded BLAS gains nothing and,
    # on a busy 2-core machine, its spinning threads made a 40-frequency sweep 6-7 times slower.
    with serial_blas():
        for start in range(0, omega.size, step):
            sl = slice(start, start + step)
            out[sl] = grid.fields(omega[sl], beta_block)
    return out


class _Grid:
    """Frequency-independent parts of Eq. (12): wavenumber grid and the phase factors.

    Every phase in Eq. (10) and (12) has the form exp(i beta_j y) = exp(i beta y) exp(-i 2 pi j y / L),
    so each sum over j is a matrix product of a (rows, J) coefficient matrix with D(beta_j)^-1
    laid out as (J, N): one BLAS call per frequency instead of a loop over j.
    """

    def __init__(self, cell, settings, x_rel, x0):
        self.cell, self.x_rel, self.dbeta = cell, x_rel, settings.dbeta
        self.beta = settings.beta
        period = cell.period
        pos = np.asarray(cell.positions)
        self.pos = pos
        j = np.arange(-settings.j_max, settings.j_max + 1)
        self.j0 = settings.j_max
        self.beta_j = self.beta[None, :] - 2 * np.pi * j[:, None] / period  # (J, N)
        # Rows for R_rs (Eq. 10): separation y = x_r - x_s, weight 1/L. Equally spaced supports
        # repeat separations (2S - 1 distinct of S^2): sum each once, then spread (self.sep_of_pair).
        sep, self.sep_of_pair = np.unique((pos[:, None] - pos[None, :]).ravel(), return_inverse=True)
        # Rows for the periodic term at point p from support s: y = x'_p - x_s, an extra
        # e^{-i 2 pi j x0/L}, and the 1/L of Eq. (12).
        obs = (x_rel[:, None] - pos[None, :]).ravel()  # (P*S,)
        coef_r = np.exp(-2j * np.pi * np.outer(sep, j) / period) / period
        coef_p = np.exp(-2j * np.pi * np.outer(obs + x0, j) / period) / period
        self.coef = np.concatenate([coef_r, coef_p])  # (S*S + P*S, J)
        self.n_r = sep.size
        self.phase_r = np.exp(1j * np.outer(sep, self.beta))  # (S*S, N)
        self.phase_p = np.exp(1j * np.outer(obs, self.beta))  # (P*S, N)
        self.phase_direct = np.exp(1j * np.outer(x_rel, self.beta))  # (P, N)
        self.phase_b = np.exp(1j * np.outer(self.beta, pos))  # (N, S): B(beta) of Eq. (8)

    def fields(self, omega: np.ndarray, beta_block: int | None = None) -> np.ndarray:
        """Eq. (12) at the points ``x_rel`` for the frequencies ``omega``, shape (n, P, 2, 2).

        The Riemann sum over beta is taken in blocks of ``beta_block`` wavenumbers (all at once
        by default), which bounds the memory of one frequency.
        """
        n_beta = self.beta.size
        block = n_beta if beta_block is None else beta_block
        # One workspace for D(beta_j)^-1 of every block (see operator_inverse).
        work = np.empty(4 * omega.size * self.beta_j.shape[0] * min(block, n_beta), dtype=complex)
        total = sum(self._partial_sum(omega, slice(start, min(start + block, n_beta)), work)
                    for start in range(0, n_beta, block))
        return (self.dbeta / (2 * np.pi)) * total

    def _partial_sum(self, omega: np.ndarray, b: slice, work: np.ndarray,
                     points_per_block: int = 8) -> np.ndarray:
        """The terms of Eq. (12) (without dbeta / 2 pi) of the wavenumbers ``beta[b]``.

        ``work`` is a flat complex workspace of at least 4 x (frequencies x J x wavenumbers).
        """
        cell, n_s = self.cell, self.pos.size
        n_w, n_p = omega.size, self.x_rel.size
        n_beta = b.stop - b.start
        shape = (4, n_w, self.beta_j.shape[0], n_beta)
        comps = operator_inverse(cell.track, omega[:, None, None], self.beta_j[None, :, b],
                                 work=work[: np.prod(shape)].reshape(shape))  # d11, d12, d22: (w, J, n)
        d0 = _entries_2x2(*(c[:, self.j0] for c in comps)).reshape(n_w, n_beta, 2, 2)  # D(beta)^-1

        # R(beta) of Eq. (10) as (w, N, 2S, 2S) with DOFs (w_1, psi_1, w_2, ...).
        r_sum = self._sum_over_j(comps, slice(0, self.n_r)) * self.phase_r[None, :, b, None, None]
        r_sum = r_sum[:, self.sep_of_pair.ravel()]
        r_mat = r_sum.reshape(n_w, n_s, n_s, n_beta, 2, 2).transpose(0, 3, 1, 4, 2, 5)
        r_mat = r_mat.reshape(n_w, n_beta, 2 * n_s, 2 * n_s)
        # A(beta)^-1 = K (I + R K)^-1 with K the support stiffness (inverse of H of Eq. 3).
        k_sup = cell.support_stiffness_matrix(omega / (2 * np.pi))[:, None]
        a_inv = k_sup @ np.linalg.inv(np.eye(2 * n_s) + r_mat @ k_sup)
        # G(beta) = A^-1 B D^-1 for both unit loads (p0 = identity).
        bd = (self.phase_b[None, b, :, None, None] * d0[:, :, None]).reshape(n_w, n_beta, 2 * n_s, 2)
        g = (a_inv @ bd).reshape(n_w, n_beta, n_s, 2, 2)

        periodic = np.empty((n_w, n_p, 2, 2), dtype=complex)
        for start in range(0, n_p, points_per_block):  # blocks of points bound the memory
            pts = slice(start, min(start + points_per_block, n_p))
            rows = slice(self.n_r + pts.start * n_s, self.n_r + pts.stop * n_s)
            phase = self.phase_p[rows.start - self.n_r : rows.stop - self.n_r, b]
            p_sum = self._sum_over_j(comps, rows) * phase[None, :, :, None, None]
            p_sum = p_sum.reshape(n_w, pts.stop - pts.start, n_s, n_beta, 2, 2)
            periodic[:, pts] = np.einsum("wpsnab,wnsbk->wpak", p_sum, g, optimize=True)
        direct = np.einsum("pn,wnab->wpab", self.phase_direct[:, b], d0, optimize=True)
        return direct - periodic

    def _sum_over_j(self, comps, rows):
        """sum_j coef[row, j] D(beta_j)^-1 for the given rows, shape (w, rows, N, 2, 2)."""
        coef = self.coef[rows]
        n_w, n_beta = comps[0].shape[:1] + comps[0].shape[2:]
        return _entries_2x2(*(coef @ c for c in comps)).reshape(n_w, -1, n_beta, 2, 2)  # 3 products, not 4


def _entries_2x2(d11: np.ndarray, d12: np.ndarray, d22: np.ndarray) -> np.ndarray:
    """The four entries of a matrix shaped like D^-1 (d21 = -d12) along a new last axis."""
    return np.stack([d11, d12, -d12, d22], -1)


def central_quantities(cell: PeriodicCell, omega: ArrayLike, settings: WavenumberSettings | None = None,
                       dxs: ArrayLike | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """w1, psi2, Q2, M1 of Eq. (14)-(16) from the fields at x' = 0, dx and 2 dx.

    Parameters
    ----------
    cell : PeriodicCell
        One period of the track.
    omega : array_like
        Circular frequencies (rad/s), shape ``(n,)``.
    settings : WavenumberSettings, optional
        Discretisation (the paper's by default).
    dxs : array_like, optional
        Several finite-difference steps (m) evaluated from one field computation, for
        convergence studies; ``settings.dx`` by default.

    Returns
    -------
    w1, psi2, Q2, M1 : ndarray
        Shape ``(n,)``, or ``(n, len(dxs))`` when ``dxs`` is given. Units m/N, rad/(N m),
        N/(N m), N m/N.
    """
    settings = settings or WavenumberSettings()
    steps = np.atleast_1d(settings.dx if dxs is None else np.asarray(dxs, dtype=float))
    x = np.concatenate([[0.0], steps, 2 * steps])
    q = displacement_fields(cell, omega, x, settings)
    n = steps.size
    y1, y2 = q[:, 1 : 1 + n], q[:, 1 + n :]
    ei, kag = cell.track.rail_moduli(np.asarray(omega, dtype=float)[:, None] / (2 * np.pi))
    w1, psi2 = q[:, 0, 0, 0], q[:, 0, 1, 1]
    m1 = -ei * odd_slope(y1[..., 1, 0], y2[..., 1, 0], steps)  # Eq. (15): M1 = -EI dpsi1/dx
    q2 = -kag * (odd_slope(y1[..., 0, 1], y2[..., 0, 1], steps) - psi2[:, None])  # Eq. (16)
    if dxs is None:
        return w1, psi2, q2[:, 0], m1[:, 0]
    return (np.repeat(w1[:, None], n, 1), np.repeat(psi2[:, None], n, 1), q2, m1)


def odd_slope(y1: np.ndarray, y2: np.ndarray, dx: float | np.ndarray) -> np.ndarray:
    """Slope at 0 of an odd function sampled at dx and 2 dx: fit a x + b x^3, return a."""
    return (8 * y1 - y2) / (6 * dx)
