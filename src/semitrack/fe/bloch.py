"""The FE track made infinite by its Bloch waves, in discrete time: transfer receptances between the points of a grid.

One period of a periodic FE track (its cell: the rail elements between two mid-span cuts, the
supports in it) is what every truncated model of that track repeats. Joined to copies of itself
without end, it is the infinite FE track: no end, no reflection. At a complex frequency s its
condensed dynamic stiffness ``S = [[S_LL, S_LR], [S_RL, S_RR]]`` on the cuts' rail DOFs
``(w, psi)`` has Bloch waves ``u_(n+1) = lambda u_n``, two decaying to the right and two to the
left. The semi-infinite tracks on either side of a cell are found without them, by cyclic
reduction of the chain of cells (:func:`_semi_infinite`: stable up to the Nyquist frequency,
where the cells hardly couple and the waves' eigenvectors are lost to round-off). They close
the cell on both sides, so that a load in one cell (cell 0) has its field there from one solve,
and in cell ``j`` the cut motion ``T^(|j| - 1)`` carries out of it.

The time domain of the engine is Newmark's average acceleration, the trapezoidal rule, whose
discrete transfer function is the continuous one at ``s = (2 / dt) (z - 1) / (z + 1)``, exactly
(:mod:`semitrack.dynamics.newmark`). On the unit circle ``z = exp(i omega dt)`` that is
``s = 2i / dt tan(omega dt / 2)``: so the receptances here, taken at those s, are the z-transforms
of the step-by-step responses an infinitely long FE model would give, and their inverse discrete
Fourier transform is its discrete impulse response (:mod:`semitrack.fe.kernels`). The grid of
frequencies is shifted by half a bin (``omega_l = 2 pi (l + 1/2) / (N dt)``) so that it holds
neither z = 1 nor z = -1.

:class:`BlochCell` holds the cell and evaluates, per frequency, everything the moving
kernels need for loads and observations on a grid of points ``x_q = x0 + q h`` of the cell
(``P h`` = the period): the field in cell 0 of a load at each point, the motion of its cuts,
the transfer ``T`` from cut to cut and what a cell's grid points show of its cuts' motion.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from ..base.errors import InputError
from ..dynamics.factor import BandOrder, band_solve
from ..model.tracks import Track
from .ends import FREE
from .models import FETrack

__all__ = ["BlochCell", "CellWaves", "warped_s"]


def warped_s(omega: np.ndarray, dt: float) -> np.ndarray:
    """The Laplace variable whose continuous response the trapezoidal rule gives at ``z = exp(i omega dt)``.

    Parameters
    ----------
    omega : ndarray
        Angular frequencies (rad/s), ``0 <= omega < pi / dt``.
    dt : float
        Time step (s).

    Returns
    -------
    ndarray of complex
        ``s = 2i / dt tan(omega dt / 2)`` (1/s).
    """
    return 2j / dt * np.tan(0.5 * omega * dt)


@dataclass(frozen=True)
class CellWaves:
    """Per frequency (first axis), what a grid of points in the cell sees of the infinite FE track.

    Attributes
    ----------
    loaded : ndarray of complex, shape (n_f, n, n_s)
        The cell's DOFs in cell 0 per unit force on each loaded DOF (:attr:`BlochCell.loaded_dofs`, the
        rail DOFs of the elements that hold grid points; m/N...).
    load_weights : scipy.sparse.csr_matrix, shape (n_s, P)
        The loaded DOFs' shares of a unit force at each grid point (the elements' shape functions):
        the field of a load at grid point p is ``loaded @ load_weights[:, p]`` (:attr:`field`).
    out_right, out_left : ndarray of complex, shape (n_f, 2, P)
        The rail's ``(w, psi)`` at the right (left) cut of cell 0 per unit force at grid point p.
    step_right, step_left : ndarray of complex, shape (n_f, 2, 2)
        ``T``: the cut's motion one cell further right (left) in the field a load sends out,
        ``u_(n+1) = T_right u_n`` (``u_(n-1) = T_left u_n``).
    shows_right, shows_left : ndarray of complex, shape (n_f, P, 2)
        w at grid point q of cell 1 (cell -1) per unit motion of its left (right) cut in that field:
        the receptance from p in cell 0 to q in cell ``j >= 1`` is
        ``shows_right[q] @ T_right^(j - 1) @ out_right[:, p]``, and to the left likewise.
    """

    loaded: np.ndarray
    load_weights: sp.csr_matrix
    out_right: np.ndarray
    out_left: np.ndarray
    step_right: np.ndarray
    step_left: np.ndarray
    shows_right: np.ndarray
    shows_left: np.ndarray

    @property
    def field(self) -> np.ndarray:
        """The cell's DOFs in cell 0 per unit force at each grid point (n_f, n, P): w at grid point q is
        :meth:`BlochCell.observe` of it. Formed on each access (P columns where :attr:`loaded` has n_s)."""
        n_f, n, n_s = self.loaded.shape
        Y = self.load_weights.T @ self.loaded.transpose(2, 0, 1).reshape(n_s, -1)  # (P, n_f * n), sparse weights
        return Y.reshape(-1, n_f, n).transpose(1, 2, 0)


class BlochCell:
    """One period of a periodic FE track, and its infinite repetition at any complex frequency.

    Parameters
    ----------
    track : Track
        A periodic track (rigid or ballasted supports; one support per period).
    elements_per_bay : int or None
        The mesh (as :class:`semitrack.TruncatedTrack` takes it; None: its default for ``f_max``).
    grid : ndarray
        Positions of the load and observation points in the cell (m from its left cut, a mid-span),
        ``0 <= x < period``.
    f_ref : None, float or dict
        Reference frequencies of the viscous damping (:meth:`semitrack.fe.models.FETrack.matrices`).
    f_max : float, optional
        The highest frequency of interest (Hz), for the default mesh.
    """

    def __init__(self, track: Track, elements_per_bay: int | None, grid: np.ndarray, f_ref=None,
                 f_max: float | None = None):
        if track.has_flexible_slab:
            raise InputError("the moving Green's functions take one support per period (rigid or ballasted "
                             "supports); a flexible slab's period is a whole slab: use its truncated FE model")
        self.track = track
        self.period = float(track.spacing)
        self.model = m = FETrack(track, 0, 1, FREE, FREE, elements_per_bay=elements_per_bay, f_max=f_max)
        self.matrices = tuple(sp.csr_matrix(A) for A in m.matrices(f_ref))
        self.left = np.array([m.dof(0.0, "w"), m.dof(0.0, "psi")])
        self.right = np.array([m.dof(self.period, "w"), m.dof(self.period, "psi")])
        self.cuts = np.r_[self.left, self.right]
        self.inner = np.setdiff1d(np.arange(m.n_dof), self.cuts)
        self.grid = np.asarray(grid, dtype=float)
        points = m.points(self.grid)
        self.grid_dofs, self.grid_weights = points.dofs[0], points.weights[0]  # (P, 4) each
        loads = m.output_matrix(self.grid).tocsc().T  # (n, P): a unit force at each grid point
        #: The DOFs a grid point's force acts on (the rail DOFs of the elements holding grid points)
        self.loaded_dofs = np.unique(self.grid_dofs)
        #: The grid points' DOFs as indices into the loaded DOFs, (P, 4)
        self.grid_loaded = np.searchsorted(self.loaded_dofs, self.grid_dofs)
        #: Their shares of a unit force at each grid point, (n_s, P) sparse (4 per point): few DOFs, many points
        self.load_weights = sp.csr_matrix(loads.tocsr()[self.loaded_dofs])
        self._end_rows = np.r_[np.repeat(self.left, 2), np.repeat(self.right, 2)]
        self._end_cols = np.r_[np.tile(self.left, 2), np.tile(self.right, 2)]
        elements = np.unique(self.grid_dofs, axis=0, return_inverse=True)[1].ravel()
        #: The grid points by element: (their indices, the element's 4 DOFs), in the order of the grid
        self.by_element = [(np.flatnonzero(elements == e), self.grid_dofs[np.flatnonzero(elements == e)[0]])
                           for e in np.unique(elements)]

        self._closed = _BandPattern(self.matrices, np.arange(m.n_dof), m.dofs.along_track(m.mesh))
        self._inner = _BandPattern(self.matrices, self.inner, None)
        self._coupling = [(A[self.inner][:, self.cuts].toarray(), A[self.cuts][:, self.inner].toarray(),
                           A[self.cuts][:, self.cuts].toarray()) for A in self.matrices]  # M, C, K

    def observe(self, field: np.ndarray) -> np.ndarray:
        """w at the grid points of cell 0 from its DOFs ``field`` (n_f, n, ...): (n_f, P, ...)."""
        return np.einsum("qa,fqa...->fq...", self.grid_weights, field[:, self.grid_dofs])

    def waves(self, s: np.ndarray) -> CellWaves:
        """The cell's view of the infinite track at the complex frequencies ``s`` (1/s), see :class:`CellWaves`."""
        s = np.atleast_1d(np.asarray(s, dtype=complex))
        powers = (s**2, s, np.ones_like(s))  # M, C, K
        D_ic, D_ci, D_cc = (sum(p[:, None, None] * blocks[b][None] for p, blocks in zip(powers, self._coupling))
                            for b in range(3))
        X = np.empty(D_ic.shape, dtype=complex)  # the inner DOFs per unit cut motion
        for i, si in enumerate(s):
            X[i] = -self._inner.solve(si, D_ic[i])
        S = D_cc + D_ci @ X
        S_ll, S_lr, S_rl, S_rr = S[:, :2, :2], S[:, :2, 2:], S[:, 2:, :2], S[:, 2:, 2:]
        K_right = _semi_infinite(S_ll, S_ll + S_rr, S_lr, S_rl)  # cells 1, 2, ... at cell 0's right cut
        K_left = _semi_infinite(S_rr, S_ll + S_rr, S_rl, S_lr)  # cells -1, -2, ... at its left cut
        T_r = -np.linalg.solve(S_rr + K_right, S_rl)
        T_l = -np.linalg.solve(S_ll + K_left, S_lr)
        ends = np.concatenate([K_left.reshape(-1, 4), K_right.reshape(-1, 4)], axis=1)  # on _end_rows, _end_cols
        Z = self._loaded_field(s, ends)
        at_cuts = (self.load_weights.T @ Z[:, np.r_[self.right, self.left], :].reshape(-1, Z.shape[2]).T).T.reshape(
            s.size, 4, -1)  # (n_f, 4, P): the cuts' motion per grid point's load (not the whole field)
        eye = np.broadcast_to(np.eye(2), T_r.shape)
        return CellWaves(Z, self.load_weights, at_cuts[:, :2], at_cuts[:, 2:], T_r, T_l,
                         self._shows(X, eye, T_r), self._shows(X, T_l, eye))

    def _loaded_field(self, s: np.ndarray, ends: np.ndarray) -> np.ndarray:
        """Cell 0's DOFs per unit force on each loaded DOF, the track on both sides closing it (n_f, n, n_s).

        A grid point's field is these combined with its shape weights (:attr:`CellWaves.field`): on a
        fine grid far fewer columns than the grid points. The moving kernels' cell-0 sums combine them
        with the load's phase in one pass (:func:`semitrack.fe.pointfield.phased_point_field`).
        """
        n, n_s = self.model.n_dof, self.loaded_dofs.size
        unit = np.zeros((n, n_s))
        unit[self.loaded_dofs, np.arange(n_s)] = 1.0
        Z = np.empty((s.size, n, n_s), dtype=complex)
        for i, si in enumerate(s):
            Z[i] = self._closed.solve(si, unit, (self._end_rows, self._end_cols, ends[i]))
        return Z

    def _shows(self, X: np.ndarray, at_left: np.ndarray, at_right: np.ndarray) -> np.ndarray:
        """w at the grid points of a cell whose cuts move as ``at_left``, ``at_right`` (n_f, 2, 2): (n_f, P, 2)."""
        n_f = X.shape[0]
        u = np.zeros((n_f, self.model.n_dof, 2), dtype=complex)
        u[:, self.left] = at_left
        u[:, self.right] = at_right
        u[:, self.inner] = X @ np.concatenate([at_left, at_right], axis=1)
        return np.einsum("qa,fqaw->fqw", self.grid_weights, u[:, self.grid_dofs, :])


