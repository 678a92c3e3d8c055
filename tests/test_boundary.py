"""The broadband boundary: vector fitting, the exact passivity test, enforcement, the fitted ends.

Independent checks: vector fitting recovers a rational function it did not build; the state
space reproduces the pole-residue form; the Hamiltonian test agrees with dense sampling (and
finds what a coarse grid misses); the fitted models of the paper's tracks are proven passive,
keep the static stiffness and the Timoshenko dashpot, and meet stated error bounds.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from synthesis_checks import check_second_order

import semitrack as st
from semitrack.boundary.fitting import track_end_limits
from semitrack.boundary.passivity import enforce_passivity, hamiltonian_crossings, passivity_report
from semitrack.boundary.rational import RationalEndStiffness, symmetric_from_columns
from semitrack.boundary.vector_fitting import pole_basis, starting_poles, vector_fit
from semitrack.equivalent.metrics import error_band_grid, error_summary
from semitrack.fe.timedomain import newmark, pulse_response
from semitrack.fe.truncation import truncation_errors
from semitrack.paper.boundary_study import order_study

BAND = (3.0, 3000.0)


def _synthetic(seed=1, n_pairs=4, n_real=3):
    """A random stable model with symmetric coefficients (not necessarily passive)."""
    rng = np.random.default_rng(seed)
    w = 2 * np.pi * np.sort(rng.uniform(10, 2000, n_pairs))
    poles = np.concatenate([-w * rng.uniform(0.01, 0.2, n_pairs) + 1j * w,
                            -2 * np.pi * np.sort(rng.uniform(1, 5000, n_real)) + 0j])
    coef = rng.normal(size=(2 * n_pairs + n_real, 3)) * np.array([3e7, 3e6, 3e5])
    return RationalEndStiffness(poles, coef, K0=np.array([[5e7, 2e7], [2e7, 1.6e7]]), D=np.diag([1.2e5, 1.2e3]))


def _min_eig_dense(model, f):
    s = 2j * np.pi * f
    Z = model.impedance(s).real
    return np.linalg.eigvalsh(0.5 * (Z + np.swapaxes(Z, 1, 2)))[:, 0]


def test_vector_fitting_recovers_a_rational_function():
    """Data from a known model are refitted to round-off from different starting poles."""
    true = _synthetic()
    f = np.geomspace(1.0, 5000.0, 400)
    s = 2j * np.pi * f
    data = pole_basis(s, true.poles) @ true.coefficients
    poles, coef = vector_fit(s, data, np.ones_like(data.real), starting_poles(1.0, 5000.0, 4, 3), n_iter=15)
    fitted = pole_basis(s, poles) @ coef
    assert np.max(np.abs(fitted - data)) / np.max(np.abs(data)) < 1e-8
    assert np.allclose(np.sort_complex(poles), np.sort_complex(true.poles), rtol=1e-6)


def test_state_space_reproduces_the_pole_residue_form():
    model = _synthetic()
    A, B, C, D = model.state_space()
    f = np.array([0.5, 37.0, 910.0, 2.5e4])
    s = 2j * np.pi * f
    X = np.linalg.solve(s[:, None, None] * np.eye(A.shape[0]) - A, np.broadcast_to(B, (f.size,) + B.shape))
    K_ss = model.K0 + s[:, None, None] * (D + C @ X)
    assert np.allclose(K_ss, model.dynamic_stiffness(f), rtol=1e-10, atol=0)
    assert np.allclose(model.receptance(f) @ model.dynamic_stiffness(f), np.eye(2), atol=1e-10)


def test_static_and_high_frequency_limits_are_exact_by_construction():
    model = _synthetic()
    assert np.allclose(model.dynamic_stiffness([1e-9])[0], model.K0, rtol=1e-6)
    f = np.array([1e8])
    assert np.allclose(model.dynamic_stiffness(f)[0] / (2j * np.pi * f[0]), model.D, rtol=1e-5,
                       atol=1e-6 * model.D.max())


def test_hamiltonian_test_agrees_with_dense_sampling():
    """Crossings sit where an eigenvalue of Re Z is zero; the verdict matches a dense grid."""
    model = _synthetic(seed=3)
    report = passivity_report(model)
    f = np.geomspace(1e-3, 1e6, 20001)
    sampled_negative = np.any(_min_eig_dense(model, f) < 0)
    assert bool(report) is (not sampled_negative)
    A, B, C, D = model.state_space()
    S = np.diag(np.diag(D) ** -0.5)
    for w in hamiltonian_crossings(A, B @ S, S @ C, S @ D @ S):
        Z = model.impedance(np.array([1j * w]))[0].real
        eig = np.linalg.eigvalsh(S @ (0.5 * (Z + Z.T)) @ S)
        assert np.min(np.abs(eig)) < 1e-6 * np.max(np.abs(eig)) + 1e-9


def test_hamiltonian_test_finds_a_violation_a_coarse_grid_misses():
    """A lightly damped pole pair with the wrong-signed residue makes Re Z negative in a band
    far narrower than the spacing of a 3 Hz grid: sampling misses it, the exact test does not."""
    w0 = 2 * np.pi * 1000.5  # half-way between two points of the 3 Hz grid
    poles = np.array([-1e-3 * w0 + 1j * w0])
    coef = np.array([[-2e6, 0.0, 0.0], [0.0, 0.0, 0.0]])  # Re Z11 < 0 within ~1.3 Hz of w0
    model = RationalEndStiffness(poles, coef, K0=np.eye(2) * 1e7, D=np.diag([1.2e5, 1.2e3]))
    grid = np.arange(3.0, 3000.1, 3.0)
    assert np.all(_min_eig_dense(model, grid) > 0)
    report = passivity_report(model)
    assert not report
    lo, hi = report.violations_hz[0]
    assert lo < 1000.5 < hi and hi - lo < 3.0


def test_enforcement_makes_a_model_passive_with_a_small_change():
    model = _synthetic(seed=3)
    assert not passivity_report(model)
    fixed, rounds = enforce_passivity(model)
    assert passivity_report(fixed) and rounds >= 1
    assert np.allclose(fixed.poles, model.poles) and np.array_equal(fixed.K0, model.K0)
    f = np.geomspace(1e-3, 1e6, 20001)
    assert np.min(_min_eig_dense(fixed, f)) > -1e-9 * np.max(np.diag(model.D))


def test_enforcement_reaches_passivity_on_a_floating_slab():
    """Sharp slab resonances (26-150 Hz) make the enforcement's cuts converge slowly: this fit
    needed 16 rounds (measured) and was returned NOT passive when the rounds stopped at 12."""
    slab = st.Slab(length=6.45, fasteners=10, E=3.6e10, I=2.869e-3, mass_per_length=956.25,
                   support_stiffness=2.55e7, eta_support=0.15, eta_slab=0.02)
    bnd = st.fit_boundary(st.slab_track(slab=slab), band=BAND, n_poles=36, seed=0)
    assert bnd.is_passive() and bnd.enforcement_rounds > 12
    assert bnd.max_error < 0.35  # measured 0.299: as good as the shipped design's fit


def test_the_constrained_step_is_the_least_squares_optimum_under_the_cuts():
    """The step through the triangular factor of ``[J r]`` (no Q formed) meets the optimality
    conditions of the convex programme, which certify its optimum independently of the method:
    feasible, and the gradient a non-negative combination of the binding cuts alone."""
    from scipy.optimize import nnls

    from semitrack.boundary.passivity import _constrained_step
    rng = np.random.default_rng(5)
    J, r = rng.normal(size=(40, 9)), rng.normal(size=40)
    G = rng.normal(size=(60, 9))
    h = G @ rng.normal(size=9) - 0.1 * rng.random(60)  # feasible (at that point)
    free = np.linalg.lstsq(J, -r, rcond=None)[0]
    assert np.any(G @ free < h)  # and the unconstrained optimum violates some
    step, active = _constrained_step(J, r, G, h)
    slack = G @ step - h
    assert np.all(slack >= -1e-9) and active.size and np.all(np.abs(slack[active]) < 1e-9)
    gradient = J.T @ (r + J @ step)  # of half the squared residual
    multipliers, misfit = nnls(G[active].T, gradient)
    assert misfit < 1e-6 * np.linalg.norm(gradient) and np.any(multipliers > 0)


def test_a_hint_changes_the_least_distance_work_not_its_answer():
    from semitrack.boundary.passivity import _least_distance
    rng = np.random.default_rng(8)
    M = rng.normal(size=(3000, 12))
    h = M @ rng.normal(size=12) - 0.1 * rng.random(3000)  # feasible, and 0 is not
    y, active = _least_distance(M, h)
    for hint in (active, rng.choice(3000, 50, replace=False), np.array([2999, 10**6])):
        y_hint, active_hint = _least_distance(M, h, hint)
        assert np.allclose(y_hint, y, rtol=1e-10, atol=1e-12) and np.array_equal(active_hint, active)


def test_the_fan_cuts_at_the_guard_grid_are_handed_over_once():
    """They depend on the poles and D only, so a later round would only repeat them."""
    from semitrack.boundary.passivity import _FixedCuts, _guard_omegas
    model = _synthetic(seed=3)
    fixed = _FixedCuts(model, _guard_omegas(model))
    G1, unit1 = fixed.newly_near(model)
    assert G1.shape[0] == unit1.size > 0
    G2, _ = fixed.newly_near(model)
    assert G2.shape[0] == 0  # the same model: nothing new
    far = RationalEndStiffness(model.poles, 0 * model.coefficients, model.K0, model.D)  # Re Z = D: far inside
    assert fixed.newly_near(far)[0].shape[0] == 0


@pytest.fixture(scope="module")
def fitted():
    """The paper's two tracks fitted once: the slab by the automatic order search (which fits 24
    and 36 poles and keeps 36), the ballasted track at the 36 poles the search also keeps there
    (measured; the same deterministic fit, without refitting 24 poles)."""
    return {"slab": st.fit_boundary(st.slab_track(), band=BAND, seed=0),
            "ballasted": st.fit_boundary(st.ballasted_track(), band=BAND, n_poles=36, seed=0)}


@pytest.mark.parametrize("name", ["slab", "ballasted"])
def test_fitted_boundary_is_proven_passive_and_keeps_the_limits(fitted, name):
    bnd = fitted[name]
    track = st.slab_track() if name == "slab" else st.ballasted_track()
    assert bnd.is_passive() and bnd.passivity.stable
    assert np.all(bnd.rational.poles.real < 0)
    K0, D = track_end_limits(track)
    exact_static = np.linalg.inv(st.semi_infinite_receptance(track, [1e-3])[0]).real
    assert np.allclose(bnd.dynamic_stiffness([1e-6])[0], exact_static, rtol=0.01)
    f = 1e7
    assert np.allclose(bnd.dynamic_stiffness([f])[0].imag / (2 * np.pi * f), D, rtol=0.01, atol=1e-3 * D.max())
    # Far outside the band the receptance is still finite and passive (Im alpha11 <= 0 here).
    far = bnd.receptance([1e-4, 1e5, 1e6])
    assert np.all(np.isfinite(far)) and np.all(far[:, 0, 0].imag <= 0)


# Measured (3 Hz grid over 3-3000 Hz, element-wise): slab 1.9 % median, 6.7 % max; ballasted
# 3.6 % / 14.5 %. The loss factors of the paper are not causal: a causal passive model with the
# static stiffness pinned cannot follow a constant loss factor eta over three decades to better
# than about 0.7-0.9 eta (Kramers-Kronig), i.e. ~7-9 % for the pads (eta 0.1) and ~20-25 % for
# the ballast (eta 0.3) alone. Bounds keep ~10 % headroom over the measured values.
HYSTERETIC_BOUNDS = {"slab": (0.02, 0.074), "ballasted": (0.04, 0.16)}


@pytest.mark.parametrize("name", ["slab", "ballasted"])
def test_fitted_boundary_error_over_the_full_band(fitted, name):
    bnd = fitted[name]
    track = st.slab_track() if name == "slab" else st.ballasted_track()
    g = error_band_grid(BAND, 3.0)
    err = error_summary(bnd.receptance(g), st.semi_infinite_receptance(track, g))
    assert err.median == pytest.approx(bnd.median_error) and err.max == pytest.approx(bnd.max_error)
    median, largest = HYSTERETIC_BOUNDS[name]
    assert bnd.median_error <= median and bnd.max_error <= largest


def test_boundary_beats_the_n5_systems_beyond_their_band(fitted, paper_fits):
    """Above the paper's fit band the N = 5 systems fail; the broadband end does not."""
    fit5 = paper_fits["slab"]  # N = 5 over the paper's band, seed 0 (conftest.py)
    g = error_band_grid((900.0, 3000.0), 3.0)
    exact = st.semi_infinite_receptance(st.slab_track(), g)
    assert error_summary(fitted["slab"].receptance(g), exact).max < 0.5 * error_summary(
        fit5.system.receptance(g), exact).max


