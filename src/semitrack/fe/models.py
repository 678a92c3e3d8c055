"""Finite-element tracks: the rail on discrete supports between two mid-span cuts, long and truncated.

The third route to the paper's quantities (after the wavenumber method and the exact transfer
method) and the test bed for the equivalent systems in truncated track models. A model is built
in three steps, one module each: the mesh and the DOF map (:mod:`semitrack.fe.mesh`), the
Timoshenko rail elements (:mod:`semitrack.fe.element`) and the assembly of the matrix families
(:mod:`semitrack.fe.assembly`); in the frequency domain every family carries its loss factor as
a complex stiffness, in the time domain a viscous damper (:mod:`semitrack.fe.damping`).

Ends
    ``"pinned"`` (w = 0, psi free), ``"free"``, ``"equivalent"`` (an :class:`EquivalentSystem`'s
    ``M, C, K`` attached; its internal DOFs become extra DOFs of the model), ``"boundary"`` (a
    :class:`~semitrack.BroadbandBoundary`: its rational end stiffness in the frequency domain,
    in time its static stiffness, dashpot and first-order states, see
    :meth:`FETrack.boundary_states`) and ``"exact"`` (the 2x2 dynamic stiffness of the missing
    semi-infinite track; frequency domain only): one class each in :mod:`semitrack.fe.ends`,
    which also mirrors a left end. What carries the pads is a class of
    :mod:`semitrack.fe.supports`.

Damping follows the track: loss factors as complex stiffness (``damping="hysteretic"``), or
their viscous equivalents (``damping="viscous"``), which are exactly the dampers of
:meth:`FETrack.matrices`, so that the frequency and time domains then describe one system.
"""

from __future__ import annotations

import copy
import functools
from collections.abc import Mapping, Sequence
from functools import lru_cache

import numpy as np
import scipy.sparse as sp
from numpy.typing import ArrayLike

from ..base.checks import (
    as_frequencies,
    as_real_array,
    brief,
    check_choice,
    check_in_range,
    check_int_at_least,
    check_positive,
    check_real,
    check_work,
)
from ..base.deprecation import deprecated_alias, renamed_keywords, warn_renamed
from ..base.errors import InputError, InputTypeError
from ..base.notices import warn_user
from ..base.threads import serial_blas
from ..boundary.fitting import BroadbandBoundary
from ..dynamics.points import PointSet
from ..dynamics.states import StateBlock
from ..dynamics.system import SecondOrderSystem
from ..equivalent.systems import EquivalentSystem
from ..methods.infinite import InfiniteTrack
from ..model.tracks import Track, require_track
from .assembly import DAMPED, TrackMatrices, assemble, supports_share
from .damping import reference_frequencies, warn_hysteretic
from .element import point_flexibility, shear_parameter, timoshenko_shape_functions
from .ends import EXACT, FREE, PINNED, BoundaryEnd, End, EndName, FarEndName, end_kinds, make_far_end, model_ends
from .mesh import KINDS, DofMap, Kind, Mesh, bay_mesh, dof_map, rail_dof
from .meshsize import (
    MAX_MESH_FREQUENCY,
    MESH_TOLERANCE,
    PROBE_ELEMENTS,
    MeshProbe,
    elements_for,
    probe_grid,
    valid_frequency,
)
from .supports import CONSTANT_SUPPORTS_ONLY, Foundation, foundation_of, support_values

__all__ = [
    "FETrack",
    "TruncatedTrack",
    "mesh_probe",
    "elements_per_bay_of",
    "require_model",
    "fe_semi_infinite_receptance",
    "fe_central_receptance",
]

#: The highest frequency of interest of a model that states none (Hz): the compendium's band.
DEFAULT_F_MAX = 3000.0

#: Most rail elements of one model: ~400 k DOFs, whose sparse factorisation takes ~0.5 s per
#: frequency (the book's longest reference track has 19 200).
MAX_ELEMENTS = 200_000
#: Most stored entries a frequency sweep forms at once (16 bytes each): a chunk of frequencies whose
#: matrices' data is formed together (64 frequencies of a 2000-DOF model).
SWEEP_VALUES = 1_000_000


def _old_end_keywords(init):
    """FETrack's ends were ``left=``/``right=`` and its second track ``right_track=`` until 0.2 (kept until 0.3)."""
    @functools.wraps(init)
    def wrapper(self, *args, **kwargs):
        if isinstance(kwargs.get("right"), (str, End)):  # an end under its old name, not a second track
            if "right_end" in kwargs:
                raise InputTypeError("FETrack got both right= naming an end and right_end=: give right_end only")
            warn_renamed("right", "right_end", "FETrack (an end)")
            kwargs["right_end"] = kwargs.pop("right")
        for old, new in (("left", "left_end"), ("right_track", "right")):
            if old in kwargs:
                if new in kwargs:
                    raise InputTypeError(f"FETrack got both {old}= and {new}=, which is its new name: give {new} only")
                warn_renamed(old, new, "FETrack")
                kwargs[new] = kwargs.pop(old)
        init(self, *args, **kwargs)

    return wrapper


