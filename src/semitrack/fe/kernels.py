"""Moving Green's functions of a periodic FE track: the rail's step-by-step response at a moving contact.

A contact moving at speed v along a periodic track, stepped by dt, sits at the points of a grid
``x_g = g h`` (h = v dt, g the step's index): when ``P h`` is the period (speed rounded so that
it is, :func:`grid_of`), it takes only P positions relative to the supports, ``p = g mod P``.
Newmark's average-acceleration rule on any FE model of the track is linear and time-invariant, so
the rail's displacement under a contact is a sum over the past steps' forces with coefficients
that depend only on the lag and on where the force acted in the period:

    w_i(n) = sum_j [ P0_j e_ij[p_j(0), n] + sum_{m=1..n} h_ij[p_j(m), n - m] F_j(m) ]

for contacts i, j (the wheels of a vehicle, ``Delta_ij = g_i - g_j`` grid steps apart): the
kernel ``h_Delta[p, k]`` is w at grid point ``g + Delta + k`` at step k per unit force at grid
point g (phase p) at step 0, and ``e_Delta[p, n]`` is w at grid point ``g + Delta + n`` at step n
when a unit force that had stood at g since ever is taken off after step 0 (the start: the
engine's runs start at rest in the static equilibrium under the preloads).

Both come from the infinite FE track (:mod:`semitrack.fe.bloch`): the trapezoidal rule's transfer
function is the continuous one at ``s = 2i / dt tan(omega dt / 2)``, so the inverse discrete
Fourier transform of the infinite track's receptance between the grid points, taken there, is the
step-by-step response of an infinitely long FE model with the same mesh, no end and no reflection.
On the grid of N frequencies ``omega_l = 2 pi (l + 1/2) / (N dt)`` (half a bin off, neither 0 nor
Nyquist) the transform is anti-periodic: the kernels are exact but for ``-h[k + N] + h[k + 2N] ...``,
which dies with the track's response over ``N dt`` (N = :data:`ALIAS_FACTOR` times the memory).
With ``z = exp(i omega dt)``, ``e``'s transform is ``(H(1) - H(z) / z) / (1 - 1/z)``, of which the
first part is half the static receptance at every step on this grid.

The receptance from grid point p of cell 0 to grid point q of cell j is
``shows[q] @ T^(|j| - 1) @ out[:, p]`` (:class:`semitrack.fe.bloch.CellWaves`): for each cell the
sum over frequencies and the cut's two DOFs is the real part of one matrix product
(P x 2 n_f) (2 n_f x P), the work of the set-up; within cell 0 it is one product per element over
its grid points. Only the loads that reach a point within the memory enter its products
(:func:`_sources`): cell 0's later loads and a short memory's far ones never do, which halves
cell 0's work and makes a memory shorter than a spacing cost P L instead of P^2.
"""

from __future__ import annotations

import hashlib
import json
import math
import time
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ..base.checks import as_real_array, check_choice, check_int_at_least, check_work, shown
from ..base.errors import InputError
from ..base.fields import check_fields
from ..base.parallel import thread_map
from ..base.progress import LIBRARY_DELAY, Progress
from ..equivalent.cache import canonical, package_source_digest
from ..model.tracks import Track
from .bloch import BlochCell, CellWaves, warped_s
from .models import DEFAULT_F_MAX
from .pointfield import phased_point_field

__all__ = ["KernelGrid", "MovingKernels", "grid_of", "loop_order", "moving_kernels", "release_starts", "track_key",
           "kernel_key",
           "ALIAS_FACTOR", "MAX_KERNEL_VALUES", "MAX_KERNEL_WORK"]

