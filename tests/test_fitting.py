"""Tests of the least-squares fit of the equivalent systems (paper Sec. 4.4, 5.2; fitting.py).

Fits are judged by error metrics, never by their parameters (those are not unique: e.g. the
dampers at a slab joint are only determined as a sum). Every tolerance is stated with its reason.
The paper's two N = 5 fits come from the session fixture ``paper_fits`` (conftest.py, through
``st.cached_fit``), computed once for the whole test session; the whole file runs in about
30-40 s on 2 cores.
"""

from __future__ import annotations

import dataclasses
import pathlib
import pickle
import warnings

import numpy as np
import pytest

import semitrack as st
from semitrack.base import records
from semitrack.base.paper_values import FIT_BANDS
from semitrack.equivalent import cache
from semitrack.equivalent.constraints import (
    ballasted_constraints,
    ballasted_from_free,
    slab_constraints,
    slab_from_free,
)
from semitrack.equivalent.fitting import (
    POOR_MEDIAN_ERROR,
    FitResult,
    default_fit_frequencies,
    fit_characteristic_frequencies,
    fit_equivalent,
)
from semitrack.equivalent.metrics import ELEMENT_ERROR, ELEMENT_ERROR_DEFINITION, error_band_grid, error_summary
from semitrack.equivalent.parametrisation import FitParametrisation, references
from semitrack.equivalent.residuals import Residuals
from semitrack.equivalent.systems import BallastedEquivalent, SlabEquivalent
from semitrack.methods.features import characteristic_frequencies
from semitrack.paper.systems import (
    TABLE4_FIT_FREQUENCIES,
    TABLE7_FIT_FREQUENCIES,
    paper_table4,
    paper_table7,
)

TRACKS = {"slab": st.slab_track, "ballasted": st.ballasted_track}
PAPER_SYSTEMS = {"slab": paper_table4, "ballasted": paper_table7}

# The fit's batched, complex-safe parameters (constraints evaluated on theta, batches of 2) and
# the system built from them by the validated builders go through the same assembly; they differ
# by rounding in the constraint relations and the batched sums of products spanning ~1e-3..1e9,
# a few 1e-16 of the largest entry.
ASSEMBLY_RTOL = 1e-12
# Central differences with h = 1e-6 in log-parameters: truncation ~h^2 = 1e-12 and rounding
# ~eps/h ~ 1e-10 of the largest entry; 1e-6 leaves margin while any wrong term is O(1).
JACOBIAN_RTOL = 1e-6
# The paper's resonances, refined by the exact method to 1e-3 Hz (features module); the fit must
# use exactly these, so 0.05 Hz only absorbs the refinement tolerance of a new search.
CHAR_ATOL_HZ = 0.05
# Passivity: relative eigenvalues >= -1e-9, the default of EquivalentSystem.is_passive.
PASSIVITY_TOL = 1e-9


@pytest.fixture(scope="module")
def slab_unconstrained(paper_fits):
    """The unconstrained slab fit, started from the constrained one (so it can only improve)."""
    c = paper_fits["slab"]
    return fit_equivalent(st.slab_track(), "slab", 5, band=FIT_BANDS["slab"], seed=0, constrained=False,
                          n_starts=4, initial=c.system)


def paper_errors(layout):
    f = error_band_grid(FIT_BANDS[layout], 3.0)
    return error_summary(PAPER_SYSTEMS[layout]().receptance(f), st.semi_infinite_receptance(TRACKS[layout](), f))


# --- the model behind the residuals ---------------------------------------------------------------
@pytest.mark.parametrize("layout", ["slab", "ballasted"])
@pytest.mark.parametrize("constrained", [True, False])
@pytest.mark.parametrize("n_bars", [1, 2, 5])
def test_parametrisation_gives_the_system_it_builds(layout, constrained, n_bars):
    track = TRACKS[layout]()
    char = fit_characteristic_frequencies(track, layout)
    model = FitParametrisation(layout, n_bars, constrained, references(track, layout, char), char)
    rng = np.random.default_rng(3)
    theta = rng.normal(scale=0.7, size=(2, model.n_theta))
    M, C, K = model.matrices(theta)
    for b in range(2):
        system = model.system(theta[b])
        for mine, ref in zip((M[b], C[b], K[b]), system.matrices()):
            np.testing.assert_allclose(mine, ref, rtol=0, atol=ASSEMBLY_RTOL * np.max(np.abs(ref)))


