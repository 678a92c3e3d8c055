"""Several wheels and a bogie: the vehicle's matrices, the linear theory of coupled wheels, and the time domain.

Independent checks: the bogie's receptance against the closed forms of its symmetric (bounce)
and antisymmetric (pitch) halves; the several-wheel linear theory against the one-wheel formula
and reciprocity; the time domain (two wheels 2.5 m apart, and a bogie, standing on a small
roughness on 10-bay models with broadband ends) against the linear theory in every
one-third-octave band 50 Hz - 2.5 kHz.
"""

import numpy as np
import pytest

import semitrack as st
from semitrack.fe.element import point_flexibility

SPEED = 100.0
BANDS = (50.0, 2500.0)
#: Time step and duration per track (as the one-wheel check of test_contact.py).
RUNS = {"slab": (4e-5, 0.82), "ballasted": (2e-5, 0.42)}


def test_bogie_matrices_are_symmetric_with_two_rigid_modes():
    for bogie in (st.Bogie(), st.Bogie(body_mass=1e4)):
        M, C, K = bogie.matrices()
        for X in (M, C, K):
            np.testing.assert_allclose(X, X.T)
        eig = np.linalg.eigvalsh(K)
        assert np.all(eig > -1e-9 * eig.max()) and np.sum(eig < 1e-9 * eig.max()) == 2  # bounce and pitch off the rail


def test_bogie_receptance_is_its_bounce_and_pitch_halves():
    bogie = st.Bogie(frame_inertia=900.0, wheelbase=2.4)
    w = bogie.wheel
    m, k1, c1, mf, J, s = w.mass, w.primary_stiffness, w.primary_damping, bogie.frame_mass, bogie.frame_inertia, 1.2
    f = np.array([2.0, 8.0, 30.0, 200.0])
    om = 2 * np.pi * f
    z1 = k1 + 1j * om * c1
    R = bogie.receptance(f)
    np.testing.assert_allclose(R, R.transpose(0, 2, 1), rtol=1e-12)
    # equal forces: w on each wheel, the frame bounces: (-om^2 m + z1) w - z1 z = F, (-om^2 mf + 2 z1) z = 2 z1 w
    bounce = 1 / (-om**2 * m + z1 - 2 * z1**2 / (-om**2 * mf + 2 * z1))
    np.testing.assert_allclose(R[:, 0, 0] + R[:, 0, 1], bounce, rtol=1e-10)
    # opposite forces: the frame pitches, its ends moving s theta: (-om^2 J + 2 s^2 z1) theta = 2 s z1 w
    pitch = 1 / (-om**2 * m + z1 - 2 * s**2 * z1**2 / (-om**2 * J + 2 * s**2 * z1))
    np.testing.assert_allclose(R[:, 0, 0] - R[:, 0, 1], pitch, rtol=1e-10)


def test_bogie_static_state_leaves_every_spring_unstretched():
    bogie = st.Bogie(body_mass=1e4)
    u0 = bogie.static_state([1e-3, 1.6e-3])
    M, C, K = bogie.matrices()
    np.testing.assert_allclose(bogie.static_loads(u0), [1e5, 1e5, 0.0, 0.0, 0.0], atol=1e-6)
    np.testing.assert_allclose(K @ u0, 0.0, atol=1e-6)