#: The discrete Fourier transform's length over the kernels' memory: its anti-periodic wrap-around
#: brings back the response ``ALIAS_FACTOR`` memories later.
ALIAS_FACTOR = 2
#: Most values the kernels and their cells' sums may hold, ``P (L + P)`` per wheel offset (8 bytes each):
#: a bogie on the ballasted track at 300 km/h, 20 us and 0.2 s holds 1.2e7.
MAX_KERNEL_VALUES = 100_000_000
#: Most work of a set-up, ``P L^2`` per wheel offset (multiply-adds over frequencies and cells): that bogie's
#: 1.1e11 took 48 s on a 2-core machine (measured), so the limit is some 4 minutes.
MAX_KERNEL_WORK = 5e11
#: Frequencies evaluated together (memory: the cell-0 receptances are P x P per frequency).
FREQUENCY_BLOCK = 128
#: The frequency blocks are summed in this many parts, one per core of a 2-core machine (on threads:
#: the matrix products release the GIL), then added. Measured on 2 cores: the slab track's bogie at
#: 300 km/h and 40 us took 5.0 s instead of 8.0 s, the ballasted track's wheel at 30 us 7.6 s instead
#: of 11.7 s, the kernels equal to the one part's to 8e-16 of their peak.
PARTIAL_SUMS = 2
#: Most values the extra parts' sums may hold (8 bytes each); a set-up larger than this sums in one part.
MAX_EXTRA_SUM_VALUES = 12_500_000


@dataclass(frozen=True)
class KernelGrid:
    """The positions a moving contact takes: speed rounded to a whole number of steps per period.

    Attributes
    ----------
    period : float
        The track's period (m): its support spacing.
    dt : float
        Time step (s).
    positions : int
        P, the steps per period.
    speed : float
        The speed the grid moves at (m/s), ``period / (P dt)``.
    offsets : tuple of int
        Each wheel's grid index relative to the first wheel's (its offset over the step ``h``,
        rounded).
    """

    period: float
    dt: float
    positions: int
    speed: float
    offsets: tuple[int, ...]

    @property
    def step(self) -> float:
        """h = speed dt (m), the distance between grid points."""
        return self.period / self.positions

    @property
    def lags(self) -> tuple[int, ...]:
        """The distinct ``Delta = g_i - g_j`` between every pair of wheels (grid steps)."""
        return tuple(sorted({i - j for i in self.offsets for j in self.offsets}))


#: Most grid steps per support spacing (a 0.6 m spacing at 1 m/s and 1e-6 s is 6e5).
MAX_STEPS_PER_SPACING = 1e6
#: Farthest a wheel may be from the first (m): a long train's length.
MAX_OFFSET = 1000.0


def grid_of(track: Track, speed: float, dt: float, offsets: Sequence[float] = (0.0,)) -> KernelGrid:
    """The grid of a contact at ``speed`` stepped by ``dt``: ``P = round(period / (speed dt))`` positions.

    Parameters
    ----------
    track : Track
        The periodic track.
    speed : float
        The wheels' speed (m/s), > 0; rounded to ``period / (P dt)`` (by at most ``1 / (2P)`` of itself).
    dt : float
        Time step (s).
    offsets : sequence of float
        The wheels' positions from the first (m), rounded to whole grid steps.

    Returns
    -------
    KernelGrid
    """
    d = float(track.spacing)
    steps = d / (speed * dt)  # per spacing: inf for a speed of 1e-308 m/s, bounded before any int()
    check_work(steps if math.isfinite(steps) else math.inf, MAX_STEPS_PER_SPACING,
               f"speed={shown(speed)} m/s and dt={shown(dt)} s pass a support spacing in {steps:.3g} steps",
               "give a higher speed or a longer dt (the kernels' set-up grows with the steps per spacing)")
    offsets = as_real_array(offsets, "offsets", ndim=1, empty=False)
    if np.abs(offsets).max() > MAX_OFFSET:
        raise InputError(f"offsets must lie within {MAX_OFFSET:g} m of the first wheel (one vehicle), "
                         f"got {shown(np.abs(offsets).max())} m")
    P = max(1, int(round(steps)))
    if P < 4:
        raise InputError(f"speed={shown(speed)} m/s and dt={shown(dt)} s pass a support spacing of {d:g} m in "
                         f"{d / (speed * dt):.3g} steps; the moving Green's functions need at least 4 steps per "
                         "spacing: give a smaller dt")
    h = d / P
    return KernelGrid(d, float(dt), P, h / dt, tuple(int(round(float(o) / h)) for o in offsets))