@pytest.mark.parametrize("layout", ["slab", "ballasted"])
@pytest.mark.parametrize("constrained", [True, False])
def test_residuals_and_analytic_jacobian(layout, constrained):
    track = TRACKS[layout]()
    char = fit_characteristic_frequencies(track, layout)
    model = FitParametrisation(layout, 4, constrained, references(track, layout, char), char)
    f = np.geomspace(*FIT_BANDS["slab"], 25)
    alpha = st.semi_infinite_receptance(track, f)
    problem = Residuals(model, f, alpha)
    theta = np.random.default_rng(5).normal(scale=0.5, size=model.n_theta)
    # residuals are the paper's Re and Im of (alpha_E - alpha)/|alpha| of alpha11, alpha12, alpha22
    a_e = model.system(theta).receptance(f)
    expected = []
    for part in (np.real, np.imag):
        d = np.stack([(a_e[:, i, j] - alpha[:, i, j]) / np.abs(alpha[:, i, j])
                      for i, j in ((0, 0), (0, 1), (1, 1))], axis=1)
        expected.append(part(d).ravel())
    np.testing.assert_allclose(problem.fun(theta), np.concatenate(expected), rtol=0, atol=1e-10)
    J = problem.jac(theta)
    h = 1e-6
    J_fd = np.array([(problem.fun(theta + h * e) - problem.fun(theta - h * e)) / (2 * h)
                     for e in np.eye(model.n_theta)]).T
    assert np.max(np.abs(J - J_fd)) <= JACOBIAN_RTOL * np.max(np.abs(J))


# --- characteristic frequencies --------------------------------------------------------------------
def test_characteristic_frequencies_of_the_paper_tracks():
    # exact det(alpha^-1) extrema: slab dip 183.7 Hz; ballasted dips 114.9, 500.5 Hz, peak 244.8 Hz
    slab = fit_characteristic_frequencies(st.slab_track(), "slab")
    assert slab["f_n"] == pytest.approx(183.741, abs=CHAR_ATOL_HZ)
    ball = fit_characteristic_frequencies(st.ballasted_track(), "ballasted")
    assert ball["f_n1"] == pytest.approx(114.858, abs=CHAR_ATOL_HZ)
    assert ball["f_n2"] == pytest.approx(500.481, abs=CHAR_ATOL_HZ)
    assert ball["f_anti"] == pytest.approx(244.798, abs=CHAR_ATOL_HZ)


def test_characteristic_frequencies_follow_the_track_not_constants():
    # a stiffer pad moves the slab resonance (about sqrt(2) for twice kv); the fit must follow
    track = st.slab_track(kv=2 * st.slab_track().kv)
    table = characteristic_frequencies(track)
    dips = table[(table["quantity"] == "det") & (table["kind"] == "dip")]["f"].to_numpy()
    f_n = fit_characteristic_frequencies(track, "slab")["f_n"]
    assert np.min(np.abs(dips - f_n)) < 1e-9
    assert f_n == pytest.approx(np.sqrt(2) * 183.741, rel=0.1)
    fit = fit_equivalent(track, "slab", 2, band=(3, 600), n_starts=1, max_nfev=20)
    assert fit.characteristic_frequencies == {"f_n": f_n}
    np.testing.assert_allclose(fit.system.k, slab_constraints(fit.system.m, fit.system.L, f_n)["k"], rtol=1e-12)


def test_default_fit_frequencies():
    char = {"f_n1": 114.9, "f_n2": 500.5, "f_anti": 244.8}
    f = default_fit_frequencies(FIT_BANDS["ballasted"], char)
    assert (f[0], f[-1]) == FIT_BANDS["ballasted"]
    assert np.all(np.diff(f) > 0)
    for v in char.values():
        assert np.any(np.isclose(f, v, rtol=1e-12, atol=0))
    assert 80 <= f.size <= 80 + 7 * 3
    # a characteristic frequency outside the band adds nothing outside the band
    g = default_fit_frequencies((3.0, 300.0), char)
    assert g[-1] == 300.0


