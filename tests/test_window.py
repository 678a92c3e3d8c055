"""The travelling window: a short FE track that moves with the vehicle a few bays at a time.

Independent checks: a model with other supports by exchange of the supports' share against one
assembled afresh; the renumbering of a move against the nodes' positions; the shadow states
against the rear boundary's own recursion stepped by hand; a window that never moves against an
FETrack of its size (the same equations: to round-off); and whole runs against the truncated
model with broadband ends that holds the whole path, on the periodic track and on a random one,
the error falling as the window grows. The compiled and NumPy loops agree; what the window
cannot do is refused by name.
"""

from pathlib import Path

import numpy as np
import pytest

import semitrack as st
from semitrack.dynamics.states import TrapezoidalStates
from semitrack.interaction.window_model import _Shadows, _stretches
from semitrack.paper.moving_study import force_agreement
from semitrack.paper.window_study import random_supports

DATA = Path(__file__).parent / "data"
SLAB = st.slab_track(damping="viscous")
BALLAST = st.ballasted_track(damping="viscous")
NE = 8  # coarse meshes: the checks are of the method, which holds for any mesh
DT, SPEED = 5e-5, 250 / 3.6


@pytest.fixture(scope="module")
def boundaries():
    return {"slab": st.load_boundary(DATA / "boundary_slab_viscous_24.json"),
            "ballasted": st.load_boundary(DATA / "boundary_ballasted_viscous_24.json")}


def _roughness(period=0.2):
    wl = 10 ** (np.arange(-15, -3) / 10)  # 3.2 cm - 0.5 m: 140 Hz - 2.2 kHz at 250 km/h
    return st.roughness_from_spectrum(SPEED, wl, np.zeros(wl.size), period=period, seed=2, dt=DT)


def _path_model(track, boundary, changes, duration, x0=0.0, bays=60):
    reach = int(np.ceil((abs(x0) + SPEED * duration) / track.spacing)) + bays
    inside = None if changes is None else {k: v for k, v in changes.items() if -reach <= k < reach}  # its own supports
    return st.TruncatedTrack(track, reach, "boundary", system=boundary, elements_per_bay=NE, changes=inside)


def test_with_changes_is_the_model_assembled_afresh(boundaries):
    """Exchanging the supports' share gives the matrices of a model built with the changes (and not the template's)."""
    rng = np.random.default_rng(0)
    changes = {k: {"kv": BALLAST.kv * rng.uniform(0.5, 2), "kb": BALLAST.kb * rng.uniform(0.5, 2),
                   "sleeper_mass": rng.uniform(60, 200), "kphi": rng.uniform(0, 1e6)} for k in range(-4, 4)}
    changes[1] = None
    template = st.FETrack(BALLAST, 4, 4, "boundary", "boundary", system=boundaries["ballasted"], elements_per_bay=NE)
    fresh = st.FETrack(BALLAST, 4, 4, "boundary", "boundary", system=boundaries["ballasted"], elements_per_bay=NE,
                       changes=changes)
    quick = template.with_changes(changes)
    for A, B, T in zip(quick.matrices(), fresh.matrices(), template.matrices()):
        assert abs(A - B).max() <= 1e-12 * abs(B).max()
        assert abs(T - B).max() > 1e-3 * abs(B).max()
    assert np.allclose(quick.receptance(200.0), fresh.receptance(200.0), rtol=1e-10, atol=0)
    back = quick.with_changes(None)
    assert all(abs(A - T).max() <= 1e-12 * abs(T).max() for A, T in zip(back.matrices(), template.matrices()))


