"""The window route of a vehicle's run: a short FE track that jumps a few bays at a time with the vehicle.

The equations are those of the FE model route (:mod:`.fe_model`: the track's FE model, the
vehicle, Hertzian contacts with loss of contact, Newmark's average acceleration and the
broadband ends' states by the trapezoidal rule), on the window of a
:class:`semitrack.WindowTrack` instead of a model that holds the whole path. The run is cut into
stretches: while the leading wheel crosses ``move`` bays the window stands still; when it enters
the next, the window moves on by them and the run continues from the same state, renumbered:

- every DOF keeps its motion (``u, v, a``) where it still lies inside the window;
- the new bays at the front enter at rest, and the front end's states are zeroed;
- the rear end's states become the *shadow* states of the node that is now the rear end: the
  rear boundary's model run, over the whole stretch that node has been in the window, on that
  node's own motion. Every node a bay apart carries its shadow (one small linear recursion per
  stretch, :class:`_Shadows`), so that the new rear end starts as if the boundary had
  always stood there.

A model's matrices and its factorisation are kept while the window moves over a stretch where
the track is the same (a periodic stretch: every jump); with changes the window's support share is
assembled again and factorised once per jump (:meth:`semitrack.FETrack.with_changes`; a jump
costs 10-25 ms in all with the run's set-up, which moves of four bays share out).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence

import numpy as np

from ..base.checks import check_gap, check_int_at_least, check_work
from ..base.errors import InputError, InputTypeError
from ..base.progress import LIBRARY_DELAY, Progress
from ..dynamics.newmark import Newmark
from ..dynamics.points import PointSet
from ..dynamics.simulate import MAX_RECORDED, check_limits, continue_run, stepping_of
from ..dynamics.states import TrapezoidalStates
from ..dynamics.system import union
from ..fe.ends import BoundaryEnd, make_end
from ..fe.gaps import GapResponse, SleeperGaps, contact_time, sleeper_gaps
from ..fe.models import FETrack
from ..fe.trackforces import TrackForces, track_forces, watched_dofs
from ..fe.window import WindowTrack
from ..model.irregularity import Irregularity
from ..model.roughness import Roughness
from ..model.vehicle import Vehicle
from ..model.wheel import Wheel
from .excitation import rail_input
from .fe_wheels import all_contacts, contact_points, static_start
from .inputs import DEFAULT_DT, check_run
from .response import ContactResponse, contact_response

__all__ = ["window_response"]


class _Windows:
    """The window's model, system and factor at each offset, kept while the track under it is the same."""

    def __init__(self, track: WindowTrack, n_left: int, n_right: int, vehicle: Vehicle, stepper: Newmark,
                 f_ref):
        self.track, self.n_left, self.n_right = track, n_left, n_right
        self.vehicle_system, self.stepper, self.f_ref = vehicle.system(), stepper, f_ref
        self._key = self._entry = None
        self._states: dict = {}  # the ends' discretised states, by the blocks they come from

    def at(self, offset: int) -> tuple[FETrack, object, object]:
        """``(model, system, (states, factor))`` of the window moved ``offset`` bays."""
        key = self.track.layout_key(offset, self.n_left, self.n_right)
        if key != self._key:
            model = self.track.model_at(offset, self.n_left, self.n_right)
            system = union({"track": model.time_domain_system(self.f_ref), "vehicle": self.vehicle_system})
            # the same ends on the same DOFs of a system of the same size share their discretised
            # states (keyed by value: a freed model's arrays may leave their ids to another boundary's)
            ends = (system.n_dof, *(b"".join(np.ascontiguousarray(X).tobytes() for X in
                                             (blk.dofs, blk.A, blk.B, blk.C, blk.port)) for blk in system.states))
            stepping = stepping_of(system, self.stepper, self._states.get(ends))
            self._states[ends] = stepping[0]
            self._key, self._entry = key, (model, system, stepping)
        return self._entry


def _offsets(track: WindowTrack, lead: np.ndarray) -> np.ndarray:
    """The window's offset (bays) at each step: the leading wheel's bay, rounded down to ``move`` bays."""
    return track.move * np.floor_divide(track.bay_of(lead), track.move)