@pytest.mark.parametrize("fmt", ["json", "mat"])
def test_export_round_trip(fitted, tmp_path, fmt):
    bnd = fitted["slab"]
    path = st.save_boundary(bnd, tmp_path / f"end.{fmt}")
    back = st.load_boundary(path)
    f = np.geomspace(0.1, 1e5, 50)
    assert np.allclose(back.dynamic_stiffness(f), bnd.dynamic_stiffness(f), rtol=1e-12)
    assert back.is_passive() and back.band == bnd.band
    assert (back.median_error, back.max_error) == pytest.approx((bnd.median_error, bnd.max_error))
    assert back.enforcement_rounds == bnd.enforcement_rounds


def test_load_refuses_a_mismatched_state_space(fitted, tmp_path):
    path = st.save_boundary(fitted["slab"], tmp_path / "end.json")
    data = json.loads(path.read_text())
    data["state_space"]["A"][0][0] *= 1.5
    path.write_text(json.dumps(data))
    with pytest.raises(ValueError, match="does not match"):
        st.load_boundary(path)


@pytest.mark.parametrize("bad, exc, match", [
    (dict(band=(3000.0, 3.0)), ValueError, "band"),
    (dict(n_poles=1), ValueError, "n_poles"),
    (dict(n_poles=1000), ValueError, "n_poles"),
    (dict(n_poles=2.5), TypeError, "n_poles"),
    (dict(df=0.0), ValueError, "df"),
    (dict(band=(3.0, 1e8)), ValueError, "at most 100000 frequencies"),
    (dict(seed=-1), ValueError, "seed"),
    (dict(seed=1.5), TypeError, "seed"),
])
def test_bad_arguments_are_named(bad, exc, match):
    with pytest.raises(exc, match=match):
        st.fit_boundary(st.slab_track(), **bad)


