"""Assembly of an FE track's matrices: one sparse pattern, one data vector per family of springs.

The model's matrices are kept apart by *family*, because each family carries its own damping:

``K_rail``
    the rail elements (:func:`semitrack.fe.element.rail_element`; loss factor ``eta_rail``);
``K_pad``
    the pads, from the rail to what carries them (:mod:`semitrack.fe.supports`); loss factor
    ``eta_pad``;
``K_ballast``
    the ballast springs ``kb`` from each sleeper to the ground (loss factor ``eta_ballast``);
``K_slab``, ``K_layer``
    a flexible slab's beam elements (loss factor ``eta_slab``) and its resilient layer's
    consistent Winkler stiffness (``eta_support``, :class:`semitrack.fe.supports.FlexibleSlabs`);
``M``
    the rail's consistent mass, the foundation's masses and the ends' mass;
``K_end``, ``C_end``
    the springs and (viscous) dampers of the ends' own systems;
``K_joint``
    the rotational springs of rail joints (undamped).

Past a transition the rail, pads and ballast are the second track's, with its loss factors:
:attr:`TrackMatrices.by_track` keeps the damped families of each track apart (:data:`DAMPED`;
each named ``"K_" + family`` of :meth:`semitrack.Track.loss_factor`).

An end (:mod:`semitrack.fe.ends`) that is a system enters with its ``M, C, K``, mirrored at the
left end; its first two DOFs are the rail's ``(w, psi)`` at the end node, the others are DOFs of
the model (:mod:`semitrack.fe.mesh`).

Every family is summed onto the same compressed-sparse-column pattern, the union of all their
entries (and of the 2x2 blocks of the frequency-dependent ends, added per frequency), so a
dynamic stiffness at one frequency is a linear combination of data vectors on a fixed pattern.

A track is a chain: renumbered once by reverse Cuthill-McKee, the pattern is a narrow band
(3-7 off-diagonals for the paper's tracks, ends included), and a dynamic stiffness is solved
as a band matrix (LAPACK ``gbsv``, partial pivoting, :mod:`semitrack.dynamics.factor`, the
factorisation the time steps use too) instead of a general sparse LU, whose fill-reducing
ordering is recomputed at every frequency: measured 2-3 times faster per frequency on a
200-bay track, the same solution to 1e-13 (:meth:`Pattern.solve`).
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np
import scipy.sparse as sp

from ..dynamics.factor import BandOrder, SparseLU, band_solve
from ..model.tracks import Track
from .element import rail_element
from .ends import End
from .mesh import SIDES, DofMap, Mesh, Side, rail_dof
from .supports import Foundation

__all__ = ["FAMILIES", "DAMPED", "Pattern", "TrackMatrices", "assemble", "supports_share"]

#: The matrix families of a track model, see the module docstring.
FAMILIES = ("K_rail", "K_pad", "K_ballast", "K_slab", "K_layer", "K_end", "C_end", "K_joint", "M")
#: The families that carry their track's loss factor, kept per track: ``"K_" + family`` of
#: :meth:`semitrack.Track.loss_factor`.
DAMPED = ("K_rail", "K_pad", "K_ballast", "K_slab", "K_layer")


class _Triplets:
    """COO triplets of one matrix in the full DOF numbering."""

    def __init__(self):
        self.rows, self.cols, self.vals = [], [], []

    def add(self, idx, block):
        """Add the square ``block`` on the DOFs ``idx``."""
        idx = np.asarray(idx)
        block = np.asarray(block, dtype=float)
        r, c = np.meshgrid(idx, idx, indexing="ij")
        self.rows.append(r.ravel())
        self.cols.append(c.ravel())
        self.vals.append(block.ravel())

    def add_many(self, idx, blocks):
        """Add n blocks: ``idx`` (n, k) DOFs of each, ``blocks`` (k, k) or (n, k, k)."""
        idx = np.asarray(idx)
        n, k = idx.shape
        blocks = np.broadcast_to(np.asarray(blocks, dtype=float), (n, k, k))
        self.rows.append(np.repeat(idx, k, axis=1).ravel())
        self.cols.append(np.tile(idx, (1, k)).ravel())
        self.vals.append(blocks.ravel())

    def coo(self):
        """``(rows, cols, vals)`` of every entry added (duplicates not summed)."""
        if not self.rows:
            return np.zeros(0, int), np.zeros(0, int), np.zeros(0)
        return np.concatenate(self.rows), np.concatenate(self.cols), np.concatenate(self.vals)


@dataclass(frozen=True)
class Pattern:
    """A fixed CSC sparsity pattern of an ``n x n`` matrix.

    Attributes
    ----------
    n : int
        Matrix size.
    keys : ndarray of int64
        ``col * n + row`` of each stored entry, sorted (CSC order).
    hint : ndarray of int, optional
        An order of the indices that :attr:`band` tries beside reverse Cuthill-McKee.
    """

    n: int
    keys: np.ndarray
    hint: np.ndarray | None = field(default=None, compare=False)

    @classmethod
    def union(cls, n: int, rows: Iterable[np.ndarray], cols: Iterable[np.ndarray],
              hint: np.ndarray | None = None) -> Pattern:
        """The pattern holding every ``(row, col)`` given; negative (removed) indices are skipped."""
        rr, cc = np.concatenate(list(rows)), np.concatenate(list(cols))
        ok = (rr >= 0) & (cc >= 0)
        return cls(n, np.unique(cc[ok].astype(np.int64) * n + rr[ok]), hint)

    @cached_property
    def indices(self) -> np.ndarray:
        """Row index of each stored entry (CSC ``indices``)."""
        return (self.keys % self.n).astype(np.int32)

    @cached_property
    def indptr(self) -> np.ndarray:
        """Start of each column in the stored entries (CSC ``indptr``)."""
        return np.searchsorted(self.keys // self.n, np.arange(self.n + 1)).astype(np.int32)

    def positions(self, rows: np.ndarray, cols: np.ndarray) -> np.ndarray:
        """Position in the data vector of each ``(row, col)``, which must be in the pattern."""
        return np.searchsorted(self.keys, np.asarray(cols).astype(np.int64) * self.n + rows)

    def sum(self, rows: np.ndarray, cols: np.ndarray, vals: np.ndarray) -> np.ndarray:
        """Data vector of the COO entries summed on the pattern; entries with an index -1 are dropped."""
        out = np.zeros(self.keys.size, dtype=float)
        ok = (rows >= 0) & (cols >= 0)
        np.add.at(out, self.positions(rows[ok], cols[ok]), vals[ok])
        return out

    def csc(self, data: np.ndarray) -> sp.csc_matrix:
        """The matrix with ``data`` on this pattern."""
        return sp.csc_matrix((data, self.indices, self.indptr), shape=(self.n, self.n))

    @cached_property
    def band(self) -> tuple[BandOrder, np.ndarray] | None:
        """``(order, positions)``: the reverse Cuthill-McKee order of the pattern and the position of
        each stored entry in LAPACK's band storage (:mod:`semitrack.dynamics.factor`); None when the
        pattern is not a narrow band (not a chain: :meth:`solve` falls back to a sparse LU)."""
        rows, cols = self.indices.astype(np.int64), self.keys // max(self.n, 1)
        order = BandOrder.of(rows, cols, self.n, self.hint)
        return None if order is None else (order, order.solver_positions(rows, cols))

    def solve(self, data: np.ndarray, rhs: np.ndarray) -> np.ndarray:
        """Solve ``A x = rhs`` for the matrix ``A`` with ``data`` on this pattern.

        As a band matrix in the pattern's reverse Cuthill-McKee order (LAPACK ``gbsv``, partial
        pivoting; see the module docstring), or by a sparse LU when the pattern is not a narrow
        band.

        Parameters
        ----------
        data : ndarray
            The stored entries (CSC order), real or complex.
        rhs : ndarray, shape (n, n_rhs)
            Right-hand sides.

        Returns
        -------
        ndarray, shape (n, n_rhs)
        """
        if self.band is None:
            return SparseLU(self.csc(np.asarray(data, dtype=np.result_type(data, rhs)))).solve(rhs)
        return band_solve(*self.band, data, rhs)


@dataclass(frozen=True)
class TrackMatrices:
    """The assembled families of a track model on one pattern.

    Attributes
    ----------
    pattern : Pattern
        The common CSC pattern (model DOFs).
    data : dict
        ``{family: data vector on the pattern}`` for each of :data:`FAMILIES` (SI units), summed
        over the tracks.
    by_track : tuple of dict
        Per track (one, or two with a transition): ``{family: data vector}`` of :data:`DAMPED`.
    exact : dict
        ``{side: positions}`` of the row-major 2x2 block of the rail's ``(w, psi)`` at each
        frequency-dependent end, where its end stiffness is added.
    """

    pattern: Pattern
    data: Mapping[str, np.ndarray]
    by_track: tuple[Mapping[str, np.ndarray], ...]
    exact: Mapping[Side, np.ndarray]

    def with_supports(self, old: tuple[dict, tuple[dict, ...]], new: tuple[dict, tuple[dict, ...]]) -> TrackMatrices:
        """The same families with the supports' share ``old`` exchanged for ``new`` (:func:`supports_share`)."""
        by_track = tuple({key: t[key] - o[key] + n[key] for key in t} for t, o, n in zip(self.by_track, old[1], new[1]))
        data = dict(self.data)
        data["M"] = self.data["M"] - old[0]["M"] + new[0]["M"]
        data.update({key: sum(t[key] for t in by_track) for key in DAMPED})
        return TrackMatrices(pattern=self.pattern, data=data, by_track=by_track, exact=self.exact)