def _stretches(offsets: np.ndarray) -> list[tuple[int, int, int]]:
    """``(offset, first row, last row)`` of each stretch; a stretch starts on the last row of the one before."""
    cuts = np.flatnonzero(np.diff(offsets)) + 1
    starts = np.r_[0, cuts]
    ends = np.r_[cuts, offsets.size] - 1
    return [(int(offsets[s]), int(max(s - 1, 0)), int(e)) for s, e in zip(starts, ends)]


class _Shadows:
    """The rear boundary's states at every node a bay apart, each driven by its own node's motion.

    The rear (left) end's block steps as ``x_n+1 = E x_n + Phi_P (y_n+1 - y_n)``, ``y`` the rail's
    ``(w, psi)`` at the node (:class:`~semitrack.dynamics.states.TrapezoidalStates`). ``E`` is
    diagonalised once (``E = V diag(lam) V^-1``), so a stretch of N steps is one weighted sum per node:
    ``z_N = lam^N z_0 + sum_n lam^(N-1-n) V^-1 Phi_P dy_n``.
    """

    def __init__(self, states: TrapezoidalStates, m_left: int | None, n_nodes: int):
        """``states``' first ``m_left`` states (None: all), the rear end's block on two DOFs, at ``n_nodes`` nodes."""
        m_left = states.n_states if m_left is None else m_left
        E = states.E.toarray()[:m_left, :m_left]
        phi = states.Phi_P.toarray()[:m_left, :2]
        self.lam, self.V = np.linalg.eig(E)
        self.Q = np.linalg.solve(self.V, phi)  # modal states per input motion (m, 2)
        self.z = np.zeros((n_nodes, self.lam.size), complex)
        self._weights: dict[int, np.ndarray] = {}

    def advance(self, y: np.ndarray) -> None:
        """Run every shadow over a stretch: ``y`` (rows, nodes, 2) the nodes' motion, row 0 the stretch's start."""
        dy = np.diff(y, axis=0)  # (N, nodes, 2)
        n = dy.shape[0]
        weights = self._weights.get(n)
        if weights is None:
            weights = self.lam[:, None] ** (n - 1 - np.arange(n))[None, :]  # (m, N)
            if len(self._weights) < 4:  # a constant speed's stretches are of two lengths; a varying one's are not
                self._weights[n] = weights
        summed = [weights @ dy[:, :, c] for c in range(2)]  # sum_n lam^(N-1-n) dy_n, (m, nodes) per input
        drive = self.Q[:, 0, None] * summed[0] + self.Q[:, 1, None] * summed[1]
        self.z = self.lam ** n * self.z + drive.T

    def jump(self, bays: int) -> np.ndarray:
        """Move ``bays`` on: the new rear end's states (real), the shadows renumbered, the new nodes' at rest."""
        rear = np.real(self.V @ self.z[bays - 1])
        self.z = np.vstack([self.z[bays:], np.zeros((bays, self.z.shape[1]), complex)])
        return rear


def _check_window(track: WindowTrack, run) -> tuple[int, int, np.ndarray]:
    """The window's bays and every wheel's path, refused where the window cannot follow the run."""
    d = track.spacing
    fastest = run.speed if run.speeds is None else float(np.max(run.speeds))
    if fastest * run.dt > 0.25 * d:
        raise InputError(f"speed * dt must be under a quarter bay ({0.25 * d:.4g} m) for the window to follow the "
                         f"wheels, got speed={fastest!r} m/s, dt={run.dt!r} s")
    path = run.path()
    span = float(np.max(path[0]) - np.min(path[0]))
    n_left, n_right = track.bays(span)
    return n_left, n_right, path