def test_track_must_be_a_track():
    with pytest.raises(TypeError, match="track"):
        st.fit_boundary("slab")


def test_symmetric_columns_helper():
    m = symmetric_from_columns(np.array([[1.0, 2.0, 3.0]]))
    assert np.array_equal(m[0], [[1.0, 2.0], [2.0, 3.0]])


# Made-up tracks beyond the paper's: soft pads on a slab, a lighter rail at another spacing on
# softer ballast.
OTHER_TRACKS = {
    "soft-pad slab": lambda: st.slab_track(kv=2.0e7, kphi=1.0e5, eta_pad=0.15, name="soft-pad slab"),
    "54E1 ballasted": lambda: st.ballasted_track(A=6.977e-3, I=23.41e-6, spacing=0.65, kv=1.2e8,
                                                 sleeper_mass=140.0, kb=6e7, name="54E1 ballasted"),
}


@pytest.mark.parametrize("name", ["slab", "ballasted", *OTHER_TRACKS])
def test_causal_damping_makes_the_boundary_near_exact(request, name):
    """With viscous (causal) damping a rational model can be exact; measured 0.1-0.16 % median,
    0.28-0.37 % max over 3-3000 Hz. (The paper's two tracks: the fits of ``viscous_fits``.)"""
    if name in OTHER_TRACKS:
        bnd = st.fit_boundary(OTHER_TRACKS[name]().replace(damping="viscous"), band=BAND)
    else:
        bnd = request.getfixturevalue("viscous_fits")[name]
    assert bnd.is_passive()
    assert bnd.median_error <= 0.002 and bnd.max_error <= 0.005