class FETrack:
    """A finite FE model of the rail on discrete supports between two mid-span cuts.

    The rail runs from ``x = -n_left d`` to ``x = n_right d`` (d the support spacing); x = 0 is a
    mid-span (the central cross-section, or the cut of a semi-infinite track when
    ``n_left = 0``), supports at ``x = (k + 1/2) d``.

    Parameters
    ----------
    track : Track
        Rail, pad and (ballasted) sleeper/ballast parameters.
    n_left, n_right : int
        Number of bays left and right of x = 0 (>= 0, at least one bay in all unless both ends
        are "equivalent" or "exact").
    left_end, right_end : {"pinned", "free", "equivalent", "boundary", "exact"} or End
        End conditions, see the module docstring (until 0.3 also ``left=``, and ``right=`` naming
        an end).
    system : EquivalentSystem, BroadbandBoundary or a pair of them, optional
        The equivalent system attached at an ``"equivalent"`` end, or the broadband boundary
        at a ``"boundary"`` end (required then); ``(left_system, right_system)`` gives each end
        its own (a transition's two tracks), ``None`` in the place of an end that takes none.
    elements_per_bay : int, optional
        Number of elements per support spacing; even (>= 2), so that mid-spans are nodes.
        Default: the fewest for which the mesh's own error (the largest relative error of w/F,
        measured on the periodic track against the exact infinite track, :mod:`semitrack.fe.meshsize`)
        stays under 1 % up to ``f_max``: on the paper's tracks 8 up to 500 Hz, 32-40 (slab) and
        54-72 (ballasted) up to 3 kHz. The error is largest at the sharp pinned-pinned peaks and
        falls as 1/n^2: 12 elements are 6-29 % off there below 3 kHz. A model whose frequencies
        asked exceed what its mesh resolves warns (:meth:`solve`), naming the elements needed.
        ``elements_per_bay * (n_left + n_right)`` may not exceed :data:`MAX_ELEMENTS` (200 000).
    changes : mapping of int to mapping or None, optional
        ``{k: {field: value}}`` sets ``kv``, ``kphi``, ``sleeper_mass`` or ``kb`` of support k
        (at ``x = (k + 1/2) d``, as :class:`semitrack.InfiniteTrack` numbers them; ``kb=0`` a
        hanging sleeper); ``{k: None}`` removes its pad (its sleeper, if any, stays on the
        ballast, off the rail). Supports outside the model are ignored.
    right : Track, optional
        A second track from the mid-span ``x_t = transition d`` on (until 0.3 also ``right_track=``):
        its rail, spacing, supports and loss factors, the same kind of damping. Bays ``kt, kt + 1,
        ...`` are its bays, their supports numbered on as :class:`semitrack.InfiniteTrack` numbers
        them, and the right end closes its semi-infinite track. A slab-to-ballast transition is
        ``right=st.ballasted_track()``.
    transition : int, optional
        ``kt``, with ``right``: ``-n_left <= kt <= n_right``.
    joints : mapping of float to float, optional
        ``{x: k_rot}``: the rail is cut at x (m, inside the model, not at a support) and joined by
        a rotational spring of ``k_rot`` N m/rad (0: a hinge); the node at x gets a second
        rotation, the rail's just right of the cut (:meth:`dof` gives the left one).
    f_max : float, optional
        The highest frequency of interest (Hz; default :data:`DEFAULT_F_MAX`, 3 kHz), which the
        default mesh resolves. In the time domain state it: the highest frequency of the loads
        (a roughness: the speed over its shortest wavelength); with an explicit
        ``elements_per_bay`` too, the model warns at once when that mesh does not resolve it.

    Attributes
    ----------
    mesh : Mesh
        Node positions, element length and support nodes (:mod:`semitrack.fe.mesh`).
    dofs : DofMap
        The DOF numbering: rail (w, psi) per node, then sleeper DOFs (ballasted track), then the
        internal DOFs of attached equivalent systems; pinned DOFs removed.
    end_models : dict
        ``{"left": End, "right": End}``: the ends as objects of :mod:`semitrack.fe.ends`
        (:attr:`left_end` and :attr:`right_end` are their names; ``left`` and ``right`` until 0.3).
    support_values : dict
        Each support's ``kv``, ``kphi``, ``sleeper_mass``, ``kb`` and ``present``, in the order
        of ``mesh.support_index`` (:func:`semitrack.fe.supports.support_values`).

    Examples
    --------
    A semi-infinite slab track of 20 bays cut at x = 0, its end receptance at 100 Hz:

    >>> import semitrack as st
    >>> model = st.FETrack(st.slab_track(), 0, 20, "free", "exact", elements_per_bay=4)
    >>> model.receptance(100.0).shape
    (2, 2)
    """

    @_old_end_keywords
    def __init__(self, track: Track, n_left: int, n_right: int, left_end: EndName | End = PINNED,
                 right_end: EndName | End = PINNED,
                 system: EquivalentSystem | BroadbandBoundary | Sequence | None = None,
                 elements_per_bay: int | None = None, changes: Mapping[int, Mapping[str, float] | None] | None = None,
                 *, right: Track | None = None, transition: int | None = None,
                 joints: Mapping[float, float] | None = None, f_max: float | None = None):
        self.n_left = check_int_at_least("n_left", n_left, 0)
        self.n_right = check_int_at_least("n_right", n_right, 0)
        given = [(name, require_track(t, name)) for name, t in (("track", track), ("right", right))
                 if t is not None or name == "track"]
        for name, t in given:
            t.require_constant(f"the finite-element track ({name})", CONSTANT_SUPPORTS_ONLY)
        foundations = tuple(foundation_of(t) for _, t in given)
        # The exact infinite track with the same changes holds their rules (one place for both); a
        # periodic track's is built only when asked for (the Bloch cell of the moving kernels never does)
        for name, value in (("changes", changes), ("joints", joints)):  # before their truth value is read
            if value is not None and not isinstance(value, Mapping):
                raise InputTypeError(f"{name} must be a mapping {{support: ...}} or None, got {brief(value)}")
        self._periodic = not (changes or right is not None or transition is not None or joints)
        self._states: tuple[StateBlock, ...] | None = None
        self._own_share = None  # the supports' share of the matrices, for with_changes
        self._infinite = None if self._periodic else _infinite_of(track, changes, right, transition, joints)
        self.tracks: tuple[Track, ...] = tuple(t for _, t in given)
        self.track = self.tracks[0]
        self.right_track = None if self._infinite is None else self._infinite.right
        self.transition = None if self._infinite is None else self._infinite.transition
        self._check_layout()
        self.end_models: dict[str, End] = model_ends(left_end, right_end, system, self.n_left + self.n_right)
        for side, end in self.end_models.items():  # a boundary must belong to the track it closes
            end.check_track(self.end_track(side))
        self.left_end, self.right_end = self.end_models["left"].name, self.end_models["right"].name
        self.f_max = DEFAULT_F_MAX if f_max is None else check_positive("f_max", f_max)
        self.elements_per_bay = self._check_elements(elements_per_bay)
        # Up to where the mesh's own error is known to be within MESH_TOLERANCE (Hz; grown as asked)
        self._mesh_checked = self.f_max if elements_per_bay is None else 0.0
        if elements_per_bay is not None and f_max is not None:  # a stated f_max (the time domain's): check it now
            self._check_mesh(self.f_max)
        self.system = system
        self.changes, self.joints = ({}, {}) if self._infinite is None else (self._infinite.changes,
                                                                             self._infinite.joints)
        self.mesh: Mesh = bay_mesh(self.track.spacing, self.n_left, self.n_right, self.elements_per_bay,
                                   right_spacing=self.tracks[-1].spacing, transition=self.transition,
                                   joints=list(self.joints))
        self.foundations: tuple[Foundation, ...] = tuple(f.placed(self.mesh) for f in foundations)
        self.foundation: Foundation = self.foundations[0]
        self.dofs: DofMap = dof_map(self.mesh, self._foundation_nodes(),
                                    {side: end.internal_dofs for side, end in self.end_models.items()},
                                    [side for side, end in self.end_models.items() if end.removes_w])
        self.support_values = support_values(self.tracks, self.mesh.support_part, self.mesh.support_index,
                                             self.changes)
        self._parts: TrackMatrices = assemble(self.tracks, self.mesh, self.dofs, self.foundations, self.end_models,
                                              self.support_values, [self.joints[x] for x in sorted(self.joints)])

    def with_changes(self, changes: Mapping[int, Mapping[str, float] | None] | None) -> FETrack:
        """The same model (mesh, ends, DOFs, pattern) with other support changes.

        Only the supports' share of the matrices is assembled again
        (:func:`~semitrack.fe.assembly.supports_share`): a few hundred microseconds where a new
        model of 6000 DOFs takes 20 ms (the travelling window, :mod:`semitrack.fe.window`, asks
        for one at every move over a random track).

        Parameters
        ----------
        changes : mapping of int to mapping or None, or None
            As the constructor's, replacing this model's; not on a model with a transition or
            joints (their rules are the exact track's, built with them).

        Returns
        -------
        FETrack
        """
        if self.transition is not None or self.joints:
            raise InputError("changes: with_changes takes a model without a transition or joints; build the model "
                             "with its changes instead")
        if changes is not None and not isinstance(changes, Mapping):
            raise InputTypeError(f"changes must be a dict of support changes by index or None, got "
                                 f"{type(changes).__name__}")
        infinite = None if not changes else _infinite_of(self.track, changes, None, None, None)  # its rules
        self._check_changes_inside({} if infinite is None else infinite.changes)
        return self._with_checked_changes({} if infinite is None else infinite.changes, infinite)

    def _with_checked_changes(self, changes: dict, infinite: InfiniteTrack | None = None) -> FETrack:
        """:meth:`with_changes` for changes already checked by the exact track's rules (a window's, a
        subset of its WindowTrack's); the exact track with them is built when asked for."""
        if self.transition is not None or self.joints:
            raise InputError("changes: a model with a transition or joints is built with its changes")
        if self._own_share is None:  # this model's own supports' share, once
            self._own_share = supports_share(self._parts, self.mesh, self.dofs, self.foundations, self.support_values)
        new = copy.copy(self)
        new._periodic = not changes
        new._infinite = infinite
        new.changes = changes
        new.support_values = support_values(self.tracks, self.mesh.support_part, self.mesh.support_index,
                                            new.changes)
        new._own_share = None
        new._parts = self._parts.with_supports(self._own_share, supports_share(self._parts, self.mesh, self.dofs,
                                                                              self.foundations, new.support_values))
        return new

    left = deprecated_alias("left_end", "left")
    right = deprecated_alias("right_end", "right")

    def _check_layout(self) -> None:
        """A transition inside the model, one kind of damping on both sides, joints on the rail inside."""
        if self.transition is not None:
            if not -self.n_left <= self.transition <= self.n_right:
                raise InputError(f"transition must be a mid-span of the model, {-self.n_left} <= kt <= "
                                 f"{self.n_right}, got {self.transition}")
            if self.right_track.damping != self.track.damping:
                raise InputError(f"the two tracks of a transition must have one kind of damping, got "
                                 f"{self.track.damping!r} and {self.right_track.damping!r}")
        d = self.track.spacing
        x_right = (self.n_right * d if self.transition is None else
                   self.transition * d + (self.n_right - self.transition) * self.right_track.spacing)
        for x in (() if self._infinite is None else self._infinite.joints):
            if not -self.n_left * d < x < x_right:
                raise InputError(f"joints must lie inside the model, {-self.n_left * d:.6g} < x < {x_right:.6g} m, "
                                 f"got {x!r}")
        self._check_changes_inside({} if self._infinite is None else self._infinite.changes)

    def _check_changes_inside(self, changes: Mapping) -> None:
        """Every changed support is one of the model's, ``-n_left <= k < n_right``: a change beyond them
        would be accepted and change nothing."""
        outside = [k for k in changes if not -self.n_left <= k < self.n_right]
        if outside:
            raise InputError(f"changes: support {outside[0]} lies outside the model, whose supports are "
                             f"{-self.n_left} to {self.n_right - 1}: give more bays or drop the change")

    def _check_elements(self, elements_per_bay: int | None) -> int:
        ne = elements_per_bay_of(self.tracks, elements_per_bay, self.f_max)
        n_elements = ne * (self.n_left + self.n_right)
        check_work(n_elements, MAX_ELEMENTS, f"{self.n_left + self.n_right} bays (n_bays, or n_left + n_right) x "
                   f"elements_per_bay = {ne} give {n_elements} elements", "use fewer bays or elements per bay")
        return ne

    def _foundation_nodes(self) -> np.ndarray:
        """The rail node of each foundation DOF, track by track (see :func:`~.assembly.assemble`)."""
        nodes = [self.mesh.support_nodes[self.mesh.support_part == p] for p in range(len(self.tracks))]
        return np.concatenate([f.dof_nodes(n) for n, f in zip(nodes, self.foundations)]).astype(np.int64)

    def infinite_track(self) -> InfiniteTrack:
        """The exact infinite track with this model's changes, transition and joints: its reference.

        Returns
        -------
        InfiniteTrack or None
            Nothing truncated, no mesh (:class:`semitrack.InfiniteTrack`); the same positions and
            support numbering as the model. None for a flexible-slab track, which InfiniteTrack
            does not hold: the model is then the periodic track, whose exact reference is
            ``st.point_receptance(track, f, x, origin="midspan")`` (x = 0 a slab joint there).
        """
        if self._infinite is None and not any(t.has_flexible_slab for t in self.tracks):
            self._infinite = InfiniteTrack(self.track, self.changes or None)  # built when first asked
        return self._infinite

    def end_track(self, side: str) -> Track:
        """The track whose semi-infinite part an end replaces: the second track at the right of a transition.

        Parameters
        ----------
        side : {"left", "right"}
            The end.

        Returns
        -------
        Track
        """
        return self.tracks[-1] if check_choice("side", side, ("left", "right")) == "right" else self.track

    def _end_dofs(self, side: str) -> np.ndarray:
        """The model DOFs ``(w, psi)`` of the rail at an end (-1 where removed)."""
        node = self.mesh.end_node(side)
        return self.dofs.index[[rail_dof(node, "w"), rail_dof(node, "psi")]]

    # --------------------------------------------------------------------------------------------
    @property
    def x(self) -> np.ndarray:
        """Positions of the rail nodes (m)."""
        return self.mesh.x

    @property
    def element_length(self) -> float:
        """Length of the longest rail element (m): every element of a bay is as long, but past a
        transition or beside a joint."""
        return float(self.mesh.lengths.max(initial=0.0))

    @property
    def support_nodes(self) -> np.ndarray:
        """Indices of the rail nodes that carry a support."""
        return self.mesh.support_nodes

    @property
    def n_nodes(self) -> int:
        """Number of rail nodes."""
        return self.mesh.n_nodes

    @property
    def n_dof(self) -> int:
        """Number of DOFs of the model (pinned DOFs removed)."""
        return self.dofs.n_dof

    @property
    def sleeper_dofs(self) -> np.ndarray:
        """Indices of the foundation's DOFs: the sleepers of a ballasted track, the slab nodes' (w, psi) of a
        flexible-slab track (empty on a rigid foundation)."""
        return self.dofs.index[self.dofs.foundation]

    def _csc(self, data: np.ndarray) -> sp.csc_matrix:
        return self._parts.pattern.csc(data)

    # --------------------------------------------------------------------------------------------
    def dof(self, x: float, kind: Kind = "w") -> int:
        """Index of a rail DOF at a node.

        Parameters
        ----------
        x : float
            Position of the node (m from x = 0), within 1e-9 d of a node.
        kind : {"w", "psi"}
            The vertical displacement (m) or the clockwise rotation (rad).

        Returns
        -------
        int
            Index in the model's DOF vector.

        Raises
        ------
        ValueError
            When x is not a node or the DOF was removed by a pinned end.

        Examples
        --------
        >>> import semitrack as st
        >>> model = st.TruncatedTrack(st.slab_track(), 1, "free", elements_per_bay=2)
        >>> model.x.tolist()[2], model.dof(0.0, "w"), model.dof(0.0, "psi")
        (0.0, 4, 5)
        """
        x = check_real("x", x)
        kind = check_choice("kind", kind, KINDS)
        j = int(np.argmin(np.abs(self.x - x)))
        if abs(self.x[j] - x) > 1e-9 * self.track.spacing:
            raise InputError(
                f"x must be a node position of the mesh (elements up to {self.element_length:.6g} m long, from "
                f"{self.x[0]:.6g} to {self.x[-1]:.6g} m), got {x!r}"
            )
        i = int(self.dofs.index[rail_dof(j, kind)])
        if i < 0:
            raise InputError(f"the {kind} DOF at x={x!r} is removed by a pinned end")
        return i

    def _weights(self, xs: np.ndarray, kind: Kind, name: str) -> tuple[np.ndarray, np.ndarray]:
        """Model DOFs (-1 where removed) and shape-function weights of ``kind`` at every position of
        ``xs``, each ``(xs.size, 4)``: the one place where the rail's shape weights are computed."""
        kind = check_choice("kind", kind, KINDS)
        lo, hi = self.x[0], self.x[-1]
        bad = ~(np.isfinite(xs) & (xs >= lo - 1e-12) & (xs <= hi + 1e-12))
        if np.any(bad):
            raise InputError(f"{name} must lie on the rail, {lo:.6g} <= x <= {hi:.6g} m, got {xs[bad][0]!r}")
        e, xi = self.mesh.locate(xs)
        h = self.mesh.lengths[e]
        rail = [self.tracks[p] for p in self.mesh.part[e]]
        phi = shear_parameter(np.array([t.E * t.I for t in rail]), np.array([t.kappa * t.A * t.G for t in rail]), h)
        n_w, n_psi = timoshenko_shape_functions(xi[:, None], h[:, None], phi[:, None])
        n_w, n_psi = n_w[:, 0], n_psi[:, 0]
        return self.dofs.index[self.mesh.element_dofs()[e]], (n_w if kind == "w" else n_psi)

    def shape_weights(self, x: float, kind: Kind = "w", *, name: str = "x") -> tuple[np.ndarray, np.ndarray]:
        """The DOFs and shape-function weights that give ``w`` (or ``psi``) at a point of the rail.

        ``w(x) = weights @ u[dofs]`` over the entries with ``dofs >= 0``; the same weights give
        the consistent nodal loads of a force at x.

        Parameters
        ----------
        x : float
            Position on the rail (m), ``self.x[0] <= x <= self.x[-1]``.
        kind : {"w", "psi"}
            Interpolate the displacement or the rotation.
        name : str
            The parameter name quoted in the error message.

        Returns
        -------
        dofs : ndarray of int, shape (4,)
            Model DOF indices ``(w_a, psi_a, w_b, psi_b)`` of the element holding x; -1 for a
            DOF removed by a pinned end.
        weights : ndarray, shape (4,)
            Shape-function values there (-, or m per rad and rad per m across w and psi).
        """
        dofs, weights = self._weights(np.array([x], dtype=float), kind, name)
        return dofs[0], weights[0]

    @renamed_keywords({"positions": "x"})
    def points(self, x: ArrayLike, kind: Kind = "w", *, moving: bool = False, name: str = "x") -> PointSet:
        """Points of the rail as a :class:`~semitrack.dynamics.points.PointSet` (loads act, responses are read).

        Parameters
        ----------
        x : array_like
            Positions on the rail (m from the centre), within the model's rail.
        kind : {"w", "psi"}
            The displacement (a vertical force acts there) or the rotation (a moment).
        moving : bool
            False: one fixed point per position. True: one point that moves, at ``x[k]`` at step k.
        name : str
            The parameter name quoted in errors.

        Returns
        -------
        PointSet
            DOFs removed by a pinned end carry weight 0.
        """
        xs = np.atleast_1d(as_real_array(x, "x")).ravel()
        dofs, weights = self._weights(xs, kind, name)
        removed = dofs < 0
        dofs, weights = np.where(removed, 0, dofs), np.where(removed, 0.0, weights)
        if moving:
            return PointSet(dofs[:, None, :], weights[:, None, :], (f"{kind} on the moving point",))
        return PointSet(dofs[None], weights[None], tuple(f"{kind}(x={xi:g} m)" for xi in xs))

    @renamed_keywords({"positions": "x"})
    def local_flexibility(self, x: ArrayLike, *, name: str = "x") -> np.ndarray:
        """The rail element's own deflection under a unit vertical force at each position (m/N).

        What the mesh's interpolation misses under a point force between nodes
        (:func:`semitrack.fe.element.point_flexibility`): in series with a wheel's contact there,
        ``w(x) = weights @ u + flexibility F``; 0 at a node.

        Parameters
        ----------
        x : array_like
            Positions on the rail (m), any shape.
        name : str
            The parameter name quoted in errors.

        Returns
        -------
        ndarray
            The shape of ``x``.
        """
        xs = as_real_array(x, "x")
        self._weights(xs.ravel(), "w", name)  # checks they lie on the rail
        e, xi = self.mesh.locate(xs.ravel())
        rail = [self.tracks[p] for p in range(len(self.tracks))]
        EI = np.array([t.E * t.I for t in rail])[self.mesh.part[e]]
        kAG = np.array([t.kappa * t.A * t.G for t in rail])[self.mesh.part[e]]
        return point_flexibility(EI, kAG, self.mesh.lengths[e], xi).reshape(xs.shape)

    @renamed_keywords({"positions": "x"})
    def output_matrix(self, x: ArrayLike, kind: Kind = "w") -> sp.csr_matrix:
        """Sparse matrix mapping the DOF vector to ``w`` (or ``psi``) at arbitrary positions.

        Uses the element shape functions, so between nodes it is the FE interpolation.

        Parameters
        ----------
        x : array_like
            Positions on the rail (m), within the model's rail; one row each, in this order.
        kind : {"w", "psi"}
            Output the displacement (m) or the rotation (rad).

        Returns
        -------
        scipy.sparse.csr_matrix, shape (n_x, n_dof)

        Examples
        --------
        >>> import semitrack as st
        >>> model = st.TruncatedTrack(st.slab_track(), 1, "free", elements_per_bay=2)
        >>> model.output_matrix([0.0, 0.1]).shape == (2, model.n_dof)
        True
        """
        return self.points(x, kind).matrix(self.n_dof)

    # --------------------------------------------------------------------------------------------
    def complex_stiffness(self, f: float | None = None) -> sp.csc_matrix:
        """Complex stiffness (N/m...): the damping of each family as a complex modulus.

        ``(1 + i eta_rail) K_rail + (1 + i eta_pad) K_pad + (1 + i eta_ballast) K_ballast + K_end``
        (and a flexible slab's ``(1 + i eta_slab) K_slab + (1 + i eta_support) K_layer``)
        where ``K_end`` holds the springs of attached equivalent systems (their dampers are
        viscous and enter as ``i omega C`` in :meth:`dynamic_stiffness`). The loss factors are
        the track's at ``f`` (:meth:`semitrack.Track.loss_factor`): constant for hysteretic
        damping, ``eta f / f_ref`` for viscous damping.

        Parameters
        ----------
        f : float, optional
            Frequency (Hz); required for a viscously damped track.
        """
        return self._csc(self._complex_k_data(f))

    def _complex_k_data(self, f: float | None = None) -> np.ndarray:
        """Data of ``K*`` at frequency ``f`` (Hz); ``f`` may be omitted for hysteretic damping."""
        if self.track.damping != "hysteretic" and f is None:
            raise InputError("a viscously damped track has a frequency-dependent K*: give f (Hz)")
        base, constant, slope = self._k_star_terms()
        return base + 1j * (constant + (1.0 if f is None else float(f)) * slope)

    def _k_star_terms(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``K*(f) = base + i (constant + f slope)`` (data on the pattern, N/m and alike).

        Each damped family's loss factor is ``eta`` (hysteretic) or ``eta f / f_ref`` (viscous:
        :meth:`semitrack.Track.loss_factor`), affine in f, so the families sum once into these three
        and a frequency costs one multiply-add over the stored entries, not one per family.
        """
        data = self._parts.data
        base, constant, slope = data["K_end"] + data["K_joint"], np.zeros(data["M"].size), np.zeros(data["M"].size)
        for tr, parts in zip(self.tracks, self._parts.by_track):
            for family in DAMPED:
                at_0, at_1 = np.asarray(tr.loss_factor(family[2:], np.array([0.0, 1.0])), dtype=float)
                base = base + parts[family]
                constant = constant + at_0 * parts[family]
                slope = slope + (at_1 - at_0) * parts[family]
        return base, constant, slope

    def mass(self) -> sp.csc_matrix:
        """Mass matrix (kg, kg m, kg m^2): rail (consistent), sleepers, attached systems."""
        return self._csc(self._parts.data["M"].copy())

    def _exact_blocks(self, omega: np.ndarray) -> dict:
        """``{side: (n_f, 2, 2)}`` end stiffness of each frequency-dependent end (exact, boundary)."""
        return {side: end.stiffness(self.end_track(side), omega, side) for side, end in self.end_models.items()
                if end.frequency_dependent}

    def _z_stack(self, f: np.ndarray, exact: dict, part: slice) -> np.ndarray:
        """Data of ``Z = K* + i omega C_end - omega^2 M`` (+ the exact blocks of frequencies ``part``) at each
        frequency of ``f`` (Hz): ``(f.size, n_stored)``."""
        d, (base, constant, slope) = self._parts.data, self._k_star_terms()
        omega = 2 * np.pi * f[:, None]
        data = np.empty((f.size, base.size), dtype=complex)
        data.real = base - (omega * omega) * d["M"]
        data.imag = constant + f[:, None] * slope + omega * d["C_end"]
        for side, block in exact.items():
            np.add.at(data, (slice(None), self._parts.exact[side]), block[part].reshape(f.size, -1))
        return data

    def dynamic_stiffness(self, f: float) -> sp.csc_matrix:
        """``Z = K* + i omega C_end - omega^2 M`` (+ exact end blocks) at one frequency.

        Parameters
        ----------
        f : float
            Frequency (Hz), positive.

        Returns
        -------
        scipy.sparse.csc_matrix of complex, shape (n_dof, n_dof)
            N/m, N/rad, N m/m, N m/rad by DOF pair.
        """
        f = np.array([float(as_frequencies(f))])
        return self._csc(self._z_stack(f, self._exact_blocks(2 * np.pi * f), slice(0, 1))[0])

    def solve(self, f: ArrayLike, rhs: ArrayLike, *, check_mesh: bool = True) -> np.ndarray:
        """Solve ``Z(f) u = rhs`` frequency by frequency (a band LU, :meth:`~.assembly.Pattern.solve`).

        Parameters
        ----------
        f : array_like
            Frequencies (Hz), scalar or 1-D.
        rhs : array_like, shape (n_dof, n_rhs)
            Load vectors (N, N m), the same at every frequency.
        check_mesh : bool
            Warn (a RuntimeWarning, once per model and range) when the frequencies exceed what
            the mesh resolves within 1 % (:mod:`semitrack.fe.meshsize`); False skips the check
            (the mesh probe itself).

        Returns
        -------
        ndarray of complex, shape (n_f, n_dof, n_rhs)
            Displacements (m) and rotations (rad).
        """
        f = np.atleast_1d(as_frequencies(f))
        if f.ndim != 1:
            raise InputError(f"f must be a scalar or a 1-D array of frequencies (Hz), got shape {f.shape}")
        rhs = np.asarray(rhs)
        if rhs.ndim != 2 or rhs.shape[0] != self.n_dof:
            raise InputError(f"rhs must have shape ({self.n_dof}, n_rhs), got {rhs.shape}")
        if check_mesh:
            self._check_mesh(float(f.max(initial=0.0)))
        exact = self._exact_blocks(2 * np.pi * f)
        out = np.empty((f.size, self.n_dof, rhs.shape[1]), dtype=complex)
        rhs_c = np.ascontiguousarray(rhs, dtype=complex)
        # The matrices' data is formed for a chunk of frequencies at once (one NumPy operation per term, not per
        # frequency), the chunk at most SWEEP_VALUES stored entries; each frequency is then one band LU.
        chunk = max(1, min(f.size, SWEEP_VALUES // max(self._parts.data["M"].size, 1)))
        with serial_blas():  # one band (or sparse) LU per frequency: threads only contend
            for lo in range(0, f.size, chunk):
                part = slice(lo, lo + chunk)
                for i, data in enumerate(self._z_stack(f[part], exact, part), start=lo):
                    out[i] = self._parts.pattern.solve(data, rhs_c)
        return out

    def _check_mesh(self, f_top: float) -> None:
        """Warn when frequencies above what the mesh resolves within MESH_TOLERANCE are asked (once per model)."""
        f_top = max(f_top, 1.0)  # the probes start at 1 Hz, and a mesh that resolves it resolves anything lower
        if f_top <= self._mesh_checked:
            return
        self._mesh_checked = f_top
        if f_top > MAX_MESH_FREQUENCY:  # beyond the probe's reach: said, and judged up to it
            warn_user(f"f reaches {f_top:.0f} Hz: the mesh's own error is measured up to "
                      f"{MAX_MESH_FREQUENCY:.0f} Hz only, so nothing above it is checked", RuntimeWarning)
            f_top = MAX_MESH_FREQUENCY
        probes = [mesh_probe(t, f_top) for t in self.tracks]
        valid = min(valid_frequency(probes, self.elements_per_bay), f_top)
        if valid < f_top:
            need = elements_for(probes, f_top)
            warn_user(f"{self.elements_per_bay} elements per bay keep the mesh's own error under "
                      f"{MESH_TOLERANCE:.0%} up to {valid:.0f} Hz only, and frequencies up to {f_top:.0f} Hz "
                      f"are asked: give elements_per_bay >= {need} (or leave it out and give f_max)",
                      RuntimeWarning)

    def receptance(self, f: ArrayLike, x: float = 0.0) -> np.ndarray:
        """2x2 point receptance at the rail node at ``x``: (w, psi) per (F, M) there.

        Parameters
        ----------
        f : float or array_like
            Frequencies (Hz); scalar or 1-D.
        x : float
            A node position (m); default the central cross-section / the cut.

        Returns
        -------
        ndarray of complex, shape (n_f, 2, 2), or (2, 2) for a scalar ``f``
            ``[[w/F (m/N), w/M (1/N)], [psi/F (1/N), psi/M (rad/(N m))]]``; F downward, M
            clockwise.
        """
        idx = [self.dof(x, "w"), self.dof(x, "psi")]
        rhs = np.zeros((self.n_dof, 2))
        rhs[idx, [0, 1]] = 1.0
        u = self.solve(f, rhs)[:, idx, :]
        return u[0] if np.ndim(f) == 0 else u

    def central_receptance(self, f: ArrayLike) -> np.ndarray:
        """:meth:`receptance` at x = 0: the central cross-section, or the end of a semi-infinite track.

        Parameters
        ----------
        f : float or array_like
            Frequencies (Hz); scalar or 1-D.

        Returns
        -------
        ndarray of complex, shape (n_f, 2, 2), or (2, 2) for a scalar ``f``
            For a complete track w1 is ``[..., 0, 0]`` (m/N) and psi2 ``[..., 1, 1]``
            (rad/(N m)); for a semi-infinite one (``n_left = 0``) the end receptance alpha.
            Units as :meth:`receptance`.
        """
        return self.receptance(f, 0.0)

    # --------------------------------------------------------------------------------------------
    def matrices(self, f_ref: float | dict | None = None) -> tuple[sp.csc_matrix, sp.csc_matrix, sp.csc_matrix]:
        """Real ``(M, C, K)`` sparse matrices for time integration (SI; DOFs as :attr:`n_dof`).

        Parameters
        ----------
        f_ref : None, float or dict
            Reference frequencies (Hz) at which the viscous damping of each family (rail, pads,
            ballast, a flexible slab and its layer) equals its loss factor: ``C = eta_rail K_rail
            / (2 pi f_rail) + eta_pad K_pad / (2 pi f_pad) + eta_ballast K_ballast / (2 pi
            f_ballast) + eta_slab K_slab / (2 pi f_slab) + eta_support K_layer / (2 pi f_layer)
            + C_end``. ``None``: the track's own (:meth:`semitrack.Track.reference_frequencies`,
            the same as a ``damping="viscous"`` track uses in the frequency domain); a float: the
            same for all; a dict: overrides for some of the keys "rail", "pad", "ballast",
            "slab", "layer".

        Returns
        -------
        M, C, K : scipy.sparse.csc_matrix
            Mass (kg...), damping (N s/m...) and stiffness (N/m...). With ``"boundary"`` ends
            ``K`` and ``C`` include the boundary's static stiffness and dashpot at the end DOFs;
            its states come from :meth:`boundary_states`.
        """
        boundaries = [end.boundary for end in self.end_models.values() if isinstance(end, BoundaryEnd)]
        warn_hysteretic(self.tracks, f_ref, max((b.max_error for b in boundaries), default=None))
        time = {side: end.time_matrices(side) for side, end in self.end_models.items()}
        d = self._parts.data
        K = sum(d[family] for family in DAMPED) + d["K_end"] + d["K_joint"]
        C = d["C_end"].copy()
        for tr, parts in zip(self.tracks, self._parts.by_track):
            fr, eta = reference_frequencies(tr, f_ref), tr.loss_factors()
            for family in DAMPED:
                name = family[2:]
                C = C + eta[name] * parts[family] / (2 * np.pi * fr[name])
        for side, parts in time.items():
            if parts is not None:
                np.add.at(K, self._parts.exact[side], parts[0].ravel())
                np.add.at(C, self._parts.exact[side], parts[1].ravel())
        return self._csc(d["M"].copy()), self._csc(C), self._csc(K)

    def boundary_states(self) -> list[StateBlock]:
        """The first-order states of the ``"boundary"`` ends (see :mod:`semitrack.dynamics.states`).

        Returns
        -------
        list of StateBlock
            One per boundary end (empty without such ends), on the end's two model DOFs
            ``(w, psi)``, with the mirror ``diag(1, -1)`` as its port at the left end. The end loads
            on the rail are ``-P (K0 P u + D P du/dt + C x)`` with ``dx/dt = A x + B P du/dt``;
            :meth:`matrices` already holds the ``K0`` and ``D`` parts.
        """
        if self._states is None:  # the ends' state space, once per model (its copies with other supports share it)
            self._states = tuple(block for side, end in self.end_models.items()
                                 for block in end.states(self._end_dofs(side), side))
        return list(self._states)

    def time_domain_system(self, f_ref: float | dict | None = None) -> SecondOrderSystem:
        """The model as a second-order system for the time domain: :meth:`matrices` and :meth:`boundary_states`.

        Parameters
        ----------
        f_ref : None, float or dict
            Reference frequencies of the viscous damping (Hz), see :meth:`matrices`.

        Returns
        -------
        SecondOrderSystem
            One DOF block, ``"track"``.
        """
        M, C, K = self.matrices(f_ref)
        return SecondOrderSystem(M, C, K, {"track": slice(0, self.n_dof)}, tuple(self.boundary_states()),
                                 self.dofs.along_track(self.mesh))

    def __repr__(self):
        names = " | ".join(repr(t.name) for t in self.tracks)
        return (f"{type(self).__name__}({names}, bays {self.n_left}+{self.n_right}, ends ({self.left_end!r}, "
                f"{self.right_end!r}), elements_per_bay={self.elements_per_bay}, n_dof={self.n_dof})")


def _infinite_of(track: Track, changes: Mapping | None, right: Track | None, transition: int | None,
                 joints: Mapping | None) -> InfiniteTrack | None:
    """The exact infinite track that holds the model's rules for changes, a transition and joints.

    None for a flexible-slab track (which InfiniteTrack does not hold), whose FE model takes
    none of them: a changed support, a transition or a joint there is refused by name.
    """
    slab = require_track(track).has_flexible_slab or (right is not None and require_track(right, "right")
                                                      .has_flexible_slab)
    if not slab:
        return InfiniteTrack(track, changes, right=right, transition=transition, joints=joints)
    asked = [name for name, value in (("changes", changes), ("right", right), ("transition", transition),
                                      ("joints", joints)) if value]
    if asked or transition is not None:
        what = ", ".join(asked) or "transition"
        raise InputError(f"a flexible-slab FE model is the periodic floating-slab track only, got {what}: a changed "
                         "support, a transition or a rail joint is not held by the slab model (whole slabs, free at "
                         "their joints) yet; model those on a rigid slab or on sleepers")
    return None


def _rail_only(track: Track) -> Track:
    """The track whose mesh error stands for the model's: a flexible slab's rail on its pads, the slab rigid.

    The rail sets the mesh's error (the slab's own elements are no longer than the rail's, and
    bend far less); InfiniteTrack, the probe's reference, holds no flexible slab.
    """
    return track.replace(slab=None) if track.has_flexible_slab else track


@lru_cache(maxsize=32)
def _probe(track: Track, top: float) -> MeshProbe:
    f = probe_grid(top)
    points = (0.0, 0.5 * track.spacing)  # a mid-span and a support
    exact = InfiniteTrack(track)
    model = FETrack(track, 3, 3, EXACT, EXACT, elements_per_bay=PROBE_ELEMENTS)
    rhs = np.zeros((model.n_dof, 2))
    for j, x in enumerate(points):
        rhs[model.dof(x), j] = 1.0
    u = model.solve(f, rhs, check_mesh=False)
    err = np.zeros(f.size)
    for j, x in enumerate(points):
        ref = exact.receptance(f, x, [x])[:, 0, 0, 0]
        err = np.maximum(err, np.abs(u[:, model.dof(x), j] - ref) / np.abs(ref))
    return MeshProbe(f, np.maximum.accumulate(err))


def mesh_probe(track: Track, f_max: float) -> MeshProbe:
    """The error of the periodic track's mesh measured up to ``f_max`` (:mod:`semitrack.fe.meshsize`).

    Three bays each side of a mid-span at :data:`~semitrack.fe.meshsize.PROBE_ELEMENTS` elements
    per bay, closed by the exact ends (the mesh the only approximation), against
    :class:`semitrack.InfiniteTrack`: w/F at a mid-span and at a support. Cached per track and
    range for the process (about a second each). For a flexible-slab track, the same rail on its
    pads on a rigid slab (the rail sets the error; the slab's elements are no longer than the rail's).

    Parameters
    ----------
    track : Track
        The periodic track.
    f_max : float
        Highest frequency (Hz); the probe runs to the next whole 500 Hz.

    Returns
    -------
    MeshProbe

    Examples
    --------
    >>> import semitrack as st
    >>> p = mesh_probe(st.slab_track(), 1000.0)
    >>> p.error_at(48, 1000.0) < p.error_at(12, 1000.0)
    True
    """
    return _probe(_rail_only(require_track(track)), float(probe_grid(f_max)[-1]))


def elements_per_bay_of(tracks: Sequence[Track], elements_per_bay: int | None, f_max: float | None = None) -> int:
    """The elements per bay of a model of ``tracks``: as given (checked even and >= 2), or the default for ``f_max``.

    Parameters
    ----------
    tracks : sequence of Track
        The model's tracks (a transition's two).
    elements_per_bay : int or None
        As :class:`FETrack` takes it; None: the fewest that keep the mesh's own error under 1 % up
        to ``f_max`` (:mod:`semitrack.fe.meshsize`).
    f_max : float, optional
        The highest frequency of interest (Hz; default :data:`DEFAULT_F_MAX`).

    Returns
    -------
    int
    """
    if elements_per_bay is None:
        top = DEFAULT_F_MAX if f_max is None else check_positive("f_max", f_max)
        return elements_for([mesh_probe(t, top) for t in tracks], top)
    ne = check_int_at_least("elements_per_bay", elements_per_bay, 2)
    if ne % 2:
        raise InputError(f"elements_per_bay must be even (mid-spans are nodes), got {ne}")
    return ne


def require_model(model: object, name: str = "model") -> FETrack:
    """``model`` if it is an :class:`FETrack`, else a TypeError that names it (as ``name``)."""
    if not isinstance(model, FETrack):
        raise InputTypeError(f"{name} must be an FETrack (e.g. TruncatedTrack), got {type(model).__name__}")
    return model


class TruncatedTrack(FETrack):
    """A truncated track: ``n_bays`` bays on each side of the central cross-section (a mid-span).

    The model is cut at mid-spans, so an equivalent system attaches exactly at its ends.

    Parameters
    ----------
    track : Track
        The track.
    n_bays : int
        Bays on each side of the centre (>= 1; 0 is allowed with "equivalent"/"exact" ends and
        then reduces to the paper's Sec. 5.3 pair of mirrored systems).
    ends : {"pinned", "free", "equivalent", "boundary", "exact"} or End
        End condition at both ends (see :mod:`semitrack.fe.models`), by name or as an end object
        of :mod:`semitrack.fe.ends`.
    system : EquivalentSystem, BroadbandBoundary or a pair of them, optional
        Required with ``ends="equivalent"`` (e.g. ``paper_table4()`` for the slab track,
        ``paper_table7()`` for the ballasted one, or a fitted system) and with
        ``ends="boundary"`` (from :func:`semitrack.fit_boundary`); with a transition
        ``(left_system, right_system)``, each fitted to its side's track.
    elements_per_bay : int, optional
        Elements per support spacing, even; default: the fewest that resolve ``f_max`` within
        1 % (see :class:`FETrack`).
    changes : mapping of int to mapping or None, optional
        Changed or removed supports, as :class:`FETrack` takes them.
    right, transition, joints : optional
        A second track from the mid-span ``x_t = transition d`` on, and rail joints, as
        :class:`semitrack.InfiniteTrack` takes them (see :class:`FETrack`).
    f_max : float, optional
        The highest frequency of interest (Hz), as :class:`FETrack` takes it.

    Examples
    --------
    Two bays each side of the centre of the slab track, closed by the paper's Table 4 system:

    >>> import semitrack as st
    >>> tt = st.TruncatedTrack(st.slab_track(), 2, ends="equivalent", system=st.paper_table4())
    >>> H = tt.central_receptance([100.0, 200.0])   # H[:, 0, 0] is w1 (m/N)
    >>> H.shape
    (2, 2, 2)
    >>> M, C, K = tt.matrices()                      # for the time domain
    >>> M.shape == (tt.n_dof, tt.n_dof)
    True
    """

    def __init__(self, track: Track, n_bays: int, ends: EndName | End = PINNED,
                 system: EquivalentSystem | BroadbandBoundary | Sequence | None = None,
                 elements_per_bay: int | None = None, changes: Mapping[int, Mapping[str, float] | None] | None = None,
                 *, right: Track | None = None, transition: int | None = None,
                 joints: Mapping[float, float] | None = None, f_max: float | None = None):
        n = check_int_at_least("n_bays", n_bays, 0)
        kind = type(ends) if isinstance(ends, End) else end_kinds(ends)[0]
        if n == 0 and not kind.closes_alone:
            raise InputError(f"n_bays must be >= 1 with ends={kind.name!r}, got 0")
        self.n_bays = n
        super().__init__(track, n, n, ends, ends, system, elements_per_bay, changes, right=right,
                         transition=transition, joints=joints, f_max=f_max)
        self.ends = kind.name  # the end condition's name; the end objects are end_models


# ------------------------------------------------------------------------------------------------
# Long tracks: the third route to alpha and w1
# ------------------------------------------------------------------------------------------------
def fe_semi_infinite_receptance(track: Track, f: ArrayLike, n_bays: int = 200, elements_per_bay: int | None = None,
                                far_end: FarEndName | End = PINNED) -> np.ndarray:
    """End receptance alpha of a long semi-infinite FE track cut at a mid-span.

    The rail starts at the cut (node 0, loaded by F and M), the first support at d/2; the
    model holds ``n_bays`` bays and ends at a mid-span with ``far_end``. Damping removes the far
    end's reflection when the track is long enough. With 12 elements per bay and 200 bays
    (130 m slab, 120 m ballasted) the median error against the exact transfer method over
    3-2997 Hz is 0.5 % (slab) and 0.3 % (ballasted); 100 bays leave 3.8 % on the slab track
    (weakly damped propagating waves above the 183 Hz cut-on), 8 elements per bay 0.8 %. The
    largest errors (tens of %) sit at the sharp second pinned-pinned peak (2.6 / 2.9 kHz),
    whose frequency the mesh shifts (24 elements per bay: 14 % / 28 %): the default mesh
    follows the highest frequency asked (:class:`FETrack`), which removes that part.

    Parameters
    ----------
    track : Track
        The track.
    f : float or array_like
        Frequencies (Hz); scalar or 1-D.
    n_bays : int
        Number of bays (>= 1).
    elements_per_bay : int, optional
        Even number of elements per support spacing; default: from the highest frequency of
        ``f`` (see :class:`FETrack`).
    far_end : {"pinned", "free", "exact"}
        The far end; ``"exact"`` terminates it with the exact semi-infinite end stiffness
        (removes the reflection, so a few bays suffice).

    Returns
    -------
    ndarray of complex, shape (n_f, 2, 2) or (2, 2)
        Units as :func:`semitrack.semi_infinite_receptance`: [[m/N, 1/N], [1/N, rad/(N m)]].

    Examples
    --------
    >>> import semitrack as st
    >>> a = fe_semi_infinite_receptance(st.slab_track(), 100.0, n_bays=2, far_end="exact", elements_per_bay=4)
    >>> bool(abs(a[0, 0] / st.semi_infinite_receptance(st.slab_track(), 100.0)[0, 0] - 1) < 0.01)
    True
    """
    end = make_far_end(far_end)
    n = check_int_at_least("n_bays", n_bays, 1)
    return FETrack(track, 0, n, FREE, end, elements_per_bay=elements_per_bay, f_max=_highest(f)).receptance(f, 0.0)


def _highest(f: ArrayLike) -> float:
    """The highest of the frequencies asked (Hz), for the default mesh: at least 1 Hz (the coarsest
    mesh is sized there and serves any lower frequency), at most the range a default mesh is sized for."""
    top = check_in_range("f", float(np.max(as_frequencies(f))), (0.0, MAX_MESH_FREQUENCY),
                         "Hz, the range a default mesh is sized for; give elements_per_bay for more")
    return max(top, 1.0)


def fe_central_receptance(track: Track, f: ArrayLike, n_bays: int = 200, elements_per_bay: int | None = None,
                          far_end: FarEndName | End = PINNED) -> np.ndarray:
    """2x2 receptance at the central cross-section (a mid-span) of a long complete FE track.

    ``n_bays`` bays on each side; ``[..., 0, 0]`` is w1 and ``[..., 1, 1]`` is psi2 of the
    paper's Eq. (14). The accuracy is that of :func:`fe_semi_infinite_receptance`.

    Parameters
    ----------
    track : Track
        The track.
    f : float or array_like
        Frequencies (Hz); scalar or 1-D.
    n_bays : int
        Number of bays on each side of the centre (>= 1).
    elements_per_bay : int, optional
        Even number of elements per support spacing; default: from the highest frequency of
        ``f`` (see :class:`FETrack`).
    far_end : {"pinned", "free", "exact"}
        Both far ends; ``"exact"`` removes their reflections.

    Returns
    -------
    ndarray of complex, shape (n_f, 2, 2) or (2, 2)
        [[w1 (m/N), w/M (1/N)], [psi/F (1/N), psi2 (rad/(N m))]] at x = 0.

    Examples
    --------
    >>> import semitrack as st
    >>> h = fe_central_receptance(st.slab_track(), 100.0, n_bays=2, far_end="exact", elements_per_bay=4)
    >>> bool(abs(h[0, 0] / st.central_response(st.slab_track(), 100.0).w1 - 1) < 0.01)
    True
    """
    end = make_far_end(far_end)
    n = check_int_at_least("n_bays", n_bays, 1)
    return TruncatedTrack(track, n, end, elements_per_bay=elements_per_bay, f_max=_highest(f)).central_receptance(f)
