"""The matrices of the equivalent systems (paper Appendices A and B), in one place.

Both layouts are a train of N rigid bars hinged together. The generalised coordinates are
``q = (w1, phi_1..phi_N)`` for the slab layout (Eq. 21, N + 1 in all) and
``q = (w1, phi_1..phi_N, w_l1..w_lN, w_r1..w_rN)`` for the ballasted one (Eq. 31, 3N + 1).

Every spring, damper and inertia of a layout belongs to a *family* (``k``, ``c_l``, ``mu``, ...)
whose members are stretched (or moved) by ``P q`` for one linear map ``P`` of the coordinates.
Its matrix is then ``P^T diag(v) P`` with ``v`` the values of the family, and

    M, C, K = sums of P^T diag(v) P over the terms of the layout's table,
    Z(omega) = K + i omega C - omega^2 M.

The maps (Eq. A.1-A.12, B.1-B.12) are

* ``A1``, ``A0``, ``A2``: downward displacement of the left end, the centre and the right end
  of each bar (``w1`` plus the lengths of the bars to its left times their rotations);
* ``E``: the rotation of each bar; ``R``: the relative rotation ``phi_{j+1} - phi_j`` at each hinge;
* ``Bl``, ``Br``: the left and right support masses (ballasted);
  ``U1 = A1 - Bl``, ``U2 = A2 - Br``: the elongation of the upper springs.

and the term tables reproduce Eq. (A.16), (A.18), (A.24) (slab) and (B.15), (B.20), (B.26)
(ballasted). This module is the only place that knows them: :class:`~.systems.SlabEquivalent`
and :class:`~.systems.BallastedEquivalent` assemble their matrices here, and the fit
(:mod:`.residuals`) evaluates its residuals and their analytic Jacobian with the same maps and
terms, batched over parameter sets and for complex parameters (complex-step derivatives).

The receptance at the left end of bar 1 is ``X[:2]`` with ``Z X = E_end`` (unit force and
moment there, :func:`end_loads`), solved per frequency with symmetric diagonal scaling
(:func:`scaled_solve`). Its derivatives follow from ``d alpha = -X^T dZ X`` through the maps
(:meth:`Assembly.receptance_sensitivities`).
"""

from __future__ import annotations

import functools
from typing import Literal, NamedTuple

import numpy as np

from ..base.errors import InputError, InputTypeError

__all__ = [
    "Layout",
    "LAYOUTS",
    "check_layout",
    "Term",
    "Assembly",
    "assembly",
    "quad",
    "dynamic_stiffness",
    "end_loads",
    "scaled_solve",
    "IllConditionedError",
]

#: The two layouts of the paper: slab (Fig. 7, Appendix A) and ballasted (Fig. 12, Appendix B).
Layout = Literal["slab", "ballasted"]

#: The layout names, in the paper's order.
LAYOUTS: tuple[Layout, ...] = ("slab", "ballasted")


def check_layout(layout: object) -> Layout:
    """Return ``layout`` if it names one of :data:`LAYOUTS`.

    Parameters
    ----------
    layout : object
        The value to check.

    Raises
    ------
    TypeError
        When it is not a str.
    ValueError
        When it is a str but not a layout name.
    """
    if not isinstance(layout, str):
        raise InputTypeError(f"layout must be a str, one of {LAYOUTS}, got {layout!r}")
    if layout not in LAYOUTS:
        raise InputError(f"layout must be one of {LAYOUTS}, got {layout!r}")
    return layout  # type: ignore[return-value]


class Term(NamedTuple):
    """One family of springs, dampers or inertias: ``kind`` gets ``P^T diag(value) P``."""

    map: str  #: name of the map P (see :meth:`Assembly.maps`)
    value: str  #: parameter family giving diag(v)
    kind: str  #: "M", "C" or "K"


# Eq. (A.16) M, (A.18) K, (A.24) C: bar masses at their centres, bar inertias, end springs and
# dampers to the ground.
_SLAB_TERMS = (Term("A0", "m", "M"), Term("E", "J", "M"), Term("A1", "k", "K"), Term("A2", "k", "K"),
               Term("A1", "c_l", "C"), Term("A2", "c_r", "C"))