def test_a_move_renumbers_each_dof_to_its_place_a_bay_on(boundaries):
    """The DOF at x in the moved window is the DOF of the same kind at the same place in the old one; the new bays'
    DOFs (and only they) are not in the old window."""
    win = st.WindowTrack(BALLAST, behind=2, ahead=3, elements_per_bay=NE, system=boundaries["ballasted"])
    old, new = win.model_at(0, 3, 4), win.model_at(3, 3, 4)
    shift = win.same_dofs(new, 3, np.arange(new.n_dof), old, 0)

    def places(model, offset):
        full = np.r_[np.repeat(model.x, 2), model.x[model.dofs.foundation_nodes]] + win.mid_span(offset)
        kind = np.r_[np.tile([0, 1], model.n_nodes), np.full(model.dofs.foundation.size, 2)]
        x, k = np.empty(model.n_dof), np.empty(model.n_dof, int)
        x[model.dofs.index], k[model.dofs.index] = full, kind
        return x, k

    (x_new, k_new), (x_old, k_old) = places(new, 3), places(old, 0)
    moved = shift >= 0
    assert np.allclose(x_old[shift[moved]], x_new[moved]) and np.array_equal(k_old[shift[moved]], k_new[moved])
    assert np.all(x_new[~moved] > x_old.max() - 1e-9)  # only the bays beyond the old front enter
    assert np.count_nonzero(~moved) == 3 * (2 * NE + 1)  # their nodes' (w, psi) and their sleepers


def test_a_window_holds_a_joint_and_a_transition_as_the_path_model_does(boundaries):
    """A bogie over a rail joint (a hinge) and from the slab track onto the ballasted one: within 0.3 % rms."""
    rough = _roughness()
    joints = {3.0: 0.0}
    run = dict(x=0.0, speed=SPEED, dt=DT, duration=0.12)
    system = (boundaries["slab"], boundaries["ballasted"])
    win = st.WindowTrack(SLAB, right=BALLAST, transition=10, joints=joints, elements_per_bay=NE, system=system)
    got = st.wheel_rail_response(win, st.Bogie(), rough, **run)
    path = st.TruncatedTrack(SLAB, 80, "boundary", system=system, elements_per_bay=NE, right=BALLAST, transition=10,
                             joints=joints)
    ref = st.wheel_rail_response(path, st.Bogie(), rough, **run)
    assert got.x[-1, 0] > 10 * SLAB.spacing + 1.0 and got.x[0, 0] < 3.0  # over the joint, onto the ballasted track
    for wheel in range(2):
        assert force_agreement(got, ref, wheel=wheel, after=0.03)["rms"] < 0.003, wheel
    assert got.infinite.transition == 10 and got.infinite.joints == joints


class _ByHand:
    """The slab boundary's rear block, stepped by hand beside the shadows, on random node motions."""

    def __init__(self, boundary, nodes: int, seed: int):
        model = st.FETrack(SLAB, 2, 2, "boundary", "boundary", system=boundary, elements_per_bay=NE)
        states = TrapezoidalStates(model.boundary_states(), DT, model.n_dof)
        m = model.boundary_states()[0].n_states
        self.E, self.phi = states.E.toarray()[:m, :m], states.Phi_P.toarray()[:m, :2]
        self.shadows, self.x = _Shadows(states, m, nodes), np.zeros((nodes, m))
        self.rng, self.nodes = np.random.default_rng(seed), nodes

    def stretch(self, rows: int) -> None:
        y = np.cumsum(self.rng.normal(size=(rows, self.nodes, 2)), axis=0) * 1e-6
        self.shadows.advance(y)
        for n in range(rows - 1):
            self.x = self.x @ self.E.T + (y[n + 1] - y[n]) @ self.phi.T

    def agree(self, got: np.ndarray, want: np.ndarray) -> bool:
        return np.allclose(got, want, rtol=1e-9, atol=1e-9 * np.abs(self.x).max())


def test_the_shadow_states_are_the_rear_boundarys_recursion(boundaries):
    """One weighted sum per stretch equals the trapezoidal recursion of the rear end's block, stepped by hand."""
    hand = _ByHand(boundaries["slab"], 3, 1)
    for rows in (40, 41, 40):
        hand.stretch(rows)
        assert hand.agree(np.real(hand.shadows.V @ hand.shadows.z.T).T, hand.x)
    assert hand.agree(hand.shadows.jump(1), hand.x[0])