@dataclass(frozen=True, eq=False)
class MovingKernels:
    """The moving Green's functions of one track, speed, time step and set of wheel offsets.

    Attributes
    ----------
    grid : KernelGrid
        Positions, speed and offsets.
    loop : ndarray, shape (n_lags, P, L)
        The impulse kernels in the order the step loop reads them, one per lag of
        :attr:`KernelGrid.lags` (in that order): ``loop[r, q, m] = h[(q - m) mod P, m]`` for
        ``Delta = lags[r]`` (m/N), so that row q holds, for a loading wheel at phase q now, the
        coefficients of its forces m steps ago (whose phase was ``q - m``): one contiguous dot
        product per step, and no re-arrangement per run. :attr:`impulse` reads them by phase.
    release : dict of (int, int) to ndarray, shape (L,)
        ``release[Delta, p][n]`` (m/N): w at ``Delta + n`` grid steps ahead of a unit force that
        stood at phase p until step 0, n steps after it was taken off; for the wheels' starts
        (phases p) only.
    flexibility : ndarray, shape (P,)
        The rail element's own deflection under a unit force at each grid point (m/N),
        :meth:`semitrack.fe.models.FETrack.local_flexibility`.
    tail : float
        The largest magnitude of the impulse kernels over the memory's last quarter over their largest:
        what the memory cuts off.
    key : dict
        What the kernels were computed for (:func:`kernel_key`: track, mesh, damping, grid, memory,
        start, the package's source): the cache's key (:mod:`semitrack.fe.kernelcache`).
    elapsed : float
        Wall time of the computation (s).
    elements_per_bay : int
        The FE mesh's elements per spacing.
    start : int
        The first wheel's phase at the start, which the releases are for.
    """

    grid: KernelGrid
    loop: np.ndarray
    release: dict
    flexibility: np.ndarray
    tail: float
    key: dict
    elapsed: float = 0.0
    elements_per_bay: int = 0
    start: int = 0

    def __post_init__(self):
        check_fields(self)  # a record built by hand is refused here, not in a method
        if self.loop.ndim != 3 or self.loop.shape[:2] != (len(self.grid.lags), self.grid.positions):
            raise InputError(f"loop must have shape (lags, positions, memory) = ({len(self.grid.lags)}, "
                             f"{self.grid.positions}, L) for its grid, got {self.loop.shape}")

    @property
    def memory(self) -> int:
        """L, the steps each kernel holds."""
        return self.loop.shape[2]

    @property
    def impulse(self) -> dict:
        """The impulse kernels by the load's phase: ``impulse[Delta][p, k]`` (m/N), w at ``Delta + k`` grid steps
        ahead of a unit force at phase p, k steps after it.

        Computed from :attr:`loop` on each access (a permutation of every kernel): for reading, not for a step loop.

        Returns
        -------
        dict of int to ndarray, shape (P, L)
        """
        return {lag: self.by_phase(lag) for lag in self.grid.lags}

    def by_phase(self, lag: int, start: int = 0) -> np.ndarray:
        """The impulse kernel of ``lag`` by the load's phase from step ``start`` on: ``h[p, m]`` for
        ``start <= m < L`` (m/N, a copy), from :attr:`loop` (``h[p, m] = loop[(p + m) mod P, m]``).

        Parameters
        ----------
        lag : int
            ``Delta``, the observing wheel's grid index minus the loading wheel's.
        start : int
            The first step, ``0 <= start < L``.

        Returns
        -------
        ndarray, shape (P, L - start)
        """
        P, L = self.loop.shape[1:]
        rows = self.rows(lag)
        start = check_int_at_least("start", start, 0)
        if start >= L:
            raise InputError(f"start must be below the memory's {L} steps, got {start}")
        m = np.arange(start, L)
        return rows[np.mod(np.arange(P)[:, None] + m[None, :], P), m[None, :]]

    def rows(self, lag: int) -> np.ndarray:
        """The impulse kernel of ``lag`` as the step loop reads it: ``K[q, m] = h[(q - m) mod P, m]`` (a view).

        Parameters
        ----------
        lag : int
            ``Delta``, the observing wheel's grid index minus the loading wheel's.

        Returns
        -------
        ndarray, shape (P, L)
        """
        return self.loop[self.grid.lags.index(check_choice("lag", lag, self.grid.lags))]


def loop_order(h: np.ndarray) -> np.ndarray:
    """An impulse kernel by the load's phase, ``h[p, m]``, in the step loop's order ``K[q, m] = h[(q - m) mod P, m]``.

    Parameters
    ----------
    h : ndarray, shape (P, L)

    Returns
    -------
    ndarray, shape (P, L)
    """
    P, L = h.shape
    phase = np.mod(np.arange(P)[:, None] - np.arange(L)[None, :], P)
    return h[phase, np.arange(L)[None, :]]