# Eq. (B.15) M, (B.20) K, (B.26) C: as the slab, plus the support masses; the upper springs are
# stretched by (bar end - support mass), the lower ones by the support mass.
_BALLASTED_TERMS = (Term("A0", "m", "M"), Term("E", "J", "M"), Term("Bl", "mu", "M"), Term("Br", "mu", "M"),
                    Term("U1", "k", "K"), Term("U2", "k", "K"), Term("U1", "c_l", "C"), Term("U2", "c_r", "C"),
                    Term("Bl", "s", "K"), Term("Br", "s", "K"), Term("Bl", "d_l", "C"), Term("Br", "d_r", "C"))
# The hinges (N > 1): R^T diag(k_phi) R is the term diag(0, K'_phi + K''_phi - K'''_phi) of Eq. (A.18).
_HINGE_TERMS = (Term("R", "k_phi", "K"), Term("R", "c_phi", "C"))


def quad(P: np.ndarray, v: np.ndarray) -> np.ndarray:
    """``P^T diag(v) P`` for every parameter set: the matrix of a family ``v`` stretched by ``P q``.

    Parameters
    ----------
    P : ndarray, shape (rows, n) or (B, rows, n)
        The map, shared by all sets or one per set (real or complex).
    v : ndarray, shape (B, rows)
        Values of the family, one row per set.

    Returns
    -------
    ndarray, shape (B, n, n)
    """
    if P.ndim == 2:
        return np.einsum("ji,bj,jk->bik", P, v, P)
    return np.matmul(np.swapaxes(P, 1, 2), v[:, :, None] * P)


