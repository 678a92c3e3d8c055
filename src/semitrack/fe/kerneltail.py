"""A long memory's tail in low rank: the moving kernels past a start, factored over the load's phase.

A moving kernel ``h[p, m]`` (:mod:`semitrack.fe.kernels`: w at a moving contact m steps after a
unit force at phase p) depends on where in the spacing the force acted mostly while the force is
near: later only the track's slow response is left, and over the P phases it is nearly of low
rank. On the paper's ballasted track at 300 km/h and 40 us, past 40 ms the first three singular
values of every kernel are 0.05-0.4 of the kernels' peak and the fourth 2e-4 (measured,
``benchmarks/bench_moving.py``). Factored past the start M0,

    h[p, m] = sum_r U[p, r] V[r, m - M0]        (m >= M0),

a wheel pair's share of the convolution past M0 is R time-invariant convolutions of the loading
wheel's forces weighted by ``U`` at their phases. Those forces are at least M0 steps old, so the
tail of a whole block of up to M0 steps is known before the block runs: it is taken at once by
FFT (:meth:`KernelTail.response`), and the step loop keeps only each kernel's head, ``m < M0``.
The step's cost is then ``k^2 M0`` plus a few FFTs a block, no longer ``k^2 L``.

The factors are those of the least-squares best rank (the kernels' SVD over the phase, from the
P x P Gram matrix of the tail); :attr:`KernelTail.error` says how far they are from the kernels.
"""

from __future__ import annotations

import weakref
from dataclasses import dataclass, field

import numpy as np
import scipy.fft
import scipy.linalg

from ..base.errors import InputError
from .kernels import MovingKernels

__all__ = ["KernelTail", "kernel_tail"]


@dataclass(frozen=True, eq=False)
class KernelTail:
    """The moving kernels split at ``start``: their heads as the loop reads them, their tails in low rank.

    Attributes
    ----------
    start : int
        M0, the first step of the tail.
    rank : int
        R, the factors' rank.
    head : ndarray, shape (n_lags, P, M0)
        The kernels' first M0 steps in the loop's order (:attr:`MovingKernels.loop`), contiguous.
    U : ndarray, shape (n_lags, P, R)
        The tails' factors over the load's phase (dimensionless).
    V : ndarray, shape (n_lags, R, L - M0)
        Their factors over the steps past M0 (m/N).
    error : float
        The largest difference between the factored tails and the kernels, over the kernels' peak.
    """

    start: int
    rank: int
    head: np.ndarray
    U: np.ndarray
    V: np.ndarray
    error: float
    _spectra: dict = field(default_factory=dict, repr=False)

    def response(self, force: np.ndarray, pair: np.ndarray, phase0: np.ndarray, first: int, last: int) -> np.ndarray:
        """The rail under each wheel from the tails, at the steps ``first..last`` (at most M0 of them).

        Parameters
        ----------
        force : ndarray, shape (n_steps + 1, k)
            The contact forces of the steps before ``first`` (N; row s is step s; rows 1 to
            ``last - M0`` are read, row 0, the preload, which the release holds, is not).
        pair : ndarray of int64, shape (k, k)
            Which kernel gives w at wheel i per force at wheel j.
        phase0 : ndarray of int64, shape (k,)
            Each wheel's phase at step 0.
        first, last : int
            The block, ``1 <= first <= last < first + M0``.

        Returns
        -------
        ndarray, shape (last - first + 1, k)
            w (m), downward as the loop's.
        """
        M0, T = self.start, self.V.shape[2]
        B = last - first + 1
        n_fft = self._length(M0)
        k, P = pair.shape[0], self.U.shape[1]
        if not 1 <= first <= last < first + M0:
            raise InputError(f"a block of the tail is 1 <= first <= last < first + {M0}, got {first}..{last}")
        s = np.arange(first - M0 - T + 1, last - M0 + 1)  # the forces' steps the block reads: T + B - 1
        held = s >= 1
        F = np.zeros((s.size, k))
        F[held] = force[s[held]]
        spectra = self._spectrum(n_fft)
        out = np.zeros((B, k))
        for i in range(k):
            total = np.zeros(n_fft // 2 + 1, dtype=complex)
            for j in range(k):
                lag = pair[i, j]
                weighted = self.U[lag][(phase0[j] + s) % P].T * F[:, j]  # (R, T + B - 1): G_r(s)
                total += np.einsum("rf,rf->f", spectra[lag], scipy.fft.rfft(weighted, n_fft, axis=1))
            out[:, i] = scipy.fft.irfft(total, n_fft)[T - 1:T - 1 + B]
        return out

    def _length(self, block: int) -> int:
        """The FFT's length for blocks of up to ``block`` steps: the circular wrap stays off the outputs."""
        return scipy.fft.next_fast_len(self.V.shape[2] + block - 1, real=True)

    def _spectrum(self, n_fft: int) -> np.ndarray:
        """``rfft(V)`` at this length, (n_lags, R, n_fft // 2 + 1), computed once."""
        if n_fft not in self._spectra:
            self._spectra[n_fft] = scipy.fft.rfft(self.V, n_fft, axis=2)
        return self._spectra[n_fft]


_MEMO: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def kernel_tail(kernels: MovingKernels, start: int, rank: int) -> KernelTail:
    """``kernels`` split at step ``start``, their tails factored to ``rank`` (computed once per kernels object).

    Parameters
    ----------
    kernels : MovingKernels
        The kernels.
    start : int
        M0, ``1 <= start < L``.
    rank : int
        R, ``1 <= rank <= P``.

    Returns
    -------
    KernelTail
    """
    loop = kernels.loop
    n_lags, P, L = loop.shape
    if not (isinstance(start, int | np.integer) and 1 <= start < L):
        raise InputError(f"start must be a whole number of steps within the memory, 1 <= start < {L}, got {start!r}")
    if not (isinstance(rank, int | np.integer) and 1 <= rank <= P):
        raise InputError(f"rank must be a whole number from 1 to the {P} phases, got {rank!r}")
    memo = _MEMO.setdefault(kernels, {})
    if (start, rank) in memo:
        return memo[start, rank]
    if ("head", start) not in memo:  # one head per start, whatever the ranks tried on it
        memo["head", start] = np.ascontiguousarray(loop[:, :, :start])
    peak = float(np.abs(loop).max())
    U = np.empty((n_lags, P, rank))
    V = np.empty((n_lags, rank, L - start))
    error = 0.0
    for r, lag in enumerate(kernels.grid.lags):
        h = kernels.by_phase(lag, start)  # (P, L - M0) by the load's phase
        # The tail's SVD over the phase from its Gram matrix, the leading vectors only (P may be thousands)
        values, vectors = scipy.linalg.eigh(h @ h.T, subset_by_index=[P - rank, P - 1])
        U[r] = vectors[:, ::-1]
        V[r] = U[r].T @ h
        error = max(error, float(np.abs(h - U[r] @ V[r]).max()) / peak)
    tail = KernelTail(start, rank, memo["head", start], U, V, error)
    memo[start, rank] = tail
    return tail
