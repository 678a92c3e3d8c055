"""A run's summary and figure: the figures are the histories' own, computed here from the arrays.

Independent check: every value of :meth:`ContactResponse.summary` is recomputed from the run's
arrays (max, min, rms over the samples after the fade-in, the static start, the counted samples
out of contact, the track's and the gaps' histories); a reference run's ratios are the quotient
of the two tables' values; wheels are named as the vehicle names them.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import semitrack as st
from semitrack import plotting

TRACK = st.ballasted_track(damping="viscous")
RUN = dict(x=[2.0, -0.5], speed=20.0, dt=1e-4, duration=0.05, ramp=0.01, watch_supports=[0, 1], bending_at=[0.0])


@pytest.fixture(scope="module")
def runs():
    rough = st.roughness_from_spectrum(20.0, dt=1e-4)
    hanging = st.TruncatedTrack(TRACK, 6, elements_per_bay=4, changes={0: {"kb": 0.0}})
    perfect = st.TruncatedTrack(TRACK, 6, elements_per_bay=4)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # a coarse mesh for a short test: its own warning is by design
        res = st.wheel_rail_response(hanging, st.Bogie(), rough, ballast_gaps={0: 1e-3}, **RUN)
        ref = st.wheel_rail_response(perfect, st.Bogie(), rough, **RUN)
    return res, ref


def test_the_summary_is_the_histories_own_figures(runs):
    res, _ = runs
    table = res.summary()
    late = res.t >= res.ramp
    for j, name in enumerate(("leading wheel", "trailing wheel")):
        force = res.force[:, j]
        expected = {"peak force (kN)": force[late].max() / 1e3, "minimum force (kN)": force[late].min() / 1e3,
                    "rms force (kN)": np.sqrt(np.mean(force[late] ** 2)) / 1e3, "static force (kN)": force[0] / 1e3,
                    "peak / static (-)": force[late].max() / force[0],
                    "time out of contact (ms)": 1e3 * res.dt * np.sum(force[late] <= 0)}
        for quantity, value in expected.items():
            assert table.loc[(name, quantity), "value"] == pytest.approx(value, rel=1e-12, abs=1e-12), quantity
    forces = res.track_forces
    assert table.loc[("support 1", "peak rail-seat force (kN)"), "value"] == pytest.approx(
        forces.rail_seat[late, 1].max() / 1e3, rel=1e-12)
    assert table.loc[("support 1", "peak ballast force (kN)"), "value"] == pytest.approx(
        forces.ballast[late, 1].max() / 1e3, rel=1e-12)
    assert table.loc[("rail at x = 0 m", "peak sagging moment (kN m)"), "value"] == pytest.approx(
        forces.bending[late, 0].max() / 1e3, rel=1e-12)
    sleeper = "hanging sleeper 0 (gap 1 mm)"
    assert table.loc[(sleeper, "peak ballast force (kN)"), "value"] == pytest.approx(
        res.gaps.force[late, 0].max() / 1e3, rel=1e-12)
    assert table.loc[(sleeper, "time on the ballast (ms)"), "value"] == pytest.approx(1e3 * res.gaps.contact_time[0])
    assert list(table.columns) == ["value"] and table.index.names == ["item", "quantity"]
    whole = res.summary(after=0.0)  # the fade-in counted: the rms moves, the static force does not
    assert whole.loc[("leading wheel", "static force (kN)"), "value"] == table.loc[("leading wheel",
                                                                                    "static force (kN)"), "value"]
    assert whole.loc[("leading wheel", "rms force (kN)"), "value"] != table.loc[("leading wheel", "rms force (kN)"),
                                                                                 "value"]


def test_a_reference_run_gives_the_ratios(runs):
    res, ref = runs
    table, own, theirs = res.summary(ref), res.summary(), ref.summary()
    assert list(table.columns) == ["value", "reference", "ratio"]
    both = theirs.index.intersection(own.index)
    np.testing.assert_allclose(table.loc[both, "reference"], theirs.loc[both, "value"], rtol=1e-14)
    np.testing.assert_allclose(table.loc[both, "ratio"], own.loc[both, "value"] / theirs.loc[both, "value"],
                               rtol=1e-14)
    assert np.isnan(table.loc[("hanging sleeper 0 (gap 1 mm)", "peak ballast force (kN)"), "reference"])
    # the hanging sleeper moves the load to its neighbour: support 1's ballast carries more
    assert table.loc[("support 1", "peak ballast force (kN)"), "ratio"] > 1.05


def test_wheels_are_named_as_the_vehicle_names_them_and_bad_arguments_are_refused(runs):
    res, _ = runs
    model = st.TruncatedTrack(TRACK, 2, elements_per_bay=4)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        one = st.wheel_rail_response(model, st.Wheel(), dt=1e-4, duration=0.01, ramp=0.004)
        two = st.wheel_rail_response(model, [st.Wheel(), st.Wheel()], x=[0.0, 0.3], dt=1e-4, duration=0.01,
                                     ramp=0.004)
    assert set(one.summary().index.get_level_values("item")) == {"wheel"}
    assert set(two.summary().index.get_level_values("item")) == {"wheel 1", "wheel 2"}
    assert st.Bogie().wheel_names == ("leading wheel", "trailing wheel")
    with pytest.raises(st.BadInput, match="same number of wheels"):
        res.summary(one)
    with pytest.raises(st.BadInput, match="reference must be a ContactResponse"):
        res.summary(res.summary())
    with pytest.raises(st.BadInput, match="after=1 s leaves no sample"):
        res.summary(after=1.0)
    with pytest.raises(st.BadInput, match="reference: after=0.04 s leaves no sample of its 0.01 s run"):
        st.interaction.summary.run_summary(res, _shortened(res, 0.01), after=0.04)
    with pytest.raises(st.BadInput, match="response must be a ContactResponse"):
        st.interaction.summary.run_summary(None)


def _shortened(res, duration):
    """The run cut at ``duration`` (s): every history's first samples."""
    n = int(np.count_nonzero(res.t <= duration + 1e-12))
    cut = {name: getattr(res, name)[:n] for name in ("t", "force", "w_wheel", "w_rail", "roughness", "x")}
    return res.__class__(**{**res.__dict__, **cut, "track_forces": None, "gaps": None})


def test_the_run_figure_names_the_wheels_and_draws_the_track_s_forces(runs):
    res, ref = runs
    fig, axes = plotting.run_figure(res, ref, title="a hanging sleeper")
    assert len(axes) == 3
    labels = [line.get_label() for line in axes[0].get_lines()]
    assert labels == ["leading wheel", "trailing wheel", "leading wheel, reference", "trailing wheel, reference"]
    np.testing.assert_array_equal(axes[0].get_lines()[1].get_ydata(), res.force[:, 1] / 1e3)
    assert [t.get_text() for t in axes[2].get_legend().get_texts()][-1] == "hanging sleeper 0 (1 mm)"
    fig, axes = plotting.run_figure(res.__class__(**{**res.__dict__, "track_forces": None, "gaps": None}))
    assert len(axes) == 1