# --- the paper's two tracks ------------------------------------------------------------------------
@pytest.mark.parametrize("layout", ["slab", "ballasted"])
def test_fit_beats_the_paper_tables_twice_over(paper_fits, layout):
    # the requirement: at least 2x better than Table 4 / Table 7 on both the median and the
    # maximum complex relative error, over the same dense 3 Hz grid of the paper's band.
    # (Measured: slab 0.022/0.090 vs 0.154/0.534; ballasted 0.056/0.142 vs 0.168/0.735.)
    fit = paper_fits[layout]
    paper = paper_errors(layout)
    np.testing.assert_allclose(fit.error_frequencies, error_band_grid(FIT_BANDS[layout], 3.0))
    assert fit.median_error <= paper.median / 2, (fit.median_error, paper.median)
    assert fit.max_error <= paper.max / 2, (fit.max_error, paper.max)
    # the reported errors are those of the returned system
    again = error_summary(fit.system.receptance(fit.error_frequencies),
                          st.semi_infinite_receptance(TRACKS[layout](), fit.error_frequencies))
    assert again.median == pytest.approx(fit.median_error, rel=1e-9)
    assert again.max == pytest.approx(fit.max_error, rel=1e-9)
    assert fit.success and fit.status > 0
    assert fit.n_bars == 5 and fit.layout == layout and fit.constrained


@pytest.mark.parametrize("layout", ["slab", "ballasted"])
def test_constrained_fit_obeys_the_paper_constraints(paper_fits, layout):
    fit = paper_fits[layout]
    s, ch = fit.system, fit.characteristic_frequencies
    if layout == "slab":
        derived = slab_constraints(s.m, s.L, ch["f_n"])
    else:
        derived = ballasted_constraints(s.m, s.L, ch["f_n1"], ch["f_n2"], ch["f_anti"])
    for name, value in derived.items():
        np.testing.assert_allclose(getattr(s, name), value, rtol=1e-12)


def _check_passive(system, band):
    params = system.parameters()
    for name, value in params.items():
        assert np.all(value >= 0), name
    assert np.all(system.L > 0)
    for X in system.matrices():
        np.testing.assert_array_equal(X, X.T)
        ev = np.linalg.eigvalsh(X)
        assert ev[0] >= -PASSIVITY_TOL * np.max(np.abs(ev))
    f = np.linspace(0.5, 2 * band[1], 800)  # beyond the band too: passivity is global
    report = system.is_passive(f, tol=PASSIVITY_TOL)
    assert report, (report.worst_frequency, float(np.min(report.min_eig_mobility)))


@pytest.mark.parametrize("layout", ["slab", "ballasted"])
def test_fitted_systems_are_passive(paper_fits, layout):
    _check_passive(paper_fits[layout].system, FIT_BANDS[layout])


def test_unconstrained_fit_shows_what_the_constraints_cost(paper_fits, slab_unconstrained):
    c, u = paper_fits["slab"], slab_unconstrained
    assert not u.constrained
    assert set(u.free_parameters) >= {"k", "J"}
    # started from the constrained optimum, the free fit can only lower the cost (the solver
    # accepts decreasing steps only); the 1e-12 relative slack absorbs rounding
    assert u.cost <= c.cost * (1 + 1e-12)
    # and it is no longer tied to Eq. (19)-(20)
    derived = slab_constraints(u.system.m, u.system.L, c.characteristic_frequencies["f_n"])
    assert not np.allclose(u.system.k, derived["k"], rtol=1e-6)
    _check_passive(u.system, FIT_BANDS["slab"])
    paper = paper_errors("slab")
    assert u.median_error <= paper.median / 2


def test_fit_with_the_paper_frequency_sets():
    slab = fit_equivalent(st.slab_track(), "slab", 5, fit_freqs="paper", n_starts=4)
    np.testing.assert_array_equal(slab.fit_freqs, TABLE4_FIT_FREQUENCIES)
    # 9 frequencies only; still better than Table 4 itself on the median (measured 0.035 vs 0.154)
    assert slab.median_error < paper_errors("slab").median
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # 5 evaluations: not converged, by design
        ball = fit_equivalent(st.ballasted_track(), "ballasted", 2, fit_freqs="paper", n_starts=1, max_nfev=5)
    np.testing.assert_array_equal(ball.fit_freqs, TABLE7_FIT_FREQUENCIES)


# --- synthetic round trips -------------------------------------------------------------------------
# The target is made by a known system of the same layout, N and constraint frequencies, so the
# optimum has zero residual. The requirement is a median error < 1e-3; near a zero-residual
# solution Gauss-Newton converges quadratically and we measured ~1e-14, so we ask for 1e-6
# (median) and 1e-5 (max): tight enough to catch any modelling mismatch, loose to rounding.
ROUND_TRIP_MEDIAN = 1e-6
ROUND_TRIP_MAX = 1e-5