@pytest.mark.slow
@pytest.mark.parametrize("name", list(OTHER_TRACKS))
def test_hysteretic_other_tracks_within_the_causality_bound(name):
    """Passive, and within 0.9 times the largest support loss factor: the best a causal model
    with K(0) pinned can do for one constant loss factor over three decades is ~0.87 eta
    (measured: soft-pad slab 10.0 %, eta 0.15; 54E1 ballasted 13.6 %, eta 0.3)."""
    track = OTHER_TRACKS[name]()
    bnd = st.fit_boundary(track, band=BAND)
    assert bnd.is_passive()
    assert bnd.max_error <= 0.9 * max(track.eta_pad, track.eta_ballast)


# ------------------------------------------------------------------------------------------------
# The boundary in finite-element truncated tracks
# ------------------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def viscous_fits():
    """Boundaries of the paper's tracks with causal (viscous) damping, the time-domain model's."""
    return {name: st.fit_boundary(make(damping="viscous"), band=BAND)
            for name, make in (("slab", st.slab_track), ("ballasted", st.ballasted_track))}


def test_the_study_fits_as_m_c_k(fitted, viscous_fits):
    """The four study fits (hysteretic and viscous, slab and ballasted, their own orders) turn into
    M, C, K that meet every target of issue 23 (tests/synthesis_checks.py)."""
    for damping, fits in (("hysteretic", fitted), ("viscous", viscous_fits)):
        for name, bnd in fits.items():
            check_second_order(bnd, f"{name} {damping}")


