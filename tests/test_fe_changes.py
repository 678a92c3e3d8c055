"""FE tracks that are not periodic: changed supports, a transition, rail joints, against the exact InfiniteTrack.

The exact infinite track with the same changes (``model.infinite_track()``, no mesh, no
truncation) is the reference. A 10-bay model closed by broadband ends must follow it within 1 %
median / 5 % max at the change and one bay away over 3-3000 Hz (causal, viscous damping on
both); the same model with pinned ends is far off; the same mesh with exact ends shows what the
mesh alone contributes.
"""

import numpy as np
import pytest

import semitrack as st

#: 3-3000 Hz every 6 Hz: the pinned-pinned peaks fall between the points no more than on the paper's grid.
F = np.arange(3.0, 3001.0, 6.0)
SLAB, BALLASTED = st.slab_track(damping="viscous"), st.ballasted_track(damping="viscous")
D1, D2 = SLAB.spacing, BALLASTED.spacing


@pytest.fixture(scope="module")
def boundaries():
    return {"slab": st.fit_boundary(SLAB), "ballasted": st.fit_boundary(BALLASTED)}


#: name: (track, TruncatedTrack keywords, which boundaries close the ends, the load point, a bay away)
CASES = {
    "failed fastener (slab)": (SLAB, {"changes": {0: None}}, "slab", 0.5 * D1, 1.5 * D1),
    "three hanging sleepers": (BALLASTED, {"changes": {k: {"kb": 0.0} for k in (-1, 0, 1)}}, "ballasted",
                               0.5 * D2, 1.5 * D2),
    "slab-to-ballast transition": (SLAB, {"right": BALLASTED, "transition": 0}, ("slab", "ballasted"),
                                   0.5 * D2, 1.5 * D2),
    "rail joint (hinge at a mid-span)": (BALLASTED, {"joints": {0.0: 0.0}}, "ballasted", 0.5 * D2, 1.5 * D2),
    "rail joint (stiff, off a node)": (SLAB, {"joints": {0.1: 1e6}}, "slab", 0.5 * D1, 1.5 * D1),
}


def _errors(model, x_load, x_away):
    """Relative error of w per F at the load and a bay away, against the model's infinite track."""
    points = [x_load, x_away]
    ref = model.infinite_track().receptance(F, x_load, points)[:, :, 0, 0]
    rhs = np.zeros((model.n_dof, 1))
    rhs[model.dof(x_load)] = 1.0
    u = model.solve(F, rhs)[:, [model.dof(x) for x in points], 0]
    return np.abs(u - ref) / np.abs(ref)


def _model(case, ends, boundaries, **kw):
    track, keywords, which, *_ = CASES[case]
    system = None
    if ends == "boundary":
        system = tuple(boundaries[w] for w in which) if isinstance(which, tuple) else boundaries[which]
    return st.TruncatedTrack(track, 10, ends=ends, system=system, elements_per_bay=48, **keywords, **kw)


@pytest.mark.parametrize("case", list(CASES))
def test_broadband_ends_follow_the_exact_imperfect_track(case, boundaries):
    e = _errors(_model(case, "boundary", boundaries), *CASES[case][3:])
    assert np.median(e[:, 0]) < 0.01 and e[:, 0].max() < 0.05, (np.median(e[:, 0]), e[:, 0].max())
    assert np.median(e[:, 1]) < 0.01 and e[:, 1].max() < 0.05, (np.median(e[:, 1]), e[:, 1].max())
    pinned = _errors(_model(case, "pinned", boundaries), *CASES[case][3:])
    assert np.median(pinned[:, 0]) > 0.1  # the same short model with pinned ends is far off


@pytest.mark.parametrize("case", ["slab-to-ballast transition", "rail joint (stiff, off a node)"])
def test_the_mesh_alone_with_exact_ends(case, boundaries):
    """Exact ends leave the mesh as the only approximation: a fraction of the broadband model's error."""
    e = _errors(_model(case, "exact", boundaries), *CASES[case][3:])
    assert np.median(e) < 0.002 and e.max() < 0.02, (np.median(e), e.max())


