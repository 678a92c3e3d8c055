"""The exact infinite track with the load and the response anywhere, local changes, a transition and joints.

The rail is cut at two mid-spans ``X_L < X_R`` that enclose every change, joint, load and
response point. Outside them the track is periodic and semi-infinite, and closes the core by its
exact end stiffness (:func:`semitrack.methods.transfer.end_stiffness`: Bloch waves, nothing
truncated). Inside, the rail is exact Timoshenko segments
(:func:`semitrack.model.timoshenko.segment_dynamic_stiffness`) between nodes at every support,
load and response point, joint and the transition; each support adds its dynamic stiffness at
its node. No mesh, no truncation: the periodic track is the special case without changes.

Positions are measured from the central cross-section, a mid-span (x = 0), as in the FE models:
support k sits at ``x = (k + 1/2) d`` (k any integer, d the spacing). A transition at the
mid-span ``x_t = kt d`` puts the rail on the second track's supports at
``x_t + (j + 1/2) d2`` (support k = kt + j) and makes the semi-infinite right part that track;
the rails meet at ``x_t``. A joint at x cuts the rail there (not at a support) and joins it by a
rotational spring (0: a hinge); w and the shear force stay continuous.
"""

from __future__ import annotations

from collections import OrderedDict
from collections.abc import Callable, Mapping

import numpy as np
from numpy.typing import ArrayLike

from ..base.checks import as_frequencies, as_real_array, check_int_at_least, check_nonnegative, check_real, check_work
from ..base.deprecation import renamed_keywords
from ..base.errors import InputError, InputTypeError
from ..base.notices import ImplausibleValueWarning, warn_user
from ..dynamics.factor import lapack_band_solve
from ..model.curves import FrequencyCurve, as_curve, stiffness_values
from ..model.timoshenko import segment_dynamic_stiffness
from ..model.tracks import SUPPORT_FIELDS, Track, require_track
from .transfer import end_stiffness

__all__ = ["SUPPORT_FIELDS", "InfiniteTrack", "support_dynamic_stiffness", "check_changes"]

#: The fields of a support that ``changes`` may set.
#: Most response points of one call, and most (frequency, point) pairs: each point is a node of the
#: band system, each pair four complex receptances held at once.
MAX_RESPONSE_POINTS = 20_000
MAX_RESPONSE_VALUES = 20_000_000  # 1.3 GB of results: a train's 50 contacts at 40 001 frequencies
#: Most supports between the farthest changes and points of one solve (12 km at 0.6 m: a solve of
#: about a second per frequency).
MAX_CORE_SUPPORTS = 20_000
#: Farthest support index from the centre (60 000 km at 0.6 m): beyond it, positions lose their metres.
MAX_SUPPORT_INDEX = 100_000_000
#: Positions closer than this fraction of the spacing are one node.
_SAME = 1e-9

#: Semi-infinite ends kept for the process: (track, frequencies, cut) -> (k_right, k_left). A study of many local
#: changes of one track asks for the same two ends at every change and every load point (the imperfect track's
#: chapter: 656 computations of a few dozen distinct ones).
_ENDS: OrderedDict = OrderedDict()
_MAX_ENDS = 64


def _end_stiffness(track: Track, omega: np.ndarray, x_cut: float) -> tuple[np.ndarray, np.ndarray]:
    """:func:`~.transfer.end_stiffness` of ``track``'s period at ``x_cut``, computed once per process (read-only)."""
    key = (track, omega.tobytes(), float(x_cut))
    try:
        hash(key)
    except TypeError:  # a track whose fields do not hash: computed each time
        return end_stiffness(track.cell(), omega, x_cut)
    if key in _ENDS:
        _ENDS.move_to_end(key)
        return _ENDS[key]
    ends = tuple(np.array(k) for k in end_stiffness(track.cell(), omega, x_cut))
    for k in ends:
        k.setflags(write=False)
    _ENDS[key] = ends
    if len(_ENDS) > _MAX_ENDS:
        _ENDS.popitem(last=False)
    return ends