def window_response(track: WindowTrack, wheel: Wheel | Vehicle | Sequence[Wheel], roughness: Roughness | None = None,
                    *, x: float | Sequence[float] = 0.0, speed: float | Callable[[float], float] = 0.0,
                    dt: float = DEFAULT_DT, duration: float = 0.1, ramp: float = 0.02,
                    f_ref: float | dict | None = None, compiled: bool | None = None, element_flexibility: bool = True,
                    profile: Irregularity | None = None, watch_supports: Sequence[int] = (),
                    bending_at: Sequence[float] = (), ballast_gaps: Mapping[int, float] | None = None
                    ) -> ContactResponse:
    """Wheels on a :class:`semitrack.WindowTrack`: :func:`semitrack.wheel_rail_response`'s run, on a window.

    Called by :func:`semitrack.wheel_rail_response` when its track is a WindowTrack; the
    parameters and the result are that function's, with ``x`` in the track's global coordinate
    (from its central mid-span). A hanging sleeper (``ballast_gaps``), a watched support
    (``watch_supports``) and a bending point (``bending_at``, m) are recorded while the window
    holds them: at rest before the window reaches them, NaN after it has left them; each must be
    within the window's reach over the run.
    """
    run = check_run(wheel, roughness, x, speed, dt, duration, ramp, varying=True)
    k = run.k
    n_left, n_right, path = _check_window(track, run)
    offsets = _offsets(track, np.max(path, axis=1))
    reach = _Reach(track, n_left, n_right, ballast_gaps, offsets)
    watched = _Watched(track, n_left, n_right, watch_supports, bending_at, offsets)
    windows = _Windows(track, n_left, n_right, run.vehicle, Newmark(run.dt), f_ref)
    model, system, stepping = windows.at(int(offsets[0]))
    # held for the run: 3 outputs per wheel, its inputs, the watched DOFs (a stretch's shadow records: below)
    check_limits(run.n_steps, system.n_dof, 3 * k + 2 * reach.n + watched.n_recorded, 11 * k,
                 f"duration={run.duration!r} s / dt={run.dt!r} s")
    if len(system.states) != 2:
        raise InputError(f"a window's only states are its two ends' (got {len(system.states)} blocks): a vehicle with "
                         "states of its own does not run on a WindowTrack yet")
    stretches = _stretches(offsets)
    longest = max(last - first + 1 for _, first, last in stretches)
    n_nodes = n_left + n_right
    check_work(longest * 2 * n_nodes, MAX_RECORDED, f"a stretch of {longest} steps x {2 * n_nodes} DOFs of the shadow "
               "nodes", "use a larger speed or dt, or a larger move")
    r = rail_input(roughness, path, run.dt, run.ramp, profile, run.vehicle.wheels)
    steps = _Steps(track, model, system, stepping, run, path, offsets, element_flexibility, reach, watched, r[0])
    with Progress("window run", run.n_steps, unit="step", delay=LIBRARY_DELAY) as bar:
        for i, (offset, first, last) in enumerate(stretches):
            if i:
                steps.jump(offset, windows.at(offset))
            steps.stretch(first, last, r, compiled)
            bar.update(last, f"window at support {offset}")
    return contact_response(route="window", t=run.t, force=steps.force, w_wheel=steps.w_wheel, w_rail=steps.w_rail,
                            roughness=r, x=path, track=track.track, vehicle=run.vehicle, speed=run.speed,
                            ramp=run.ramp, period=None if roughness is None else roughness.period,
                            n_dof=system.n_dof, elapsed=steps.elapsed, infinite=track.infinite_track(),
                            track_forces=watched.forces(run.dt, f_ref, reach), gaps=reach.response(run.dt),
                            speeds=run.speeds)