def test_stretches_cut_where_the_lead_wheel_enters_a_bay():
    """Each stretch starts on the last row of the one before; the first row starts the run."""
    assert _stretches(np.array([0, 0, 0, 1, 1, 2])) == [(0, 0, 2), (1, 2, 4), (2, 4, 5)]
    assert _stretches(np.array([3, 3])) == [(3, 0, 1)]


def test_a_window_that_never_moves_is_the_fetrack_of_its_size(boundaries):
    """A stationary wheel: no move, so the window's run is an FETrack's run of the same bays and changes."""
    changes = {0: {"kv": 0.5 * SLAB.kv}, 2: None, 40: None}
    win = st.WindowTrack(SLAB, changes, behind=3, ahead=4, elements_per_bay=NE, system=boundaries["slab"])
    n_left, n_right = win.bays(0.0)
    model = st.FETrack(SLAB, n_left, n_right, "boundary", "boundary", system=boundaries["slab"], elements_per_bay=NE,
                       changes={0: {"kv": 0.5 * SLAB.kv}, 2: None})
    rough = st.roughness_from_spectrum(10.0, [0.1, 0.05], [0.0, 0.0], period=0.05, dt=DT)
    run = dict(x=0.1, dt=DT, duration=0.04, ramp=0.01)
    a = st.wheel_rail_response(win, st.Wheel(), rough, **run)
    b = st.wheel_rail_response(model, st.Wheel(), rough, **run)
    assert a.route == "window" and b.route == "fe model"
    assert np.allclose(a.force, b.force, rtol=0, atol=1e-9 * np.abs(b.force).max())


def test_the_periodic_window_follows_the_path_model_and_converges(boundaries):
    """A wheel at 250 km/h on the periodic slab track: the error falls as the window grows ahead of it."""
    rough = _roughness()
    run = dict(x=0.0, speed=SPEED, dt=DT, duration=0.12)
    ref = st.wheel_rail_response(_path_model(SLAB, boundaries["slab"], None, 0.12, bays=160), st.Wheel(), rough, **run)
    errors = []
    for bays in (6, 16, None):  # None: the default, 60 bays each side; the reference has 160 past the path
        win = st.WindowTrack(SLAB, behind=bays, ahead=bays, elements_per_bay=NE, system=boundaries["slab"])
        errors.append(force_agreement(st.wheel_rail_response(win, st.Wheel(), rough, **run), ref, after=0.03)["rms"])
    assert errors[0] > errors[1] > errors[2], errors
    assert errors[2] < 0.003, errors


def test_a_bogie_over_a_random_track_at_the_default_lengths(boundaries):
    """Log-normal pads (20 %) and ballast (30 %), a failed fastener, two sleepers hanging over 0.5 and 1 mm gaps:
    each wheel within 0.3 % rms and every band within 0.05 dB of the path model; the sleepers' ballast forces too."""
    changes = random_supports(BALLAST, range(-120, 120), seed=4, failed=(6,))
    gaps = {2: 0.5e-3, 9: 1e-3}
    changes.update({kk: {"kb": 0.0} for kk in gaps})
    rough = _roughness()
    run = dict(x=-3.0, speed=SPEED, dt=DT, duration=0.12, ballast_gaps=gaps, watch_supports=[-2, 5, 9, 30],
               bending_at=[3.3])
    win = st.WindowTrack(BALLAST, changes, elements_per_bay=NE, system=boundaries["ballasted"])
    assert (win.behind, win.ahead) == (38, 38)  # the default lengths of the ballasted track's decay rate
    got = st.wheel_rail_response(win, st.Bogie(), rough, **run)
    ref = st.wheel_rail_response(_path_model(BALLAST, boundaries["ballasted"], changes, 0.12, -3.0), st.Bogie(),
                                 rough, **run)
    for wheel in range(2):
        agree = force_agreement(got, ref, wheel=wheel, after=0.03, band=(160.0, 2000.0))
        assert agree["rms"] < 0.003, (wheel, agree["rms"])
        assert agree["worst_level_difference"] < 0.05, (wheel, agree["worst_level_difference"])
    assert np.allclose(got.x, ref.x) and got.infinite is win.infinite_track()
    held = ~np.isnan(got.gaps.force)
    assert np.array_equal(got.gaps.supports, [2, 9]) and held[:, 1].all()  # support 9 is inside to the end
    assert np.max(np.abs(got.gaps.force - ref.gaps.force)[held]) < 0.01 * np.max(ref.gaps.force)
    assert np.all(ref.gaps.contact_time > 0)
    ours, theirs = got.track_forces, ref.track_forces
    assert np.array_equal(ours.supports, theirs.supports) and np.allclose(ours.x_supports, theirs.x_supports)
    assert not np.isnan(ours.rail_seat).any()  # the default window holds them all, from start to end
    for name in ("rail_seat", "ballast", "bending"):
        a, b = getattr(ours, name), getattr(theirs, name)
        held_rows = ~np.isnan(a)
        assert np.max(np.abs(a - b)[held_rows]) < 0.01 * np.max(np.abs(b)), name


