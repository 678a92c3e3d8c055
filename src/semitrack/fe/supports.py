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

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from ..base.errors import InputError
from ..model.curves import FrequencyCurve
from ..model.tracks import Track

__all__ = ["FE_SUPPORT_FIELDS", "Foundation", "RigidFoundation", "SleepersOnBallast", "foundation_of", "support_values"]


#: The support fields an FE model's ``changes`` may set (a loss factor is its family's: the same at every support).
FE_SUPPORT_FIELDS = ("kv", "kphi", "sleeper_mass", "kb")


#: What the FE models tell a track with frequency-dependent supports to do instead.
CONSTANT_SUPPORTS_ONLY = (
    "the FE supports are constant springs and dampers; a measured curve is not a causal model, and a standard "
    "linear solid would need an internal DOF they do not have. In the frequency domain use st.InfiniteTrack (exact, "
    "local changes too) or st.semi_infinite_receptance; for an FE or time-domain model give constant kv, kphi, "
    "eta_pad fitted where it matters (and sleeper_mass, kb for a measured sleeper), or end a truncated model with "
    "st.fit_boundary of the measured track")


def support_values(tracks: Sequence[Track], parts: np.ndarray, indices: np.ndarray, changes: Mapping | None
                   ) -> dict[str, np.ndarray]:
    """Each support's ``kv``, ``kphi``, ``sleeper_mass`` and ``kb``, and whether it is there.

    Parameters
    ----------
    tracks : sequence of Track
        The model's tracks: one, or the two of a transition.
    parts : ndarray of int
        The track of each support of the model (an index into ``tracks``), in order along x.
    indices : ndarray of int
        The index k of each support (support k of the first track sits at ``x = (k + 1/2) d``).
    changes : mapping, optional
        ``{k: {field: value}}`` (fields of :data:`FE_SUPPORT_FIELDS`) or ``{k: None}`` (no support).

    Returns
    -------
    dict
        ``{"kv", "kphi", "sleeper_mass", "kb": ndarray, "present": ndarray of bool}``, one entry
        per support (sleeper and ballast values 0 on a slab track), and each support's track's own
        ``"kb_track"`` and ``"sleeper_mass_track"`` (for a removed support's sleeper).
    """
    values = {name: np.array([float(getattr(tracks[p], name) or 0.0) for p in parts]) for name in FE_SUPPORT_FIELDS}
    values["present"] = np.ones(len(parts), dtype=bool)
    values["kb_track"], values["sleeper_mass_track"] = values["kb"].copy(), values["sleeper_mass"].copy()
    where = {int(k): i for i, k in enumerate(indices)}
    for k, fields in (changes or {}).items():
        if k not in where:
            continue
        i = where[k]
        if fields is None:
            values["present"][i] = False
            continue
        for name, value in fields.items():
            if name not in FE_SUPPORT_FIELDS:
                raise InputError(f"changes[{k}][{name!r}]: the FE models change {FE_SUPPORT_FIELDS} of a support; a "
                                 "loss factor is its family's, the same at every support (InfiniteTrack takes it)")
            if isinstance(value, FrequencyCurve):
                raise InputError(f"changes[{k}][{name!r}] is a frequency-dependent curve: {CONSTANT_SUPPORTS_ONLY}")
            values[name][i] = value
    return values


@dataclass(frozen=True)
class Foundation:
    """The base of the foundation kinds (see the module docstring)."""

    name: ClassVar[str] = ""

    def n_dofs(self, n_supports: int) -> int:
        """Number of DOFs the foundation adds for ``n_supports`` supports."""
        return 0

    def assemble(self, parts: dict, support_nodes: np.ndarray, dofs: np.ndarray, values: Mapping[str, np.ndarray]
                 ) -> None:
        """Add the pads and what is under them to the families ``parts`` (triplets of full DOF indices).

        Parameters
        ----------
        parts : dict
            ``{family: triplets}`` of :mod:`semitrack.fe.assembly`.
        support_nodes : ndarray of int
            The rail nodes that carry a support.
        dofs : ndarray of int
            Full indices of the foundation's own DOFs (:meth:`n_dofs` of them).
        values : mapping
            Each support's values (:func:`support_values`).
        """
        psi = 2 * support_nodes + 1
        parts["K_pad"].add_many(psi[:, None], (values["kphi"] * values["present"])[:, None, None])


@dataclass(frozen=True)
class RigidFoundation(Foundation):
    """Pads from the rail to the ground (the paper's slab track)."""

    name: ClassVar[str] = "rigid foundation"

    def assemble(self, parts: dict, support_nodes: np.ndarray, dofs: np.ndarray, values: Mapping[str, np.ndarray]
                 ) -> None:
        super().assemble(parts, support_nodes, dofs, values)
        parts["K_pad"].add_many(2 * support_nodes[:, None], (values["kv"] * values["present"])[:, None, None])


@dataclass(frozen=True)
class SleepersOnBallast(Foundation):
    """Pads on sleeper masses on ballast springs (the paper's ballasted track): one DOF per support.

    A removed support keeps its sleeper DOF, the track's sleeper on the track's ballast but with
    no pad to the rail (decoupled, it changes no response of the rail), so that the numbering
    stays the same.
    """

    name: ClassVar[str] = "sleepers on ballast"

    def n_dofs(self, n_supports: int) -> int:
        return n_supports

    def assemble(self, parts: dict, support_nodes: np.ndarray, dofs: np.ndarray, values: Mapping[str, np.ndarray]
                 ) -> None:
        super().assemble(parts, support_nodes, dofs, values)
        on = values["present"]
        pad = (values["kv"] * on)[:, None, None] * np.array([[1.0, -1.0], [-1.0, 1.0]])
        parts["K_pad"].add_many(np.stack([2 * support_nodes, dofs], 1), pad)
        kb = np.where(on, values["kb"], values["kb_track"])
        mass = np.where(on, values["sleeper_mass"], values["sleeper_mass_track"])
        parts["K_ballast"].add_many(dofs[:, None], kb[:, None, None])
        parts["M"].add_many(dofs[:, None], mass[:, None, None])


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