def test_left_boundary_end_is_the_mirror_of_the_right(fitted):
    """A boundary at either end matches the exact end (same mesh) within the boundary's error."""
    track, bnd = st.slab_track(), fitted["slab"]
    f = np.array([50.0, 400.0, 1500.0])
    exact = st.FETrack(track, 4, 4, "exact", "exact", elements_per_bay=8).central_receptance(f)
    for left, right in (("boundary", "exact"), ("exact", "boundary")):
        h = st.FETrack(track, 4, 4, left, right, system=bnd, elements_per_bay=8).central_receptance(f)
        for i in (0, 1):  # w1 and psi2 (the cross terms vanish for the symmetric exact model)
            assert np.max(np.abs(h[:, i, i] / exact[:, i, i] - 1)) < bnd.max_error


# Measured, 10 bays, 48 elements per bay, central w1 against the exact infinite track over
# 3-3000 Hz (median / max): hysteretic slab 0.86 % / 2.3 %, ballasted 1.35 % / 5.2 % (the
# boundary's causality-limited error); viscous slab 0.05 % / 0.76 %, ballasted 0.04 % / 1.9 %
# (the mesh's own error at the sharp second pinned-pinned peak). Pinned ends: 36-97 % median.
TRUNCATED_BOUNDS = {("slab", "hysteretic"): (0.01, 0.05), ("ballasted", "hysteretic"): (0.015, 0.06),
                    ("slab", "viscous"): (0.01, 0.05), ("ballasted", "viscous"): (0.01, 0.05)}


