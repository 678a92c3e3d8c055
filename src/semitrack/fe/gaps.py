"""Hanging sleepers over a gap: a ballast that carries a sleeper only once the sleeper has closed a gap.

A voided (hanging) sleeper is the most studied support defect: a gap ``g`` (m) opens between its
bottom and the ballast, so the sleeper hangs from the rail through its pad and the ballast takes
it only once it has moved down by ``g``:

    F_ballast = kb max(w_sleeper - g, 0)        (compression positive, w downward)

``g = 0`` is a plain unilateral support (it takes no tension, and lifts off where the linear one
would pull); ``g`` larger than the sleeper ever moves is the linear ``kb = 0`` sleeper of
:class:`semitrack.InfiniteTrack` (the limit ``g -> infinity``). The sleeper's ballast stiffness is
the track's ``kb`` at that support; its ballast damping is left out (a dashpot that acts only in
contact is no longer linear and would make the contact law depend on velocity).

In the engine each gap is one more contact of :class:`semitrack.dynamics.contact.HertzContacts`,
a unilateral linear spring between the sleeper's DOF and the ground (a point of weight 0), solved
with the wheels' contacts at every step: the ballast force is never negative. The model must
hold the sleeper without its linear ballast, ``changes={k: {"kb": 0.0}}``; the static start
closes the gaps the preloads close (:func:`static_with_gaps`).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from ..base.checks import check_gap, check_int_at_least
from ..base.errors import InputError, InputTypeError
from ..dynamics.factor import factorise
from ..dynamics.points import PointSet
from .models import FETrack

__all__ = ["SleeperGaps", "sleeper_gaps", "static_with_gaps", "contact_time", "GapResponse"]


@dataclass(frozen=True)
class SleeperGaps:
    """The gaps of a model's hanging sleepers, checked: support indices, their sleeper DOFs, gaps and ballast.

    Attributes
    ----------
    supports : ndarray of int
        Support indices k.
    dofs : ndarray of int
        The model DOF of each sleeper.
    gaps : ndarray
        The gaps (m).
    stiffness : ndarray
        The ballast stiffness under each sleeper once the gap is closed (N/m): the track's kb.
    """

    supports: np.ndarray
    dofs: np.ndarray
    gaps: np.ndarray
    stiffness: np.ndarray

    @property
    def n(self) -> int:
        """Number of gaps."""
        return self.supports.size

    def points(self, rows: int) -> PointSet:
        """The ground under each sleeper: points of weight 0, ``rows`` rows (1, or one per step)."""
        return PointSet(np.zeros((rows, self.n, 1), np.int64), np.zeros((rows, self.n, 1)),
                        tuple(f"ground under support {k}" for k in self.supports))

    def forces(self, w: np.ndarray) -> np.ndarray:
        """The ballast forces (N) for the sleepers' displacements ``w`` (m), ``kb max(w - g, 0)``."""
        return self.stiffness * np.maximum(w - self.gaps, 0.0)


def sleeper_gaps(model: FETrack, gaps: Mapping[int, float]) -> SleeperGaps:
    """Check the gaps against the model: ballasted supports inside it, held without their linear ballast.

    Parameters
    ----------
    model : FETrack
        The model.
    gaps : mapping of int to float
        ``{k: g}``: support k's sleeper hangs over a gap of g m (>= 0).

    Returns
    -------
    SleeperGaps
    """
    if not isinstance(gaps, Mapping):
        raise InputTypeError(f"ballast_gaps must be a mapping {{support index: gap (m)}}, got {gaps!r}")
    index = {int(k): i for i, k in enumerate(model.mesh.support_index)}
    ks, dofs, gs, kbs = [], [], [], []
    for k, g in gaps.items():
        k = check_int_at_least("ballast_gaps key (a support index)", k, -10**9)
        if k not in index:
            raise InputError(f"ballast_gaps: support {k} is not in the model (its supports are {min(index)} to "
                             f"{max(index)})")
        i = index[k]
        sleeper = int(model.dofs.foundation_dof_under(model.mesh.support_nodes[i])[0])
        if sleeper < 0 or not model.tracks[int(model.mesh.support_part[i])].is_ballasted:
            raise InputError(f"ballast_gaps: support {k} has no sleeper on ballast (a slab track's pads sit on the "
                             "ground or on a slab)")
        if model.support_values["kb"][i] != 0 or not model.support_values["present"][i]:
            raise InputError(f"ballast_gaps: build the model with changes={{{k}: {{'kb': 0.0}}}} so that support {k}'s "
                             "sleeper hangs from the rail without its linear ballast; the gap's ballast replaces it")
        ks.append(k)
        dofs.append(sleeper)
        gs.append(check_gap(f"ballast_gaps[{k}]", g))
        kbs.append(float(model.support_values["kb_track"][i]))
    return SleeperGaps(np.array(ks, np.int64), np.array(dofs, np.int64), np.array(gs, float), np.array(kbs, float))


def static_with_gaps(K: sp.csc_matrix, load: np.ndarray, gaps: SleeperGaps, max_rounds: int = 50) -> np.ndarray:
    """The static state under ``load`` with the gaps that it closes closed: an active-set solve.

    Parameters
    ----------
    K : sparse matrix
        The stiffness without the gaps' ballast (N/m...).
    load : ndarray
        The static load (N).
    gaps : SleeperGaps
        The gaps.
    max_rounds : int
        Active-set rounds before giving up (each closes or opens at least one gap).

    Returns
    -------
    ndarray
        Displacements (m): every closed gap's sleeper below its gap, every open one above.
    """
    closed = np.zeros(gaps.n, dtype=bool)
    for _ in range(max_rounds):
        k_add = sp.csc_matrix((gaps.stiffness * closed, (gaps.dofs, gaps.dofs)), shape=K.shape)
        rhs = load.copy()
        np.add.at(rhs, gaps.dofs, gaps.stiffness * gaps.gaps * closed)  # kb (w - g): a load kb g on the sleeper
        u = factorise((K + k_add).tocsc()).solve(rhs)
        w = u[gaps.dofs]
        now = w > gaps.gaps
        if np.array_equal(now, closed):
            return u
        closed = now
    raise RuntimeError(f"the static state with gaps did not settle in {max_rounds} rounds")


def contact_time(force: np.ndarray, dt: float) -> np.ndarray:
    """The time each hanging sleeper spent on its ballast (s): a step per sample with a force after the start.

    Parameters
    ----------
    force : ndarray, shape (n_steps + 1, n_gaps)
        The ballast forces (N).
    dt : float
        The time step (s).

    Returns
    -------
    ndarray, shape (n_gaps,)
    """
    return dt * np.count_nonzero(force[1:] > 0, axis=0)


@dataclass(frozen=True, eq=False)
class GapResponse:
    """What the hanging sleepers did in a run.

    Attributes
    ----------
    supports : ndarray of int
        The supports' indices.
    gaps : ndarray
        Their gaps (m).
    force : ndarray, shape (n_steps + 1, n_gaps)
        The ballast force under each sleeper (N), >= 0.
    opening : ndarray, shape (n_steps + 1, n_gaps)
        The gap left open, ``g - w_sleeper`` (m): positive while open, negative (the ballast
        compressed) in contact.
    contact_time : ndarray
        The time each sleeper spent on its ballast (s).
    """

    supports: np.ndarray
    gaps: np.ndarray
    force: np.ndarray
    opening: np.ndarray
    contact_time: np.ndarray
