"""Point sets: where loads act and responses are read, as DOFs and weights at every step.

A point of a structure (the contact point of a wheel on the rail, a probe, a moving load) acts
on a few DOFs with weights: the shape functions of the element that holds it. A load ``F`` at
the point adds ``F * weights`` to those DOFs; the response there is ``weights @ u[dofs]``. A
point that moves has DOFs and weights per time step; one that stands still has one row. A DOF
that a boundary condition removed carries weight 0 (index 0), so every point has the same
number of entries and no mask is needed anywhere else.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from ..base.errors import InputError

__all__ = ["PointSet"]


@dataclass(frozen=True)
class PointSet:
    """Points given by DOFs and weights, fixed or per time step.

    Parameters
    ----------
    dofs : array_like of int, shape (n_rows, n_points, n_weights)
        The DOFs of each point; ``n_rows`` is 1 for points that stand still, else the number of
        time steps + 1 (a row per step, from t = 0).
    weights : array_like, shape (n_rows, n_points, n_weights)
        The weight of each DOF (-; 0 for a removed DOF).
    labels : tuple of str
        A label per point.

    Examples
    --------
    Two fixed points, each on one DOF:

    >>> p = PointSet.on_dofs([3, 5])
    >>> p.values(np.arange(10.0)).tolist(), p.moving
    ([3.0, 5.0], False)
    """

    dofs: np.ndarray
    weights: np.ndarray
    labels: tuple = field(default=())

    def __post_init__(self):
        dofs = np.asarray(self.dofs, dtype=np.int64)
        weights = np.asarray(self.weights, dtype=float)
        if dofs.ndim != 3 or weights.shape != dofs.shape:
            raise InputError(f"dofs and weights must have one shape (n_rows, n_points, n_weights), got "
                             f"{dofs.shape} and {weights.shape}")
        if np.any(dofs < 0):
            raise InputError("dofs must be non-negative (a removed DOF is index 0 with weight 0)")
        labels = tuple(self.labels) or tuple(f"point {i}" for i in range(dofs.shape[1]))
        if len(labels) != dofs.shape[1]:
            raise InputError(f"labels must name each of the {dofs.shape[1]} points, got {len(labels)}")
        object.__setattr__(self, "dofs", np.ascontiguousarray(dofs))
        object.__setattr__(self, "weights", np.ascontiguousarray(weights))
        object.__setattr__(self, "labels", labels)

    @classmethod
    def on_dofs(cls, dofs, labels: tuple = ()) -> PointSet:
        """Fixed points, each the DOF itself with weight 1."""
        dofs = np.asarray(dofs, dtype=np.int64).reshape(1, -1, 1)
        return cls(dofs, np.ones(dofs.shape), labels or tuple(f"dof {i}" for i in dofs.ravel()))

    @classmethod
    def from_matrix(cls, B, labels: tuple = ()) -> PointSet:
        """Fixed points from the columns of an ``(n, n_points)`` matrix (its non-zero entries)."""
        B = sp.csc_matrix(B)
        B.eliminate_zeros()
        width = max(int(np.diff(B.indptr).max()) if B.shape[1] else 1, 1)
        dofs = np.zeros((1, B.shape[1], width), dtype=np.int64)
        weights = np.zeros((1, B.shape[1], width))
        for j in range(B.shape[1]):
            lo, hi = B.indptr[j], B.indptr[j + 1]
            dofs[0, j, : hi - lo], weights[0, j, : hi - lo] = B.indices[lo:hi], B.data[lo:hi]
        return cls(dofs, weights, labels)

    @classmethod
    def stacked(cls, sets) -> PointSet:
        """Several point sets as one, their points in order (all fixed, or all moving over the same steps)."""
        sets = list(sets)
        width = max(p.dofs.shape[2] for p in sets)
        rows = {p.dofs.shape[0] for p in sets}
        if len(rows) != 1:
            raise InputError(f"point sets stack only with the same rows (fixed, or the same steps), got {sorted(rows)}")

        def padded(p, key):
            a = getattr(p, key)
            return np.pad(a, ((0, 0), (0, 0), (0, width - a.shape[2])))

        return cls(np.concatenate([padded(p, "dofs") for p in sets], 1),
                   np.concatenate([padded(p, "weights") for p in sets], 1), sum((p.labels for p in sets), ()))

    @property
    def n_points(self) -> int:
        """Number of points."""
        return self.dofs.shape[1]

    @property
    def moving(self) -> bool:
        """Whether the points have DOFs and weights per step."""
        return self.dofs.shape[0] > 1

    def at(self, k: int) -> tuple[np.ndarray, np.ndarray]:
        """DOFs and weights at step ``k``, each ``(n_points, n_weights)``."""
        row = k if self.moving else 0
        return self.dofs[row], self.weights[row]

    def values(self, u: np.ndarray, k: int = 0) -> np.ndarray:
        """The interpolated values ``weights @ u[dofs]`` at step ``k``, one per point."""
        dofs, weights = self.at(k)
        return np.einsum("pw,pw->p", weights, u[dofs])

    def matrix(self, n: int, k: int = 0):
        """The ``(n_points, n)`` sparse matrix of the points at step ``k``: ``values = matrix @ u``."""
        dofs, weights = self.at(k)
        rows = np.repeat(np.arange(self.n_points), dofs.shape[1])
        return sp.csr_matrix((weights.ravel(), (rows, dofs.ravel())), shape=(self.n_points, n))

    def renumbered(self, where: np.ndarray) -> PointSet:
        """The same points with DOF ``i`` renamed ``where[i]`` (e.g. into a band order)."""
        return PointSet(where[self.dofs], self.weights, self.labels)