def test_round_trip_slab_three_bars():
    true = slab_from_free(m=[8.0, 30.0, 120.0], L=[0.15, 0.3, 0.4], c_l=[200.0, 1500.0, 3000.0],
                          c_r=[500.0, 2000.0, 8000.0], k_phi=[1.5e7, 5e6], c_phi=[300.0, 1000.0], f_n=175.0)
    fit = fit_equivalent(st.slab_track(), "slab", 3, band=FIT_BANDS["slab"], target=true.receptance,
                         characteristic={"f_n": 175.0}, n_starts=4, seed=1)
    assert fit.median_error < ROUND_TRIP_MEDIAN
    assert fit.max_error < ROUND_TRIP_MAX
    assert fit.success
    # identifiable combinations are recovered (masses, lengths, hinge springs; joint damper sums)
    np.testing.assert_allclose(fit.system.m, true.m, rtol=1e-6)
    np.testing.assert_allclose(fit.system.L, true.L, rtol=1e-6)
    np.testing.assert_allclose(fit.system.k_phi, true.k_phi, rtol=1e-6)
    joint = lambda s: s.c_r[:-1] + s.c_l[1:]  # noqa: E731 - hinged ends move together
    np.testing.assert_allclose(joint(fit.system), joint(true), rtol=1e-6)


def test_round_trip_ballasted_two_bars_sampled_target():
    true = ballasted_from_free(m=[10.0, 60.0], L=[0.2, 0.5], c_l=[100.0, 2000.0], c_r=[3000.0, 500.0],
                               k_phi=[1e7], c_phi=[800.0], d_l=[5000.0, 15000.0], d_r=[8000.0, 3000.0],
                               f_n1=110.0, f_n2=480.0, f_anti=250.0)
    f = np.linspace(*FIT_BANDS["ballasted"], 250)
    char = {"f_n1": 110.0, "f_n2": 480.0, "f_anti": 250.0}
    fit = fit_equivalent(st.ballasted_track(), "ballasted", 2, band=FIT_BANDS["ballasted"],
                         target=(f, true.receptance(f)), characteristic=char, n_starts=4)
    assert fit.median_error < ROUND_TRIP_MEDIAN
    assert fit.max_error < ROUND_TRIP_MAX
    np.testing.assert_array_equal(fit.error_frequencies, f)  # sampled target: errors on its samples
    np.testing.assert_array_equal(fit.fit_freqs, f)
    with pytest.raises(ValueError, match="fit_freqs"):
        fit_equivalent(st.ballasted_track(), "ballasted", 2, target=(f, true.receptance(f)),
                       characteristic=char, fit_freqs=[100.5])


def test_characteristic_frequencies_from_a_callable_target():
    # detection works on any receptance: here a 2-bar slab system (its own det dip, not 175 Hz)
    true = slab_from_free(m=[20.0, 80.0], L=[0.3, 0.4], c_l=[500.0, 500.0], c_r=[500.0, 500.0],
                          k_phi=[5e6], c_phi=[500.0], f_n=175.0)
    f = np.arange(3.0, 3000.0, 3.0)
    det = np.abs(1.0 / np.linalg.det(true.receptance(f)))
    f_n = fit_characteristic_frequencies(st.slab_track(), "slab", target=true.receptance)["f_n"]
    i = int(np.argmin(np.abs(f - f_n)))
    assert det[i] <= det[i - 1] and det[i] <= det[i + 1]  # a dip of |det(alpha^-1)|


# --- machinery --------------------------------------------------------------------------------------
def test_deterministic_for_a_fixed_seed():
    kw = dict(layout="slab", n_bars=3, band=(3, 600), n_starts=3, max_nfev=50)
    a = fit_equivalent(st.slab_track(), seed=7, **kw)
    b = fit_equivalent(st.slab_track(), seed=7, **kw)
    c = fit_equivalent(st.slab_track(), seed=8, **kw)
    np.testing.assert_array_equal(a.theta, b.theta)
    np.testing.assert_array_equal(a.start_costs, b.start_costs)
    assert a.system == b.system
    assert a.start_costs[0] == c.start_costs[0]  # start 0 is the deterministic guess
    assert not np.array_equal(a.start_costs[1:], c.start_costs[1:])