def support_dynamic_stiffness(track: Track, f: np.ndarray, fields: Mapping[str, float] | None = None,
                              label: str = "") -> tuple[np.ndarray, np.ndarray]:
    """The vertical and rotational dynamic stiffness of one support of ``track``, some fields changed.

    The pad ``kv (1 + i eta_pad)`` in series with the sleeper on ballast
    ``kb (1 + i eta_ballast) - omega^2 m_s`` (a ballasted track), or on the ground; the
    rotational pad ``kphi (1 + i eta_pad)`` on the ground. A viscous track's changed dampers
    keep the track's reference frequencies (:meth:`semitrack.Track.reference_frequencies`).

    Parameters
    ----------
    track : Track
        The track whose support this is (not a flexible slab).
    f : ndarray
        Frequencies (Hz).
    fields : mapping, optional
        New values of :data:`SUPPORT_FIELDS` (SI); ``kb=0`` is a hanging sleeper; ``kv`` and
        ``kphi`` may be stiffness curves (their values as they are). A measured ``foundation`` of
        the track stays under every pad.
    label : str
        Prefix of the fields' names in messages (e.g. ``"changes[3]"``).

    Returns
    -------
    kv_dyn, kphi_dyn : ndarray of complex
        N/m and N m/rad, the shape of ``f``.
    """
    p = {name: getattr(track, name) for name in SUPPORT_FIELDS}
    p.update(fields or {})
    omega = 2 * np.pi * f
    pad = 1 + 1j * track.loss_factor("pad", f, p["eta_pad"])
    named = {key: f"{label}[{key!r}]" if label and key in (fields or {}) else key for key in ("kv", "kphi")}
    kv = stiffness_values(named["kv"], p["kv"], f, pad)
    kphi = stiffness_values(named["kphi"], p["kphi"], f, pad, allow_zero=True)
    if track.is_ballasted:
        ballast = p["kb"] * (1 + 1j * track.loss_factor("ballast", f, p["eta_ballast"])) - omega**2 * p["sleeper_mass"]
        with np.errstate(divide="ignore", invalid="ignore"):
            kv = np.where(kv == 0, 0.0, kv * ballast / (kv + ballast))  # 1 / (1/kv + 1/ballast)
    elif track.foundation is not None:
        kv = kv / (1 + kv * track.foundation_receptance(f))  # 1 / (1/kv + G)
    return np.broadcast_to(kv, f.shape).astype(complex), np.broadcast_to(kphi, f.shape).astype(complex)


def check_changes(changes, ballasted: Callable[[int], bool]) -> dict[int, dict | None]:
    """``changes`` checked: ``{support index: {field: value >= 0} or None}``.

    Parameters
    ----------
    changes : mapping or None
        As :class:`InfiniteTrack` takes it.
    ballasted : callable
        ``ballasted(k)``: whether support k has a sleeper (so that its sleeper and ballast fields
        may be set).

    Returns
    -------
    dict
    """
    if changes is None:
        return {}
    if not isinstance(changes, Mapping):
        raise InputTypeError(f"changes must be a mapping {{support index: {{field: value}} or None}}, got {changes!r}")
    out = {}
    for k, fields in changes.items():
        k = check_int_at_least("changes key (a support index)", k, -10**9)
        if fields is None:
            out[k] = None
            continue
        if not isinstance(fields, Mapping):
            raise InputTypeError(f"changes[{k}] must be a mapping of support fields or None (no support), "
                                 f"got {fields!r}")
        unknown = sorted(set(fields) - set(SUPPORT_FIELDS))
        if unknown:
            raise InputError(f"changes[{k}] names unknown support fields {unknown}; the fields are {SUPPORT_FIELDS}")
        if not ballasted(k) and {"sleeper_mass", "kb", "eta_ballast"} & set(fields):
            raise InputError(f"changes[{k}] sets sleeper or ballast fields on a support of a track without sleepers")
        out[k] = {name: _change_value(f"changes[{k}][{name!r}]", name, value) for name, value in fields.items()}
        if isinstance(out[k].get("kv"), float) and out[k]["kv"] == 0.0:
            warn_user(f"changes[{k}]['kv']=0 N/m: support {k}'s pad carries no vertical load (pads hold 10^7-10^9 "
                      f"N/m); a failed fastener or a missing support is changes={{{k}: None}}, a worn pad its "
                      "stiffness in N/m", ImplausibleValueWarning)
    return out