def _add_foundations(shared: dict, damped: Sequence[dict], mesh: Mesh, dofs: DofMap,
                     foundations: Sequence[Foundation], supports: Mapping[str, np.ndarray]) -> None:
    """Add each track's pads and what carries them (its foundation DOFs numbered track by track)."""
    start = 0
    for p, foundation in enumerate(foundations):
        on = mesh.support_part == p
        n_own = foundation.n_dofs(int(on.sum()))
        foundation.assemble({**damped[p], "M": shared["M"]}, mesh.support_nodes[on],
                            dofs.foundation[start:start + n_own], {key: v[on] for key, v in supports.items()})
        start += n_own


def supports_share(matrices: TrackMatrices, mesh: Mesh, dofs: DofMap, foundations: Sequence[Foundation],
                   supports: Mapping[str, np.ndarray]) -> tuple[dict, tuple[dict, ...]]:
    """What the supports add to each family, on the model's pattern: ``(shared, by_track)`` data vectors.

    The families are linear in the supports' values and the pattern holds every support's
    entries whatever its values (a removed pad adds zeros), so a model with other support values
    is the same model with this share exchanged (:meth:`TrackMatrices.with_supports`).
    """
    shared = {"M": _Triplets()}
    damped = [{key: _Triplets() for key in DAMPED} for _ in foundations]
    _add_foundations(shared, damped, mesh, dofs, foundations, supports)
    pattern = matrices.pattern

    def summed(triplets):
        r, c, v = triplets.coo()
        return pattern.sum(dofs.index[r], dofs.index[c], v)

    return {"M": summed(shared["M"])}, tuple({key: summed(t) for key, t in g.items()} for g in damped)