def test_larger_n_runs_and_stays_passive():
    # the machinery is meant for N >= 10: one short run on a wider band
    fit = fit_equivalent(st.slab_track(), "slab", 10, band=(3, 1500), n_starts=2, max_nfev=60)
    assert fit.n_bars == 10 and fit.system.n_bars == 10
    assert fit.theta.size == 6 * 10 - 2
    _check_passive(fit.system, (3, 1500))


def test_warns_when_the_fit_did_not_converge():
    with pytest.warns(RuntimeWarning, match=r"status 0.*n_starts 1"):
        fit = fit_equivalent(st.slab_track(), "slab", 3, n_starts=1, max_nfev=2)
    assert not fit.success and fit.status == 0


def test_warns_when_the_fit_is_poor():
    # one bar cannot follow the slab receptance up to 900 Hz (median error ~0.8)
    with pytest.warns(RuntimeWarning, match="poor"):
        fit = fit_equivalent(st.slab_track(), "slab", 1, n_starts=2)
    assert fit.median_error > POOR_MEDIAN_ERROR


def test_no_warning_for_a_good_fit():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        fit_equivalent(st.slab_track(), "slab", 3, band=(3, 300), n_starts=2)


def test_fit_result_is_frozen_and_complete(paper_fits):
    fit = paper_fits["slab"]
    assert isinstance(fit, FitResult)
    with pytest.raises(dataclasses.FrozenInstanceError):
        fit.median_error = 0.0
    for name in ("fit_freqs", "error_frequencies", "theta", "start_costs", "at_bound"):
        assert not getattr(fit, name).flags.writeable, name
    assert isinstance(fit.system, SlabEquivalent)
    assert isinstance(paper_fits["ballasted"].system, BallastedEquivalent)
    assert fit.n_starts == 20 and fit.start_costs.size == 20
    assert fit.cost <= np.min(fit.start_costs)  # continuing the screened starts only lowers the cost
    assert 0 <= fit.best_start < fit.n_starts
    d = fit.diagnostics()
    assert {"status", "message", "cost", "nfev", "optimality", "n_starts"} <= set(d)
    assert np.all(np.isin(fit.characteristic_frequencies["f_n"], fit.fit_freqs))


@pytest.mark.parametrize("layout", ["slab", "ballasted"])
def test_fit_result_prints_as_a_readable_summary(paper_fits, layout):
    fit = paper_fits[layout]
    text = str(fit)
    assert text == repr(fit)
    lines = text.splitlines()
    assert lines[0] == f"FitResult: {layout} layout, N = 5 bars"
    band = f"{fit.band[0]:g}-{fit.band[1]:g} Hz"
    assert any(band in line for line in lines)
    # The errors are quoted in per cent with their metric named and defined.
    errors = next(line for line in lines if line.strip().startswith(ELEMENT_ERROR))
    assert f"median {100 * fit.median_error:.2f} %, max {100 * fit.max_error:.2f} %" in errors
    assert ELEMENT_ERROR_DEFINITION in text
    assert f"{fit.cost:.4g}" in text
    for name, value in fit.characteristic_frequencies.items():
        assert f"{name} = {value:.2f} Hz" in text
    assert text.endswith(repr(fit.system))  # the parameters, one per line with units
    assert "highest natural frequency" in lines[-1]
    assert max(len(line) for line in lines) <= 100 and "array(" not in text


def test_fit_leaves_blas_threading_as_it_found_it():
    """The fit limits BLAS to one thread only for its own duration (two threads before it here,
    whatever the test process runs with, so that a fit that kept its one thread is caught)."""
    from threadpoolctl import threadpool_info, threadpool_limits

    with threadpool_limits(limits=2, user_api="blas"):
        before = [lib["num_threads"] for lib in threadpool_info() if lib["user_api"] == "blas"]
        fit_equivalent(st.slab_track(), layout="slab", n_bars=1, band=(3.0, 200.0), n_starts=1, max_nfev=5)
        after = [lib["num_threads"] for lib in threadpool_info() if lib["user_api"] == "blas"]
    assert before == after and set(before) == {2}