def test_several_wheel_theory_reduces_to_one_wheel_and_is_reciprocal():
    f = np.array([40.0, 300.0, 1200.0])
    slab = st.slab_track()
    one = st.wheel_rail_force(slab, f, st.Wheel(), 0.1, origin="support")
    listed = st.wheel_rail_force(slab, f, [st.Wheel()], [0.1], origin="support")
    np.testing.assert_allclose(listed[:, 0, 0], one, rtol=1e-10)
    H = st.wheel_rail_force(slab, f, [st.Wheel(), st.Wheel(mass=400.0)], [0.1, 1.3], origin="support")
    np.testing.assert_allclose(H[:, 0, 1], H[:, 1, 0], rtol=1e-9)  # rail and wheels are reciprocal
    assert np.min(np.abs(H[:, 0, 1] / H[:, 0, 0])) > 1e-3  # coupled through the rail
    # far apart on the well-damped ballasted track the coupling vanishes above the sleeper resonance
    far = st.wheel_rail_force(st.ballasted_track(), f[1:], [st.Wheel(), st.Wheel()], [0.1, 30.1], origin="support")
    alone = st.wheel_rail_force(st.ballasted_track(), f[1:], st.Wheel(), 0.1, origin="support")
    np.testing.assert_allclose(far[:, 0, 0], alone, rtol=1e-3)
    bogie = st.wheel_rail_force(slab, f, st.Bogie(), x=0.2, origin="support")
    listed = st.wheel_rail_force(slab, f, st.Bogie(), x=[0.2, -2.3], origin="support")
    np.testing.assert_allclose(bogie, listed, rtol=1e-12)
    changed = st.InfiniteTrack(slab, changes={0: None})
    assert not np.allclose(st.wheel_rail_force(changed, f, st.Bogie(), x=0.2, origin="support"), bogie)


def test_vehicle_positions_are_checked():
    with pytest.raises(st.BadInput, match="one position per wheel"):
        st.wheel_rail_force(st.slab_track(), 100.0, [st.Wheel(), st.Wheel()], 0.0, origin="support")
    with pytest.raises(st.BadInput, match="follow the vehicle's wheel offsets"):
        st.wheel_rail_force(st.slab_track(), 100.0, st.Bogie(), [0.0, -2.0], origin="support")
    with pytest.raises(st.BadInput, match="primary suspensions"):
        st.Bogie(wheel=st.Wheel())
    with pytest.raises(TypeError, match="a list of them or a vehicle"):
        st.wheel_rail_force(st.slab_track(), 100.0, "bogie", origin="support")


def test_local_flexibility_is_the_element_under_a_point_force():
    """Zero at nodes, the clamped Timoshenko element's between them (two sub-elements, independent algebra)."""
    model = st.TruncatedTrack(st.slab_track(), 2, elements_per_bay=8)
    h = model.element_length
    assert model.local_flexibility(model.x[[0, 5, 9]]).tolist() == [0.0, 0.0, 0.0]
    g = model.local_flexibility(0.3 * h)
    tr = model.track
    K = [st.fe.element.timoshenko_element(tr.E * tr.I, tr.kappa * tr.A * tr.G, 1.0, 1.0, s)[0] for s in
         (0.3 * h, 0.7 * h)]
    assert g == pytest.approx(np.linalg.inv(K[0][2:, 2:] + K[1][:2, :2])[0, 0], rel=1e-12)
    assert g == pytest.approx(point_flexibility(tr.E * tr.I, tr.kappa * tr.A * tr.G, h, 0.3), rel=1e-12)


@pytest.fixture(scope="module")
def roughness():
    lam = st.third_octave_bands(0.04, 2.0)[0]
    return st.roughness_from_spectrum(SPEED, lam, np.full(lam.size, -10.0), period=0.1, seed=1)


@pytest.mark.parametrize("name", ["slab", "ballasted"])
def test_two_wheels_and_a_bogie_follow_the_several_wheel_theory(name, roughness):
    """Within 0.3 dB in every band at both wheels (measured: 0.11 dB slab, 0.15 dB ballasted), and
    not without the rail elements' own flexibility under the contacts on the slab track."""
    track = (st.slab_track if name == "slab" else st.ballasted_track)(damping="viscous")
    dt, duration = RUNS[name]
    model = st.TruncatedTrack(track, 10, "boundary", system=st.fit_boundary(track, band=(3, 3000), n_poles=24))
    for vehicle, x in (([st.Wheel(), st.Wheel()], [1.25, -1.25]), (st.Bogie(), 1.25)):
        res = st.wheel_rail_response(model, vehicle, roughness, x=x, dt=dt, duration=duration)
        assert not res.lost_contact and res.force.shape[1] == 2
        for i in range(2):
            transfer = st.contact_transfer(res, band=BANDS, wheel=i)
            assert transfer.centres.size == 18
            assert np.max(np.abs(transfer.error_db)) < 0.3, (vehicle, i, transfer.error_db)
    if name == "slab":
        bare = st.wheel_rail_response(model, [st.Wheel(), st.Wheel()], roughness, x=[1.25, -1.25], dt=dt,
                                      duration=duration, element_flexibility=False)
        assert np.max(np.abs(st.contact_transfer(bare, band=BANDS, wheel=0).error_db)) > 0.25