class _Reach:
    """The hanging sleepers the window meets: each one's stretches, and what it did over the run."""

    def __init__(self, track: WindowTrack, n_left: int, n_right: int, ballast_gaps: Mapping[int, float] | None,
                 offsets: np.ndarray):
        if ballast_gaps is not None and not isinstance(ballast_gaps, Mapping):
            raise InputTypeError(f"ballast_gaps must be a mapping {{support index: gap (m)}}, got {ballast_gaps!r}")
        self.track, self.n_left, self.n_right = track, n_left, n_right
        stops = np.unique(offsets)
        self.gaps = {}
        for kk, g in (ballast_gaps or {}).items():  # the FE route's rules, checked before any step
            kk = check_int_at_least("ballast_gaps key (a support index)", kk, -10**9)
            self.gaps[kk] = check_gap(f"ballast_gaps[{kk}]", g)
            if not any(track.holds(kk, int(o), n_left, n_right) for o in stops):
                lo, hi = int(stops[0]) - n_left, int(stops[-1]) + n_right - 1
                raise InputError(f"ballast_gaps: support {kk} is beyond the window's reach over this run (supports "
                                 f"{lo} to {hi})")
            change = track.changes.get(kk, {})
            if not track.tracks[track.part_at(kk)].is_ballasted:
                raise InputError(f"ballast_gaps: support {kk} has no sleeper on ballast")
            if change is None or change.get("kb", None) != 0:
                raise InputError(f"ballast_gaps: build the WindowTrack with changes={{{kk}: {{'kb': 0.0}}}} so that "
                                 f"support {kk}'s sleeper hangs from the rail without its linear ballast")
        self.n = len(self.gaps)
        self.supports = np.array(sorted(self.gaps), np.int64)
        self.force = np.zeros((offsets.size, self.n))
        self.opening = np.tile(np.array([self.gaps[kk] for kk in self.supports]), (offsets.size, 1))
        self.left = np.full(self.n, offsets.size)  # the first row after the window has left each

    def local(self, offset: int) -> dict:
        """The gaps inside the window moved ``offset`` bays, in its numbering."""
        held = (kk for kk in self.gaps if self.track.holds(kk, offset, self.n_left, self.n_right))
        return {kk - offset: self.gaps[kk] for kk in held}

    def record(self, gaps: SleeperGaps | None, offset: int, rows: slice, force: np.ndarray, w: np.ndarray) -> None:
        """A stretch's columns of the hanging sleepers it held (after the wheels')."""
        if gaps is None:
            return
        where = np.searchsorted(self.supports, gaps.supports + offset)
        self.force[rows, where] = force
        self.opening[rows, where] = gaps.gaps - w
        self.left[where] = rows.stop

    def force_of(self, support: int) -> np.ndarray:
        """The ballast force under a hanging sleeper over the run (N; NaN after the window has left it)."""
        j = int(np.searchsorted(self.supports, support))
        after = np.arange(self.force.shape[0]) >= self.left[j]
        return np.where(after, np.nan, self.force[:, j])

    def response(self, dt: float) -> GapResponse | None:
        if not self.n:
            return None
        after = np.arange(self.force.shape[0])[:, None] >= self.left[None, :]
        force, opening = np.where(after, np.nan, self.force), np.where(after, np.nan, self.opening)
        return GapResponse(supports=self.supports, gaps=np.array([self.gaps[kk] for kk in self.supports]),
                           force=force, opening=opening, contact_time=contact_time(np.nan_to_num(force), dt))