@pytest.mark.parametrize(
    "kwargs, exc, match",
    [
        (dict(layout="rail"), ValueError, "layout"),
        (dict(layout=3), TypeError, "layout"),
        (dict(n_bars=0), ValueError, "n_bars"),
        (dict(n_bars=2.5), TypeError, "n_bars"),
        (dict(band=(900, 3)), ValueError, "band"),
        (dict(band=(-1, 900)), ValueError, "band"),
        (dict(band=5), TypeError, "band"),
        (dict(fit_freqs="dense"), ValueError, "fit_freqs"),
        (dict(fit_freqs=[10.0, -5.0]), ValueError, "fit_freqs"),
        (dict(seed=-1), ValueError, "seed"),
        (dict(seed=1.5), TypeError, "seed"),
        (dict(n_starts=0), ValueError, "n_starts"),
        (dict(constrained="yes"), TypeError, "constrained"),
        (dict(target=np.ones((5, 2, 2))), TypeError, "target"),
        (dict(target=lambda f: np.ones((3, 2, 2))), ValueError, "target"),
        (dict(characteristic={"f_n1": 100.0}), ValueError, "characteristic"),
        (dict(characteristic={"f_n": -3.0}), ValueError, "characteristic"),
        (dict(characteristic=[183.0]), TypeError, "characteristic"),
        (dict(max_nfev=0), ValueError, "max_nfev"),
        (dict(error_df=0), ValueError, "error_df"),
        (dict(initial=paper_table7()), ValueError, "initial"),
        (dict(initial="table4"), TypeError, "initial"),
    ],
)
def test_bad_arguments_are_named(kwargs, exc, match):
    args = dict(layout="slab", n_bars=2, n_starts=1, max_nfev=1)
    args.update(kwargs)
    with pytest.raises(exc, match=match):
        fit_equivalent(st.slab_track(), **args)


def test_bad_track_and_ballasted_characteristic_order():
    with pytest.raises(TypeError, match="track"):
        fit_equivalent("slab", "slab", 2)
    with pytest.raises(ValueError, match="f_n1 < f_anti < f_n2"):
        fit_equivalent(st.ballasted_track(), "ballasted", 2, n_starts=1, max_nfev=1,
                       characteristic={"f_n1": 100.0, "f_n2": 200.0, "f_anti": 300.0})


def test_layout_defaults_from_the_track():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        fit = fit_equivalent(st.ballasted_track(), n_bars=1, n_starts=1, max_nfev=1)
    assert fit.layout == "ballasted" and fit.band == FIT_BANDS["ballasted"]


# --- fits computed once (cache.py) --------------------------------------------------------------------
# A small fit keeps these tests fast; what is tested is the bookkeeping, not the fit.
SMALL = dict(n_bars=2, band=(3.0, 300.0), n_starts=1, max_nfev=20)


@pytest.fixture
def counted_fits(monkeypatch):
    """Count the fits that cached_fit computes, with an empty in-process memo."""
    calls = []

    def counting(**kwargs):
        calls.append(kwargs)
        return fit_equivalent(**kwargs)

    monkeypatch.setattr(cache, "fit_equivalent", counting)
    cache.clear_fit_memo()
    yield calls
    cache.clear_fit_memo()


def _same_fit(a, b):
    np.testing.assert_array_equal(a.theta, b.theta)
    np.testing.assert_array_equal(a.start_costs, b.start_costs)
    assert a.system == b.system and a.cost == b.cost and a.median_error == b.median_error


def test_cached_fit_is_fit_equivalent_computed_once(counted_fits):
    track = st.slab_track()
    first = st.cached_fit(track, "slab", **SMALL)
    _same_fit(first, fit_equivalent(track, "slab", **SMALL))
    assert len(counted_fits) == 1
    # the same arguments, spelt otherwise (int band, defaults given), hit the memo
    again = st.cached_fit(st.slab_track(), "slab", n_bars=2, band=(3, 300), seed=0, n_starts=1, max_nfev=20,
                          constrained=True, error_df=3.0)
    assert again is first and len(counted_fits) == 1