class _BandPattern:
    """The band solve of ``K + s C + s^2 M`` restricted to some DOFs, one frequency at a time."""

    def __init__(self, matrices, dofs: np.ndarray, hint: np.ndarray | None):
        M, C, K = (A[dofs][:, dofs].tocoo() for A in matrices)
        pattern = sp.coo_matrix((np.ones(M.nnz + C.nnz + K.nnz),
                                 (np.r_[M.row, C.row, K.row], np.r_[M.col, C.col, K.col])), shape=M.shape).tocsr()
        pattern.sum_duplicates()
        self.rows, self.cols = (a.astype(np.int64) for a in pattern.nonzero())
        self.values = [np.asarray(A.tocsr()[self.rows, self.cols]).ravel() for A in (M, C, K)]
        self.order = BandOrder.of(self.rows, self.cols, len(dofs), None if hint is None else np.asarray(hint))
        self.positions = self.order.solver_positions(self.rows, self.cols)
        self.index = {(int(r), int(c)): k for k, (r, c) in enumerate(zip(self.rows, self.cols))}
        self._slots: dict = {}

    def solve(self, s: complex, rhs: np.ndarray, extra=None) -> np.ndarray:
        """``(K + s C + s^2 M + extra)^-1 rhs``; ``extra`` = (rows, cols, values) on stored entries."""
        data = s * s * self.values[0] + s * self.values[1] + self.values[2]
        if extra is not None:
            rows, cols, values = extra
            key = (rows.tobytes(), cols.tobytes())
            if key not in self._slots:
                self._slots[key] = np.array([self.index[int(r), int(c)] for r, c in zip(rows, cols)])
            data = data.astype(complex)
            np.add.at(data, self._slots[key], values)
        return band_solve(self.order, self.positions, data, rhs)


