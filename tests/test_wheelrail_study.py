"""The wheel-rail chapter's study functions on small models (the chapter runs them at full size).

Checks: the linear theory's closed-form limits, the bookkeeping of the stationary runs and the
cost table, the time-step halving measure and the rolling lines of a short run.
"""

import numpy as np
import pytest

import semitrack as st
from semitrack.paper import wheelrail_study as study


def test_the_linear_theory_meets_its_closed_forms():
    limits = study.linear_limits(st.slab_track(), st.Wheel(), [30.0, 500.0, 2000.0])
    assert limits.shape == (3, 1) and limits.max().max() < 1e-4  # measured ~1e-5 (rigid track: 1e6 stiffer)


def test_linear_force_finds_the_wheel_bounce():
    lin = study.linear_force({"slab": st.slab_track()}, st.Wheel(), np.geomspace(20.0, 3000.0, 400))
    assert lin.peaks.loc["slab", "wheel bounce (Hz)"].between(60.0, 68.0).all()
    assert set(lin.curves) == {("slab", "above a support"), ("slab", "at mid-span")}


def test_stationary_runs_and_their_cost():
    track = st.slab_track(damping="viscous")
    lam = st.third_octave_bands(0.1, 0.5)[0]
    rough = st.roughness_from_spectrum(100.0, lam, np.full(lam.size, -10.0), period=0.05, seed=1)
    runs = study.stationary_runs({"slab": track}, {}, st.Wheel(), rough, {"slab": (4e-5, 0.12)},
                                 [("pinned, {bays} bays", "pinned", {"slab": 2})], band=(200.0, 1000.0))
    assert list(runs.runs) == [("slab", "pinned, 2 bays")]
    cost = study.cost_table(runs)
    row = cost.loc[("slab", "pinned, 2 bays")]
    model, res = runs.runs["slab", "pinned, 2 bays"]
    assert row["DOFs + states"] == model.n_dof + 1 and row["length (m)"] == pytest.approx(4 * track.spacing)
    assert row["max band error (dB)"] == pytest.approx(np.abs(runs.transfers["slab", "pinned, 2 bays"].error_db).max())


def test_halving_change_needs_half_the_step():
    model = st.TruncatedTrack(st.slab_track(), 2, elements_per_bay=4)
    runs = {dt: st.wheel_rail_response(model, st.Wheel(), st.corrugation(30.0, 0.05, 1e-6), dt=dt, duration=0.03,
                                       ramp=0.01) for dt in (4e-5, 2e-5)}
    assert 0 <= study.halving_change(runs[4e-5], runs[2e-5]) < 1e-2
    with pytest.raises(ValueError, match="fine must have half the time step of coarse"):
        study.halving_change(runs[2e-5], runs[4e-5])


def test_rolling_lines_find_the_support_passing_line():
    """With 48 elements per bay the largest line above 100 Hz of a smooth rail is v/d."""
    track = st.slab_track(damping="viscous")
    model = st.TruncatedTrack(track, 6, elements_per_bay=48)
    runs = study.rolling_runs({(300.0, 48): model}, st.Wheel(), x_start=-3.0, dt=4e-5)
    with pytest.raises(ValueError, match="names 12 elements per bay, but the model has 48"):
        study.rolling_runs({(300.0, 12): model}, st.Wheel())
    lines = study.rolling_lines(runs, after=0.01).iloc[0]
    assert abs(lines["largest line above 100 Hz (Hz)"] - lines["v/d (Hz)"]) <= 2 * lines["bin (Hz)"]
