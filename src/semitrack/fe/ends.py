"""The ends of a finite track model, one class per kind, and the mirror of a left end in one place.

A model is cut at mid-spans; what closes each cut is an end (:func:`make_end` takes the names
users write, ``"pinned"``, ``"free"``, ``"equivalent"``, ``"boundary"``, ``"exact"``):

``PinnedEnd``
    w = 0 at the end node, psi free: removes the end's w.
``FreeEnd``
    nothing attached.
``EquivalentEnd``
    any end system's ``M, C, K`` (a :class:`~semitrack.equivalent.mechanical.MechanicalSystem`:
    the paper's multi-rigid-body :class:`~semitrack.EquivalentSystem`, or a broadband boundary in
    second-order form, :meth:`~semitrack.BroadbandBoundary.matrix_system`): its first two DOFs are
    the rail's ``(w, psi)`` at the end node, the others become DOFs of the model. One code path
    attaches every such system.
``BoundaryEnd``
    a broadband boundary (:class:`~semitrack.BroadbandBoundary`): its rational end stiffness in
    the frequency domain; in time its static stiffness and dashpot join ``K`` and ``C`` and its
    first-order states are integrated alongside (:class:`~semitrack.dynamics.states.StateBlock`).
``ExactEnd``
    the exact 2x2 dynamic stiffness of the missing semi-infinite track
    (:func:`semitrack.methods.transfer.end_stiffness`); frequency domain only.

Every end describes itself for the right end of a model (the semi-infinite track to the right
of the cut). A left end sees the mirror image: with ``P = diag(1, -1)`` (the mirror turns the
clockwise rotation round), a 2x2 end stiffness becomes ``P K P``, a system's rotation
``phi_1`` is the rail's ``-psi``, and a state block is driven by ``P (w, psi)``. :func:`mirror`
and :func:`mirrored` are the only places that apply it.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import ClassVar, Literal

import numpy as np

from ..base.checks import check_choice
from ..base.errors import InputError, InputTypeError
from ..boundary.fitting import BroadbandBoundary
from ..boundary.validation import check_boundary_physics, check_boundary_track
from ..dynamics.states import StateBlock
from ..equivalent.assembly import dynamic_stiffness
from ..equivalent.mechanical import MechanicalSystem
from ..methods.transfer import end_stiffness
from ..model.tracks import Track

__all__ = ["END_NAMES", "EndName", "FAR_END_NAMES", "FarEndName", "End", "PinnedEnd", "FreeEnd", "EquivalentEnd",
           "BoundaryEnd", "ExactEnd", "PINNED", "FREE", "EXACT", "make_end", "model_ends", "make_far_end", "end_kinds",
           "mirror", "mirrored", "MIRROR"]

#: An end of a model.
Side = Literal["left", "right"]
#: The mirror of an end: w unchanged, the clockwise rotation reversed.
MIRROR = np.diag([1.0, -1.0])


def mirror(side: Side) -> np.ndarray:
    """The map from the rail's ``(w, psi)`` at an end to the end's own: :data:`MIRROR` at the left, else I.

    Examples
    --------
    >>> mirror("left").tolist(), mirror("right").tolist()
    ([[1.0, 0.0], [0.0, -1.0]], [[1.0, 0.0], [0.0, 1.0]])
    """
    return MIRROR.copy() if side == "left" else np.eye(2)


def mirrored(X: np.ndarray, side: Side) -> np.ndarray:
    """A right end's matrix (or stack of matrices) as the left end sees it, ``S X S``.

    ``S`` is ``diag(1, -1, 1, ..., 1)``: the rail's rotation at the end DOF 1 reversed, any
    internal DOFs unchanged. At the right end ``X`` itself.

    Parameters
    ----------
    X : ndarray, shape (..., n, n)
        An end's matrix in its own DOF order, the rail's ``(w, psi)`` first.
    side : {"left", "right"}
        Which end of the model.

    Returns
    -------
    ndarray, shape (..., n, n)

    Examples
    --------
    >>> mirrored(np.array([[1.0, 2.0], [2.0, 3.0]]), "left").tolist()
    [[1.0, -2.0], [-2.0, 3.0]]
    """
    if side == "right":
        return X
    s = np.ones(X.shape[-1])
    s[1] = -1.0
    return s[:, None] * X * s[None, :]


@dataclass(frozen=True)
class End:
    """What closes a cut of an FE track model: the base of the end kinds (see the module docstring).

    Attributes
    ----------
    name : str
        The kind's name, as :func:`make_end` takes it.
    label : str
        How tables and figures call it.
    removes_w : bool
        The end node's w is removed (pinned).
    frequency_dependent : bool
        A 2x2 end stiffness is added at the end node per frequency (:meth:`stiffness`).
    time_domain : bool
        Whether the end has time-domain matrices.
    closes_alone : bool
        Whether it closes a model of zero bays (a system or an end stiffness, not a condition).
    """

    name: ClassVar[str] = ""
    removes_w: ClassVar[bool] = False
    frequency_dependent: ClassVar[bool] = False
    time_domain: ClassVar[bool] = True
    closes_alone: ClassVar[bool] = False
    system_type: ClassVar[type | None] = None
    label: str = field(default="", compare=False)

    def __post_init__(self):
        if not self.label:
            object.__setattr__(self, "label", self.name)

    @property
    def system(self):
        """The attached system or boundary (None for pinned, free and exact ends)."""
        return None

    def check_track(self, track: Track) -> None:
        """Refuse closing a model of ``track`` with an end that belongs to another track (none here).

        Parameters
        ----------
        track : Track
            The track of the model.
        """

    @property
    def internal_dofs(self) -> int:
        """DOFs the end adds to the model beyond the rail's ``(w, psi)`` at its node."""
        return 0

    def matrices(self, side: Side) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
        """``(M, C, K)`` assembled into the model on the end's DOFs (ports first), or None."""
        return None

    def stiffness(self, track: Track, omega: np.ndarray, side: Side) -> np.ndarray:
        """The frequency-dependent 2x2 end stiffness at ``omega`` (rad/s), ``(n_f, 2, 2)``."""
        raise NotImplementedError(f"a {self.name} end has no frequency-dependent stiffness")

    def dynamic_stiffness(self, track: Track, omega: np.ndarray, side: Side) -> np.ndarray:
        """All the end adds at ``omega`` (rad/s) on its DOFs, ports first: ``(n_f, p, p)``, p = 2 + internal DOFs."""
        if self.frequency_dependent:
            return self.stiffness(track, omega, side)
        parts = self.matrices(side)
        if parts is None:
            return np.zeros((omega.size, 2, 2), dtype=complex)
        return dynamic_stiffness(*parts, omega)

    def time_matrices(self, side: Side) -> tuple[np.ndarray, np.ndarray] | None:
        """``(K0, D)``: the 2x2 stiffness and dashpot the end adds to ``K`` and ``C`` in time, or None."""
        if not self.time_domain:
            others = [repr(cls.name) for cls in _KINDS.values() if cls.time_domain]
            raise InputError(f"ends={self.name!r} is frequency dependent and has no time-domain matrices; use "
                             f"{', '.join(others[:-1])} or {others[-1]}")
        return None

    def states(self, dofs: np.ndarray, side: Side) -> list[StateBlock]:
        """The first-order states the end adds in time on the model DOFs ``dofs`` = ``(w, psi)``."""
        return []