def _semi_infinite(surface, bulk, ahead, behind, tol: float = 1e-15, max_doublings: int = 60) -> np.ndarray:
    """The dynamic stiffness a semi-infinite chain of cells presents at its first cut, batched over the first axis.

    The chain's equations are ``surface u_0 + ahead u_1 = f_0`` and ``behind u_(n-1) + bulk u_n +
    ahead u_(n+1) = 0``; eliminating every other cut (cyclic reduction, one doubling of the reach
    per pass) leaves ``surface u_0 = f_0`` once ``ahead`` has died away, which takes about
    ``log2(log(tol) / log|lambda|)`` passes for the least decaying Bloch wave ``lambda``: a few at high
    frequencies, some 20 for a lightly damped propagating wave. Stable where the Bloch waves' own
    eigenvectors are not (near the Nyquist frequency the cells hardly couple).
    """
    surface, bulk, ahead, behind = (np.array(a, dtype=complex) for a in (surface, bulk, ahead, behind))
    scale = np.abs(bulk).max(axis=(1, 2))
    for _ in range(max_doublings):
        if np.all(np.abs(ahead).max(axis=(1, 2)) <= tol * scale):
            return surface
        inv = np.linalg.inv(bulk)
        a_inv, b_inv = ahead @ inv, behind @ inv
        surface = surface - a_inv @ behind
        bulk = bulk - a_inv @ behind - b_inv @ ahead
        ahead, behind = -a_inv @ ahead, -b_inv @ behind
    raise RuntimeError(f"the semi-infinite track's stiffness did not converge in {max_doublings} doublings: a Bloch "
                       "wave that does not decay (no damping?)")