@pytest.mark.parametrize("name, damping", list(TRUNCATED_BOUNDS))
def test_ten_bay_track_with_boundary_ends_matches_the_infinite_track(fitted, viscous_fits, name, damping):
    make = st.slab_track if name == "slab" else st.ballasted_track
    track = make(damping=damping)
    bnd = (fitted if damping == "hysteretic" else viscous_fits)[name]
    f = error_band_grid(BAND, 6.0)
    w1 = st.central_response(track, f).w1
    h = st.TruncatedTrack(track, 10, ends="boundary", system=bnd, elements_per_bay=48).central_receptance(f)
    err = np.abs(h[:, 0, 0] / w1 - 1)
    median, largest = TRUNCATED_BOUNDS[(name, damping)]
    assert np.median(err) <= median and err.max() <= largest
    pinned = st.TruncatedTrack(track, 10, ends="pinned", elements_per_bay=48).central_receptance(f)
    assert np.median(np.abs(pinned[:, 0, 0] / w1 - 1)) > 20 * np.median(err)


def test_time_domain_reproduces_the_frequency_domain_to_round_off(viscous_fits):
    """Newmark with the boundary's states is the trapezoidal (bilinear) map of the continuous
    model: the DFT of an impulse response equals the model's frequency response at the warped
    frequencies (2/dt) tan(omega dt/2), to ~1e-10 once the response has decayed."""
    track = st.slab_track(damping="viscous")
    model = st.TruncatedTrack(track, 3, ends="boundary", system=st.fit_boundary(track, n_poles=24),
                              elements_per_bay=8)
    M, C, K = model.matrices()
    dt, n = 2e-5, 2**15
    b = np.zeros((model.n_dof, 1))
    i0 = model.dof(0.0, "w")
    b[i0, 0] = 1.0
    g = np.zeros(n)
    g[1] = 1.0
    hist = newmark(M, C, K, (b, g[:, None]), dt, n - 1, outputs=[i0], attachments=model.boundary_states())
    assert np.abs(hist.u[-100:, 0]).max() < 1e-10 * np.abs(hist.u[:, 0]).max()  # decayed: no wrap-around
    fk = np.fft.rfftfreq(n, dt)[1:1500:37]
    ratio = (np.fft.rfft(hist.u[:, 0]) / np.fft.rfft(g))[1:1500:37]
    warped = np.tan(np.pi * fk * dt) / (np.pi * dt)
    assert np.max(np.abs(ratio / model.central_receptance(warped)[:, 0, 0] - 1)) < 1e-8


def test_long_run_with_an_enforced_passive_boundary_stays_bounded(fitted):
    """The hysteretic ballasted boundary needed passivity enforcement; with it a viscous rail
    model rings down over 1 s (a non-passive end would feed energy in and grow)."""
    bnd = fitted["ballasted"]
    model = st.TruncatedTrack(st.ballasted_track(), 2, ends="boundary", system=bnd, elements_per_bay=4)
    hist = pulse_response(model, x=(0.0,), f_max=3000.0, dt=5e-5, duration=1.0)
    u = np.abs(hist.u[:, 0])
    assert np.all(np.isfinite(u))
    assert u[-2000:].max() < 1e-6 * u.max()