def test_changes_change_the_answer():
    """A model with a change differs from the periodic one where the change matters: the checks above can fail."""
    plain = st.TruncatedTrack(SLAB, 4, ends="exact", elements_per_bay=16)
    for kw in ({"changes": {0: None}}, {"right": BALLASTED, "transition": 0}, {"joints": {0.0: 0.0}}):
        other = st.TruncatedTrack(SLAB, 4, ends="exact", elements_per_bay=16, **kw)
        a, b = plain.receptance([50.0, 500.0], 0.0), other.receptance([50.0, 500.0], 0.0)
        assert np.max(np.abs(a[:, 0, 0] - b[:, 0, 0]) / np.abs(a[:, 0, 0])) > 0.05, kw


def test_transition_model_is_reciprocal_and_one_system_in_both_domains():
    """Across a transition the receptance is reciprocal, and the viscous frequency domain is exactly
    K + i omega C - omega^2 M of the time domain (each track's dampers at its own reference frequencies)."""
    model = st.TruncatedTrack(SLAB, 3, ends="pinned", elements_per_bay=8, right=BALLASTED, transition=1,
                              joints={-0.2: 5e5})
    a, b = -1.5 * D1, 1 * D1 + 1.5 * D2
    rhs = np.zeros((model.n_dof, 2))
    rhs[model.dof(a), 0] = rhs[model.dof(b), 1] = 1.0
    u = model.solve([80.0, 900.0], rhs)
    np.testing.assert_allclose(u[:, model.dof(b), 0], u[:, model.dof(a), 1], rtol=1e-9)
    M, C, K = model.matrices()
    for f in (80.0, 900.0):
        w = 2 * np.pi * f
        Z = (K + 1j * w * C - w**2 * M).toarray()
        np.testing.assert_allclose(model.dynamic_stiffness(f).toarray(), Z, rtol=1e-12, atol=1e-12 * np.abs(Z).max())


def test_transition_layout():
    """Bays past kt are the second track's: its spacing, its supports numbered on, its sleepers."""
    model = st.TruncatedTrack(SLAB, 2, elements_per_bay=4, right=BALLASTED, transition=0)
    np.testing.assert_allclose(model.x[model.support_nodes], [-1.5 * D1, -0.5 * D1, 0.5 * D2, 1.5 * D2])
    assert model.mesh.support_index.tolist() == [-2, -1, 0, 1]
    assert model.sleeper_dofs.size == 2 and model.end_track("right") is model.right_track
    assert model.x[-1] == pytest.approx(2 * D2)


def test_layout_rules():
    with pytest.raises(st.BadInput, match="transition must be a mid-span of the model"):
        st.TruncatedTrack(SLAB, 2, right=BALLASTED, transition=3)
    with pytest.raises(st.BadInput, match="right and transition go together"):
        st.TruncatedTrack(SLAB, 2, right=BALLASTED)
    with pytest.raises(st.BadInput, match="one kind of damping"):
        st.TruncatedTrack(SLAB, 2, right=st.ballasted_track(), transition=0)
    with pytest.raises(st.BadInput, match="joints must lie inside the model"):
        st.TruncatedTrack(SLAB, 2, joints={5.0: 0.0})
    with pytest.raises(st.BadInput, match="a joint cuts the rail between supports"):
        st.TruncatedTrack(SLAB, 2, joints={0.5 * D1: 0.0})
    with pytest.raises(st.BadInput, match="the pair"):
        st.TruncatedTrack(SLAB, 2, ends="equivalent", system=(st.paper_table4(),) * 3)
    with pytest.raises(st.BadInput, match="takes none"):
        st.FETrack(SLAB, 2, 2, "pinned", "equivalent", system=(st.paper_table4(), st.paper_table4()))


def test_joints_given_in_any_order_keep_their_own_stiffness():
    """Two joints, a hinge and a stiff one, listed right to left or left to right: each keeps its stiffness
    (exact ends: the mesh alone; swapped, the receptance was 34-68 % off)."""
    track = st.ballasted_track(damping="viscous")
    for joints in ({0.7: 0.0, -0.7: 1e9}, {-0.7: 1e9, 0.7: 0.0}):
        model = st.TruncatedTrack(track, 3, ends="exact", elements_per_bay=48, joints=joints)
        e = _errors(model, 0.3, 0.9)
        assert np.median(e) < 0.005 and e.max() < 0.05, (joints, np.median(e), e.max())