def test_the_compiled_and_numpy_loops_agree_on_a_window(boundaries):
    """Both loops through the moves of a short run, on a random track."""
    changes = random_supports(SLAB, range(-30, 30), seed=2)
    win = st.WindowTrack(SLAB, changes, behind=3, ahead=5, elements_per_bay=NE, system=boundaries["slab"])
    run = dict(x=0.0, speed=SPEED, dt=DT, duration=0.03, ramp=0.01)
    a = st.wheel_rail_response(win, st.Wheel(), _roughness(), compiled=True, **run)
    b = st.wheel_rail_response(win, st.Wheel(), _roughness(), compiled=False, **run)
    assert np.allclose(a.force, b.force, rtol=0, atol=1e-9 * np.abs(b.force).max())


@pytest.mark.parametrize(("kwargs", "match"), [
    ({"right": BALLAST}, "right and transition"),
    ({"joints": {0.325: 0.0}}, "joint"),
    ({"behind": 1}, "behind"),
    ({"ahead": 10**6}, "ahead"),
])
def test_the_window_refuses_what_it_cannot_hold(boundaries, kwargs, match):
    with pytest.raises(st.BadInput, match=match):
        st.WindowTrack(SLAB, system=boundaries["slab"], elements_per_bay=NE, **kwargs)


def test_a_boundary_of_another_track_and_a_flexible_slab_are_refused(boundaries):
    with pytest.raises(st.BadInput, match="boundary"):
        st.WindowTrack(SLAB, system=boundaries["ballasted"], elements_per_bay=NE)
    with pytest.raises(st.BadInput, match="flexible slab"):
        st.WindowTrack(st.example_track("floating-slab"), elements_per_bay=NE)


@pytest.mark.parametrize(("kwargs", "match"), [
    ({"watch_supports": [400]}, "watch_supports: support 400 is beyond"),
    ({"bending_at": [-300.0]}, "bending_at"),
    ({"ballast_gaps": {0: 1e-3}}, "kb"),
    ({"ballast_gaps": {500: 1e-3}}, "beyond the window"),
    ({"speed": 1e4}, "speed"),
])
def test_a_run_on_a_window_refuses_what_it_cannot_reach(boundaries, kwargs, match):
    win = st.WindowTrack(BALLAST, behind=3, ahead=5, elements_per_bay=NE, system=boundaries["ballasted"])
    run = dict(x=0.0, speed=SPEED, dt=DT, duration=0.03) | kwargs
    with pytest.raises(st.BadInput, match=match):
        st.wheel_rail_response(win, st.Wheel(), None, **run)


