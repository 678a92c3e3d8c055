"""What carries the pads of an FE track model: one class per kind of foundation, asked by the assembly.

Each support of the model is a rail node with a pad on it (a vertical spring ``kv`` and a
rotational spring ``kphi``, loss factor ``eta_pad``). Under the pads:

``RigidFoundation``
    the slab track of the paper: both pad springs from the rail node to the ground.
``SleepersOnBallast``
    the ballasted track: ``kphi`` from the rail rotation to the ground (the sleeper does not
    rotate), ``kv`` between the rail node and a sleeper mass, the ballast ``kb`` (loss factor
    ``eta_ballast``) from the sleeper to the ground: one DOF per support.

``FlexibleSlabs``
    a flexible slab (:class:`semitrack.Slab`) under every ``S`` pads: ``kphi`` from the rail
    rotation to the ground (the slab's rotation is not coupled to the rail, as in the exact
    method's G_rs), ``kv`` between the rail node and the slab node under it; each slab a beam of
    its own (Euler-Bernoulli, or Timoshenko with the slab's shear stiffness and rotary inertia:
    the element of :func:`semitrack.fe.element.timoshenko_element`, family ``K_slab``, loss factor
    ``eta_slab``) free at both its ends, on the resilient layer as a distributed Winkler spring
    (the element's consistent stiffness ``k_L int N_w^T N_w``, family ``K_layer``, loss factor
    ``eta_support``). Slabs are not connected to each other; a gap ``S d - L`` between them is
    left empty. Each span between fasteners has as many slab elements as the rail has per bay
    (so slab and rail nodes coincide there), each overhang as many as keep them no longer.

A foundation adds its own DOFs to the model (:meth:`Foundation.n_dofs`) and its springs and
masses to the matrix families of :mod:`semitrack.fe.assembly` (:meth:`Foundation.assemble`);
one whose DOFs depend on the mesh is laid on it first (:meth:`Foundation.placed`).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np

from ..base.errors import InputError
from ..model.curves import FrequencyCurve
from ..model.slab import Slab
from ..model.tracks import Track
from .element import timoshenko_element
from .mesh import Mesh

__all__ = ["FE_SUPPORT_FIELDS", "Foundation", "RigidFoundation", "SleepersOnBallast", "FlexibleSlabs", "foundation_of",
           "support_values"]


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

    def placed(self, mesh: Mesh) -> Foundation:
        """The foundation laid on the rail's ``mesh`` (itself, unless its DOFs depend on the mesh).

        Parameters
        ----------
        mesh : Mesh
            The rail's mesh (:mod:`semitrack.fe.mesh`), its supports those this foundation carries.

        Returns
        -------
        Foundation
        """
        return self

    def dof_nodes(self, support_nodes: np.ndarray) -> np.ndarray:
        """The rail node beside each of the foundation's DOFs (for the band order along the track).

        Parameters
        ----------
        support_nodes : ndarray of int
            The rail nodes that carry this foundation's supports, in order along x.

        Returns
        -------
        ndarray of int, shape (n_dofs,)
        """
        return np.asarray(support_nodes[:self.n_dofs(len(support_nodes))], dtype=np.int64)

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


@dataclass(frozen=True)
class FlexibleSlabs(Foundation):
    """Flexible slabs on a resilient layer under the pads, each slab free at its ends (module docstring).

    Parameters
    ----------
    slab : Slab
        The slab (per rail), carrying ``slab.fasteners`` consecutive supports.
    spacing : float
        The rail's support spacing d (m).
    x : ndarray
        Positions of the slab nodes (m, the model's x), slab after slab; empty until
        :meth:`placed`.
    elements : ndarray of int, shape (n_elements, 2)
        The two slab nodes of each slab element.
    fastener_nodes : ndarray of int
        The slab node under each support of the model, in order along x.
    rail_nodes : ndarray of int
        The rail node nearest each slab node.

    Examples
    --------
    >>> import semitrack as st
    >>> from semitrack.fe.mesh import bay_mesh
    >>> mat = st.Slab(length=1.3, fasteners=2, E=3.6e10, I=2.9e-3, mass_per_length=956.0,
    ...               support_stiffness=2.55e7, eta_support=0.15)
    >>> laid = FlexibleSlabs(mat, 0.65).placed(bay_mesh(0.65, 2, 2, 4))
    >>> laid.x.size, laid.n_dofs(4), laid.fastener_nodes.tolist()
    (18, 36, [2, 6, 11, 15])
    """

    name: ClassVar[str] = "flexible slabs on a resilient layer"
    slab: Slab
    spacing: float
    x: np.ndarray = field(default_factory=lambda: np.zeros(0), compare=False)
    elements: np.ndarray = field(default_factory=lambda: np.zeros((0, 2), np.int64), compare=False)
    fastener_nodes: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int64), compare=False)
    rail_nodes: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int64), compare=False)

    def n_dofs(self, n_supports: int) -> int:
        return 2 * self.x.size

    def dof_nodes(self, support_nodes: np.ndarray) -> np.ndarray:
        return np.repeat(self.rail_nodes, 2)

    def placed(self, mesh: Mesh) -> FlexibleSlabs:
        s, d = self.slab.fasteners, self.spacing
        index = mesh.support_index
        slab_of = index // s  # support k sits at (k + 1/2) d; the joints (the slabs' cut) at multiples of S d
        whole = index.size and index.size % s == 0 and index[0] % s == 0 and np.all(np.diff(index) == 1)
        if not whole:
            raise InputError(
                f"a flexible-slab FE model holds whole slabs, its ends at slab joints (the track's cut, slab "
                f"cut='joint', is x = 0): n_left and n_right (n_bays) must be multiples of slab.fasteners = {s}, "
                f"got the supports {int(index[0]) if index.size else 0}..{int(index[-1]) if index.size else -1}")
        h_max = float(mesh.lengths.max())
        overhang = 0.5 * (self.slab.length - (s - 1) * d)
        xs, elements, fasteners = [], [], []
        for m in np.unique(slab_of):
            p = (index[slab_of == m] + 0.5) * d
            edges = np.concatenate([[p[0] - overhang], p, [p[-1] + overhang]])
            pieces = [np.linspace(a, b, max(1, int(np.ceil((b - a) / h_max - 1e-9))) + 1)[:-1]
                      for a, b in zip(edges[:-1], edges[1:])]
            nodes = np.concatenate(pieces + [edges[-1:]])
            start = sum(x.size for x in xs)
            elements.append(start + np.stack([np.arange(nodes.size - 1), np.arange(1, nodes.size)], 1))
            fasteners.append(start + np.searchsorted(nodes, p - 1e-9 * d))
            xs.append(nodes)
        x = np.concatenate(xs)
        rail = np.clip(np.searchsorted(mesh.x, x), 1, mesh.n_nodes - 1)
        rail = np.where(np.abs(mesh.x[rail - 1] - x) <= np.abs(mesh.x[rail] - x), rail - 1, rail)
        return FlexibleSlabs(self.slab, d, x, np.concatenate(elements), np.concatenate(fasteners).astype(np.int64),
                             rail.astype(np.int64))

    def assemble(self, parts: dict, support_nodes: np.ndarray, dofs: np.ndarray, values: Mapping[str, np.ndarray]
                 ) -> None:
        super().assemble(parts, support_nodes, dofs, values)
        slab = self.slab
        pad = (values["kv"] * values["present"])[:, None, None] * np.array([[1.0, -1.0], [-1.0, 1.0]])
        parts["K_pad"].add_many(np.stack([2 * support_nodes, dofs[2 * self.fastener_nodes]], 1), pad)
        a, b = self.elements[:, 0], self.elements[:, 1]
        el_dofs = dofs[np.stack([2 * a, 2 * a + 1, 2 * b, 2 * b + 1], 1)]
        lengths = self.x[b] - self.x[a]
        shear = np.inf if slab.shear_stiffness is None else slab.shear_stiffness
        for h in np.unique(lengths.round(12)):
            same = np.isclose(lengths, h, rtol=1e-9, atol=0)
            k_el, m_el = timoshenko_element(slab.E * slab.I, shear, slab.mass_per_length, slab.rotary_inertia, h)
            layer = timoshenko_element(slab.E * slab.I, shear, slab.support_stiffness, 0.0, h)[1]
            parts["K_slab"].add_many(el_dofs[same], k_el)
            parts["K_layer"].add_many(el_dofs[same], layer)
            parts["M"].add_many(el_dofs[same], m_el)


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
    InputError
        For a flexible slab cut inside a slab (``slab.cut`` other than "joint"): the FE models
        end at slab joints, the only cuts where the missing track meets the model through the
        rail alone (measured: a 10-bay model cut at slab centres with exact ends is 20-50 % off
        the infinite track at 30-400 Hz, the slab's shear and moment across the cut missing).

    Examples
    --------
    >>> from semitrack.model.tracks import ballasted_track
    >>> foundation_of(ballasted_track()).name
    'sleepers on ballast'
    """
    if track.has_flexible_slab:
        if track.slab.cut_span != 0:
            raise InputError(f"the FE models cut a flexible-slab track at slab joints (x = 0 and the ends), got "
                             f"slab cut={track.slab.cut!r}: only at a joint does the model meet the missing track "
                             "through the rail alone (inside a slab the slab carries shear and bending across the "
                             "cut, which no end on the rail holds); give the slab cut='joint' (the exact method "
                             "semi_infinite_receptance takes the other cuts)")
        return FlexibleSlabs(track.slab, track.spacing)
    return SleepersOnBallast() if track.is_ballasted else RigidFoundation()
