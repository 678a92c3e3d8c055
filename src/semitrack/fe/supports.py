"""What carries the pads of an FE track model: one class per kind of foundation, asked by the assembly.

Each support of the model is a rail node with a pad on it (a vertical spring ``kv`` and a
rotational spring ``kphi``, loss factor ``eta_pad``). Under the pads:

``RigidFoundation``
    the slab track of the paper: both pad springs from the rail node to the ground.
``SleepersOnBallast``
    the ballasted track: ``kphi`` from the rail rotation to the ground (the sleeper does not
    rotate), ``kv`` between the rail node and a sleeper mass, the ballast ``kb`` (loss factor
    ``eta_ballast``) from the sleeper to the ground: one DOF per support.

A foundation adds its own DOFs to the model (:meth:`Foundation.n_dofs`) and its springs and
masses to the matrix families of :mod:`semitrack.fe.assembly` (:meth:`Foundation.assemble`). A
flexible slab under the pads (:class:`semitrack.Slab`) is a foundation the FE models do not
have yet: :func:`foundation_of` says so.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from ..model.tracks import Track

__all__ = ["Foundation", "RigidFoundation", "SleepersOnBallast", "foundation_of"]


@dataclass(frozen=True)
class Foundation:
    """The base of the foundation kinds (see the module docstring)."""

    name: ClassVar[str] = ""

    def n_dofs(self, n_supports: int) -> int:
        """Number of DOFs the foundation adds for ``n_supports`` supports."""
        return 0

    def assemble(self, parts: dict, support_nodes: np.ndarray, dofs: np.ndarray, track: Track) -> None:
        """Add the pads and what is under them to the families ``parts`` (triplets of full DOF indices).

        Parameters
        ----------
        parts : dict
            ``{family: triplets}`` of :mod:`semitrack.fe.assembly`.
        support_nodes : ndarray of int
            The rail nodes that carry a support.
        dofs : ndarray of int
            Full indices of the foundation's own DOFs (:meth:`n_dofs` of them).
        track : Track
            Pad and foundation parameters.
        """
        psi = 2 * support_nodes + 1
        if track.kphi > 0:
            parts["K_pad"].add_many(psi[:, None], np.array([[track.kphi]]))


@dataclass(frozen=True)
class RigidFoundation(Foundation):
    """Pads from the rail to the ground (the paper's slab track)."""

    name: ClassVar[str] = "rigid foundation"

    def assemble(self, parts: dict, support_nodes: np.ndarray, dofs: np.ndarray, track: Track) -> None:
        super().assemble(parts, support_nodes, dofs, track)
        parts["K_pad"].add_many(2 * support_nodes[:, None], np.array([[track.kv]]))


@dataclass(frozen=True)
class SleepersOnBallast(Foundation):
    """Pads on sleeper masses on ballast springs (the paper's ballasted track): one DOF per support."""

    name: ClassVar[str] = "sleepers on ballast"

    def n_dofs(self, n_supports: int) -> int:
        return n_supports

    def assemble(self, parts: dict, support_nodes: np.ndarray, dofs: np.ndarray, track: Track) -> None:
        super().assemble(parts, support_nodes, dofs, track)
        pad = track.kv * np.array([[1.0, -1.0], [-1.0, 1.0]])
        parts["K_pad"].add_many(np.stack([2 * support_nodes, dofs], 1), pad)
        parts["K_ballast"].add_many(dofs[:, None], np.array([[track.kb]]))
        parts["M"].add_many(dofs[:, None], np.array([[track.sleeper_mass]]))


def foundation_of(track: Track) -> Foundation:
    """The foundation of a track's FE model.

    Parameters
    ----------
    track : Track
        The track.

    Returns
    -------
    Foundation

    Raises
    ------
    NotImplementedError
        For a flexible slab (``track.slab``), which the FE models do not hold yet.

    Examples
    --------
    >>> from semitrack.model.tracks import ballasted_track
    >>> foundation_of(ballasted_track()).name
    'sleepers on ballast'
    """
    if track.has_flexible_slab:
        raise NotImplementedError(
            "the finite-element track models hold pads on a rigid foundation or on sleepers; a flexible "
            "slab (track.slab) is not modelled there yet: use the exact method (semi_infinite_receptance, "
            "point_receptance), which handles it")
    return SleepersOnBallast() if track.is_ballasted else RigidFoundation()