def test_a_constant_speed_function_is_the_constant_speed(boundaries):
    """speed=lambda t: v runs the run of speed=v, to round-off (the path is the same integral)."""
    win = st.WindowTrack(SLAB, behind=4, ahead=6, elements_per_bay=NE, system=boundaries["slab"])
    rail = _roughness().along_rail(0.5, 6.0, fade=0.5)
    run = dict(x=0.0, dt=DT, duration=0.05, profile=rail)
    a = st.wheel_rail_response(win, st.Bogie(), speed=SPEED, **run)
    b = st.wheel_rail_response(win, st.Bogie(), speed=lambda t: SPEED, **run)
    assert np.allclose(a.x, b.x, rtol=0, atol=1e-12) and np.allclose(b.speeds, SPEED)
    assert np.allclose(a.force, b.force, rtol=0, atol=1e-8 * np.abs(a.force).max())
    assert a.speeds is None


def test_a_braking_bogie_follows_the_integral_of_its_speed_on_both_fe_routes(boundaries):
    """250 -> 200 km/h over the run: positions as the closed form, the window as the path model on a rough rail."""
    duration, v0, v1 = 0.1, 250 / 3.6, 200 / 3.6
    speed = lambda t: v0 + (v1 - v0) * t / duration  # noqa: E731
    rail = _roughness().along_rail(0.2, 7.0, fade=0.3)
    changes = random_supports(BALLAST, range(-60, 60), seed=3)
    run = dict(x=0.0, speed=speed, dt=DT, duration=duration, profile=rail)
    win = st.WindowTrack(BALLAST, changes, elements_per_bay=NE, system=boundaries["ballasted"])
    got = st.wheel_rail_response(win, st.Bogie(), **run)
    t = got.t
    exact = v0 * t + 0.5 * (v1 - v0) / duration * t**2
    assert np.allclose(got.x[:, 0], exact, rtol=0, atol=1e-12)
    assert np.allclose(got.x[:, 1] - got.x[:, 0], got.x[0, 1] - got.x[0, 0])
    ref = st.wheel_rail_response(_path_model(BALLAST, boundaries["ballasted"], changes, duration), st.Bogie(), **run)
    for wheel in range(2):
        assert force_agreement(got, ref, wheel=wheel, after=0.02, band=(160.0, 2000.0))["rms"] < 0.003
    assert np.allclose(got.speeds, [speed(tk) for tk in t]) and got.speed == v0


def test_a_varying_speed_is_refused_where_it_cannot_run(boundaries):
    win = st.WindowTrack(SLAB, behind=3, ahead=5, elements_per_bay=NE, system=boundaries["slab"])
    with pytest.raises(st.BadInput, match="roughness"):
        st.wheel_rail_response(win, st.Wheel(), _roughness(), speed=lambda t: SPEED, dt=DT, duration=0.03)
    with pytest.raises(st.BadInput, match="non-negative"):
        st.wheel_rail_response(win, st.Wheel(), speed=lambda t: SPEED - 3000 * t, dt=DT, duration=0.03)
    with pytest.raises(st.BadInput, match="speed"):
        st.moving_green_response(SLAB, st.Wheel(), speed=lambda t: 10.0, dt=DT, duration=0.03)


def test_a_roughness_along_the_rail_is_the_signal_at_its_speed():
    """r(x) = r_t((x - start) / v) inside the fades, within the linear interpolation's 0.3 %; zero at both ends."""
    rough = _roughness()
    rail = rough.along_rail(1.0, 8.0, fade=0.5)
    x = np.linspace(1.6, 8.4, 2001)
    expected = rough((x - 1.0) / rough.speed)
    assert np.max(np.abs(rail(x) - expected)) < 3e-3 * np.max(np.abs(expected))
    assert rail(1.0) == 0.0 and rail(9.0) == 0.0
    with pytest.raises(st.BadInput, match="length"):
        rough.along_rail(0.0, 0.5, fade=0.5)