@pytest.mark.parametrize("name", ["slab", "ballasted"])
def test_time_domain_pulse_against_a_long_reference(viscous_fits, name):
    """A Hann pulse with content to ~5 kHz (f_max 6 kHz), recorded at the centre and three bays
    away over 30 ms; the 100-bay pinned reference is reflection-free in that window (200 bays give
    the same errors). Measured L2 errors: boundary slab 0.14 % / 0.38 %, ballasted 0.33 % / 1.2 %;
    pinned 25 % / 49 % and 16 % / 45 %."""
    track = (st.slab_track if name == "slab" else st.ballasted_track)(damping="viscous")
    out = truncation_errors(track, None, n_bays=10, reference_bays=100, ends=("pinned", "boundary"),
                            boundary=viscous_fits[name], elements_per_bay=8, x=(0.0, 3 * track.spacing),
                            f_max=6000.0, dt=1e-5, duration=0.03)
    assert np.all(out["errors"]["boundary"] < 0.015)
    assert np.all(out["errors"]["pinned"] > 10 * out["errors"]["boundary"])


@pytest.mark.parametrize("bad, match", [
    (dict(D=np.diag([1.0, -1.0])), "positive definite"),
    (dict(D=np.array([[1.0, 0.5], [0.0, 1.0]])), "symmetric"),
    (dict(poles=np.array([-1.0 - 5.0j])), "Im > 0"),
    (dict(poles=np.array([]), coefficients=np.zeros((0, 3))), "at least one pole"),
])
def test_rational_model_refuses_what_it_cannot_represent(bad, match):
    args = dict(poles=np.array([-1.0 + 5.0j]), coefficients=np.zeros((2, 3)), K0=np.eye(2), D=np.eye(2))
    with pytest.raises(ValueError, match=match):
        RationalEndStiffness(**{**args, **bad})


def test_rational_model_does_not_alias_its_inputs():
    coef = np.zeros((2, 3))
    model = RationalEndStiffness(np.array([-1.0 + 5.0j]), coef, np.eye(2), np.eye(2))
    coef[0, 0] = 1.0
    assert model.coefficients[0, 0] == 0.0


def test_viscous_slab_ignores_a_ballast_loss_factor():
    """A slab track has no ballast: its eta_ballast (kept when the ballast is removed) damps nothing."""
    track = st.ballasted_track(damping="viscous").replace(sleeper_mass=None, kb=None)
    assert np.all(track.loss_factor("ballast", [10.0, 100.0]) == 0)
    h = st.TruncatedTrack(track, 2, elements_per_bay=4).central_receptance([100.0])
    assert np.all(np.isfinite(h))


def test_moving_load_with_boundary_ends(viscous_fits):
    """A load crossing the middle of a 10-bay slab model at 360 km/h: with boundary ends the rail
    follows the 100-bay reference to 3e-6 (L2, under the load and at the centre), against
    1.2e-3 / 1.8e-3 with pinned ends (measured)."""
    track = st.slab_track(damping="viscous")
    out = truncation_errors(track, None, n_bays=10, reference_bays=100, excitation="moving",
                            ends=("pinned", "boundary"), boundary=viscous_fits["slab"], elements_per_bay=8,
                            x=(0.0,), speed=100.0, x_start=-2.0, x_end=2.0, dt=2e-5)
    assert np.all(out["errors"]["boundary"] < 1e-5)
    assert np.all(out["errors"]["pinned"] > 100 * out["errors"]["boundary"])


def test_orders_tried_are_the_fits_at_those_orders(viscous_fits):
    """The order study reuses the automatic search's orders instead of refitting them: that is
    right only if each recorded trial is what a fit at that fixed order gives."""
    bnd, track = viscous_fits["slab"], st.slab_track(damping="viscous")
    for n, trial in bnd.orders_tried.items():
        again = st.fit_boundary(track, band=BAND, n_poles=n)
        assert (trial.median, trial.max, trial.passive, trial.enforcement_rounds) == (
            again.median_error, again.max_error, bool(again.is_passive()), again.enforcement_rounds)
    study = order_study(track, tuple(bnd.orders_tried), reuse=[bnd])
    assert study["median error (%)"].tolist() == [100 * t.median for t in bnd.orders_tried.values()]
