"""A truncated track that travels with the vehicle: a short FE window over an infinite track with changes.

:class:`WindowTrack` describes an infinite track carrying local changes (any number: every
support of a random track), a transition to a second track and rail joints, with exactly the
meaning of :class:`semitrack.InfiniteTrack` and :class:`semitrack.TruncatedTrack`: x from the
central mid-span, support k at ``x = (k + 1/2) d`` (past a transition ``x_t + (k - kt + 1/2) d2``).
It holds no mesh of the whole track. A run (:mod:`semitrack.interaction.window_model`) asks it for
the FE model of the stretch around the vehicle, :meth:`WindowTrack.model_at`: ``behind`` bays
behind the rearmost wheel and ``ahead`` bays ahead of the leading one (at least), each end closed
by the broadband boundary of the track it stands on (:func:`semitrack.fit_boundary`, fitted once
per track), on the same elements per bay wherever it stands, so that moving it by ``move`` bays
is a renumbering of its DOFs by their places along the track (:meth:`WindowTrack.same_dofs`).

The lengths ahead and behind set the error. What the window gets wrong is what it cannot hold:
the new bay that enters at the front at rest, and the track beyond either end, which its
boundaries stand for as the nominal track: on a random track the reflections of the supports out
there are lost on both sides. These errors travel to the wheels and back through the track, so
they fall as the track's decay rate: the error level in a band falls at about twice the track's
least decay rate per metre of the length ahead, and the rear wheel's as much per metre behind.
The default ``ahead`` and ``behind`` are the length that attenuates that round trip by
:data:`DEFAULT_ATTENUATION` at the least one-third-octave decay rate over 50 Hz-2.5 kHz
(:func:`semitrack.track_decay_rate`, of the track's loss factors taken as hysteretic damping, as
a measured track's would be): 38 bays on the paper's ballasted track, 60 on its slab track.
Measured against the model that holds the path, a bogie at 250 km/h over random tracks (pads
log-normal with a CoV of 20 %, ballast 30 %, a failed fastener, hanging sleepers): 0.03-0.11 % rms
of the force's fluctuation per wheel, every one-third-octave band 50 Hz - 2.5 kHz within 0.02 dB
(the book's chapter, 16 elements per bay; ``benchmarks/bench_window.py`` on the default mesh);
one wheel on the periodic slab track within 0.3 % of the moving Green's functions (``tests/``).
The error falls about 0.4 dB a bay added on both sides (the chapter's table of lengths).
"""

from __future__ import annotations

import functools
import math
from collections.abc import Mapping, Sequence

import numpy as np
from numpy.typing import ArrayLike

from ..base.checks import as_real_array, check_int_at_least, check_nonnegative, check_positive, check_work
from ..base.errors import InputError
from ..boundary.fitting import BroadbandBoundary, fit_boundary
from ..methods.decay import track_decay_rate
from ..methods.infinite import InfiniteTrack
from ..model.tracks import Track, require_track
from .ends import BoundaryEnd, make_end
from .models import DEFAULT_F_MAX, FETrack, elements_per_bay_of
from .supports import CONSTANT_SUPPORTS_ONLY, support_values

__all__ = ["DEFAULT_ATTENUATION", "DECAY_BAND", "DEFAULT_MOVE", "WindowTrack", "least_decay_rate"]

#: The round-trip attenuation (dB) at the track's least decay rate that sets the default lengths
#: ahead and behind: 38 bays on the ballasted track, 60 on the slab track of the paper.
DEFAULT_ATTENUATION = 20.0
#: The one-third-octave bands (Hz) whose least decay rate sets the default lengths.
DECAY_BAND = (50.0, 2500.0)
#: Bays a window moves at a time by default (see :class:`WindowTrack`).
DEFAULT_MOVE = 4
#: Most bays a window may hold (its model's size is what a step costs).
MAX_WINDOW_BAYS = 2_000
#: Farthest a window moves from x = 0 (bays): 60 000 km of track at 0.6 m.
MAX_OFFSET_BAYS = 100_000_000