def test_the_periodic_window_follows_the_moving_greens_functions(boundaries):
    """Against the route with nothing truncated (moving Green's functions on the same mesh): within 0.3 % rms."""
    kernels = st.moving_green_kernels(SLAB, SPEED, DT, memory=0.15, elements_per_bay=NE)
    speed = kernels.grid.speed  # the speed rounded to whole steps a spacing
    rough = st.roughness_from_spectrum(speed, 10 ** (np.arange(-15, -3) / 10), np.zeros(12), period=0.2, seed=2,
                                       dt=DT)
    green = st.moving_green_response(SLAB, st.Wheel(), rough, speed=SPEED, dt=DT, duration=0.12, memory=0.15,
                                     elements_per_bay=NE, kernels=kernels)
    win = st.WindowTrack(SLAB, elements_per_bay=NE, system=boundaries["slab"])
    got = st.wheel_rail_response(win, st.Wheel(), rough, x=green.x[0], speed=speed, dt=DT, duration=0.12)
    assert force_agreement(got, green, after=0.03)["rms"] < 0.003  # 0.27 % measured (the window's 60 bays ahead)


def test_a_wheel_flat_on_the_window_as_on_the_moving_greens_functions(boundaries):
    """A new 50 mm flat at 250 km/h, met twice as the window travels: its impacts as on the route with nothing
    truncated, within 0.3 % rms of the force's fluctuation."""
    kernels = st.moving_green_kernels(SLAB, SPEED, DT, memory=0.15, elements_per_bay=NE)
    wheel = st.Wheel(defects=[st.WheelFlat(0.05, position=0.5)])
    green = st.moving_green_response(SLAB, wheel, None, speed=SPEED, dt=DT, duration=0.06, memory=0.15,
                                     elements_per_bay=NE, kernels=kernels)
    win = st.WindowTrack(SLAB, elements_per_bay=NE, system=boundaries["slab"])
    got = st.wheel_rail_response(win, wheel, x=green.x[0], speed=kernels.grid.speed, dt=DT, duration=0.06)
    assert green.force.max() > 2 * wheel.preload
    assert force_agreement(got, green, after=0.0)["rms"] < 0.003


def test_a_watched_support_is_at_rest_before_the_window_and_unknown_after_it(boundaries):
    """A short window passes a support: zero force until the window reaches it, NaN once it has left it."""
    win = st.WindowTrack(BALLAST, behind=3, ahead=3, elements_per_bay=NE, system=boundaries["ballasted"])
    res = st.wheel_rail_response(win, st.Wheel(), speed=SPEED, dt=DT, duration=0.2, watch_supports=[12],
                                 bending_at=[7.65])
    seat, bend = res.track_forces.rail_seat[:, 0], res.track_forces.bending[:, 0]
    came = np.argmax(seat != 0)
    assert 0 < came and np.all(seat[:came] == 0) and np.isnan(seat[-1]) and np.isnan(bend[-1])
    assert seat[~np.isnan(seat)].max() > 0.2 * st.Wheel().preload  # the wheel passed over it
    assert res.track_forces.x_supports[0] == pytest.approx(12.5 * BALLAST.spacing)


def test_a_short_window_passes_wholly_onto_the_second_track(boundaries):
    """Front, then rear, cross the transition: each end takes its track's boundary and the rear its shadows."""
    system = (boundaries["slab"], boundaries["ballasted"])
    win = st.WindowTrack(SLAB, right=BALLAST, transition=4, elements_per_bay=NE, system=system, behind=6, ahead=6)
    run = dict(x=0.0, speed=SPEED, dt=DT, duration=0.16)
    got = st.wheel_rail_response(win, st.Wheel(), _roughness(), **run)
    path = st.TruncatedTrack(SLAB, 80, "boundary", system=system, elements_per_bay=NE, right=BALLAST, transition=4)
    ref = st.wheel_rail_response(path, st.Wheel(), _roughness(), **run)
    n_left, _ = win.bays(0.0)
    assert win.bay_of(got.x[-1]) - n_left > 4  # the rear end is past the transition at the end
    assert force_agreement(got, ref, after=0.03)["rms"] < 0.03  # a short window: a few per cent, not more