@dataclass(frozen=True)
class PinnedEnd(End):
    """w = 0 at the end node, psi free."""

    name: ClassVar[str] = "pinned"
    removes_w: ClassVar[bool] = True


@dataclass(frozen=True)
class FreeEnd(End):
    """Nothing attached."""

    name: ClassVar[str] = "free"


@dataclass(frozen=True)
class EquivalentEnd(End):
    """An end system's ``M, C, K`` attached at the end node (see the module docstring)."""

    name: ClassVar[str] = "equivalent"
    closes_alone: ClassVar[bool] = True
    system_type: ClassVar[type] = MechanicalSystem
    equivalent: MechanicalSystem | None = None

    def __post_init__(self):
        super().__post_init__()
        _require_system(self, self.equivalent)

    @property
    def system(self) -> MechanicalSystem:
        return self.equivalent

    @property
    def internal_dofs(self) -> int:
        return self.equivalent.n_dof - 2

    def matrices(self, side: Side) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        return tuple(mirrored(X, side) for X in self.equivalent.matrices())


@dataclass(frozen=True)
class BoundaryEnd(End):
    """A broadband boundary: rational end stiffness in frequency, static stiffness, dashpot and states in time."""

    name: ClassVar[str] = "boundary"
    frequency_dependent: ClassVar[bool] = True
    closes_alone: ClassVar[bool] = True
    system_type: ClassVar[type] = BroadbandBoundary
    boundary: BroadbandBoundary | None = None

    def __post_init__(self):
        super().__post_init__()
        _require_system(self, self.boundary)
        check_boundary_physics(self.boundary.rational, self.boundary.passivity, "the boundary end's model")

    @property
    def system(self) -> BroadbandBoundary:
        return self.boundary

    def check_track(self, track: Track) -> None:
        """Refuse a boundary fitted to another track (its pinned ``K0`` or dashpot differs by > 1 %).

        Parameters
        ----------
        track : Track
            The track of the model.
        """
        check_boundary_track(self.boundary.rational, track, f"the boundary (fitted to {self.boundary.track_name!r})")

    def stiffness(self, track: Track, omega: np.ndarray, side: Side) -> np.ndarray:
        return mirrored(self.boundary.dynamic_stiffness(omega / (2 * np.pi)), side)

    def time_matrices(self, side: Side) -> tuple[np.ndarray, np.ndarray]:
        model = self.boundary.rational
        return mirrored(model.K0, side), mirrored(model.D, side)

    def states(self, dofs: np.ndarray, side: Side) -> list[StateBlock]:
        ss = self.boundary.state_space()
        return [StateBlock(dofs=dofs, A=ss.A, B=ss.B, C=ss.C, port=mirror(side),
                           label=f"broadband boundary, {side} end")]


