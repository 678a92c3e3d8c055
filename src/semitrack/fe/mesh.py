"""The mesh of an FE track and its DOF map: node positions, supports, and the numbering of every DOF.

Geometry
    x is measured from the central cross-section (or the cut of a semi-infinite track), which is
    a mid-span; the supports sit at ``x = (k + 1/2) d`` and the ends of the model are mid-spans,
    so the paper's equivalent system attaches exactly at an end. Each half bay is divided into
    ``elements_per_bay / 2`` equal elements (so mid-spans and supports are nodes).

DOF numbering (the *full* numbering, before pinned DOFs are removed)
    the rail's ``(w, psi)`` per node, node by node (``2 j`` and ``2 j + 1``); then the second
    rotation of each joint (the rail's rotation just right of the cut), in order along x; then the
    foundation's DOFs (one vertical DOF per sleeper on a ballasted track, in the order of the
    supports; :mod:`semitrack.fe.supports`); then the internal DOFs of the end at the left, then
    those at the right (an equivalent system's DOFs but its first two, which are the rail's
    ``(w, psi)`` at the end node). A pinned end removes the rail's ``w`` at its end node;
    :attr:`DofMap.index` maps the full numbering to the model's (``-1`` for a removed DOF).
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from typing import Literal

import numpy as np

__all__ = ["Side", "Kind", "SIDES", "KINDS", "Mesh", "bay_mesh", "DofMap", "rail_dof", "dof_map"]

#: An end of the model.
Side = Literal["left", "right"]
#: A rail DOF at a node: vertical displacement (m) or clockwise rotation (rad).
Kind = Literal["w", "psi"]
KINDS: tuple[Kind, Kind] = ("w", "psi")
SIDES: tuple[Side, Side] = ("left", "right")


@dataclass(frozen=True)
class Mesh:
    """Nodes and elements of the rail between two mid-span cuts.

    Attributes
    ----------
    x : ndarray
        Node positions (m), increasing.
    lengths : ndarray
        Length of each element (m): equal within a bay, shorter where a joint splits one.
    part : ndarray of int
        The track each element belongs to: 0, or 1 past a transition.
    support_nodes : ndarray of int
        Indices of the nodes that carry a support, in order along x.
    support_index : ndarray of int
        The index k of each support (:class:`semitrack.InfiniteTrack`'s numbering).
    support_part : ndarray of int
        The track each support belongs to.
    joint_nodes : ndarray of int
        Nodes where the rail is cut by a joint: the element on the right of one takes a rotation
        DOF of its own (numbered after every node's, see the module docstring).
    """

    x: np.ndarray
    lengths: np.ndarray
    part: np.ndarray
    support_nodes: np.ndarray
    support_index: np.ndarray
    support_part: np.ndarray
    joint_nodes: np.ndarray

    @property
    def n_nodes(self) -> int:
        """Number of rail nodes."""
        return self.x.size

    @property
    def n_elements(self) -> int:
        """Number of rail elements."""
        return self.x.size - 1

    @property
    def n_rail_dofs(self) -> int:
        """Number of the rail's DOFs: two per node, one more per joint."""
        return 2 * self.n_nodes + self.joint_nodes.size

    def element_dofs(self) -> np.ndarray:
        """Full DOF indices ``(w_a, psi_a, w_b, psi_b)`` of every element, shape (n_elements, 4).

        The element on the right of a joint node takes that joint's own rotation as ``psi_a``."""
        out = 2 * np.arange(self.n_elements)[:, None] + np.arange(4)[None, :]
        out[self.joint_nodes, 1] = 2 * self.n_nodes + np.arange(self.joint_nodes.size)
        return out

    def end_node(self, side: Side) -> int:
        """Index of the node at the ``"left"`` or ``"right"`` end."""
        return 0 if side == "left" else self.n_nodes - 1

    def locate(self, xp: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The element that holds each position of ``xp`` (m) and the local coordinate ``xi`` in [0, 1] there.

        Positions must lie on the rail (the caller checks); a node between two elements belongs to
        the element on its right, the last node to the last element.
        """
        xp = np.asarray(xp, dtype=float)
        e = np.clip(np.searchsorted(self.x, xp, side="right") - 1, 0, self.n_elements - 1)
        return e, np.clip((xp - self.x[e]) / self.lengths[e], 0.0, 1.0)


def bay_mesh(spacing: float, n_left: int, n_right: int, elements_per_bay: int, *, right_spacing: float | None = None,
             transition: int | None = None, joints: Iterable[float] = ()) -> Mesh:
    """Mesh of ``n_left`` bays left and ``n_right`` bays right of a mid-span at x = 0.

    Parameters
    ----------
    spacing : float
        Support spacing d (m).
    n_left, n_right : int
        Bays left and right of x = 0 (checked by the caller).
    elements_per_bay : int
        Even number of elements per bay (checked by the caller).
    right_spacing : float, optional
        The spacing d2 (m) of the second track, from the transition on.
    transition : int, optional
        ``kt``: the bays from the mid-span ``x_t = kt d`` on are the second track's, of length
        d2, their supports at ``x_t + (j + 1/2) d2`` numbered ``kt + j``; ``-n_left <= kt <= n_right``.
    joints : iterable of float
        Positions (m) where the rail is cut (checked by the caller: on the rail, not at a
        support); each becomes a node, splitting the element it falls in.

    Returns
    -------
    Mesh
        Nodes from ``-n_left d`` to the right end; supports in the middle of every bay.

    Examples
    --------
    >>> m = bay_mesh(0.6, 1, 1, 4)
    >>> m.x.round(2).tolist(), m.support_nodes.tolist()
    ([-0.6, -0.45, -0.3, -0.15, 0.0, 0.15, 0.3, 0.45, 0.6], [2, 6])
    >>> bay_mesh(0.6, 1, 1, 2, right_spacing=0.65, transition=0).x.round(3).tolist()
    [-0.6, -0.3, 0.0, 0.325, 0.65]
    """
    bays = np.arange(-n_left, n_right)
    kt = n_right if transition is None else transition
    part = (bays >= kt).astype(np.int64)
    d2 = spacing if right_spacing is None else right_spacing
    starts = np.where(part == 0, bays * spacing, kt * spacing + (bays - kt) * d2)
    widths = np.where(part == 0, spacing, d2)
    ne = elements_per_bay
    x = (starts[:, None] + widths[:, None] * (np.arange(ne) / ne)[None, :]).ravel()
    x = np.append(x, starts[-1] + widths[-1] if bays.size else -n_left * spacing)
    cuts = np.sort(np.asarray(list(joints), dtype=float))
    x = np.unique(np.concatenate([x, cuts]))
    x = x[np.concatenate([[True], np.diff(x) > 1e-9 * min(spacing, d2)])]
    x[np.abs(x) < 1e-12 * spacing] = 0.0
    def node(xs):  # the nearest node of each position (the nodes are sorted)
        j = np.clip(np.searchsorted(x, xs), 1, max(x.size - 1, 1))
        return np.where(np.abs(x[j - 1] - xs) <= np.abs(x[np.minimum(j, x.size - 1)] - xs), j - 1, j)

    mids = 0.5 * (x[:-1] + x[1:])
    element_bay = np.clip(np.searchsorted(starts, mids, side="right") - 1, 0, max(bays.size - 1, 0))
    return Mesh(x=x, lengths=np.diff(x), part=part[element_bay] if bays.size else np.zeros(0, np.int64),
                support_nodes=node(starts + widths / 2).astype(np.int64), support_index=bays.astype(np.int64),
                support_part=part, joint_nodes=node(cuts).astype(np.int64))


@dataclass(frozen=True)
class DofMap:
    """Where each DOF of an FE track sits, in the full numbering and in the model's.

    Attributes
    ----------
    n_full : int
        Number of DOFs before pinned DOFs are removed.
    foundation : ndarray of int
        Full indices of the foundation's DOFs (the sleepers; empty for a rigid foundation).
    foundation_nodes : ndarray of int
        The rail node each foundation DOF sits under.
    systems : dict
        ``{side: full indices of the internal DOFs}`` of each end that has some.
    index : ndarray of int
        Model index of each full DOF; -1 where a pinned end removed it.
    """

    n_full: int
    foundation: np.ndarray
    foundation_nodes: np.ndarray
    systems: Mapping[Side, np.ndarray]
    index: np.ndarray

    @property
    def n_dof(self) -> int:
        """Number of DOFs of the model (pinned DOFs removed)."""
        return int(np.count_nonzero(self.index >= 0))

    def foundation_dof_under(self, nodes) -> np.ndarray:
        """The model DOF of the first foundation DOF under each rail node (a sleeper's, or a slab node's w);
        -1 where none is.

        Parameters
        ----------
        nodes : array_like of int
            Rail nodes.

        Returns
        -------
        ndarray of int
        """
        first = {}
        for j, n in enumerate(self.foundation_nodes):
            first.setdefault(int(n), j)
        return np.array([self.index[self.foundation[first[int(n)]]] if int(n) in first else -1
                         for n in np.atleast_1d(nodes)], dtype=np.int64)

    def along_track(self, mesh: Mesh) -> np.ndarray:
        """The model's DOFs in the order of their place along the track: each node's (w, psi),
        a joint's second rotation, then its sleeper; an end's own DOFs beside its end node.

        A band order for the factorisations (:class:`semitrack.dynamics.factor.BandOrder`): a
        sleeper right after its rail node keeps the half-bandwidth at 3, where reverse
        Cuthill-McKee places the sleepers so that it is 6.
        """
        n_rail = 2 * mesh.n_nodes
        position = np.empty(self.n_full)
        rank = np.empty(self.n_full)
        position[:n_rail] = np.repeat(mesh.x, 2)
        rank[:n_rail] = np.tile([0.0, 1.0], mesh.n_nodes)
        position[n_rail:mesh.n_rail_dofs] = mesh.x[mesh.joint_nodes]
        rank[n_rail:mesh.n_rail_dofs] = 1.5
        position[self.foundation] = mesh.x[self.foundation_nodes]
        rank[self.foundation] = 2.0
        for side, internal in self.systems.items():
            node = mesh.end_node(side)
            position[internal] = mesh.x[node]
            rank[internal] = (-1.0 if side == "left" else 3.0) + np.arange(internal.size) / (internal.size + 1)
        full = np.lexsort((rank, position))
        model = self.index[full]
        return model[model >= 0]


def rail_dof(node: int, kind: Kind = "w") -> int:
    """Full index of the rail DOF ``kind`` ("w" or "psi") at ``node``."""
    return 2 * node + (kind == "psi")


def dof_map(mesh: Mesh, foundation_nodes: np.ndarray, system_dofs: Mapping[Side, int], pinned: Iterable[Side]
            ) -> DofMap:
    """Number the DOFs of a track model (see the module docstring).

    Parameters
    ----------
    mesh : Mesh
        The rail's mesh.
    foundation_nodes : ndarray of int
        The rail node under which each of the foundation's DOFs sits (one per support on a
        ballasted track, none on a slab track), in the order they are numbered.
    system_dofs : mapping
        ``{side: number of internal DOFs}`` of the end at that side (sides without any may be left out).
    pinned : iterable of {"left", "right"}
        Ends whose rail ``w`` is removed.

    Returns
    -------
    DofMap

    Examples
    --------
    >>> dofs = dof_map(bay_mesh(0.6, 1, 1, 4), np.array([2, 6]), {"right": 3}, ["left"])
    >>> dofs.n_full, dofs.n_dof, dofs.foundation.tolist(), dofs.systems["right"].tolist()
    (23, 22, [18, 19], [20, 21, 22])
    """
    foundation_nodes = np.asarray(foundation_nodes, dtype=np.int64)
    foundation = mesh.n_rail_dofs + np.arange(foundation_nodes.size)
    n_full = mesh.n_rail_dofs + foundation_nodes.size
    systems = {}
    for side in SIDES:
        if system_dofs.get(side, 0):
            systems[side] = np.arange(n_full, n_full + system_dofs[side])
            n_full += system_dofs[side]
    keep = np.ones(n_full, dtype=bool)
    for side in pinned:
        keep[rail_dof(mesh.end_node(side), "w")] = False
    index = np.full(n_full, -1, dtype=np.int64)
    index[keep] = np.arange(int(keep.sum()))
    return DofMap(n_full=n_full, foundation=foundation, foundation_nodes=foundation_nodes, systems=systems,
                  index=index)