def test_a_jump_of_several_bays_takes_the_shadow_of_the_new_rear_node(boundaries):
    """jump(3) gives the recursion of node 2 and renumbers the rest; the next stretch continues each node's own."""
    hand = _ByHand(boundaries["slab"], 5, 5)
    hand.stretch(30)
    assert hand.agree(hand.shadows.jump(3), hand.x[2])
    hand.x = np.vstack([hand.x[3:], np.zeros((3, hand.x.shape[1]))])  # nodes 3, 4 are now 0, 1; three enter at rest
    hand.stretch(31)
    assert hand.agree(np.real(hand.shadows.V @ hand.shadows.z.T).T, hand.x)


def test_the_shadow_states_beat_a_rear_end_started_at_rest(boundaries, monkeypatch):
    """With 3 bays behind, the shadows' rear states leave a third of the error of states zeroed at each jump."""
    rough = _roughness()
    run = dict(x=0.0, speed=SPEED, dt=DT, duration=0.12)
    ref = st.wheel_rail_response(_path_model(SLAB, boundaries["slab"], None, 0.12, bays=100), st.Wheel(), rough, **run)
    win = st.WindowTrack(SLAB, behind=3, ahead=60, elements_per_bay=NE, system=boundaries["slab"])
    shadowed = force_agreement(st.wheel_rail_response(win, st.Wheel(), rough, **run), ref, after=0.03)["rms"]
    jump = _Shadows.jump
    monkeypatch.setattr(_Shadows, "jump", lambda self, bays: 0.0 * jump(self, bays))
    at_rest = force_agreement(st.wheel_rail_response(win, st.Wheel(), rough, **run), ref, after=0.03)["rms"]
    assert shadowed < 0.5 * at_rest, (shadowed, at_rest)  # measured 0.42 % and 1.35 %


@pytest.mark.parametrize(("changes", "gaps", "match"), [
    ({500: {"eta_pad": 0.3}}, None, r"changes\[500\]"),
    ({}, {2.7: 1e-3}, "ballast_gaps key"),
    ({2: {"kb": 0.0}}, {2: "abc"}, "ballast_gaps"),
    ({}, {2: 1e-3}, "support 2's sleeper"),
])
def test_changes_and_gaps_are_checked_before_any_step(boundaries, changes, gaps, match):
    """Each by the FE models' rules and under its own support number, whether or not the run reaches it."""
    with pytest.raises(st.BadInput, match=match):
        win = st.WindowTrack(BALLAST, changes, behind=3, ahead=3, elements_per_bay=NE, system=boundaries["ballasted"])
        st.wheel_rail_response(win, st.Wheel(), speed=SPEED, dt=DT, duration=0.03, ballast_gaps=gaps)


def test_continue_run_checks_the_state_it_is_given(boundaries):
    """The run's size is bounded as simulate bounds it, and each part of the state is refused by its name."""
    from semitrack.dynamics.newmark import Newmark
    from semitrack.dynamics.simulate import continue_run

    system = st.FETrack(SLAB, 2, 2, "boundary", "boundary", system=boundaries["slab"],
                        elements_per_bay=NE).time_domain_system()
    n, m = system.n_dof, sum(blk.n_states for blk in system.states)
    state = dict(u=np.zeros(n), v=np.zeros(n), a=np.zeros(n), x=np.zeros(m))
    out = continue_run(system, Newmark(DT), 3, **state)
    assert out.u.shape == (n,) and out.x.shape == (m,) and not out.u.any()  # at rest, unloaded: it stays so
    for name in state:
        with pytest.raises(st.BadInput, match=f"{name} must have shape"):
            continue_run(system, Newmark(DT), 3, **(state | {name: np.zeros(3)}))
    with pytest.raises(st.BadInput, match="n_steps"):
        continue_run(system, Newmark(DT), 10**12, **state)