class WindowTrack:
    """An infinite track with local changes, modelled in time by a short FE window that moves with the vehicle.

    Parameters
    ----------
    track : Track
        Rail, pads and foundation (a rigid slab or sleepers on ballast; not a flexible slab).
    changes : mapping of int to mapping or None, optional
        ``{k: {field: value}}`` changes support k as :class:`semitrack.InfiniteTrack` does
        (``kv``, ``kphi``, ``sleeper_mass``, ``kb``; ``{k: None}`` a failed fastener); any number.
    right, transition, joints
        A second track from mid-span ``transition`` on and rail joints ``{x: k_rot}``, as
        :class:`semitrack.InfiniteTrack` takes them; each end of the window is closed by the
        boundary of the track it stands on.
    behind, ahead : int, optional
        Bays behind the rearmost wheel and ahead of the leading wheel (>= 2 each). Default: the
        length that attenuates the round trip by :data:`DEFAULT_ATTENUATION` dB at the track's
        least decay rate, on each side (see the module docstring for the accuracy measured).
    elements_per_bay : int, optional
        Elements per bay, as :class:`semitrack.FETrack` (default: the fewest that resolve ``f_max``).
    f_max : float, optional
        The highest frequency of interest (Hz; default 3 kHz).
    system : BroadbandBoundary or pair of them, optional
        The broadband boundary of the track's semi-infinite end (with a transition, one per
        track); default fitted once by :func:`semitrack.fit_boundary` over 3 Hz - 3 kHz (a few
        seconds) and kept.
    move : int
        Bays the window moves at a time (>= 1; default :data:`DEFAULT_MOVE`): each move costs a
        new model, a factorisation and the run's set-up again (a few milliseconds), so moving
        further less often saves that, for ``move - 1`` more bays ahead.

    Examples
    --------
    >>> import semitrack as st
    >>> win = st.WindowTrack(st.slab_track(damping="viscous"), {3: None}, behind=4, ahead=8, elements_per_bay=8)
    >>> win.behind, win.ahead, sorted(win.changes)
    (4, 8, [3])
    """

    def __init__(self, track: Track, changes: Mapping[int, Mapping[str, float] | None] | None = None, *,
                 right: Track | None = None, transition: int | None = None, joints: Mapping | None = None,
                 behind: int | None = None, ahead: int | None = None, elements_per_bay: int | None = None,
                 f_max: float | None = None, system: BroadbandBoundary | Sequence | None = None,
                 move: int = DEFAULT_MOVE):
        self._infinite = InfiniteTrack(require_track(track), changes, right=right, transition=transition,
                                       joints=joints)  # the rules of changes, a transition and joints, in one place
        self.track, self.right, self.transition = self._infinite.track, self._infinite.right, self._infinite.transition
        self.tracks = (self.track,) if self.right is None else (self.track, self.right)
        for name, t in zip(("track", "right"), self.tracks):
            if t.has_flexible_slab:
                raise InputError(f"{name}: a WindowTrack takes a rigid slab or a ballasted track, not a flexible slab "
                                 "(use TruncatedTrack)")
        if self.right is not None and self.right.damping != self.track.damping:
            raise InputError(f"the two tracks of a transition must have one kind of damping, got "
                             f"{self.track.damping!r} and {self.right.damping!r}")
        for name, t in zip(("track", "right"), self.tracks):
            t.require_constant(f"the finite-element track ({name})", CONSTANT_SUPPORTS_ONLY)
        self.changes: dict[int, dict | None] = dict(self._infinite.changes)
        self.joints: dict[float, float] = dict(self._infinite.joints)
        keys = np.array(sorted(self.changes), dtype=np.int64)  # the FE models' rules for every change, now
        support_values(self.tracks, np.array([self.part_at(k) for k in keys], dtype=np.int64), keys, self.changes)
        self.f_max = DEFAULT_F_MAX if f_max is None else check_positive("f_max", f_max)
        self._f_max_given = f_max is not None
        self.elements_per_bay = elements_per_bay_of(self.tracks, elements_per_bay, self.f_max)
        if elements_per_bay is not None and f_max is not None:  # a stated mesh and band: warn once, now
            for t in self.tracks:
                FETrack(t, 1, 1, elements_per_bay=self.elements_per_bay, f_max=self.f_max)
        self._boundaries = self._check_systems(system)
        self._templates: dict = {}  # the plain window of each track and size
        self.move = check_int_at_least("move", move, 1)
        if self.move > MAX_WINDOW_BAYS // 4:
            raise InputError(f"move must be at most {MAX_WINDOW_BAYS // 4} bays, got {move}")
        self._ahead = None if ahead is None else self._check_bays("ahead", ahead)
        self._behind = None if behind is None else self._check_bays("behind", behind)

    def _check_systems(self, system) -> list:
        """The given boundary of each track (None where it is to be fitted), each checked against its track."""
        given = list(system) if isinstance(system, (tuple, list)) else [system] * len(self.tracks)
        if len(given) != len(self.tracks):
            raise InputError(f"system must be a BroadbandBoundary or one per track ({len(self.tracks)}), got "
                             f"{len(given)}")
        for b, t in zip(given, self.tracks):
            if b is not None and not isinstance(b, BroadbandBoundary):
                raise InputError(f"system must be a BroadbandBoundary of the track, got {type(b).__name__}")
            if b is not None:
                make_end(BoundaryEnd.name, b).check_track(t)
        return given

    @staticmethod
    def _check_bays(name: str, value: int) -> int:
        value = check_int_at_least(name, value, 2)
        if value > MAX_WINDOW_BAYS:
            raise InputError(f"{name} must be at most {MAX_WINDOW_BAYS} bays, got {value}")
        return value

    @property
    def spacing(self) -> float:
        """The least support spacing d (m) of the track (of both, with a transition)."""
        return min(t.spacing for t in self.tracks)

    def boundary_of(self, part: int = 0) -> BroadbandBoundary:
        """The broadband boundary of the first track (``part=0``) or the second (1), fitted on first use.

        Parameters
        ----------
        part : int
            0 or 1.

        Returns
        -------
        BroadbandBoundary
        """
        part = check_int_at_least("part", part, 0)
        if part >= len(self.tracks):
            raise InputError(f"part must be 0{' or 1' if len(self.tracks) > 1 else ''}, got {part}")
        if self._boundaries[part] is None:
            self._boundaries[part] = fit_boundary(self.tracks[part])
        return self._boundaries[part]

    @property
    def boundary(self) -> BroadbandBoundary:
        """The first track's broadband boundary (fitted on first use when none was given)."""
        return self.boundary_of(0)

    def _default_ahead(self) -> int:
        return max(2, max(math.ceil(DEFAULT_ATTENUATION / (2.0 * least_decay_rate(t) * t.spacing))
                          for t in self.tracks))

    @property
    def ahead(self) -> int:
        """Bays ahead of the leading wheel."""
        if self._ahead is None:
            self._ahead = self._default_ahead()
        return self._ahead

    @property
    def behind(self) -> int:
        """Bays behind the rearmost wheel."""
        if self._behind is None:
            self._behind = self.ahead
        return self._behind

    def infinite_track(self) -> InfiniteTrack:
        """The exact infinite track with the same changes, transition and joints: the reference of the window."""
        return self._infinite

    def mid_span(self, bay: ArrayLike) -> np.ndarray:
        """The position (m) of mid-span ``bay``: ``bay d``, or past a transition ``x_t + (bay - kt) d2``.

        Parameters
        ----------
        bay : array_like of int
            Mid-span indices (support k sits between mid-spans k and k + 1).

        Returns
        -------
        ndarray
        """
        j = as_real_array(bay, "bay")
        if self.transition is None:
            return j * self.track.spacing
        kt = self.transition
        return np.where(j <= kt, j * self.track.spacing, kt * self.track.spacing + (j - kt) * self.right.spacing)

    def origin(self, offset: int, n_left: int, n_right: int) -> float:
        """Where the window's local x = 0 lies on the track (m): x_global = x_local + origin.

        The mid-span ``offset``; but a window that holds the transition is an FETrack with it, whose
        x is the first track's (mid-span j at ``j d1`` up to the transition), so its x = 0 lies at
        ``offset d1`` even when that mid-span is past the transition.

        Parameters
        ----------
        offset : int
            Bays the window has moved from x = 0.
        n_left, n_right : int
            Its bays left and right of its own mid-span.

        Returns
        -------
        float
        """
        if self.transition is not None and -n_left <= self.transition - offset <= n_right:
            return offset * self.track.spacing
        return float(self.mid_span(offset))

    def bay_of(self, x: ArrayLike) -> np.ndarray:
        """The bay that holds each position (m): the mid-span index at or before it.

        Parameters
        ----------
        x : array_like
            Positions (m).

        Returns
        -------
        ndarray of int
        """
        x = as_real_array(x, "x")
        first = np.floor(x / self.track.spacing + 1e-12)
        if self.transition is None:
            return first.astype(np.int64)
        kt, x_t = self.transition, self.transition * self.track.spacing
        second = kt + np.floor((x - x_t) / self.right.spacing + 1e-12)
        return np.where(x < x_t, first, second).astype(np.int64)

    def bays(self, span: float) -> tuple[int, int]:
        """``(n_left, n_right)``: the bays of a window for a vehicle ``span`` m long.

        The leading wheel stays within the ``move`` bays right of the window's local x = 0 (it jumps
        back by them as it leaves them), ``move`` bays' slack kept behind for the stretch after a
        jump.

        Parameters
        ----------
        span : float
            The vehicle's length from its first to its last wheel (m).

        Returns
        -------
        tuple of int
        """
        span = check_nonnegative("span", span)
        check_work(span / self.spacing, MAX_WINDOW_BAYS, f"span={span!r} m is {span / self.spacing:.3g} bays",
                   "a vehicle is shorter than the window's bays")
        n_left = self.behind + math.ceil(span / self.spacing - 1e-9) + self.move
        n_right = self.ahead + self.move
        if n_left + n_right > MAX_WINDOW_BAYS:
            raise InputError(f"behind, ahead: the vehicle and behind + ahead need {n_left + n_right} bays, more "
                             f"than {MAX_WINDOW_BAYS}")
        return n_left, n_right

    def local_changes(self, offset: int, n_left: int, n_right: int) -> dict:
        """The changes of the supports inside the window moved ``offset`` bays, in its own numbering.

        Parameters
        ----------
        offset : int
            Bays the window has moved from x = 0.
        n_left, n_right : int
            Its bays left and right of its own mid-span.

        Returns
        -------
        dict
            ``{k - offset: change}`` for the supports k inside it.
        """
        return {k - offset: v for k, v in self.changes.items() if self.holds(k, offset, n_left, n_right)}

    @staticmethod
    def holds(support: int, offset: int, n_left: int, n_right: int) -> bool:
        """Whether support ``support`` lies inside the window moved ``offset`` bays.

        Parameters
        ----------
        support : int
            A support's index k.
        offset : int
            Bays the window has moved from x = 0.
        n_left, n_right : int
            Its bays left and right of its own mid-span.

        Returns
        -------
        bool
        """
        return -n_left <= support - offset < n_right

    def _local_joints(self, offset: int, n_left: int, n_right: int) -> dict:
        lo, hi = self.mid_span([offset - n_left, offset + n_right])
        origin = self.origin(offset, n_left, n_right)
        return {float(x - origin): kr for x, kr in self.joints.items() if lo < x < hi}

    def model_at(self, offset: int, n_left: int, n_right: int) -> FETrack:
        """The window's FE model moved by ``offset`` bays: x_global = x_local + :meth:`origin`.

        Parameters
        ----------
        offset : int
            Bays the window has moved from x = 0.
        n_left, n_right : int
            Its bays left and right of its own mid-span x = 0 (:meth:`bays`).

        Returns
        -------
        FETrack
            With broadband boundary ends (each its side's track's), the supports inside it numbered
            from its own mid-span. On one track and without joints: the plain window of that size
            (built once) with the window's changes (:meth:`FETrack.with_changes`); across a
            transition or with joints, built afresh.
        """
        offset = check_int_at_least("offset", offset, -MAX_OFFSET_BAYS)
        if offset > MAX_OFFSET_BAYS:
            raise InputError(f"offset must be at most {MAX_OFFSET_BAYS} bays, got {offset!r}")
        for name, value in (("n_left", n_left), ("n_right", n_right)):
            if check_int_at_least(name, value, 0) > MAX_WINDOW_BAYS:
                raise InputError(f"{name} must be at most {MAX_WINDOW_BAYS} bays, got {value!r}")
        n_left, n_right = (check_int_at_least(name, n, 1) for name, n in (("n_left", n_left), ("n_right", n_right)))
        changes = self.local_changes(offset, n_left, n_right)
        joints = self._local_joints(offset, n_left, n_right)
        kt = None if self.transition is None else self.transition - offset
        f_max = self.f_max if self._f_max_given else None
        if kt is not None and -n_left <= kt <= n_right or joints:
            left, right = (0, 1) if kt is not None and -n_left <= kt <= n_right else (self.part_at(offset),) * 2
            two = left != right
            return FETrack(self.tracks[left], n_left, n_right, BoundaryEnd.name, BoundaryEnd.name,
                           system=(self.boundary_of(left), self.boundary_of(right)),
                           elements_per_bay=self.elements_per_bay, changes=changes,
                           right=self.tracks[right] if two else None, transition=kt if two else None,
                           joints=joints or None, f_max=f_max)
        part = self.part_at(offset)
        key = (part, n_left, n_right)
        if key not in self._templates:
            self._templates[key] = FETrack(self.tracks[part], n_left, n_right, BoundaryEnd.name, BoundaryEnd.name,
                                           system=self.boundary_of(part), elements_per_bay=self.elements_per_bay,
                                           f_max=f_max)
        return self._templates[key]._with_checked_changes(changes)

    def part_at(self, bay: int) -> int:
        """Which track (0 or 1) lies right of mid-span ``bay``: where a window with no transition inside stands.

        Parameters
        ----------
        bay : int
            A mid-span index.

        Returns
        -------
        int
        """
        return int(self.transition is not None and bay >= self.transition)

    def layout_key(self, offset: int, n_left: int, n_right: int) -> tuple:
        """What makes two windows' models the same: their tracks, transition, joints and changes.

        Parameters
        ----------
        offset : int
            Bays the window has moved from x = 0.
        n_left, n_right : int
            Its bays left and right of its own mid-span.

        Returns
        -------
        tuple
            Equal for two offsets whose windows have the same matrices.
        """
        changes = self.local_changes(offset, n_left, n_right)
        kt = None if self.transition is None else self.transition - offset
        inside = kt is not None and -n_left <= kt <= n_right
        return (kt if inside else self.part_at(offset), tuple(sorted(self._local_joints(offset, n_left, n_right))),
                tuple(sorted((k, None if v is None else tuple(sorted(v.items()))) for k, v in changes.items())))

    def same_dofs(self, from_window: FETrack, from_offset: int, dofs: np.ndarray, to_window: FETrack,
                  to_offset: int) -> np.ndarray:
        """The DOFs of ``to_window`` that are the same DOFs of the track as ``dofs`` of ``from_window`` (-1: not in it).

        Read from the DOFs' places along the track and their kinds (rail w, rail psi, sleeper,
        a joint's second rotation), each window's local x placed at its :meth:`origin`.

        Parameters
        ----------
        from_window, to_window : FETrack
            Two windows' models.
        from_offset, to_offset : int
            Their offsets (bays).
        dofs : ndarray of int
            DOFs of ``from_window``.

        Returns
        -------
        ndarray of int, the shape of ``dofs``
        """
        have = _dof_keys(from_window, self.origin(from_offset, from_window.n_left, from_window.n_right))[
            np.asarray(dofs, dtype=np.int64)]
        keys = _dof_keys(to_window, self.origin(to_offset, to_window.n_left, to_window.n_right))
        order = np.argsort(keys)
        pos = np.clip(np.searchsorted(keys[order], have), 0, keys.size - 1)
        return np.where(keys[order][pos] == have, order[pos], -1)

    def shadow_nodes(self, window: FETrack, offset: int) -> np.ndarray:
        """The rail nodes at the window's mid-spans, from a bay inside the rear end to the front end.

        Each is the rear end of a later window: a run keeps its boundary states in the shadow
        (:mod:`semitrack.interaction.window_model`).

        Parameters
        ----------
        window : FETrack
            The window's model.
        offset : int
            Its offset (bays).

        Returns
        -------
        ndarray of int
        """
        spans = self.mid_span(np.arange(offset - window.n_left + 1, offset + window.n_right + 1))
        local = spans - self.origin(offset, window.n_left, window.n_right)
        nodes = np.searchsorted(window.x, local - 1e-9)
        return nodes.astype(np.int64)

    def __repr__(self):
        lengths = ("default" if self._behind is None else self._behind, "default" if self._ahead is None
                   else self._ahead)
        return (f"WindowTrack({' | '.join(repr(t.name) for t in self.tracks)}, {len(self.changes)} changes, "
                f"{len(self.joints)} joints, behind={lengths[0]}, ahead={lengths[1]}, move={self.move}, "
                f"elements_per_bay={self.elements_per_bay})")


