"""A truncated track that travels with the vehicle: a short FE window over an infinite track with changes.

:class:`WindowTrack` describes an infinite track carrying local changes (any number: every
support of a random track), with exactly the meaning of :class:`semitrack.InfiniteTrack` and
:class:`semitrack.TruncatedTrack`: x from the central mid-span, support k at ``x = (k + 1/2) d``.
It holds no mesh of the whole track. A run (:mod:`semitrack.interaction.window_model`) asks it for
the FE model of the stretch around the vehicle, :meth:`WindowTrack.model_at`: ``behind`` bays
behind the rearmost wheel and ``ahead`` bays ahead of the leading one (at least), closed at both ends by
broadband boundaries (:func:`semitrack.fit_boundary`, fitted once per track), on the same mesh
per bay wherever it stands, so that moving it by ``move`` bays is a renumbering of its DOFs
(:meth:`WindowTrack.shift_map`).

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
Half the length behind doubled the rear wheel's error on the random ballasted track (0.37 % at 17
bays behind, 33 ahead), and the error falls about 0.4 dB a bay added on both sides.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Mapping

import numpy as np

from ..base.checks import check_int_at_least, check_positive
from ..base.errors import InputError
from ..boundary.fitting import BroadbandBoundary, fit_boundary
from ..methods.decay import track_decay_rate
from ..methods.infinite import InfiniteTrack
from ..model.tracks import Track, require_track
from .ends import BoundaryEnd, make_end
from .models import DEFAULT_F_MAX, FETrack, elements_per_bay_of

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
        A transition to a second track and rail joints, as :class:`semitrack.InfiniteTrack`
        takes them: not yet held by the window, refused when given.
    behind, ahead : int, optional
        Bays behind the rearmost wheel and ahead of the leading wheel (>= 2 each). Default: the
        length that attenuates the round trip by :data:`DEFAULT_ATTENUATION` dB at the track's
        least decay rate, on each side (see the module docstring for the accuracy measured).
    elements_per_bay : int, optional
        Elements per bay, as :class:`semitrack.FETrack` (default: the fewest that resolve ``f_max``).
    f_max : float, optional
        The highest frequency of interest (Hz; default 3 kHz).
    system : BroadbandBoundary, optional
        The broadband boundary of the track's semi-infinite end; default fitted once by
        :func:`semitrack.fit_boundary` over 3 Hz - 3 kHz (a few seconds) and kept.
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
                 f_max: float | None = None, system: BroadbandBoundary | None = None, move: int = DEFAULT_MOVE):
        self.track = require_track(track)
        if self.track.has_flexible_slab:
            raise InputError("track: a WindowTrack takes a rigid slab or a ballasted track, not a flexible slab "
                             "(use TruncatedTrack)")
        for name, value in (("right", right), ("transition", transition), ("joints", joints)):
            if value is not None and value != {}:
                raise InputError(f"{name}: a WindowTrack does not hold a transition or joints yet; use "
                                 "TruncatedTrack over the whole path")
        self._infinite = InfiniteTrack(self.track, changes)
        self.changes: dict[int, dict | None] = dict(self._infinite.changes)
        self.f_max = DEFAULT_F_MAX if f_max is None else check_positive("f_max", f_max)
        self.elements_per_bay = elements_per_bay_of((self.track,), elements_per_bay, self.f_max)
        if elements_per_bay is not None and f_max is not None:  # a stated mesh and band: warn once, now
            FETrack(self.track, 1, 1, elements_per_bay=self.elements_per_bay, f_max=self.f_max)
        if system is not None and not isinstance(system, BroadbandBoundary):
            raise InputError(f"system must be a BroadbandBoundary of the track, got {type(system).__name__}")
        if system is not None:
            make_end(BoundaryEnd.name, system).check_track(self.track)
        self._boundary = system
        self._template: FETrack | None = None  # the periodic window of the last size asked
        self.move = check_int_at_least("move", move, 1)
        if self.move > MAX_WINDOW_BAYS // 4:
            raise InputError(f"move must be at most {MAX_WINDOW_BAYS // 4} bays, got {move}")
        self._ahead = None if ahead is None else self._check_bays("ahead", ahead)
        self._behind = None if behind is None else self._check_bays("behind", behind)

    @staticmethod
    def _check_bays(name: str, value: int) -> int:
        value = check_int_at_least(name, value, 2)
        if value > MAX_WINDOW_BAYS:
            raise InputError(f"{name} must be at most {MAX_WINDOW_BAYS} bays, got {value}")
        return value

    @property
    def spacing(self) -> float:
        """The support spacing d (m)."""
        return self.track.spacing

    @property
    def boundary(self) -> BroadbandBoundary:
        """The broadband boundary at both ends (fitted on first use when none was given)."""
        if self._boundary is None:
            self._boundary = fit_boundary(self.track)
        return self._boundary

    def _default_ahead(self) -> int:
        return max(2, math.ceil(DEFAULT_ATTENUATION / (2.0 * least_decay_rate(self.track) * self.spacing)))

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
        """The exact infinite track with the same changes: the reference of the window."""
        return self._infinite

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
        n_left = self.behind + math.ceil(span / self.spacing - 1e-9) + self.move
        n_right = self.ahead + self.move
        if n_left + n_right > MAX_WINDOW_BAYS:
            raise InputError(f"the vehicle and behind + ahead need {n_left + n_right} bays, more than "
                             f"{MAX_WINDOW_BAYS}")
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
        return {k - offset: v for k, v in self.changes.items() if -n_left <= k - offset < n_right}

    def model_at(self, offset: int, n_left: int, n_right: int) -> FETrack:
        """The window's FE model moved by ``offset`` bays: x_global = x_local + offset d.

        Parameters
        ----------
        offset : int
            Bays the window has moved from x = 0.
        n_left, n_right : int
            Its bays left and right of its own mid-span x = 0 (:meth:`bays`).

        Returns
        -------
        FETrack
            With broadband boundary ends, the supports inside it numbered from its own mid-span: the
            periodic window of that size (built once) with the window's changes
            (:meth:`FETrack.with_changes`).
        """
        if self._template is None or (self._template.n_left, self._template.n_right) != (n_left, n_right):
            self._template = FETrack(self.track, n_left, n_right, BoundaryEnd.name, BoundaryEnd.name,
                                     system=self.boundary,
                                     elements_per_bay=self.elements_per_bay,
                                     f_max=self.f_max if self.f_max != DEFAULT_F_MAX else None)
        return self._template._with_checked_changes(self.local_changes(offset, n_left, n_right))

    def shift_map(self, window: FETrack) -> np.ndarray:
        """For each DOF of a window moved on, the DOF of the window before it (-1: it enters at rest).

        A window's layout is the same wherever it stands (one mesh per bay, no internal DOFs at
        its ends), so the map is read from the DOFs' places along the track: a DOF at local x
        in the new window is the DOF of the same kind at ``x + move d`` in the old one.

        Parameters
        ----------
        window : FETrack
            The window's model at any offset (:meth:`model_at`).

        Returns
        -------
        ndarray of int, shape (n_dof,)
        """
        return self.moved_dofs(window, np.arange(window.n_dof), -self.move)

    @staticmethod
    def moved_dofs(window: FETrack, dofs: np.ndarray, bays: int) -> np.ndarray:
        """The DOFs of the window ``bays`` further on that are the same DOFs of the track as ``dofs`` (-1: outside).

        Parameters
        ----------
        window : FETrack
            The window's model at any offset.
        dofs : ndarray of int
            DOFs of that window.
        bays : int
            How far on the other window stands (negative: behind).

        Returns
        -------
        ndarray of int, the shape of ``dofs``
        """
        keys = _dof_keys(window)
        wanted = keys[np.asarray(dofs, dtype=np.int64)] - 4 * bays * window.elements_per_bay  # in element lengths
        order = np.argsort(keys)
        pos = np.clip(np.searchsorted(keys[order], wanted), 0, keys.size - 1)
        return np.where(keys[order][pos] == wanted, order[pos], -1)

    @staticmethod
    def shadow_nodes(window: FETrack) -> np.ndarray:
        """The rail nodes a bay apart, from a bay inside the rear end to the front end.

        Each is the rear end of a later window: a run keeps its boundary states in the shadow
        (:mod:`semitrack.interaction.window_model`).

        Parameters
        ----------
        window : FETrack
            The window's model.

        Returns
        -------
        ndarray of int
        """
        return np.arange(window.elements_per_bay, window.n_nodes, window.elements_per_bay)

    def __repr__(self):
        return (f"WindowTrack({self.track.name!r}, {len(self.changes)} changes, behind={self._behind}, "
                f"ahead={self._ahead}, elements_per_bay={self.elements_per_bay})")


@functools.lru_cache(maxsize=16)
def least_decay_rate(track: Track) -> float:
    """The track's least one-third-octave decay rate over :data:`DECAY_BAND` (dB/m), kept per track.

    Of the track's loss factors as hysteretic damping (as measured on a track): the rule of the
    default lengths was found with it; a viscous track's own rises with frequency and would
    shorten the window.
    """
    loss = track.replace(damping="hysteretic") if track.damping != "hysteretic" else track
    return float(np.min(track_decay_rate(loss, band=DECAY_BAND).decay_rate))


def _dof_keys(model: FETrack) -> np.ndarray:
    """An integer per model DOF: 4 x its node (in element lengths from the left end) + its kind (w, psi, sleeper)."""
    dofs, mesh = model.dofs, model.mesh
    if dofs.systems or mesh.joint_nodes.size:
        raise InputError("a window's DOFs must be the rail's and its sleepers' only")
    node = np.empty(dofs.n_full, np.int64)
    kind = np.empty(dofs.n_full, np.int64)
    n_rail = 2 * mesh.n_nodes
    node[:n_rail] = np.repeat(np.arange(mesh.n_nodes), 2)
    kind[:n_rail] = np.tile([0, 1], mesh.n_nodes)
    node[dofs.foundation] = dofs.foundation_nodes
    kind[dofs.foundation] = 2
    keys = np.empty(dofs.n_dof, np.int64)
    keep = dofs.index >= 0
    keys[dofs.index[keep]] = 4 * node[keep] + kind[keep]
    return keys