class _Watched:
    """The supports and bending points watched over a run, each read on the first window that holds it.

    A watched thing's DOFs are followed from window to window (:meth:`WindowTrack.same_dofs`), and
    its forces come from its whole history on that first window's model
    (:func:`semitrack.fe.trackforces.track_forces`): at rest before the window reaches it, NaN
    after the window has left it.
    """

    def __init__(self, track: WindowTrack, n_left: int, n_right: int, supports: Sequence[int],
                 bending_at: Sequence[float], offsets: np.ndarray):
        self.track, self.rows = track, offsets.size
        stops = np.unique(offsets)
        self.items = []  # (what, its global index or position, reference offset, reference model, watch)
        if np.ndim(supports) != 1 and not isinstance(supports, (list, tuple)):
            raise InputTypeError(f"watch_supports must be a sequence of support indices, got {supports!r}")
        for k in supports:
            k = check_int_at_least("watch_supports", k, -10**9)
            inside = np.array([o for o in stops if track.holds(k, int(o), n_left, n_right)], dtype=np.int64)
            if not inside.size:
                raise InputError(f"watch_supports: support {k} is beyond the window's reach over this run (supports "
                                 f"{int(stops[0]) - n_left} to {int(stops[-1]) + n_right - 1})")
            self._add("support", k, int(inside[0]), n_left, n_right)
        for xb in np.atleast_1d(np.asarray(bending_at, dtype=float)).ravel():
            inside = stops[(track.mid_span(stops - n_left) < xb) & (xb < track.mid_span(stops + n_right))]
            if not (np.isfinite(xb) and inside.size):
                lo, hi = track.mid_span([int(stops[0]) - n_left, int(stops[-1]) + n_right])
                raise InputError(f"bending_at: {xb!r} m is beyond the window's reach over this run ({lo:.6g} to "
                                 f"{hi:.6g} m)")
            self._add("bending", float(xb), int(inside[0]), n_left, n_right)
        self.history = [np.zeros((self.rows, item[4].dofs.size)) for item in self.items]
        self.left = np.full(len(self.items), self.rows)
        self.n_recorded = sum(h.shape[1] for h in self.history)

    def _add(self, what: str, where, offset: int, n_left: int, n_right: int) -> None:
        model = self.track.model_at(offset, n_left, n_right)
        watch = (watched_dofs(model, [where - offset]) if what == "support" else
                 watched_dofs(model, (), [where - self.track.origin(offset, n_left, n_right)]))
        self.items.append((what, where, offset, model, watch))

    def held(self, window: FETrack, offset: int) -> list[tuple[int, np.ndarray]]:
        """``(item, its DOFs in the window at offset)`` of the watched things the window holds whole."""
        out = []
        for i, (_, _, ref, model, watch) in enumerate(self.items):
            dofs = self.track.same_dofs(model, ref, watch.dofs, window, offset)
            if np.all(dofs >= 0):
                out.append((i, dofs))
        return out

    def record(self, held: list, rows: slice, values: np.ndarray) -> None:
        """A stretch's records of the watched DOFs (columns in the order of ``held``)."""
        start = 0
        for i, dofs in held:
            self.history[i][rows] = values[:, start:start + dofs.size]
            self.left[i] = rows.stop
            start += dofs.size

    def forces(self, dt: float, f_ref, reach: _Reach) -> TrackForces | None:
        """The watched supports' rail-seat and ballast forces and the bending, as the FE model route gives them."""
        if not self.items:
            return None
        parts, after = [], np.arange(self.rows)[:, None]
        for i, (what, where, ref, model, watch) in enumerate(self.items):
            history = np.where(after >= self.left[i], np.nan, self.history[i])
            parts.append((what, where, self.track.origin(ref, model.n_left, model.n_right),
                          track_forces(model, watch, history, dt, f_ref)))
        sup = [(where, origin, f) for what, where, origin, f in parts if what == "support"]
        bend = [(where, f) for what, where, _, f in parts if what == "bending"]
        rows = self.rows
        ballast = None
        if self.track.track.is_ballasted:
            ballast = np.column_stack([f.ballast[:, 0] for _, _, f in sup]) if sup else np.zeros((rows, 0))
            for j, (k, _, _) in enumerate(sup):  # a hanging sleeper's ballast is its gap's contact
                if k in reach.gaps:
                    ballast[:, j] = reach.force_of(k)
        return TrackForces(supports=np.array([k for k, _, _ in sup], np.int64),
                           x_supports=np.array([f.x_supports[0] + origin for _, origin, f in sup]),
                           rail_seat=np.column_stack([f.rail_seat[:, 0] for _, _, f in sup]) if sup else np.zeros(
                               (rows, 0)),
                           ballast=ballast, x_bending=np.array([xb for xb, _ in bend]),
                           bending=np.column_stack([f.bending[:, 0] for _, f in bend]) if bend else np.zeros((rows, 0)))


