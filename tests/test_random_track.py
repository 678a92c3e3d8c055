"""Random tracks: the drawn fields have the asked statistics, every draw its own stream, and the models take them.

Independent checks: the sample mean, coefficient of variation and correlation length of many
draws against the asked ones within a few standard errors (computed from the draws' own
sampling variance, so the bounds are neither loose nor luck); the voids' and failed fasteners'
counts exact, their positions uniform over the stretch; a realisation reproduced from its seed
alone, and unchanged when another field is added; the changes read by the three models and the
hanging sleepers by the gap rule of the FE runs.
"""

import math

import numpy as np
import pytest

import semitrack as st
from semitrack.model.random_track import MAX_GAP, RANDOM_FIELDS, autoregression
from semitrack.paper.window_study import random_supports

BALLAST = st.ballasted_track(damping="viscous")
SLAB = st.slab_track(damping="viscous")


def test_every_field_the_fe_models_take_may_scatter():
    from semitrack.fe.supports import FE_SUPPORT_FIELDS
    assert RANDOM_FIELDS == FE_SUPPORT_FIELDS


@pytest.mark.parametrize("name, cov", [("kv", 0.2), ("kb", 0.5), ("kphi", 0.1), ("sleeper_mass", 0.05)])
def test_independent_fields_have_the_asked_mean_and_coefficient_of_variation(name, cov):
    n = 200_000
    rt = st.random_track(BALLAST, 0, n - 1, cov={name: cov}, seed=11)
    x = rt.values[name] / getattr(BALLAST, name)
    # standard errors of the sample mean and standard deviation of a log-normal of mean 1
    se_mean = cov / math.sqrt(n)
    kurt = math.exp(4 * math.log1p(cov**2)) + 2 * math.exp(3 * math.log1p(cov**2)) + 3 * math.exp(
        2 * math.log1p(cov**2)) - 6  # excess kurtosis of a log-normal
    se_std = cov * math.sqrt((kurt + 2) / (4 * n))
    assert abs(x.mean() - 1) < 4 * se_mean
    assert abs(x.std() - cov) < 4 * se_std
    assert (x > 0).all()
    np.testing.assert_allclose(np.corrcoef(x[:-1], x[1:])[0, 1], 0.0, atol=4 / math.sqrt(n))