def _change_value(label: str, name: str, value: object) -> float | FrequencyCurve:
    """A changed support field: a number >= 0, or for a pad stiffness also a curve of stiffness."""
    if name in ("kv", "kphi"):
        value = as_curve(label, value, "stiffness")
        if isinstance(value, FrequencyCurve):
            return value
    return check_nonnegative(label, value)


class InfiniteTrack:
    """The exact infinite track, possibly with changed supports, a transition and rail joints.

    Parameters
    ----------
    track : Track
        The track (left of a transition, or everywhere); not a flexible slab.
    changes : mapping of int to mapping or None, optional
        ``{k: {field: value}}`` sets fields of :data:`SUPPORT_FIELDS` at support k (at
        ``x = (k + 1/2) d``; past a transition, the second track's support ``j = k - kt``); a
        hanging sleeper is ``{"kb": 0.0}``, a worn pad a lower ``kv``; ``{k: None}`` removes the
        support (pad and sleeper gone). ``kv`` and ``kphi`` may be curves of frequency
        (:class:`semitrack.FrequencyTable`, a function of f), which hold their own damping; a number
        takes the track's ``eta_pad``.
    right : Track, optional
        The track from the transition on (its rail and supports; not a flexible slab).
    transition : int, optional
        ``kt``: the transition sits at the mid-span ``x_t = kt d``; required with ``right``.
    joints : mapping of float to float, optional
        ``{x: k_rot}``: the rail is cut at x (m, not at a support) and joined by a rotational
        spring of ``k_rot`` N m/rad (0: a hinge).

    Examples
    --------
    A hanging sleeper at x = d/2 of the ballasted track, the receptance there and a bay away:

    >>> import semitrack as st
    >>> inf = st.InfiniteTrack(st.ballasted_track(), changes={0: {"kb": 0.0}})
    >>> inf.receptance([100.0, 500.0], 0.3, [0.3, 0.9]).shape
    (2, 2, 2, 2)
    """

    def __init__(self, track: Track, changes: Mapping[int, Mapping[str, float] | None] | None = None, *,
                 right: Track | None = None, transition: int | None = None,
                 joints: Mapping[float, float] | None = None):
        self.track = _plain(require_track(track), "track")
        self.right = None if right is None else _plain(require_track(right, "right"), "right")
        if (right is None) != (transition is None):
            raise InputError("right and transition go together: give the second track and the mid-span index kt "
                             f"of the transition, got right={'a Track' if right is not None else None}, "
                             f"transition={transition!r}")
        self.transition = None if transition is None else check_int_at_least("transition", transition, -10**9)
        self.x_t = None if self.transition is None else self.transition * self.track.spacing
        self.changes = check_changes(changes, lambda k: self._track_of(k).is_ballasted)
        self.joints = self._check_joints(joints)

    # --------------------------------------------------------------------------------------------
    def _track_of(self, k: int) -> Track:
        """The track that support k belongs to."""
        return self.right if self.transition is not None and k >= self.transition else self.track

    @renamed_keywords({"k": "support"})
    def support_position(self, support: int) -> float:
        """Position of a support (m from the centre).

        Parameters
        ----------
        support : int
            The support's index k (``k=`` until 0.3): at ``(k + 1/2) d``, or past a transition
            ``x_t + (k - kt + 1/2) d2``.

        Returns
        -------
        float
        """
        support = check_int_at_least("support", support, -MAX_SUPPORT_INDEX)
        if support > MAX_SUPPORT_INDEX:
            raise InputError(f"support must be within {MAX_SUPPORT_INDEX} of the centre, got {support}")
        if self.transition is not None and support >= self.transition:
            return self.x_t + (support - self.transition + 0.5) * self.right.spacing
        return (support + 0.5) * self.track.spacing

    def _support_index_near(self, x: float) -> int | None:
        """The support at x (within rounding), if any."""
        if self.transition is not None and x > self.x_t:
            d, k0, x0 = self.right.spacing, self.transition, self.x_t
        else:
            d, k0, x0 = self.track.spacing, 0, 0.0
        k = int(np.floor((x - x0) / d))
        return k + k0 if abs(x - x0 - (k + 0.5) * d) <= _SAME * d else None

    def _check_joints(self, joints) -> dict[float, float]:
        if joints is None:
            return {}
        if not isinstance(joints, Mapping):
            raise InputTypeError(f"joints must be a mapping {{x (m): rotational stiffness (N m/rad)}}, got {joints!r}")
        out = {}
        for x, k_rot in joints.items():
            x = check_real("joints key (a position, m)", x)
            if not np.isfinite(x):
                raise InputError(f"joints positions must be finite, got {x!r}")
            if self._support_index_near(x) is not None:
                raise InputError(f"a joint cuts the rail between supports: x={x!r} m is support "
                                 f"{self._support_index_near(x)}")
            if self.x_t is not None and abs(x - self.x_t) <= _SAME * self.track.spacing:
                raise InputError(f"a joint at the transition x_t={self.x_t!r} m is not modelled; move it off")
            out[x] = check_nonnegative(f"joints[{x!r}]", k_rot)
        return out

    # --------------------------------------------------------------------------------------------
    def _core(self, points: np.ndarray) -> tuple[float, float]:
        """The cuts X_L < X_R (mid-spans of the periodic parts) that enclose everything local."""
        d = self.track.spacing
        left = [k for k in self.changes if self.transition is None or k < self.transition]
        right = [k for k in self.changes if self.transition is not None and k >= self.transition]
        xs = np.concatenate([points, list(self.joints)])
        # Only what is local bounds the core: a perfect track's core encloses the points alone, wherever
        # they are (a core from support 0 to a point 5 km away took seconds for the same receptance).
        k_lo = int(np.floor(min(xs.min() / d, min(left, default=np.inf),
                                self.transition if self.x_t is not None else np.inf)))
        x_left = k_lo * d - d  # a bay to spare: the cut is a clean mid-span
        if self.transition is None:
            k_hi = int(np.ceil(max(xs.max() / d, max(left, default=-np.inf) + 1)))
            return x_left, (k_hi + 1) * d
        d2 = self.right.spacing
        j_hi = int(np.ceil(max((xs.max() - self.x_t) / d2, max((k - self.transition + 1 for k in right), default=0),
                               0)))
        return x_left, self.x_t + (j_hi + 1) * d2

    def _nodes(self, points: np.ndarray) -> tuple[np.ndarray, dict, float, float]:
        """Node positions, ``{node: support index}`` and the cuts."""
        x_left, x_right = self._core(points)
        spanned = (x_right - x_left) / min(self.track.spacing, self.right.spacing if self.right is not None else np.inf)
        check_work(spanned, MAX_CORE_SUPPORTS, f"x_load, x and the track's changes and joints span {spanned:.3g} "
                   "supports", "bring them closer together (each support between them is a node of the solve)")
        supports = {}
        if self.transition is None:
            ks = range(int(round(x_left / self.track.spacing)), int(round(x_right / self.track.spacing)))
        else:
            kt, d2 = self.transition, self.right.spacing
            ks = [*range(int(round(x_left / self.track.spacing)), kt),
                  *range(kt, kt + int(round((x_right - self.x_t) / d2)))]
        for k in ks:
            supports[self.support_position(k)] = k
        extra = [x_left, x_right, *points, *self.joints] + ([self.x_t] if self.x_t is not None else [])
        xs = np.unique(np.concatenate([list(supports), extra]))
        tol = _SAME * min(self.track.spacing, self.right.spacing if self.right is not None else np.inf)
        keep = np.concatenate([[True], np.diff(xs) > tol])
        xs = xs[keep]
        at_support = {int(np.argmin(np.abs(xs - x))): k for x, k in supports.items()}
        return xs, at_support, x_left, x_right

    def _dofs(self, xs: np.ndarray) -> tuple[np.ndarray, np.ndarray, dict[int, int]]:
        """DOFs: w and psi per node, a second psi at a joint (its right side)."""
        joint_nodes = {int(np.argmin(np.abs(xs - x))): k for x, k in self.joints.items()}
        w, psi_left, psi_right, n = [], [], [], 0
        for j in range(xs.size):
            w.append(n)
            psi_left.append(n + 1)
            psi_right.append(n + 2 if j in joint_nodes else n + 1)
            n += 3 if j in joint_nodes else 2
        return np.array(w), (np.array(psi_left), np.array(psi_right), n), joint_nodes

    def _assemble(self, f: np.ndarray, xs: np.ndarray, at_support: dict, x_left: float, x_right: float
                  ) -> tuple[_Band, np.ndarray, np.ndarray]:
        """The core's dynamic stiffness in band storage (the nodes run along x: a chain)."""
        omega = 2 * np.pi * f
        w, (psi_l, psi_r, n), joint_nodes = self._dofs(xs)
        Z = _Band(f.size, n, 4 if joint_nodes else 3)
        lengths = np.diff(xs)
        mids = 0.5 * (xs[:-1] + xs[1:])
        on_right = (mids > self.x_t) if self.x_t is not None else np.zeros(lengths.size, bool)
        for rail, which in ((self.track, ~on_right), (self.right, on_right)):
            if rail is None or not which.any():
                continue
            segs = segment_dynamic_stiffness(rail, omega, lengths[which])  # (m, n_f, 4, 4)
            for seg, j in zip(segs, np.flatnonzero(which)):
                Z.add([w[j], psi_r[j], w[j + 1], psi_l[j + 1]], seg)
        for node, k in at_support.items():
            fields = self.changes.get(k, {})
            if fields is None:
                continue  # the support removed
            kv, kphi = support_dynamic_stiffness(self._track_of(k), f, fields, f"changes[{k}]")
            Z.add([w[node]], kv[:, None, None])
            Z.add([psi_l[node]], kphi[:, None, None])
        for node, k_rot in joint_nodes.items():
            Z.add([psi_l[node], psi_r[node]], np.broadcast_to(k_rot * np.array([[1.0, -1.0], [-1.0, 1.0]]),
                                                              (f.size, 2, 2)))
        left_cell = self.track.cell()
        Z.add([w[0], psi_l[0]], _end_stiffness(self.track, omega, left_cell.central_section + x_left)[1])
        right_track = self.track if self.transition is None else self.right
        x_cut = right_track.cell().central_section + (x_right if self.transition is None else x_right - self.x_t)
        Z.add([w[-1], psi_r[-1]], _end_stiffness(right_track, omega, x_cut)[0])
        return Z, w, psi_l

    def receptance(self, f: ArrayLike, x_load: float, x: ArrayLike) -> np.ndarray:
        """Response (w, psi) at each ``x`` to a unit force and a unit moment on the rail at ``x_load``.

        Parameters
        ----------
        f : array_like
            Frequencies (Hz), positive.
        x_load : float
            Where the force and the moment act (m from the centre); not at a joint.
        x : float or array_like
            Where the rail's displacement and rotation are read (m); not at a joint.

        Returns
        -------
        ndarray of complex, shape (n_f, n_x, 2, 2)
            ``[..., i, k]``: w (m, i = 0) or psi (rad, i = 1) per F (N, k = 0) or M (N m, k = 1),
            w downward and psi clockwise as everywhere in the package. Reciprocal:
            ``receptance(f, a, [b])[:, 0] == receptance(f, b, [a])[:, 0].transpose(0, 2, 1)``.
        """
        f = np.atleast_1d(as_frequencies(f))
        if f.ndim != 1:  # the result's first axis is the frequency
            raise InputError(f"f must be a number or a 1-D array of frequencies (Hz), got shape {f.shape}")
        x_load = check_real("x_load", x_load)
        xr = np.atleast_1d(as_real_array(x, "x", empty=False)).ravel()
        check_work(xr.size, MAX_RESPONSE_POINTS, f"x holds {xr.size} response points", "split them over calls")
        check_work(f.size * xr.size, MAX_RESPONSE_VALUES, f"{f.size} frequencies at {xr.size} points",
                   "split the frequencies or the points over calls")
        points = np.concatenate([[x_load], xr])
        if not np.all(np.isfinite(points)) or np.any(np.abs(points) > 1e6):
            raise InputError(f"x_load and x must be finite positions within 1e6 m, got {points[:5]}")
        for p in points:
            if any(abs(p - j) <= _SAME * self.track.spacing for j in self.joints):
                raise InputError(f"a load or response point at the joint x={p!r} m has two rotations; move it off")
        xs, at_support, x_left, x_right = self._nodes(points)
        node = lambda p: int(np.argmin(np.abs(xs - p)))  # noqa: E731
        out = np.empty((f.size, xr.size, 2, 2), dtype=complex)
        for start in range(0, f.size, _CHUNK):  # a few MB of band storage at a time
            part = slice(start, start + _CHUNK)
            Z, w, psi = self._assemble(f[part], xs, at_support, x_left, x_right)
            load = node(x_load)
            rhs = np.zeros((Z.n, 2))
            rhs[w[load], 0] = rhs[psi[load], 1] = 1.0
            rows = np.array([[w[node(p)], psi[node(p)]] for p in xr])
            out[part] = Z.solve(rhs)[:, rows, :]
        return out


