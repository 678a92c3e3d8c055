"""Second-order systems ``M a + C v + K u = f`` with named DOF blocks, and their union.

A system is what a time or frequency-domain solver needs of a structure and nothing of where it
came from: sparse real ``M, C, K``, the names of its DOF blocks (``{"track": slice(0, 483),
"wheel 0": slice(483, 484)}``) and the first-order state blocks attached to its DOFs
(:class:`semitrack.dynamics.states.StateBlock`). Several systems (a track, wheels, a bogie, end
models) join by :func:`union`: block-diagonal matrices, the blocks renamed by part, plus the
springs and dampers that connect DOFs of different parts.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from ..base.errors import InputError, InputTypeError
from .states import StateBlock

__all__ = ["SecondOrderSystem", "Connection", "union", "as_real_matrix"]


def as_real_matrix(name: str, X, n: int | None = None) -> sp.csc_matrix:
    """A real square sparse matrix from a dense or sparse one, checked (name quoted in errors)."""
    if not sp.issparse(X):
        try:
            X = np.asarray(X, dtype=float)
        except (TypeError, ValueError):
            raise InputTypeError(f"{name} must be a real matrix (dense or scipy.sparse), "
                                 f"got {type(X).__name__}") from None
        X = sp.csc_matrix(X)
    if np.iscomplexobj(X.data):
        raise InputTypeError(f"{name} must be real, got a complex matrix")
    if X.ndim != 2 or X.shape[0] != X.shape[1]:
        raise InputError(f"{name} must be square, got shape {X.shape}")
    if n is not None and X.shape[0] != n:
        raise InputError(f"{name} must have shape ({n}, {n}) like M, got {X.shape}")
    return sp.csc_matrix(X, dtype=float)


@dataclass(frozen=True, eq=False)
class SecondOrderSystem:
    """``M a + C v + K u = f``: real sparse matrices, named DOF blocks and attached state blocks.

    Parameters
    ----------
    M, C, K : sparse or dense real matrices, shape (n, n)
        Mass (kg...), damping (N s/m...) and stiffness (N/m...).
    blocks : mapping of str to slice, optional
        Named ranges of DOFs; default one block ``"dofs"`` of all.
    states : sequence of StateBlock
        First-order elements attached to DOFs (their static stiffness and dashpot, if any, are
        part of ``K`` and ``C``).
    order : array_like of int, optional
        A suggested elimination order of the DOFs (a permutation), e.g. by position along a
        track; the factorisation takes it where it gives a narrower band than its own.

    Examples
    --------
    >>> s = SecondOrderSystem([[2.0]], [[0.0]], [[8.0]])
    >>> s.n_dof, list(s.blocks)
    (1, ['dofs'])
    """

    M: sp.csc_matrix
    C: sp.csc_matrix
    K: sp.csc_matrix
    blocks: Mapping[str, slice] = field(default_factory=dict)
    states: tuple[StateBlock, ...] = ()
    order: np.ndarray | None = None

    def __post_init__(self):
        M = as_real_matrix("M", self.M)
        n = M.shape[0]
        object.__setattr__(self, "M", M)
        object.__setattr__(self, "C", as_real_matrix("C", self.C, n))
        object.__setattr__(self, "K", as_real_matrix("K", self.K, n))
        object.__setattr__(self, "blocks", dict(self.blocks) or {"dofs": slice(0, n)})
        object.__setattr__(self, "states", tuple(self.states))
        if self.order is not None:
            order = np.asarray(self.order, dtype=np.int64)
            if order.shape != (n,) or not np.array_equal(np.sort(order), np.arange(n)):
                raise InputError(f"order must be a permutation of the {n} DOFs, got {self.order!r}")
            object.__setattr__(self, "order", order)
        for blk in self.states:
            if not isinstance(blk, StateBlock):
                raise InputTypeError(f"states must be StateBlocks, got {type(blk).__name__}")
            if blk.dofs.size and not (0 <= blk.dofs.min() and blk.dofs.max() < n):
                raise InputError(f"state block {blk.label!r} acts on DOFs {blk.dofs.tolist()} outside [0, {n})")

    @property
    def n_dof(self) -> int:
        """Number of DOFs."""
        return self.M.shape[0]

    def dofs(self, block: str) -> np.ndarray:
        """The DOF indices of a named block."""
        try:
            s = self.blocks[block]
        except KeyError:
            raise KeyError(f"no DOF block {block!r}; the blocks are {list(self.blocks)}") from None
        return np.arange(self.n_dof)[s]


@dataclass(frozen=True)
class Connection:
    """A spring ``k`` and a damper ``c`` between two DOFs of a union (or a DOF and the ground).

    Attributes
    ----------
    a, b : tuple of (str, int)
        ``(part name, local DOF)`` of each end; ``b=None`` connects ``a`` to the ground.
    k : float
        Stiffness (N/m).
    c : float
        Viscous damping (N s/m).
    """

    a: tuple[str, int]
    b: tuple[str, int] | None
    k: float
    c: float = 0.0


def union(parts: Mapping[str, SecondOrderSystem], connections: Sequence[Connection] = ()) -> SecondOrderSystem:
    """Join systems into one: block-diagonal matrices, blocks named ``"<part>"`` or ``"<part>.<block>"``.

    Parameters
    ----------
    parts : mapping of str to SecondOrderSystem
        The systems, in DOF order.
    connections : sequence of Connection
        Springs and dampers between DOFs of the parts (or to the ground).

    Returns
    -------
    SecondOrderSystem

    Examples
    --------
    A mass on a spring on a mass:

    >>> one = SecondOrderSystem([[1.0]], [[0.0]], [[0.0]])
    >>> two = union({"upper": one, "lower": one}, [Connection(("upper", 0), ("lower", 0), 100.0)])
    >>> two.K.toarray().tolist(), two.dofs("lower").tolist()
    ([[100.0, -100.0], [-100.0, 100.0]], [1])
    """
    offsets, blocks, states, orders, start = {}, {}, [], [], 0
    for name, part in parts.items():
        if not isinstance(part, SecondOrderSystem):
            raise InputTypeError(f"part {name!r} must be a SecondOrderSystem, got {type(part).__name__}")
        offsets[name] = start
        for block, s in part.blocks.items():
            key = name if len(part.blocks) == 1 else f"{name}.{block}"
            blocks[key] = slice(start + (s.start or 0), start + (s.stop if s.stop is not None else part.n_dof))
        states.extend(blk.renumbered(start + np.arange(part.n_dof)) for blk in part.states)
        orders.append(start + (part.order if part.order is not None else np.arange(part.n_dof)))
        start += part.n_dof
    links = {"K": [], "C": []}  # (row, col, value) of each connection's spring and damper
    for link in connections:
        idx = [_global(offsets, parts, end) for end in (link.a, link.b) if end is not None]
        sign = np.array([1.0, -1.0])[: len(idx)]
        for X, value in (("K", link.k), ("C", link.c)):
            for i, si in zip(idx, sign):
                for j, sj in zip(idx, sign):
                    links[X].append((i, j, si * sj * value))
    M, C, K = (_block_diagonal([getattr(p, X) for p in parts.values()], links.get(X, []), start) for X in "MCK")
    order = np.concatenate(orders) if any(p.order is not None for p in parts.values()) else None
    return SecondOrderSystem(M, C, K, blocks, tuple(states), order)


def _block_diagonal(blocks: Sequence[sp.spmatrix], extra: Sequence[tuple[int, int, float]], n: int) -> sp.csc_matrix:
    """The blocks on the diagonal plus ``extra`` entries, summed: by triplets (a LIL matrix costs
    20 ms on a 6000-DOF track, which the travelling window pays at every move)."""
    rows, cols, vals, start = [], [], [], 0
    for X in blocks:
        coo = sp.coo_matrix(X)
        rows.append(coo.row + start)
        cols.append(coo.col + start)
        vals.append(coo.data)
        start += X.shape[0]
    if extra:
        r, c, v = zip(*extra)
        rows.append(np.asarray(r))
        cols.append(np.asarray(c))
        vals.append(np.asarray(v, dtype=float))
    return sp.csc_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(n, n))


def _global(offsets: dict, parts: Mapping, end: tuple[str, int]) -> int:
    name, local = end
    if name not in parts:
        raise InputError(f"connection names part {name!r}; the parts are {list(parts)}")
    if not 0 <= local < parts[name].n_dof:
        raise InputError(f"connection DOF {local} of part {name!r} must be in [0, {parts[name].n_dof})")
    return offsets[name] + int(local)
