"""The decay chapter's studies: tables built from the package's results, checked against them."""

import numpy as np
import pandas as pd
import pytest

import semitrack as st
from semitrack.methods.decay import EN15461_BAYS
from semitrack.paper import decay_study as study

F = np.array([50.0, 150.0, 400.0, 1200.0, 2500.0])


def test_local_change_curves_are_point_receptances():
    track = st.ballasted_track()
    cases = {"perfect": st.InfiniteTrack(track), "hanging": st.InfiniteTrack(track, {0: {"kb": 0.0}})}
    xs = [0.3, 0.9]
    curves = study.local_change_curves(cases, F, xs)
    for label, inf in cases.items():
        assert curves[label].shape == (F.size, 2)
        for j, x in enumerate(xs):
            np.testing.assert_allclose(curves[label][:, j], inf.receptance(F, x, [x])[:, 0, 0, 0], rtol=1e-13)


def test_change_ratio_table_takes_the_largest_ratio_in_each_range():
    f = np.array([10.0, 20.0, 30.0, 40.0])
    ref = np.ones((4, 1), dtype=complex)
    curves = {"ref": ref, "soft": np.array([[2.0], [3.0j], [1.0], [0.5]])}
    table = study.change_ratio_table(f, curves, "ref", ("here",), {"low": (10.0, 20.0), "high": (25.0, 40.0)})
    assert table.loc[("soft", "here"), "low"] == 3.0 and table.loc[("soft", "here"), "high"] == 1.0
    assert list(table.index) == [("soft", "here")]


def test_pinned_length_table_is_twenty_db_over_the_lowest_rate_above_the_range():
    rates = {"slab": st.track_decay_rate(st.slab_track(), band=(100.0, 1000.0), df=5.0)}
    table = study.pinned_length_table(rates, {"slab": 0.65})
    tdr = rates["slab"]
    keep = (tdr.centres > 240) & tdr.valid  # a band the standard's checks reject reads high: not counted
    assert not tdr.valid[tdr.centres > 240].all()
    lowest = tdr.decay_rate[keep].min()
    row = table.loc["slab"]
    assert row["lowest decay rate (dB/m)"] == lowest and row["20 dB away (m)"] == 20 / lowest
    assert row["grid (m)"] == tdr.distances[-1]
    assert row["bays"] == 20 / lowest / 0.65 and row["pinned model around one wheel (m)"] == 40 / lowest
    decay = study.decay_table(rates)
    limit = decay["", "ISO 3095 limit (dB/m)"]
    meets = decay["slab", "meets the limit"]
    assert np.isnan(limit.loc[100.0]) and pd.isna(meets.loc[100.0])  # the standard sets no limit there
    assert ((decay["slab", "decay rate (dB/m)"] >= limit) == (meets == 1))[limit.notna()].all()
    assert isinstance(decay, pd.DataFrame) and decay.index.name == "band (Hz)"


def test_a_grid_without_a_valid_band_is_refused():
    rates = {"slab": st.track_decay_rate(st.slab_track(), band=(800.0, 800.0), df=5.0)}
    with pytest.raises(ValueError, match="longer grid"):
        study.pinned_length_table(rates, {"slab": 0.65})


def test_long_grid_carries_the_standard_s_grid_on():
    grid = study.long_grid(300, 6)
    n = len(EN15461_BAYS)
    np.testing.assert_array_equal(grid[:n], EN15461_BAYS)
    np.testing.assert_array_equal(np.diff(grid[n - 1:]), 6.0)
    assert grid[-1] == 300


def test_the_three_change_measures_on_a_spring_whose_stiffness_halves():
    """A rail on a stiff, lightly damped bed against the same with one support gone: the static
    ratio is the receptance ratio at 0.1 Hz, the peak ratio each curve's own maximum, and the
    largest ratio the pointwise maximum; against numbers computed here from the curves."""
    slab = st.slab_track()
    cases = {"perfect track": st.InfiniteTrack(slab), "failed fastener": st.InfiniteTrack(slab, {0: None})}
    f = np.geomspace(20.0, 200.0, 60)
    x = [0.5 * slab.spacing]
    curves = study.local_change_curves(cases, f, x)
    table = study.change_measure_table(cases, f, curves, "perfect track", x, ("here",))
    row = table.loc[("failed fastener", "here")]
    h, h0 = np.abs(curves["failed fastener"][:, 0]), np.abs(curves["perfect track"][:, 0])
    assert row["largest ratio of |w/F|"] == pytest.approx((h / h0).max())
    assert row["peak over peak"] == pytest.approx(h.max() / h0.max())
    static = [c.receptance([0.1], x[0], x)[0, 0, 0, 0].real for c in cases.values()]
    assert row["static stiffness drop"] == pytest.approx(static[1] / static[0]) and row["static stiffness drop"] > 1
    assert row["largest ratio of |w/F|"] >= row["peak over peak"]  # the peak ratio is read at the changed peak too
    sensitivity = study.damping_sensitivity_table(slab, {"failed fastener": {0: None}}, f, x, ("here",))
    largest = ("damping x 1", "largest ratio of |w/F|")
    assert sensitivity[largest].iloc[0] == pytest.approx(row["largest ratio of |w/F|"])
    assert (sensitivity[("damping x 0.5", "largest ratio of |w/F|")].iloc[0]
            > 1.5 * sensitivity[("damping x 1", "largest ratio of |w/F|")].iloc[0])