@functools.lru_cache(maxsize=16)
def least_decay_rate(track: Track) -> float:
    """The track's least one-third-octave decay rate over :data:`DECAY_BAND` (dB/m), kept per track.

    Of the track's loss factors as hysteretic damping (as measured on a track): the rule of the
    default lengths was found with it; a viscous track's own rises with frequency and would
    shorten the window.
    """
    loss = track.replace(damping="hysteretic") if track.damping != "hysteretic" else track
    return float(np.min(track_decay_rate(loss, band=DECAY_BAND).decay_rate))


def _dof_keys(model: FETrack, origin: float) -> np.ndarray:
    """An integer per model DOF: its place along the track (nm, the window's x = 0 at ``origin``) x 4 + its kind.

    The kinds: 0 the rail's w, 1 its psi, 2 a foundation DOF (a sleeper), 3 a joint's second rotation.
    """
    dofs, mesh = model.dofs, model.mesh
    if dofs.systems:
        raise InputError("a window's DOFs must be the rail's, its joints' and its sleepers' only")
    place = np.rint((mesh.x + origin) * 1e9).astype(np.int64)  # nm: far finer than any mesh, exact for equal x
    node = np.empty(dofs.n_full, np.int64)
    kind = np.empty(dofs.n_full, np.int64)
    n_rail = 2 * mesh.n_nodes
    node[:n_rail] = np.repeat(np.arange(mesh.n_nodes), 2)
    kind[:n_rail] = np.tile([0, 1], mesh.n_nodes)
    node[n_rail:mesh.n_rail_dofs] = mesh.joint_nodes
    kind[n_rail:mesh.n_rail_dofs] = 3
    node[dofs.foundation] = dofs.foundation_nodes
    kind[dofs.foundation] = 2
    keys = np.empty(dofs.n_dof, np.int64)
    keep = dofs.index >= 0
    keys[dofs.index[keep]] = 4 * place[node[keep]] + kind[keep]
    return keys
