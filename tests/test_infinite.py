"""The exact infinite track with load and response anywhere, changed supports, transitions and joints.

Independent checks: the exact point receptance (``st.point_receptance``, Bloch waves at one cut)
where nothing is changed; reciprocity; a transition to the same track is no transition; a long
FE model with exact ends and the same changed supports, converging at second order with the
mesh; a joint's two limits (a rigid joint is no joint, a hinge carries no moment).
"""

import numpy as np
import pytest

import semitrack as st

F = np.array([3.0, 50.0, 183.0, 600.0, 945.0, 1500.0, 2500.0, 3000.0])
TRACKS = {"slab": st.slab_track, "ballasted": st.ballasted_track}


def _rel(a, b):
    """Largest difference relative to the largest entry of ``b``, per frequency, then the worst."""
    return float(np.max(np.abs(a - b).reshape(a.shape[0], -1).max(1) / np.abs(b).reshape(b.shape[0], -1).max(1)))


@pytest.mark.parametrize("name", TRACKS)
def test_the_periodic_track_is_the_exact_point_receptance(name):
    """At a mid-span, a support and in between, to 1e-10 (measured 1e-14): the same exact method,
    cut at the point, against a core of exact segments closed by the exact ends."""
    track = TRACKS[name]()
    inf = st.InfiniteTrack(track)
    for x in (0.0, 0.5 * track.spacing, 0.2, -3.1):
        H = inf.receptance(F, x, [x])[:, 0]
        assert _rel(H, st.point_receptance(track, F, x=x, origin="midspan")) < 1e-10, x


@pytest.mark.parametrize("name", TRACKS)
def test_transfer_receptances_are_reciprocal_with_and_without_changes(name):
    track = TRACKS[name]()
    changed = {0: {"kv": 0.2 * track.kv}, 2: None, -1: {"kphi": 0.0}}
    if track.is_ballasted:
        changed[3] = {"kb": 0.0}
    for inf in (st.InfiniteTrack(track), st.InfiniteTrack(track, changed, joints={1.1: 2e5}),
                st.InfiniteTrack(track, changed, right=st.slab_track(kv=8e7), transition=4)):
        a, b = 0.13, 2.71
        Hab, Hba = inf.receptance(F, a, [b])[:, 0], inf.receptance(F, b, [a])[:, 0]
        assert _rel(Hab, Hba.transpose(0, 2, 1)) < 1e-10


@pytest.mark.parametrize("name", TRACKS)
def test_a_transition_to_the_same_track_is_no_transition(name):
    track = TRACKS[name]()
    xs = [-0.4, 0.9, 1.3, 4.0]
    same = st.InfiniteTrack(track, right=track, transition=2).receptance(F, 0.2, xs)
    assert _rel(same, st.InfiniteTrack(track).receptance(F, 0.2, xs)) < 1e-10


CHANGES = {"slab": {"failed fastener": {0: None}, "worn pad": {0: {"kv": 5e6}}},
           "ballasted": {"failed fastener": {0: None}, "hanging sleeper": {0: {"kb": 0.0}}}}


@pytest.mark.parametrize("name, case", [(n, c) for n in CHANGES for c in CHANGES[n]])
def test_changed_supports_against_a_long_fe_model_with_exact_ends(name, case):
    """w per F at the change and one bay away, at five frequencies 50 Hz - 2.5 kHz, against
    TruncatedTrack(6 bays each side, exact ends, the same changes): second order in the element
    length (each doubling divides the error by 3.6-4.1, measured) and below 0.5 % with 48
    elements per bay (measured 0.19 % at most, at 2.5 kHz)."""
    track, changes = TRACKS[name](), CHANGES[name][case]
    f = np.array([50.0, 200.0, 700.0, 1500.0, 2500.0])
    xs = [0.5 * track.spacing, 1.5 * track.spacing]
    exact = st.InfiniteTrack(track, changes).receptance(f, xs[0], xs)[..., 0, 0]
    errors = []
    for n_el in (12, 24, 48):
        model = st.TruncatedTrack(track, 6, "exact", elements_per_bay=n_el, changes=changes)
        rhs = np.zeros((model.n_dof, 1))
        rhs[model.dof(xs[0]), 0] = 1.0
        u = model.solve(f, rhs)[:, [model.dof(x) for x in xs], 0]
        errors.append(np.max(np.abs(u / exact - 1)))
    assert errors[2] < 5e-3
    assert 3.0 < errors[0] / errors[1] < 4.5 and 3.0 < errors[1] / errors[2] < 4.5


