"""The wheel-flat chapter's studies: their tables read the runs they make, and two closed forms.

Closed forms: the wheel leaves a slowly varying rigid rail over a new flat above
``sqrt(P0 R / m)``; the curvature of a new flat sets in as a step, which the wheel on its contact
spring overshoots two-fold, so on a very stiff track it leaves at ``sqrt(P0 R / (2 m))``.
"""

import numpy as np
import pytest

import semitrack as st
from semitrack.paper import flats_study as study


@pytest.fixture(scope="module")
def ballasted():
    return st.InfiniteTrack(st.ballasted_track())


def test_the_flat_meets_the_rail_after_its_lead():
    wheel = study.flat_wheel(0.05, "rounded", lead=0.02)
    flat = wheel.defects[0]
    assert flat.position == pytest.approx(0.045) and flat.shape == "rounded" and wheel.primary_stiffness == 1.2e6
    x = np.array([0.0, 0.0199, 0.0201])
    assert np.all(st.wheel_centre_path(wheel, x)[:2] < 1e-9) and st.wheel_centre_path(wheel, x)[2] > 0
    assert study.flat_wheel(0.05, contact="point").contact == "point"


def test_the_slow_criterion_of_leaving_a_rigid_rail():
    wheel = study.flat_wheel(0.05)
    assert study.kinematic_loss_speed(wheel) == pytest.approx(3.6 * np.sqrt(1e5 * 0.46 / 600), rel=0.01)
    rounded = study.flat_wheel(0.05, "rounded")
    assert study.kinematic_loss_speed(rounded) > study.kinematic_loss_speed(wheel)  # it curves less


def test_a_very_stiff_track_loses_the_wheel_where_the_step_s_overshoot_says():
    track = st.ballasted_track()
    stiff = st.InfiniteTrack(track.replace(kv=1000 * track.kv, kb=1000 * track.kb))
    table = study.loss_speed_table({"stiff": stiff}, {"new 50 mm": (0.05, "new")}, lo=10.0, hi=60.0, tol=0.5)
    step = 3.6 * np.sqrt(1e5 * 0.46 / (2 * 600))
    assert table.loc["new 50 mm", "stiff (km/h)"] == pytest.approx(step, rel=0.06)
    assert table.loc["new 50 mm", "rigid rail (km/h)"] == pytest.approx(step * np.sqrt(2), rel=0.01)


def test_the_impact_table_reads_its_runs(ballasted):
    table = study.impact_table({"ballasted": ballasted}, (0.05,), ("new",), (30, 70))
    assert list(table.columns) == ["P1 (kN)", "P2 (kN)", "without contact (ms)", "on the descent (ms)"]
    wheel = study.flat_wheel(0.05)
    run = study.flat_run(ballasted, wheel, 70)
    row = table.loc[("ballasted", "new", 50.0, 70)]
    assert row["P1 (kN)"] == pytest.approx(run.force.max() / 1e3)
    assert row["P1 (kN)"] >= row["P2 (kN)"] > 100 and row["without contact (ms)"] >= row["on the descent (ms)"] > 0
    assert table.loc[("ballasted", "new", 50.0, 30), "without contact (ms)"] == 0  # tests/test_wheel_flats.py's case
    assert run.t[-1] == pytest.approx((0.01 + 0.05) / (70 / 3.6) + study.AFTER, abs=2 * study.DT)  # lead + flat


def test_the_contact_models_differ_on_a_flat(ballasted):
    table = study.contact_model_table({"ballasted": ballasted}, {"new 50 mm": (0.05, "new")}, (60,))
    row = table.loc[("ballasted", "new 50 mm", 60)]
    assert row["P1, point against centre path (%)"] == pytest.approx(100 * (row["P1, point (kN)"]
                                                                         / row["P1, centre path (kN)"] - 1))
    assert abs(row["P1, point against centre path (%)"]) > 10


def test_the_fe_studies_and_the_figures_draw():
    from semitrack import plotting

    track = st.ballasted_track(damping="viscous")
    model = st.TruncatedTrack(track, 4, "pinned", elements_per_bay=8)
    runs = study.track_force_runs(model, 0.05, "new", (60,), at=0.3, watch=(-1, 0, 1))
    table = study.track_force_table(runs)
    assert table.loc[60, "P1 (kN)"] == pytest.approx(runs[60].force.max() / 1e3)
    assert table.loc[60, "largest rail-seat force (kN)"] == pytest.approx(runs[60].track_forces.rail_seat.max() / 1e3)
    start = runs[60].x[0]
    assert start == pytest.approx(0.3 - 1.5)
    weld = study.weld_contact_table(model, st.DippedWeld(0.04, 0.05, 0.0), (100,), start=-1.0, stop=0.5)
    assert weld.loc[100, "P1, centre path (kN)"] > 100
    impacts = study.impact_table({"ballasted": st.InfiniteTrack(st.ballasted_track())}, (0.05,), ("new", "rounded"),
                                 (30, 70))
    assert len(plotting.impact_speed_figure(impacts)[1]) == 1
    wheels = {"new": st.Wheel(defects=[st.WheelFlat(0.05)])}
    x = np.linspace(-0.03, 0.03, 61)
    curves = study.centre_path_curves(wheels, x)
    np.testing.assert_array_equal(curves["new"][1], st.wheel_centre_path(wheels["new"], x))
    assert len(plotting.centre_path_figure(x, curves)[1][0].lines) == 2
    assert len(plotting.contact_filter_figure([0.01, 0.1], st.contact_filter([0.01, 0.1], 6e-3), 6e-3)[1]) == 1