def test_cached_fit_folder_is_read_back_and_survives_corruption(counted_fits, tmp_path):
    track = st.ballasted_track()
    folder = tmp_path / "cache"  # created by cached_fit
    first = st.cached_fit(track, "ballasted", cache_dir=folder, **SMALL)
    files = list(folder.glob("fit-*.json"))
    assert [f.name for f in files] == [f"fit-{cache.fit_cache_key(track, 'ballasted', **SMALL)}.json"]
    assert not list(folder.glob("*.tmp"))  # the atomic write left no temporary file
    cache.clear_fit_memo()  # a new process: only the folder remembers
    back = st.cached_fit(track, "ballasted", cache_dir=folder, **SMALL)
    assert len(counted_fits) == 1
    _same_fit(back, first)
    assert not back.theta.flags.writeable and not back.system.m.flags.writeable  # read-only when read back
    junks = (b"", b"not json", pickle.dumps({"a": 1}), b'{"d": {"a": 1}}', b'{"r": "Track", "v": {}}')
    for junk in junks:  # empty, corrupt, an old pickle, not a FitResult, a type the cache never builds
        files[0].write_bytes(junk)
        cache.clear_fit_memo()
        _same_fit(st.cached_fit(track, "ballasted", cache_dir=folder, **SMALL), first)
        _same_fit(records.loads(files[0].read_text(), cache._record_types()), first)  # rewritten
    assert len(counted_fits) == 1 + len(junks)


def test_cache_keys_tell_arguments_apart():
    track = st.slab_track()
    key = cache.fit_cache_key(track, "slab", **SMALL)
    assert len(key) == 64
    assert key == cache.fit_cache_key(track, "slab", n_bars=2, band=(3, 300), n_starts=1, max_nfev=20, seed=0,
                                      fit_freqs=None, target=None)
    others = [
        cache.fit_cache_key(track, "slab", **(SMALL | {"n_bars": 3})),
        cache.fit_cache_key(track, "slab", **(SMALL | {"band": (3.0, 301.0)})),
        cache.fit_cache_key(track, "slab", **SMALL, seed=1),
        cache.fit_cache_key(track, "slab", **SMALL, constrained=False),
        cache.fit_cache_key(track, "slab", **SMALL, fit_freqs=[10.0, 100.0]),
        cache.fit_cache_key(track, "slab", **SMALL, fit_freqs="paper"),
        cache.fit_cache_key(track, "slab", **SMALL, characteristic={"f_n": 180.0}),
        cache.fit_cache_key(track, "slab", **SMALL, initial=slab_from_free([1.0, 2.0], [0.3, 0.3], [1, 1], [1, 1],
                                                                            [1e6], [1.0], f_n=180.0)),
        cache.fit_cache_key(track.replace(kv=1.01 * track.kv), "slab", **SMALL),
        cache.fit_cache_key(track, "ballasted", **SMALL),
    ]
    assert len(set(others + [key])) == len(others) + 1
    # the track's name is a label, not a parameter
    assert cache.fit_cache_key(track.replace(name="mine"), "slab", **SMALL) == key
    # the paper's band is the default band
    assert cache.fit_cache_key(track, "slab") == cache.fit_cache_key(track, "slab", band=FIT_BANDS["slab"])
    with pytest.raises(TypeError, match="callable target"):
        cache.fit_cache_key(track, "slab", target=lambda f: np.ones((f.size, 2, 2)))
    with pytest.raises(TypeError, match="n_start"):
        cache.fit_cache_key(track, "slab", n_start=3)
    with pytest.raises(ValueError, match="layout"):
        cache.fit_cache_key(track, "floating")


def test_cache_key_follows_the_package_source(monkeypatch, tmp_path):
    # the digest covers every *.py file below the folder, by path and content, and nothing else
    digest = cache.package_source_digest
    assert cache._PACKAGE_DIR == pathlib.Path(st.__file__).resolve().parent  # the installed package's own files
    (tmp_path / "sub").mkdir()
    (tmp_path / "a.py").write_text("x = 1\n")
    only_a = digest(tmp_path)
    (tmp_path / "sub" / "b.py").write_text("")
    with_b = digest(tmp_path)
    (tmp_path / "a.py").write_text("x = 2\n")
    changed_a = digest(tmp_path)
    assert len({only_a, with_b, changed_a}) == 3
    (tmp_path / "notes.txt").write_text("not code")
    assert digest(tmp_path) == changed_a
    # and the key follows the digest
    key = cache.fit_cache_key(st.slab_track(), "slab")
    monkeypatch.setattr(cache, "package_source_digest", lambda root=None: "0" * 64)
    assert cache.fit_cache_key(st.slab_track(), "slab") != key


# --- sweeps computed once (cache.py): the book's paper-method sweeps ------------------------------------
SWEEP_F = np.array([3.0, 183.0, 945.0])