def test_a_bogie_stands_still_on_a_smooth_rail_and_contact_transfer_needs_a_wheel():
    model = st.TruncatedTrack(st.ballasted_track(damping="viscous"), 4, elements_per_bay=8)
    res = st.wheel_rail_response(model, st.Bogie(body_mass=8e3), x=1.1, dt=5e-5, duration=0.05)
    np.testing.assert_allclose(res.force, 1e5, rtol=1e-9)
    np.testing.assert_allclose(res.x[0], [1.1, -1.4])
    assert res.n_dof == model.n_dof + 5
    with pytest.raises(st.BadInput, match="needs wheel=i"):
        st.contact_transfer(res)
    with pytest.raises(st.BadInput, match="below the number of wheels"):
        st.contact_transfer(res, wheel=2)


def test_the_element_flexibility_removes_most_of_the_mesh_line_of_a_rolling_wheel():
    """A wheel rolling on a smooth rail at 300 km/h: the support-passing line v/d is the track's, the line
    v/h of passing the element nodes is the mesh's (measured 2770 N bare, 221 N with the flexibility,
    12 elements per bay; the support line 1785 N either way). Compiled and NumPy loops agree with it."""
    track = st.slab_track(damping="viscous")
    model = st.TruncatedTrack(track, 20, "boundary", system=st.fit_boundary(track, band=(3, 3000), n_poles=24),
                              elements_per_bay=12)
    v = 300 / 3.6
    lines = {}
    for flexible in (False, True):
        res = st.wheel_rail_response(model, st.Wheel(), x=-5.0, speed=v, dt=2e-5, duration=0.12,
                                     element_flexibility=flexible)
        f, amplitude = res.force_spectrum(after=0.03)
        lines[flexible] = [amplitude[np.abs(f - line) < 3 * (f[1] - f[0])].max()
                           for line in (v / track.spacing, v / model.element_length)]
    assert lines[True][0] == pytest.approx(lines[False][0], rel=0.01)
    assert lines[True][1] < lines[False][1] / 8
    runs = [st.wheel_rail_response(model, st.Bogie(), x=-5.0, speed=v, dt=2e-5, duration=0.03,
                                   compiled=compiled) for compiled in (True, False)]
    motion = np.max(np.abs(runs[1].force - 1e5))
    assert np.max(np.abs(runs[0].force - runs[1].force)) < 1e-10 * motion
    np.testing.assert_allclose(runs[0].w_rail, runs[1].w_rail, rtol=0, atol=1e-10 * np.abs(runs[1].w_rail).max())


def test_several_wheels_on_a_flexible_slab_are_refused_by_the_linear_theory():
    """A flexible slab has no InfiniteTrack: the several-wheel theory is refused, not replaced by one wheel's."""
    track = st.example_track("floating-slab").replace(damping="viscous")
    model = st.TruncatedTrack(track, 10, "pinned", elements_per_bay=8)
    res = st.wheel_rail_response(model, [st.Wheel(), st.Wheel()], st.corrugation(100.0, 0.1, 1e-7),
                                 x=[0.0, -2.5], dt=5e-5, duration=0.03, ramp=0.005)
    with pytest.raises(st.BadInput, match="several wheels needs the exact InfiniteTrack"):
        st.contact_transfer(res, band=(1000.0, 1000.0), wheel=0)