def test_a_rigid_joint_is_no_joint_and_a_hinge_carries_no_moment():
    track = st.slab_track()
    x_joint = 0.15
    plain = st.InfiniteTrack(track).receptance(F, 0.0, [0.0, 0.3])
    rigid = st.InfiniteTrack(track, joints={x_joint: 1e16}).receptance(F, 0.0, [0.0, 0.3])
    assert _rel(rigid, plain) < 1e-6
    hinge = st.InfiniteTrack(track, joints={x_joint: 0.0})
    static = hinge.receptance([0.1], 0.0, [0.0])[0, 0, 0, 0].real
    assert static > 1.1 * st.InfiniteTrack(track).receptance([0.1], 0.0, [0.0])[0, 0, 0, 0].real  # softer
    # a hinge transmits no moment: the rail rotates freely on either side of it
    psi = hinge.receptance([100.0], 0.0, [x_joint - 1e-3, x_joint + 1e-3])[0, :, 1, 0]
    assert abs(psi[0] - psi[1]) > 0.1 * abs(psi[0])


def test_a_transition_leads_to_the_other_track():
    """Slab to ballasted at x_t = 0: far into the ballasted side the point receptance is the
    ballasted track's, as the wave reflected at the transition decays on its way there and back:
    at 300 Hz 30 bays away within 1e-10 (measured 3e-16); at 945 Hz, where the ballasted track's
    waves travel far, 3 % at 30 bays and 3e-4 at 100 (measured)."""
    slab, ballast = st.slab_track(), st.ballasted_track()
    inf = st.InfiniteTrack(slab, right=ballast, transition=0)

    def off(f, bays):
        x = bays * ballast.spacing  # a mid-span of the ballasted side
        return _rel(inf.receptance([f], x, [x])[:, 0], st.point_receptance(ballast, [f], x=0.0, origin="midspan"))

    assert off(300.0, 30) < 1e-10
    assert off(945.0, 100) < 1e-3 < 0.01 < off(945.0, 30)
    with pytest.raises(ValueError, match="changes\\[-1\\] sets sleeper or ballast fields on a support of a track"):
        st.InfiniteTrack(slab, {-1: {"kb": 0.0}}, right=ballast, transition=0)
    st.InfiniteTrack(slab, {1: {"kb": 0.0}}, right=ballast, transition=0)  # a ballasted support: fine


def test_bad_input_is_refused_with_its_name():
    track = st.slab_track()
    with pytest.raises(ValueError, match="changes\\[0\\] names unknown support fields \\['E'\\]"):
        st.InfiniteTrack(track, {0: {"E": 1.0}})
    with pytest.raises(ValueError, match="changes\\[0\\]\\['kv'\\] must be non-negative"):
        st.InfiniteTrack(track, {0: {"kv": -1.0}})
    with pytest.raises(ValueError, match="right and transition go together"):
        st.InfiniteTrack(track, right=track)
    with pytest.raises(ValueError, match="a joint cuts the rail between supports"):
        st.InfiniteTrack(track, joints={0.325: 0.0})
    with pytest.raises(ValueError, match="a load or response point at the joint"):
        st.InfiniteTrack(track, joints={0.1: 0.0}).receptance(F, 0.1, [0.0])
    with pytest.raises(ValueError, match="a flexible slab"):
        st.InfiniteTrack(st.example_track("floating-slab"))
    with pytest.raises(ValueError, match="the FE models change"):
        st.TruncatedTrack(track, 3, changes={0: {"eta_pad": 0.1}})


@pytest.mark.parametrize("change", [{0: None}, {0: {"kb": 0.0}}, {0: {"kv": 1e7}}])
def test_a_load_on_a_changed_support_scales_every_response_alike(change):
    """With the load over the only changed support the change adds one vertical force at the load
    point (the rail does not turn there, by symmetry, so no moment), and w(x) moves by one factor at
    every x: a property the solver does not build in."""
    track = st.ballasted_track()
    x0 = 0.5 * track.spacing  # support 0
    xs = [-1.7, 0.1, x0, 1.2, 4.4]
    ratio = st.InfiniteTrack(track, change).receptance(F, x0, xs)[:, :, 0, 0] / \
        st.InfiniteTrack(track).receptance(F, x0, xs)[:, :, 0, 0]
    assert np.max(np.abs(ratio / ratio[:, [2]] - 1)) < 1e-9
    assert np.max(np.abs(ratio[:, 2] - 1)) > 1e-3  # and the change is felt