def test_cached_central_response_is_central_response_computed_once(monkeypatch, tmp_path):
    calls = []
    real = cache.central_response

    def counting(*args, **kwargs):
        calls.append(args)
        return real(*args, **kwargs)

    monkeypatch.setattr(cache, "central_response", counting)
    cache.clear_fit_memo()
    folder = tmp_path / "cache"
    track = st.slab_track()
    sweep = cache.cached_central_response(track, SWEEP_F, cache_dir=folder)
    direct = st.central_response(track, SWEEP_F, method="wavenumber")
    for name in ("f", "w1", "psi2", "Q2", "M1"):  # the same numbers, bit for bit
        np.testing.assert_array_equal(getattr(sweep.response, name), getattr(direct, name))
    assert sweep.response.method == "wavenumber" and sweep.elapsed > 0
    assert cache.cached_central_response(track, list(SWEEP_F), "wavenumber", cache_dir=folder) is sweep
    files = list(folder.glob("response-*.json"))
    assert [f.name for f in files] == [f"response-{cache.response_cache_key(track, SWEEP_F)}.json"]
    cache.clear_fit_memo()  # a new process: only the folder remembers, elapsed included
    back = cache.cached_central_response(track, SWEEP_F, cache_dir=folder)
    np.testing.assert_array_equal(back.response.alpha, sweep.response.alpha)
    assert back.elapsed == sweep.elapsed and len(calls) == 1
    files[0].write_bytes(b"not a pickle")  # unreadable: computed again
    cache.clear_fit_memo()
    np.testing.assert_array_equal(cache.cached_central_response(track, SWEEP_F, cache_dir=folder).response.w1,
                                  direct.w1)
    assert len(calls) == 2
    cache.clear_fit_memo()


def test_response_cache_keys_tell_arguments_apart():
    track = st.slab_track()
    key = cache.response_cache_key(track, SWEEP_F)
    assert key == cache.response_cache_key(track.replace(name="mine"), list(SWEEP_F), "wavenumber")
    others = [cache.response_cache_key(track, SWEEP_F[:2]),
              cache.response_cache_key(track, SWEEP_F, "transfer"),
              cache.response_cache_key(track, SWEEP_F, beta_max=785.4),
              cache.response_cache_key(track.replace(kv=1.01 * track.kv), SWEEP_F),
              cache.fit_cache_key(track, "slab")]
    assert len(set(others + [key])) == len(others) + 1


# --- hopeless runs stop early (multistart.py) -----------------------------------------------------------
def test_a_run_stops_only_when_it_cannot_reach_its_target():
    """At twice its recent rate of descent a run must still end above its target to be stopped."""
    from scipy.optimize import OptimizeResult

    from semitrack.equivalent.multistart import _PRUNE_WINDOW, _Hopeless

    def feed(callback, costs):
        for n, cost in enumerate(costs, start=1):
            callback(OptimizeResult(nfev=n, cost=cost))

    flat = [1.0 - 1e-4 * k for k in range(_PRUNE_WINDOW + 1)]  # at 2 x its rate: 0.981 at 100 evaluations
    with pytest.raises(StopIteration):
        feed(_Hopeless(target=0.9, budget=100), flat)
    feed(_Hopeless(target=0.9, budget=100), flat[:_PRUNE_WINDOW])  # too few iterations to judge
    feed(_Hopeless(target=0.985, budget=100), flat)  # reachable at 2 x its rate: goes on
    feed(_Hopeless(target=0.9, budget=100), [1.0 - 0.01 * k for k in range(_PRUNE_WINDOW + 1)])  # steep


def test_stopping_hopeless_runs_changes_no_fit(monkeypatch):
    """The same fit, bit for bit, with every run taken to its full budget (a small ballasted fit
    whose screening stops 8 of 20 runs early, measured)."""
    from semitrack.equivalent import multistart

    kw = dict(layout="ballasted", n_bars=2, band=(3.0, 400.0), seed=3, n_starts=20, max_nfev=200)
    pruned = fit_equivalent(st.ballasted_track(), **kw)
    monkeypatch.setattr(multistart._Hopeless, "__call__", lambda self, intermediate_result: None)  # never stop
    full = fit_equivalent(st.ballasted_track(), **kw)
    np.testing.assert_array_equal(pruned.theta, full.theta)
    assert pruned.cost == full.cost and pruned.best_start == full.best_start and pruned.nfev == full.nfev
    stopped = pruned.start_costs != full.start_costs
    assert stopped.any() and np.all(pruned.start_costs[stopped] > full.start_costs[stopped])