def track_key(track: Track) -> str:
    """SHA-256 (hex) of the track's parameters (every field but its name).

    Parameters
    ----------
    track : Track
        The track.

    Returns
    -------
    str
    """
    return hashlib.sha256(json.dumps(canonical(track), sort_keys=True).encode()).hexdigest()


def kernel_key(track: Track, elements_per_bay: int | None, grid: KernelGrid, memory: int, f_ref=None,
               start: int = 0, f_max: float | None = None) -> dict:
    """What the kernels depend on, as JSON-able values (floats bit-exact as hexadecimal).

    The mesh is keyed as asked: a number of elements, or the default for ``f_max`` (which the
    package's source and the track determine), so that a cache is read without resolving it.

    Parameters
    ----------
    track : Track
        The track.
    elements_per_bay : int or None
        The mesh asked for (None: the default for ``f_max``).
    grid : KernelGrid
        Steps per spacing, time step and offsets.
    memory : int
        L, steps.
    f_ref : None, float or dict
        Reference frequencies of the viscous damping.
    start : int
        The phase of the vehicle's origin at the start.
    f_max : float, optional
        With ``elements_per_bay=None``: the highest frequency the default mesh resolves (Hz).

    Returns
    -------
    dict
    """
    mesh = (["elements", int(elements_per_bay)] if elements_per_bay is not None else
            ["default up to", canonical(float(DEFAULT_F_MAX if f_max is None else f_max))])
    return {"track": track_key(track), "mesh": mesh, "dt": float(grid.dt).hex(),
            "positions": int(grid.positions), "offsets": [int(o) for o in grid.offsets], "memory": int(memory),
            "start": int(start), "f_ref": canonical(f_ref), "source": package_source_digest()}