def _plain(track: Track, name: str) -> Track:
    if track.has_flexible_slab:
        raise InputError(f"{name}: InfiniteTrack holds pads on a rigid foundation or on sleepers; a flexible slab "
                         "(track.slab) is not modelled with changes: use semi_infinite_receptance or "
                         "point_receptance for the periodic floating-slab track")
    return track


#: Frequencies assembled and solved at a time.
_CHUNK = 256


class _Band:
    """A stack of band matrices (one per frequency) in LAPACK's storage, ``ab[:, w + i - j, j] = A[i, j]``."""

    def __init__(self, n_f: int, n: int, width: int):
        self.ab = np.zeros((n_f, 2 * width + 1, n), dtype=complex)
        self.n, self.width = n, width

    def add(self, idx, block: np.ndarray) -> None:
        """Add the ``(n_f, p, p)`` blocks on the DOFs ``idx``."""
        w = self.width
        for a, i in enumerate(idx):
            for b, j in enumerate(idx):
                self.ab[:, w + i - j, j] += block[:, a, b]

    def solve(self, rhs: np.ndarray) -> np.ndarray:
        """``A^-1 rhs`` per frequency (banded LU with partial pivoting), ``(n_f, n, c)``.

        The system is scaled symmetrically by ``|A_ii|^-1/2`` first: w and psi differ by decades.
        """
        w, n = self.width, self.n
        s = 1.0 / np.sqrt(np.abs(self.ab[:, w, :]))  # (n_f, n)
        i = np.arange(2 * w + 1)[:, None] - w + np.arange(n)[None, :]  # row of each stored entry
        inside = (i >= 0) & (i < n)
        columns = np.zeros((self.ab.shape[0], n, 3 * w + 1), dtype=complex)  # LAPACK's layout, with pivot room
        columns[:, :, w:] = (self.ab * np.where(inside, s[:, np.clip(i, 0, n - 1)], 0.0) * s[:, None, :]
                             ).transpose(0, 2, 1)
        out = np.empty((self.ab.shape[0], n, rhs.shape[1]), dtype=complex)
        for k in range(self.ab.shape[0]):
            out[k] = s[k][:, None] * lapack_band_solve(columns[k], w, s[k][:, None] * rhs.astype(complex))
        return out