@dataclass(frozen=True)
class ExactEnd(End):
    """The exact dynamic stiffness of the missing semi-infinite track (frequency domain only)."""

    name: ClassVar[str] = "exact"
    frequency_dependent: ClassVar[bool] = True
    time_domain: ClassVar[bool] = False
    closes_alone: ClassVar[bool] = True

    def stiffness(self, track: Track, omega: np.ndarray, side: Side) -> np.ndarray:
        return _exact_pair(track, omega)[0 if side == "right" else 1]


class _ExactCache:
    """The last exact end pair computed: a model with exact ends at both sides needs it once."""

    key, value = None, None


def _exact_pair(track: Track, omega: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    key = (id(track), track, omega.tobytes())
    if _ExactCache.key != key:
        cell = track.cell()
        _ExactCache.key, _ExactCache.value = key, end_stiffness(cell, omega, cell.central_section)
    return _ExactCache.value


#: The ends that need nothing, for defaults and studies.
PINNED, FREE, EXACT = PinnedEnd(), FreeEnd(), ExactEnd()

_KINDS: dict[str, type[End]] = {kind.name: kind for kind in (PinnedEnd, FreeEnd, EquivalentEnd, BoundaryEnd, ExactEnd)}
#: The names of the end kinds, as users write them.
END_NAMES = tuple(_KINDS)
EndName = Literal["pinned", "free", "equivalent", "boundary", "exact"]
#: The ends that need no system: the far end of a long track.
FAR_END_NAMES = tuple(name for name, cls in _KINDS.items() if cls.system_type is None)
FarEndName = Literal["pinned", "free", "exact"]


def _require_system(end: End, system) -> None:
    kind = end.system_type
    if not isinstance(system, kind):
        # The paper's name for what an 'equivalent' end takes; any MechanicalSystem (M, C, K) will do.
        shown = "EquivalentSystem" if kind is MechanicalSystem else kind.__name__
        also = (" (or any MechanicalSystem, e.g. BroadbandBoundary.matrix_system())"
                if kind is MechanicalSystem else "")
        article = "an" if shown[0] in "AEIOU" else "a"
        raise InputTypeError(f"system must be {article} {shown} for {article} {end.name!r} end{also}, "
                             f"got {type(system).__name__}")


def end_kinds(*names: str) -> tuple[type[End], ...]:
    """The end classes of the given names (each checked)."""
    return tuple(_KINDS[check_choice("ends", name, END_NAMES)] for name in names)


def model_ends(left: str | End, right: str | End, system=None, n_bays: int = 1,
               track: Track | None = None) -> dict[str, End]:
    """The two ends of a model from what users write, with the rules that tie them to the system and bays.

    Parameters
    ----------
    left, right : str or End
        The ends (names of :data:`END_NAMES`, or End objects).
    system : EquivalentSystem, BroadbandBoundary or a pair, optional
        The system of the named end kinds that need one: one for both ends, or
        ``(left_system, right_system)`` (a transition: each side's track has its own).
    n_bays : int
        Bays of the model in all: with none, both ends must close the model alone (systems or
        end stiffnesses).
    track : Track, optional
        The model's track: each end checks that it belongs to it (:meth:`End.check_track`; a
        boundary fitted to another track is refused).

    Returns
    -------
    dict
        ``{"left": End, "right": End}``.
    """
    names = [end if isinstance(end, End) else check_choice(side, end, END_NAMES) for side, end in
             (("left", left), ("right", right))]
    kinds = [type(end) if isinstance(end, End) else _KINDS[end] for end in names]
    needs = [cls.system_type is not None and not isinstance(end, End) for cls, end in zip(kinds, names)]
    if isinstance(system, (tuple, list)):
        if len(system) != 2:
            raise InputError(f"system as a sequence must be the pair (left_system, right_system), got {len(system)} "
                             "items")
        systems = list(system)
        for side, end, need, given in zip(("left", "right"), (left, right), needs, systems):
            if given is not None and not need:
                raise InputError(f"system for the {side} end is given, but its end {_name(end)!r} takes none")
    else:
        if len({cls for cls, need in zip(kinds, needs) if need}) > 1:
            raise InputError("one system cannot close both an 'equivalent' and a 'boundary' end: give "
                             "(left_system, right_system)")
        if system is not None and not any(needs):
            raise InputError(f"system is only used with an 'equivalent' or 'boundary' end, got ends "
                             f"({_name(left)!r}, {_name(right)!r})")
        systems = [system if need else None for need in needs]
    ends = {side: make_end(end, given) for side, end, given in zip(("left", "right"), names, systems)}
    if n_bays == 0 and not all(end.closes_alone for end in ends.values()):
        alone = ", ".join(repr(cls.name) for cls in _KINDS.values() if cls.closes_alone)
        raise InputError(f"a model with zero bays (n_left = n_right = 0) needs {alone} ends, got ends "
                         f"({_name(left)!r}, {_name(right)!r})")
    for end in ends.values() if track is not None else ():
        end.check_track(track)
    return ends


def make_far_end(end: str | End) -> End:
    """The far end of a long track: an end that needs no system (one of :data:`FAR_END_NAMES`)."""
    if not isinstance(end, End):
        check_choice("far_end", end, FAR_END_NAMES)
    made = make_end(end)
    if made.system_type is not None:
        raise InputError(f"far_end must be one of {FAR_END_NAMES}, got {made.name!r}")
    return made


def _name(end: str | End) -> str:
    return end.name if isinstance(end, End) else end


def make_end(kind: str | End, system: MechanicalSystem | BroadbandBoundary | None = None, label: str = "") -> End:
    """An end from its name and, for ``"equivalent"`` and ``"boundary"``, its system.

    Parameters
    ----------
    kind : str or End
        One of :data:`END_NAMES`, or an end already made (returned as it is; ``system`` must be
        None then).
    system : MechanicalSystem or BroadbandBoundary, optional
        Required by ``"equivalent"`` (an :class:`~semitrack.EquivalentSystem` or any other
        :class:`~semitrack.equivalent.mechanical.MechanicalSystem`) and ``"boundary"``
        (a :class:`~semitrack.BroadbandBoundary`) ends; refused by the others.
    label : str
        How tables and figures call it (default: the kind's name).

    Returns
    -------
    End

    Examples
    --------
    >>> make_end("pinned").removes_w, make_end("exact").time_domain
    (True, False)
    """
    if isinstance(kind, End):
        if system is not None:
            raise InputError(f"system is given by the end itself for an End object, got also {type(system).__name__}")
        return kind
    (cls,) = end_kinds(kind)
    if cls.system_type is None:
        if system is not None:
            raise InputError(f"system is only used with an 'equivalent' or 'boundary' end, got ends={kind!r}")
        return cls(label=label)
    if cls is EquivalentEnd:
        return EquivalentEnd(label=label, equivalent=system)
    return BoundaryEnd(label=label, boundary=system)