class _Steps:
    """The run's state across the window's moves, and its records."""

    def __init__(self, track: WindowTrack, model: FETrack, system, stepping, run, path: np.ndarray,
                 offsets: np.ndarray, element_flexibility: bool, reach: _Reach, watched: _Watched, r0: np.ndarray):
        self.track, self.run, self.path, self.reach, self.watched = track, run, path, reach, watched
        self.flexible = bool(element_flexibility)
        self.offset = int(offsets[0])
        self._use(model, system, stepping)
        local0 = path[:1] - track.origin(self.offset, model.n_left, model.n_right)
        K_track = system.K[:self.n_track, :self.n_track]  # the vehicle meets the track through its contacts only
        self.u, self.vehicle_loads = static_start(model, run.vehicle, K_track, model.points(local0[0]),
                                                  model.local_flexibility(local0)[0] * self.flexible,
                                                  self._gaps(self.offset), r0)
        self.v, self.a = np.zeros_like(self.u), None
        self.x = np.zeros(stepping[0].n_states)
        n_nodes = model.n_left + model.n_right
        self.shadows = [_Shadows(_rear_states(track.boundary_of(part), run.dt), None, n_nodes)
                        for part in range(len(track.tracks))]
        rows = run.n_steps + 1
        self.force, self.w_wheel, self.w_rail = (np.empty((rows, run.k)) for _ in range(3))
        self.elapsed = 0.0

    def _use(self, model: FETrack, system, stepping) -> None:
        """Step on this window's model from now on."""
        self.model, self.system, self.stepping = model, system, stepping
        self.n_track = model.n_dof
        nodes = self.track.shadow_nodes(model, self.offset)
        self.node_dofs = np.stack([model.dofs.index[2 * nodes], model.dofs.index[2 * nodes + 1]], axis=1)
        self.m_left = system.states[0].n_states

    def _gaps(self, offset: int) -> SleeperGaps | None:
        local = self.reach.local(offset)
        return sleeper_gaps(self.model, local) if local else None

    def jump(self, offset: int, window: tuple) -> None:
        """Move on to ``offset``: the state renumbered (see the module docstring), the new window's model."""
        old, old_offset, n_old = self.model, self.offset, self.n_track
        model = window[0]
        shift = self.track.same_dofs(model, offset, np.arange(model.n_dof), old, old_offset)
        moved = []
        for q in (self.u, self.v, self.a):
            on_track = np.where(shift >= 0, q[np.maximum(shift, 0)], 0.0)
            moved.append(np.concatenate([on_track, q[n_old:]]))
        self.u, self.v, self.a = moved
        bays = offset - old_offset
        rear = [sh.jump(bays) for sh in self.shadows]  # every track's rear model follows every node
        self.offset = offset
        self._use(*window)
        part = self.track.part_at(offset - model.n_left)  # the track behind the new rear end
        x = np.zeros(self.stepping[0].n_states)
        x[:self.m_left] = rear[part]  # the rear end's states; the front end's (after them) at rest
        self.x = x

    def stretch(self, first: int, last: int, r: np.ndarray, compiled: bool | None) -> None:
        """Step the window from row ``first`` to row ``last``."""
        run, model, k, offset = self.run, self.model, self.run.k, self.offset
        local = self.path[first:last + 1] - self.track.origin(offset, model.n_left, model.n_right)
        points = contact_points(model, local, run.moving)
        flex = model.local_flexibility(local if run.moving else local[:1]) * self.flexible
        gaps = self._gaps(offset)
        vehicle_dofs = self.n_track + np.arange(self.vehicle_loads.size)
        contacts = all_contacts(vehicle_dofs[:k], points, run.vehicle.wheels, r[first:last + 1], flex, gaps)
        rows = last - first + 1
        loads = [(PointSet.on_dofs(vehicle_dofs), np.tile(self.vehicle_loads, (rows, 1)))]
        held = self.watched.held(model, offset)
        record = np.concatenate([self.node_dofs.ravel(), *(dofs for _, dofs in held)])
        out = continue_run(self.system, Newmark(run.dt), rows - 1, u=self.u, v=self.v, a=self.a, x=self.x,
                           loads=loads, contacts=contacts, record=record, stepping=self.stepping, compiled=compiled)
        res = out.response
        skip = 0 if first == 0 else 1  # row 0 of a later stretch is the last row of the one before
        kept = slice(first + skip, last + 1)
        self.force[kept] = res["contact force"][skip:, :k]
        self.w_wheel[kept] = res["wheel"][skip:, :k]
        self.w_rail[kept] = res["rail"][skip:, :k]
        self.reach.record(gaps, offset, kept, res["contact force"][skip:, k:], res["wheel"][skip:, k:])
        n_shadow = self.node_dofs.size
        motion = res["dofs"][:, :n_shadow].reshape(rows, -1, 2)
        for sh in self.shadows:
            sh.advance(motion)
        self.watched.record(held, kept, res["dofs"][skip:, n_shadow:])
        self.u, self.v, self.a, self.x = out.u, out.v, out.a, out.x
        self.elapsed += res.elapsed


def _rear_states(boundary, dt: float) -> TrapezoidalStates:
    """A boundary's block at a rear (left) end on two DOFs, discretised: what the shadows run."""
    block = make_end(BoundaryEnd.name, boundary).states(np.array([0, 1]), "left")[0]
    return TrapezoidalStates([block], dt, 2)