def _add_rail(parts: dict, mesh: Mesh, track: Track, which: np.ndarray) -> None:
    """The rail elements ``which`` of ``track``: one element matrix per distinct length."""
    el_dofs = mesh.element_dofs()[which]
    lengths = mesh.lengths[which]
    for h in np.unique(lengths):
        same = lengths == h
        k_el, m_el = rail_element(track, float(h))
        parts["K_rail"].add_many(el_dofs[same], k_el)
        parts["M"].add_many(el_dofs[same], m_el)


def _add_joints(parts: dict, mesh: Mesh, joints: Sequence[float]) -> None:
    """A rotational spring between the two rotations at each joint node (left, then the joint's own)."""
    for i, (node, k_rot) in enumerate(zip(mesh.joint_nodes, joints)):
        parts["K_joint"].add([rail_dof(int(node), "psi"), 2 * mesh.n_nodes + i],
                             k_rot * np.array([[1.0, -1.0], [-1.0, 1.0]]))


def _add_ends(parts: dict, mesh: Mesh, dofs: DofMap, ends: Mapping[Side, End]) -> None:
    """The ends' own ``M, C, K`` (equivalent systems, mirrored at the left) on their node and internal DOFs."""
    for side, end in ends.items():
        matrices = end.matrices(side)
        if matrices is None:
            continue
        node = mesh.end_node(side)
        idx = np.concatenate(([rail_dof(node, "w"), rail_dof(node, "psi")], dofs.systems.get(side, [])))
        for family, X in zip(("M", "C_end", "K_end"), matrices):
            parts[family].add(idx, X)