@pytest.mark.parametrize("n, a", [(1, 0.5), (255, 0.9), (256, 0.9), (1000, 0.999999), (5000, 0.3), (700, 0.0)])
def test_the_blocked_autoregression_is_the_recursion(n, a):
    drive = np.random.default_rng(n).standard_normal(n)
    z, prev = np.empty(n), 0.0
    for k in range(n):  # the recursion, term by term
        prev = a * prev + drive[k]
        z[k] = prev
    np.testing.assert_allclose(autoregression(drive, a), z, rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("length", [0.6, 3.0, 30.0])
def test_a_correlation_length_is_that_of_the_log_of_the_field(length):
    d, n = BALLAST.spacing, 200_000
    rt = st.random_track(BALLAST, -n // 2, n // 2 - 1, cov={"kv": 0.3}, correlation_length=length, seed=3)
    z = np.log(rt.values["kv"] / BALLAST.kv)
    z = (z - z.mean()) / z.std()
    a = math.exp(-d / length)
    for lag in (1, 2, 5):
        rho = float(np.mean(z[:-lag] * z[lag:]))
        # the variance of an AR(1) sample autocorrelation (Bartlett): (1 + a^2)(1 - a^2k)/(1 - a^2) - 2k a^2k
        var = ((1 + a**2) * (1 - a ** (2 * lag)) / (1 - a**2) - 2 * lag * a ** (2 * lag)) / n
        assert abs(rho - a**lag) < 5 * math.sqrt(var) + 1e-12, (lag, rho, a**lag)
    fitted = -d / math.log(float(np.mean(z[:-1] * z[1:])))
    assert fitted == pytest.approx(length, rel=0.05)
    # the field itself keeps the mean and the coefficient of variation asked: a stationary sequence from the start
    first = np.array([st.random_track(BALLAST, 0, 4, cov={"kv": 0.3}, correlation_length=length, seed=s)
                      .values["kv"] for s in range(4000)]) / BALLAST.kv
    np.testing.assert_allclose(first.mean(axis=0), 1.0, atol=4 * 0.3 / math.sqrt(4000))
    np.testing.assert_allclose(first.std(axis=0), 0.3, rtol=0.1)


def test_voids_and_failed_fasteners_are_exact_counts_drawn_uniformly_and_never_together():
    counts = np.zeros(100)
    for s in range(400):
        rt = st.random_track(BALLAST, -50, 49, voids=dict(fraction=0.1, gap=(0.5e-3, 2e-3)), failed=0.05, seed=s)
        assert rt.voided.size == 10 and rt.failed.size == 5 and rt.gaps.size == 10
        assert not np.intersect1d(rt.voided, rt.failed).size
        assert ((rt.gaps >= 0.5e-3) & (rt.gaps <= 2e-3)).all()
        counts[rt.voided + 50] += 1
        changes, gaps = rt.changes, rt.ballast_gaps
        assert all(changes[k] == {"kb": 0.0} for k in rt.voided.tolist())
        assert all(changes[k] is None for k in rt.failed.tolist())
        assert sorted(gaps) == rt.voided.tolist() and len(changes) == 15
    # each support voided 400 x 0.1 = 40 times on average: a chi-square over the 100 supports
    chi2 = float(((counts - 40) ** 2 / 40).sum())
    assert chi2 < 160, chi2  # 99 degrees of freedom: the 99.99th percentile is about 150


def test_a_realisation_depends_on_its_seed_alone_and_each_draw_has_its_own_stream():
    a = st.random_track(BALLAST, -20, 20, cov={"kv": 0.2}, seed=(5, 3))
    b = st.random_track(BALLAST, -20, 20, cov={"kv": 0.2}, seed=(5, 3))
    np.testing.assert_array_equal(a.values["kv"], b.values["kv"])
    more = st.random_track(BALLAST, -20, 20, cov={"kv": 0.2, "kb": 0.3}, voids=dict(fraction=0.1), failed=0.1,
                           seed=(5, 3))
    np.testing.assert_array_equal(more.values["kv"], a.values["kv"])  # adding fields and voids leaves kv as drawn
    other = st.random_track(BALLAST, -20, 20, cov={"kv": 0.2}, seed=(5, 4))
    assert not np.array_equal(other.values["kv"], a.values["kv"])
    assert a.seed == (5, 3) and st.random_track(BALLAST, 0, 3, seed=7).seed == 7
    # every seed its own draw: an int and the tuple of it, trailing zeros, entries beyond 32 bits
    seeds = [5, (5,), (5, 0), (5, 0, 0), (0, 5), (2**32 + 5, 0), (5, 1, 0), (5, 1), 2**32 + 5, 2**63]
    draws = [st.random_track(BALLAST, 0, 3, cov={"kv": 0.2}, seed=s).values["kv"].tobytes() for s in seeds]
    assert len(set(draws)) == len(seeds)


def test_zero_scatter_draws_nothing_and_a_cov_of_zero_leaves_the_field_nominal():
    rt = st.random_track(BALLAST, 0, 9, cov={"kv": 0.0})
    assert rt.values == {} and rt.changes == {} and rt.ballast_gaps == {}


def test_the_models_read_the_changes_and_the_gaps_as_their_own():
    rt = st.random_track(BALLAST, -6, 6, cov={"kv": 0.3, "kb": 0.3}, voids=dict(fraction=0.2, gap=1e-3),
                         failed=0.1, seed=1)
    inf = st.InfiniteTrack(BALLAST, changes=rt.changes)
    fe = st.TruncatedTrack(BALLAST, 16, "exact", elements_per_bay=8, changes=rt.changes)
    f = np.array([50.0, 400.0])
    exact = inf.receptance(f, 0.3, [0.3])[:, 0, 0, 0]
    np.testing.assert_allclose(fe.receptance(f, 0.3)[:, 0, 0], exact, rtol=0.02)
    win = st.WindowTrack(BALLAST, rt.changes, behind=4, ahead=6, elements_per_bay=6,
                         system=st.load_boundary("tests/data/boundary_ballasted_viscous_24.json"))
    assert win.changes == rt.changes
    run = st.wheel_rail_response(win, st.Wheel(), speed=20.0, dt=1e-4, duration=0.03, x=0.0,
                                 ballast_gaps=rt.ballast_gaps)
    assert run.gaps is not None and sorted(run.gaps.supports.tolist()) == rt.voided.tolist()


def test_the_table_has_one_row_per_support():
    rt = st.random_track(BALLAST, -3, 3, cov={"kv": 0.2}, voids=dict(fraction=0.3), failed=0.15, seed=2)
    t = rt.table()
    assert t.support.tolist() == list(range(-3, 4))
    np.testing.assert_allclose(t.x, (np.arange(-3, 4) + 0.5) * BALLAST.spacing)
    assert (t.void_gap > 0).sum() == 2 and t.failed.sum() == 1
    np.testing.assert_array_equal(t.kv, rt.values["kv"])
    assert "voided" in repr(rt)


def test_the_window_studys_random_supports_are_numpys_log_normal_to_rounding():
    """random_supports (the window chapter's draw order) through the shared factors: numpy's own
    log-normal of the same stream to within an ulp or two (exp of a scaled normal, against numpy's)."""
    changes = random_supports(BALLAST, range(0, 50_000), cov_pad=0.2, cov_ballast=0.3, seed=1)
    kv = np.array([c["kv"] for c in changes.values()]) / BALLAST.kv
    kb = np.array([c["kb"] for c in changes.values()]) / BALLAST.kb
    rng = np.random.default_rng(1)
    for drawn, cov in ((kv, 0.2), (kb, 0.3)):
        s2 = math.log1p(cov**2)
        np.testing.assert_allclose(drawn, rng.lognormal(-0.5 * s2, math.sqrt(s2), 50_000), rtol=1e-15)
        assert abs(drawn.mean() - 1) < 4 * cov / math.sqrt(drawn.size)


@pytest.mark.parametrize("kwargs, names", [
    (dict(track="ballasted"), "track"),
    (dict(first=1.5), "first"), (dict(first="0"), "first"), (dict(last=-20), "last"),
    (dict(last=2_000_000), "last"), (dict(first=-10**10), "first"),
    (dict(cov=[0.2]), "cov"), (dict(cov={"E": 0.1}), "cov"), (dict(cov={"kv": -0.1}), "cov"),
    (dict(cov={"kv": float("nan")}), "cov"), (dict(cov={"kv": "0.2"}), "cov"), (dict(cov={"kv": 11.0}), "cov"),
    (dict(correlation_length=0.0), "correlation_length"), (dict(correlation_length=float("inf")), "correlation_length"),
    (dict(correlation_length="3"), "correlation_length"),
    (dict(voids=0.1), "voids"), (dict(voids={"fraction": 1.5}), "voids"), (dict(voids={"share": 0.1}), "voids"),
    (dict(voids={"fraction": 0.1, "gap": 0.5}), "voids"), (dict(voids={"fraction": 0.1, "gap": (2e-3, 1e-3)}), "voids"),
    (dict(voids={"fraction": 0.1, "gap": (1e-3,)}), "voids"), (dict(voids={"fraction": 0.1, "gap": -1e-3}), "voids"),
    (dict(failed=-0.1), "failed"), (dict(failed=True), "failed"), (dict(failed="0.1"), "failed"),
    (dict(voids={"fraction": 0.7}, failed=0.7), "failed"),
    (dict(seed=-1), "seed"), (dict(seed=1.5), "seed"), (dict(seed=()), "seed"), (dict(seed=(1, -2)), "seed[1]"),
    (dict(seed=2**200), "seed"), (dict(seed="1"), "seed"),
])
def test_bad_arguments_are_refused_naming_them(kwargs, names):
    args = dict(track=BALLAST, first=-10, last=10) | kwargs
    track, first, last = args.pop("track"), args.pop("first"), args.pop("last")
    with pytest.raises(st.BadInput, match=names.replace("[", r"\[")):
        st.random_track(track, first, last, **args)


def test_what_a_slab_track_does_not_have_is_refused():
    with pytest.raises(st.BadInput, match="cov"):
        st.random_track(SLAB, 0, 9, cov={"kb": 0.2})
    with pytest.raises(st.BadInput, match="voids"):
        st.random_track(SLAB, 0, 9, voids=dict(fraction=0.1))
    assert st.random_track(SLAB, 0, 9, cov={"kv": 0.2}, failed=0.2).failed.size == 2


def test_a_random_track_built_by_hand_is_checked_field_by_field():
    good = st.random_track(BALLAST, 0, 4, cov={"kv": 0.2}, voids=dict(fraction=0.2), seed=0)
    rebuilt = st.RandomTrack(BALLAST, 0, 4, dict(good.values), good.voided, good.gaps, good.failed, good.seed)
    assert rebuilt.changes == good.changes and rebuilt.ballast_gaps == good.ballast_gaps
    assert not rebuilt.values["kv"].flags.writeable
    bad = [dict(values={"kv": np.ones(3)}), dict(values={"kv": -np.ones(5)}), dict(values={"E": np.ones(5)}),
           dict(voided=np.array([7]), gaps=np.array([1e-3])), dict(voided=np.array([1]), gaps=np.array([0.5])),
           dict(voided=np.array([1]), gaps=np.zeros(0)), dict(voided=np.array([1.5]), gaps=np.array([1e-3])),
           dict(voided=np.array([1]), gaps=np.array([1e-3]), failed=np.array([1])), dict(track="x"),
           dict(first=9), dict(seed=-3)]
    for change in bad:
        fields = dict(track=BALLAST, first=0, last=4) | change
        with pytest.raises(st.BadInput, match="RandomTrack|last|seed"):
            st.RandomTrack(**fields)
    with pytest.raises(st.BadInput, match="voided"):
        st.RandomTrack(SLAB, 0, 4, voided=np.array([1]), gaps=np.array([1e-3]))
    assert MAX_GAP == 0.05