class Assembly:
    """The maps and the term table of one layout with ``n_bars`` bars.

    Parameters
    ----------
    layout : {"slab", "ballasted"}
        The layout.
    n_bars : int
        Number of bars N >= 1.

    Attributes
    ----------
    layout : str
        The layout.
    n_bars : int
        N.
    n_dof : int
        Number of coordinates, N + 1 (slab) or 3N + 1 (ballasted).
    terms : tuple of Term
        The families of the layout, in the order of Appendix A/B.
    length_weights : dict
        For the maps that depend on the lengths, ``W[r, j] = d P[r, 1 + j] / d L_j`` (N, N).
    """

    def __init__(self, layout: Layout, n_bars: int):
        self.layout, self.n_bars = check_layout(layout), int(n_bars)
        N = self.n_bars
        self.n_dof = N + 1 if layout == "slab" else 3 * N + 1
        self.terms = (_SLAB_TERMS if layout == "slab" else _BALLASTED_TERMS) + (_HINGE_TERMS if N > 1 else ())
        self._tril = np.tril(np.ones((N, N)), -1)  # [j, i] = 1 for the bars i left of bar j
        eye = np.eye(N)
        self.length_weights = {"A1": self._tril, "U1": self._tril, "A0": self._tril + 0.5 * eye,
                               "A2": self._tril + eye, "U2": self._tril + eye}
        n, idx = self.n_dof, np.arange(N)
        self._constant = {"E": np.zeros((N, n)), "R": np.zeros((max(N - 1, 0), n))}
        self._constant["E"][idx, 1 + idx] = 1.0
        self._constant["R"][idx[:-1], 1 + idx[:-1]] = -1.0
        self._constant["R"][idx[:-1], 2 + idx[:-1]] = 1.0
        if layout == "ballasted":
            self._constant["Bl"] = np.zeros((N, n))
            self._constant["Bl"][idx, N + 1 + idx] = 1.0  # Eq. (B.12)
            self._constant["Br"] = np.zeros((N, n))
            self._constant["Br"][idx, 2 * N + 1 + idx] = 1.0
        self._stack_terms()

    def _stack_terms(self) -> None:
        """The rows of every term, one after the other (the stacked form of the sensitivities).

        ``term_rows[t]`` is the slice of term ``t``'s rows; ``_row_kind`` the index of each row's
        kind (K, C, M); ``_row_weights`` (rows, N) each row's length weights (zero for the maps
        that do not depend on the lengths).
        """
        N, start = self.n_bars, 0
        self.term_rows: list[slice] = []
        kinds, weights = [], []
        for term in self.terms:
            n_rows = N - 1 if term.map == "R" else N
            self.term_rows.append(slice(start, start + n_rows))
            start += n_rows
            kinds.append(np.full(n_rows, "KCM".index(term.kind)))
            W = self.length_weights.get(term.map)
            weights.append(np.zeros((n_rows, N)) if W is None else W)
        self.n_term_rows = start
        self._row_kind = np.concatenate(kinds)
        self._row_weights = np.concatenate(weights)

    def maps(self, L: np.ndarray) -> dict[str, np.ndarray]:
        """The maps from ``q`` to the elongation of every family (Eq. A.1-A.12, B.1-B.12).

        Parameters
        ----------
        L : ndarray, shape (B, N)
            Bar lengths (m) of B parameter sets, real or complex.

        Returns
        -------
        dict
            ``A1, A0, A2`` (and ``U1, U2``), each (B, N, n_dof); ``E, R, Bl, Br`` (rows, n_dof),
            shared by all sets.
        """
        B, N, n = L.shape[0], self.n_bars, self.n_dof
        A1 = np.zeros((B, N, n), dtype=L.dtype)
        A1[:, :, 0] = 1.0
        A1[:, :, 1 : N + 1] = self._tril[None] * L[:, None, :]
        idx = np.arange(N)
        A0, A2 = A1.copy(), A1.copy()
        A0[:, idx, 1 + idx] += 0.5 * L
        A2[:, idx, 1 + idx] += L
        out = {"A0": A0, "A1": A1, "A2": A2, **self._constant}
        if self.layout == "ballasted":
            out.update(U1=A1 - self._constant["Bl"], U2=A2 - self._constant["Br"])
        return out

    def matrices(self, params: dict[str, np.ndarray]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """M, C, K as sums of ``P^T diag(v) P`` over the terms (Eq. A.16, A.18, A.24, B.15, B.20, B.26).

        Parameters
        ----------
        params : dict
            Every parameter family of the layout, each (B, size), real or complex.

        Returns
        -------
        M, C, K : ndarray, shape (B, n_dof, n_dof)
            Not symmetrised; rows are generalised forces (N or N m).
        """
        L = params["L"]
        maps = self.maps(L)
        out = {kind: np.zeros((L.shape[0], self.n_dof, self.n_dof), dtype=L.dtype) for kind in "MCK"}
        for term in self.terms:
            out[term.kind] = out[term.kind] + quad(maps[term.map], params[term.value])
        return out["M"], out["C"], out["K"]

    def projected_maps(self, X: np.ndarray, L: np.ndarray) -> dict[str, np.ndarray]:
        """``P X`` for every map, without forming the maps.

        Parameters
        ----------
        X : ndarray, shape (n_f, n_dof, c)
            Displacement fields (e.g. the solutions of :func:`scaled_solve`).
        L : ndarray, shape (N,)
            Real bar lengths (m).

        Returns
        -------
        dict
            One (n_f, rows, c) array per map name.
        """
        N = self.n_bars
        X0, Xp = X[:, 0, :], X[:, 1 : N + 1, :]
        A1 = X0[:, None, :] + (self._tril * L[None, :])[None] @ Xp
        out = {"A1": A1, "A0": A1 + 0.5 * L[None, :, None] * Xp, "A2": A1 + L[None, :, None] * Xp,
               "E": Xp, "R": Xp[:, 1:, :] - Xp[:, :-1, :]}
        if self.layout == "ballasted":
            Bl, Br = X[:, N + 1 : 2 * N + 1, :], X[:, 2 * N + 1 :, :]
            out.update(Bl=Bl, Br=Br, U1=A1 - Bl, U2=out["A2"] - Br)
        return out

    def stacked_sensitivities(self, X: np.ndarray, params: dict[str, np.ndarray], omega: np.ndarray,
                              pairs) -> tuple[np.ndarray, np.ndarray]:
        """Derivatives of receptance elements with respect to every value (stacked) and every length.

        With ``X = Z^-1 E_end`` the end receptance is ``X[:2]`` and ``d alpha = -X^T dZ X``. With
        ``Z = sum phi P^T diag(v) P`` (``phi`` = 1, ``i omega``, ``-omega^2`` for K, C, M) and
        ``Y = P X`` (rows ``Y_r``, shape (n_f, 2)), a change of a value ``v_r`` gives
        ``-phi Y_r^T Y_r``; a change of a length ``L_j``, which moves column ``1 + j`` of the maps
        by the weights ``W[r, j]``, gives ``-(Xj^T S_j + S_j^T Xj)`` with
        ``S_j = sum_r phi_r v_r W[r, j] Y_r`` over the rows of every term and
        ``Xj = X[:, 1 + j, :]``. O(n_f N) per term, in a few array operations over all rows.

        Parameters
        ----------
        X : ndarray, shape (n_f, n_dof, 2)
            The solutions for a unit force and a unit moment at the end (:func:`end_loads`).
        params : dict
            The real parameter families, each (size,).
        omega : ndarray, shape (n_f,)
            Angular frequencies (rad/s).
        pairs : sequence of (int, int)
            The (row, column) of the receptance elements wanted, e.g. ``ELEMENTS.values()``.

        Returns
        -------
        d_rows : ndarray, shape (n_f, n_elements, n_term_rows)
            ``d alpha_e / d v_r`` for the rows of every term, in the order of :attr:`terms`
            (term ``t`` holds the rows ``term_rows[t]`` of its value family).
        d_lengths : ndarray, shape (n_f, n_elements, N)
            ``d alpha_e / d L_j``.
        """
        a_idx, b_idx = np.array([a for a, _ in pairs]), np.array([b for _, b in pairs])
        Y = self.projected_maps(X, params["L"])
        Y = np.concatenate([Y[term.map] for term in self.terms], axis=1)  # (n_f, rows, 2)
        phi = np.stack([np.ones_like(omega, dtype=complex), 1j * omega, -(omega**2) + 0j], axis=1)[:, self._row_kind]
        phiY = phi[:, :, None] * Y
        d_rows = np.stack([phiY[:, :, a] * Y[:, :, b] for a, b in zip(a_idx, b_idx)], axis=1)
        np.negative(d_rows, out=d_rows)
        v = np.concatenate([params[term.value] for term in self.terms])
        n_f, N = X.shape[0], self.n_bars
        S = ((v[:, None] * self._row_weights).T @ np.swapaxes(phiY, 0, 1).reshape(self.n_term_rows, -1))
        S = np.swapaxes(S.reshape(N, n_f, -1), 0, 1)  # (n_f, N, 2): one product over all frequencies
        Xp = X[:, 1 : self.n_bars + 1, :]
        H = Xp[:, :, a_idx] * S[:, :, b_idx] + S[:, :, a_idx] * Xp[:, :, b_idx]
        return d_rows, -np.swapaxes(H, 1, 2)

    def receptance_sensitivities(self, X: np.ndarray, params: dict[str, np.ndarray], omega: np.ndarray,
                                 pairs) -> tuple[dict[str, np.ndarray], np.ndarray]:
        """Derivatives of receptance elements with respect to every value and every length.

        :meth:`stacked_sensitivities` with the rows of the terms of one value family summed.

        Parameters
        ----------
        X, params, omega, pairs
            As for :meth:`stacked_sensitivities`.

        Returns
        -------
        d_values : dict
            Per value family, ``d alpha_e / d v_r`` of shape (n_f, rows, n_elements).
        d_lengths : ndarray, shape (n_f, n_elements, N)
            ``d alpha_e / d L_j``.
        """
        d_rows, d_lengths = self.stacked_sensitivities(X, params, omega, pairs)
        d_values: dict[str, np.ndarray] = {}
        for term, rows in zip(self.terms, self.term_rows):
            Q = np.swapaxes(d_rows[:, :, rows], 1, 2)
            d_values[term.value] = Q if term.value not in d_values else d_values[term.value] + Q
        return d_values, d_lengths


@functools.lru_cache(maxsize=64)
def assembly(layout: Layout, n_bars: int) -> Assembly:
    """The :class:`Assembly` of a layout with ``n_bars`` bars, built once and shared.

    Parameters
    ----------
    layout, n_bars
        As for :class:`Assembly`.
    """
    return Assembly(layout, n_bars)


def dynamic_stiffness(M: np.ndarray, C: np.ndarray, K: np.ndarray, omega: np.ndarray) -> np.ndarray:
    """``Z = K + i omega C - omega^2 M`` at every angular frequency.

    Parameters
    ----------
    M, C, K : ndarray, shape (n, n)
        Mass, damping and stiffness matrices (SI).
    omega : ndarray, shape (n_f,)
        Angular frequencies (rad/s).

    Returns
    -------
    ndarray of complex, shape (n_f, n, n)
    """
    w = np.asarray(omega, dtype=float)[:, None, None]
    if any(np.iscomplexobj(X) for X in (M, C, K)):
        return K[None] + 1j * w * C[None] - w**2 * M[None]
    # Real and imaginary parts written directly: the same numbers as K + i w C - w^2 M, without
    # the complex temporaries (this runs once per evaluation of a fit).
    Z = np.empty((w.shape[0],) + np.shape(K), dtype=complex)
    Z.real = K[None] - w**2 * M[None]
    Z.imag = w * C[None]
    return Z


def end_loads(n_dof: int) -> np.ndarray:
    """Right-hand sides ``(n_dof, 2)``: a unit force on ``w1`` and a unit moment on ``phi_1``.

    Parameters
    ----------
    n_dof : int
        Number of coordinates.
    """
    E = np.zeros((n_dof, 2))
    E[0, 0] = E[1, 1] = 1.0
    return E


class IllConditionedError(InputError):
    """``Z`` is singular or too ill-conditioned at some frequency (:func:`scaled_solve`).

    Attributes
    ----------
    index : int
        The first frequency index concerned.
    cond : float
        The scaled condition number there.
    n_bad : int
        How many frequencies are concerned.
    """

    def __init__(self, index: int, cond: float, n_bad: int, limit: float):
        self.index, self.cond, self.n_bad, self.limit = index, cond, n_bad, limit
        super().__init__(f"condition number {cond:.3g} > {limit:.0e} after scaling at frequency index {index} "
                         f"({n_bad} frequencies)")


def scaled_solve(Z: np.ndarray, rhs: np.ndarray, cond_limit: float | None = None) -> np.ndarray:
    """Solve ``Z(f) x = rhs`` for every frequency, with symmetric diagonal scaling.

    ``Z`` is scaled to ``S Z S`` with ``S = diag(|Z_ii|^-1/2)``, which makes the solve independent
    of the units of the coordinates (metres and radians, stiffnesses spanning decades).

    Parameters
    ----------
    Z : ndarray of complex, shape (n_f, n, n)
        Dynamic stiffness matrices.
    rhs : ndarray, shape (n, c)
        Right-hand sides, shared by all frequencies.
    cond_limit : float, optional
        When given, raise :class:`IllConditionedError` if the scaled condition number exceeds
        it (or is not finite) at some frequency. Without it, an exactly singular ``Z`` raises
        :class:`numpy.linalg.LinAlgError`.

    Returns
    -------
    ndarray of complex, shape (n_f, n, c)
    """
    d = np.sqrt(np.abs(np.diagonal(Z, axis1=1, axis2=2)))
    s = 1.0 / np.where(d > 0, d, 1.0)
    Zs = s[:, :, None] * Z * s[:, None, :]
    if cond_limit is not None:
        with np.errstate(all="ignore"):
            cond = np.linalg.cond(Zs)
        bad = ~np.isfinite(cond) | (cond > cond_limit)
        if np.any(bad):
            i = int(np.argmax(bad))
            raise IllConditionedError(i, float(cond[i]), int(bad.sum()), cond_limit)
    return s[:, :, None] * np.linalg.solve(Zs, s[:, :, None] * rhs[None])