def _end_blocks(mesh: Mesh, dofs: DofMap, ends: Mapping[Side, End]) -> dict:
    """``{side: (rows, cols)}`` model indices of the 2x2 block at each frequency-dependent end, row-major."""
    out = {}
    for side in SIDES:
        if side in ends and ends[side].frequency_dependent:
            node = mesh.end_node(side)
            idx = dofs.index[[rail_dof(node, "w"), rail_dof(node, "psi")]]
            r, c = np.meshgrid(idx, idx, indexing="ij")
            out[side] = (r.ravel(), c.ravel())
    return out


def assemble(tracks: Sequence[Track], mesh: Mesh, dofs: DofMap, foundations: Sequence[Foundation],
             ends: Mapping[Side, End], supports: Mapping[str, np.ndarray], joints: Sequence[float] = ()
             ) -> TrackMatrices:
    """Assemble every family of a track model on one pattern (see the module docstring).

    Parameters
    ----------
    tracks : sequence of Track
        Rail, pad and (ballasted) sleeper and ballast parameters: one track, or the two of a
        transition (``mesh.part`` and ``mesh.support_part`` say which is where).
    mesh : Mesh
        The rail's mesh.
    dofs : DofMap
        The DOF numbering; pinned DOFs (index -1) are dropped. The foundation DOFs are numbered
        track by track, in the order of the supports.
    foundations : sequence of Foundation
        What carries the pads of each track (:mod:`semitrack.fe.supports`).
    ends : mapping of side to End
        The model's ends (:mod:`semitrack.fe.ends`): their own matrices are assembled, and the
        2x2 blocks of the frequency-dependent ones are put in the pattern.
    supports : mapping
        Each support's values (:func:`semitrack.fe.supports.support_values`).
    joints : sequence of float
        The rotational stiffness (N m/rad) of each joint of ``mesh.joint_nodes`` (in order of x).

    Returns
    -------
    TrackMatrices
    """
    shared = {key: _Triplets() for key in FAMILIES if key not in DAMPED}
    damped = [{key: _Triplets() for key in DAMPED} for _ in tracks]
    for p, track in enumerate(tracks):
        _add_rail({**damped[p], "M": shared["M"]}, mesh, track, mesh.part == p)
    _add_foundations(shared, damped, mesh, dofs, foundations, supports)
    _add_joints(shared, mesh, joints)
    _add_ends(shared, mesh, dofs, ends)
    groups = [shared, *damped]
    reduced = [{key: (dofs.index[r], dofs.index[c], v) for key, (r, c, v) in ((k, t.coo()) for k, t in g.items())}
               for g in groups]
    blocks = _end_blocks(mesh, dofs, ends)
    entries = [e for g in reduced for e in g.values()]
    pattern = Pattern.union(dofs.n_dof, [r for r, _, _ in entries] + [r for r, _ in blocks.values()],
                            [c for _, c, _ in entries] + [c for _, c in blocks.values()], dofs.along_track(mesh))
    by_track = tuple({key: pattern.sum(*e) for key, e in g.items()} for g in reduced[1:])
    data = {key: pattern.sum(*e) for key, e in reduced[0].items()}
    data.update({key: sum(t[key] for t in by_track) for key in DAMPED})
    exact = {side: pattern.positions(r, c) for side, (r, c) in blocks.items()}
    return TrackMatrices(pattern=pattern, data=data, by_track=by_track, exact=exact)