def _frequencies(n_fft: int, dt: float) -> np.ndarray:
    """``omega_l = 2 pi (l + 1/2) / (N dt)`` for l < N/2 (rad/s): one half of the shifted grid."""
    return 2 * np.pi * (np.arange(n_fft // 2) + 0.5) / (n_fft * dt)


def _cells(P: int, lag: int, L: int) -> range:
    """The cells j that grid points ``p + lag + k`` (0 <= p < P, 0 <= k < L) fall in."""
    return range((lag) // P, (P - 1 + lag + L - 1) // P + 1)


def _scatter(block: np.ndarray, j: int, lag: int, out: np.ndarray, p0: int | None = None) -> None:
    """``out[p, k] += block[p, q]`` where ``k = j P + q - p - lag`` lies in the memory (one row p0: ``out[k]``)."""
    P, L = block.shape[-1], out.shape[-1]
    if p0 is not None:
        k = j * P + np.arange(P) - p0 - lag
        keep = (k >= 0) & (k < L)
        out[k[keep]] += block[keep]
        return
    src = _sources(P, j, 0, P - 1, [lag], L)  # the rows with a value in the memory: a band when L < P
    p = np.arange(src.start, src.stop)[:, None]
    k = j * P + np.arange(P)[None, :] - p - lag
    keep = (k >= 0) & (k < L)
    rows = np.broadcast_to(p, k.shape)[keep]
    out[rows, k[keep]] += block[src][keep]


@dataclass
class _Sums:
    """The sums over frequencies in progress: every cell's block of each kernel.

    ``impulse[j]``: (n_lags, P, P), ``[r, p, q]`` for the lag ``lags[r]``; ``release[j]``:
    (n_starts, P), ``[r, q]`` for the start ``starts[r] = (lag, p0)``.
    """

    lags: list
    starts: list
    impulse: dict
    release: dict

    def add(self, other: _Sums) -> None:
        """Add another part's sums to these."""
        for mine, theirs in ((self.impulse, other.impulse), (self.release, other.release)):
            for j in mine:
                mine[j] += theirs[j]


def _sources(P: int, j: int, q_lo: int, q_hi: int, lags: Sequence[int], L: int) -> slice:
    """The load phases p of cell 0 whose kernels reach grid points ``q_lo..q_hi`` of cell j within the memory.

    ``h[p, k]`` is read at ``k = j P + q - p - lag`` for ``0 <= k < L``: a short memory (L < P, a slow
    wheel or a long step) needs only a band of the P x P pairs, and the set-up then costs P L, not P^2.
    """
    return slice(max(0, j * P + q_lo - max(lags) - L + 1), min(P, j * P + q_hi - min(lags) + 1))


def _near(cell: BlochCell, w: CellWaves, omega: np.ndarray, dt: float, sums: _Sums, weights: dict,
          L: int) -> None:
    """Cell 0's share: one product per element over its grid points, the lags and the loads reaching them.

    The field of a load at each grid point with its phase is formed once a block, DOF first
    (:func:`semitrack.fe.pointfield.phased_point_field`), so an element's four DOFs are one block of it.
    """
    P = cell.grid.size
    at_p = np.exp(-1j * dt * omega[:, None] * np.arange(P)[None, :])  # (n_f, P): the load at p
    field = phased_point_field(w.loaded, cell.grid_loaded, cell.grid_weights, at_p)  # (n, n_f, P)
    lags = np.array(sums.lags, dtype=float)
    to_lag = np.exp(-1j * dt * omega[None, :] * lags[:, None]) * weights["impulse"]  # (n_lags, n_f)
    p0 = np.array([p for _, p in sums.starts], dtype=np.int64)
    to_start = np.exp(-1j * dt * omega[None, :] * np.array([lag for lag, _ in sums.starts], float)[:, None]
                      ) * weights["release"]
    for points, dofs in cell.by_element:
        at_q = np.exp(1j * dt * omega[None, :] * points[:, None])  # (|Q|, n_f)
        sub = field[dofs[0]:dofs[0] + 4] if np.all(np.diff(dofs) == 1) else field[dofs]  # (4, n_f, P)
        spans = [_sources(P, 0, int(points.min()), int(points.max()), [lag], L) for lag in sums.lags]
        # The lags that reach these points from cell 0 (a wheel ahead of them by more than the cell reaches them
        # from cell 1 on), in one product over the loads any of them reaches: the element's field is read once.
        reach = [r for r, src in enumerate(spans) if src.start < src.stop] if 0 in sums.impulse else []
        if reach:
            src = slice(min(spans[r].start for r in reach), max(spans[r].stop for r in reach))
            E = (to_lag[reach][:, None, :] * at_q[None]).reshape(-1, omega.size)  # (reach x |Q|, n_f)
            Z = np.matmul(E, sub[:, :, src]).reshape(4, len(reach), points.size, -1)  # (4, reach, |Q|, loads)
            block = np.einsum("qa,arqp->rpq", cell.grid_weights[points], Z.real)
            for i, r in enumerate(reach):
                sums.impulse[0][r][src, points] += block[i]
        if 0 in sums.release:
            Z = np.einsum("ql,rl,alr->rqa", at_q, to_start, sub[:, :, p0])
            sums.release[0][:, points] += np.einsum("qa,rqa->rq", cell.grid_weights[points], Z).real


def _far(cell: BlochCell, w: CellWaves, omega: np.ndarray, dt: float, sums: _Sums, weights: dict, L: int) -> None:
    """The other cells' share: per cell one real matrix product over (frequency, wave) for the kernels that
    reach it, over the loads that reach the cell within the memory.

    The loads' side of every lag, ``out`` with its phases, is formed once per block; a cell forms only
    its view ``B`` (the lags share it), so the products are most of the work.
    """
    P = cell.grid.size
    q = np.arange(P)
    at_p = np.exp(-1j * dt * omega[:, None] * q[None, :])
    at_q = np.exp(1j * dt * omega[:, None] * q[None, :])
    lags = np.array(sums.lags, dtype=float)
    to_lag = np.exp(-1j * dt * omega[None, :] * lags[:, None]) * weights["impulse"]
    p0 = np.array([p for _, p in sums.starts], dtype=np.int64)
    to_start = np.exp(-1j * dt * omega[None, :] * np.array([lag for lag, _ in sums.starts], float)[:, None]
                      ) * weights["release"]
    for side in (1, -1):
        js = sorted(side * j for j in set(sums.impulse) | set(sums.release) if side * j > 0)
        if not js:
            continue
        out, step, shows = ((w.out_right, w.step_right, w.shows_right) if side > 0 else
                            (w.out_left, w.step_left, w.shows_left))
        A = (out * at_p[:, None, :]).transpose(2, 0, 1)  # (P, n_f, 2)
        A = (A[None] * to_lag[:, None, :, None]).reshape(len(sums.lags), P, -1)  # (lags, P, n_f * 2): (l, a)
        A_re, A_im = A.real.copy(), A.imag.copy()
        A0 = (out[:, :, p0].transpose(2, 0, 1) * (at_p[:, p0].T * to_start)[:, :, None]).reshape(p0.size, -1)
        V = shows * at_q[:, :, None]  # (n_f, P, 2): the view from cell 1, then T^(j-1) further
        power = 1
        for j in js:
            for _ in range(j - power):
                V = V @ step
            power = j
            B = (V * np.exp(1j * dt * omega * side * j * P)[:, None, None]).transpose(0, 2, 1).reshape(-1, P)
            # The lags whose memory reaches this cell: a run of them, the lags being sorted
            reach = [r for r, lag in enumerate(sums.lags) if side * j in _cells(P, lag, L)]
            if side * j in sums.impulse and reach:
                run = slice(reach[0], reach[-1] + 1)
                src = _sources(P, side * j, 0, P - 1, sums.lags[run], L)
                sums.impulse[side * j][run, src] += (np.matmul(A_re[run, src], np.ascontiguousarray(B.real)) -
                                                     np.matmul(A_im[run, src], np.ascontiguousarray(B.imag)))
            if side * j in sums.release:
                sums.release[side * j] += (A0 @ B).real


def _frequency_sums(cell: BlochCell, omega: np.ndarray, dt: float, weights: dict, lags: list, starts: list,
                    L: int) -> _Sums:
    """Every cell's block of each kernel, summed over the frequencies ``omega`` block by block.

    The blocks are summed in :data:`PARTIAL_SUMS` parts where their sums are small enough
    (:data:`MAX_EXTRA_SUM_VALUES`), on threads where there are cores, then added.
    """
    P = cell.grid.size
    impulse_cells = sorted(set().union(*(_cells(P, g, L) for g in lags)))
    release_cells = sorted(set().union(*(_cells(P, g + p, L) for g, p in starts)))

    def empty_sums() -> _Sums:
        return _Sums(lags, starts, {j: np.zeros((len(lags), P, P)) for j in impulse_cells},
                     {j: np.zeros((len(starts), P)) for j in release_cells})

    blocks = list(range(0, omega.size, FREQUENCY_BLOCK))
    size = (len(impulse_cells) * len(lags) * P + len(release_cells) * len(starts)) * P
    n_parts = PARTIAL_SUMS if size * (PARTIAL_SUMS - 1) <= MAX_EXTRA_SUM_VALUES and len(blocks) >= PARTIAL_SUMS else 1
    with Progress("moving kernels", len(blocks), unit="block", delay=LIBRARY_DELAY) as bar:

        def part_sums(part: np.ndarray) -> _Sums:
            """The sums over the frequency blocks starting at ``part``."""
            sums = empty_sums()
            for lo in part:
                window = slice(lo, lo + FREQUENCY_BLOCK)
                w = cell.waves(warped_s(omega[window], dt))
                block_weights = {kind: value[window] for kind, value in weights.items()}
                _near(cell, w, omega[window], dt, sums, block_weights, L)
                _far(cell, w, omega[window], dt, sums, block_weights, L)
                bar.advance()
            return sums

        # The parts' number follows from the problem alone, never from the cores, so the kernels are the
        # same numbers wherever they run; thread_map holds BLAS on one thread (many mid-sized products and
        # small solves: threaded BLAS gained 11 % on a quiet 2-core machine and lost 3-5x beside other jobs).
        sums, *others = thread_map(part_sums, np.array_split(np.array(blocks, dtype=np.int64), n_parts))
    for other in others:
        sums.add(other)
    return sums


def _static_release(cell: BlochCell, w0: CellWaves, p0: int, j: int) -> np.ndarray:
    """The static receptance from cell 0's grid point p0 to the grid points of cell j (P,), from one zero frequency."""
    if j == 0:  # the loaded column alone: the whole P x P matrix of a slow wheel's grid was gigabytes
        return cell.observe(w0.loaded @ w0.load_weights[:, [p0]].toarray())[0, :, 0].real
    out, step, shows = ((w0.out_right, w0.step_right, w0.shows_right) if j > 0 else
                        (w0.out_left, w0.step_left, w0.shows_left))
    return (shows[0] @ np.linalg.matrix_power(step[0], abs(j) - 1) @ out[0][:, p0]).real


def release_starts(grid: KernelGrid, start: int) -> list[tuple[int, int]]:
    """The releases a start needs: ``(Delta, p)`` for every wheel pair, p the loading wheel's phase.

    Parameters
    ----------
    grid : KernelGrid
        The grid and the wheels' offsets.
    start : int
        The phase of the vehicle's reference point (its first offset's origin) at the start.

    Returns
    -------
    list of (int, int)
        Sorted.
    """
    P = grid.positions
    phases = [(start + o) % P for o in grid.offsets]
    return sorted({(gi - gj, pj) for gi in grid.offsets for gj, pj in zip(grid.offsets, phases)})


def moving_kernels(track: Track, elements_per_bay: int | None, grid: KernelGrid, memory: int, f_ref=None,
                   f_max: float | None = None, start: int = 0) -> MovingKernels:
    """The moving Green's functions of every wheel pair of ``grid`` over ``memory`` steps.

    Parameters
    ----------
    track : Track
        A periodic track with one support per period.
    elements_per_bay : int or None
        The FE mesh (as :class:`semitrack.TruncatedTrack`; None: its default for ``f_max``).
    grid : KernelGrid
        From :func:`grid_of`.
    memory : int
        L, the steps each kernel holds.
    f_ref : None, float or dict
        Reference frequencies of the viscous damping.
    f_max : float, optional
        The highest frequency of interest (Hz), which the default mesh resolves.
    start : int
        The first wheel's phase at the start (0 <= start < P): the releases of the standing
        preloads are computed for the wheels' starts only.

    Returns
    -------
    MovingKernels
    """
    began = time.perf_counter()
    P, dt, L = grid.positions, grid.dt, int(memory)
    lags = list(grid.lags)
    request = (f"{P} steps per spacing, a memory of {L} steps and {len(lags)} wheel offset(s) (speed "
               f"{grid.speed:.6g} m/s, dt={dt!r} s)")
    hint = "use a larger dt, a higher speed, a shorter memory or fewer wheels"
    check_work(P * (L + P) * len(lags), MAX_KERNEL_VALUES, f"{request} hold {P * (L + P) * len(lags)} values", hint)
    check_work(float(P) * L * L * len(lags), MAX_KERNEL_WORK, f"{request} take {float(P) * L * L * len(lags):.3g} "
               "multiply-adds", hint)
    cell = BlochCell(track, elements_per_bay, grid.step * np.arange(P), f_ref, f_max)
    n_fft = 2 * ALIAS_FACTOR * int(math.ceil(L / 2))
    omega = _frequencies(n_fft, dt)
    z = np.exp(1j * omega * dt)
    weights = {"impulse": np.full(omega.size, 2.0 / n_fft), "release": -2.0 / n_fft / (z - 1.0)}
    starts = release_starts(grid, start)
    sums = _frequency_sums(cell, omega, dt, weights, lags, starts, L)
    w0 = cell.waves(np.zeros(1))
    loop = np.empty((len(lags), P, L))
    h0 = None
    for r, lag in enumerate(lags):
        out = np.zeros((P, L))
        for j in _cells(P, lag, L):
            _scatter(sums.impulse[j][r], j, lag, out)
        loop[r] = loop_order(out)
        h0 = out if lag == 0 else h0
    release = {}
    for r, (lag, p0) in enumerate(starts):  # e's first part: half the static receptance at every step on this grid
        out = np.zeros(L)
        for j in _cells(P, lag + p0, L):
            _scatter(sums.release[j][r] + 0.5 * _static_release(cell, w0, p0, j), j, lag, out, p0)
        release[lag, p0] = out
    tail = float(np.abs(h0[:, 3 * L // 4:]).max() / np.abs(h0).max())
    flexibility = cell.model.local_flexibility(cell.grid)
    ne = int(cell.model.elements_per_bay)
    return MovingKernels(grid, loop, release, flexibility, tail,
                         kernel_key(track, elements_per_bay, grid, L, f_ref, start, f_max),
                         time.perf_counter() - began, ne, int(start))
