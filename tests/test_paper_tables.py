"""The book's table builders: paper values beside ours, fit errors, the mirrored pair, the audits."""

import numpy as np
import pandas as pd
import pytest

import semitrack as st
from semitrack.base.paper_values import FIT_BANDS, TABLE2_SLAB, TABLE7, TABLE7_S1_TRANSPOSED
from semitrack.paper.convergence import (
    continuous_limit_study,
    convergence_study,
    element_error_table,
    settings_gain_table,
)
from semitrack.paper.systems import paper_table7_s1_transposed
from semitrack.paper.tables import (
    FIT_ERROR_TARGETS,
    fit_error_table,
    inversion_error_table,
    mirrored_pair,
    mirrored_pair_table,
    parameter_comparison,
    system_comparison,
)


def test_parameter_comparison_puts_the_paper_beside_the_preset(track):
    table = parameter_comparison(track)
    label = "paper (Tables 2, 5)" if track.is_ballasted else "paper (Table 2)"
    assert list(table.columns[-2:]) == [label, "deviation (%)"]
    assert (table["deviation (%)"] == 0).all()
    soft = parameter_comparison(st.slab_track(kv=TABLE2_SLAB["kv"] / 2))
    assert soft.set_index("symbol").loc["k_v", "deviation (%)"] == pytest.approx(-50.0)


def test_system_comparison_has_both_systems():
    table = system_comparison(st.paper_table7(), paper_table7_s1_transposed(), "paper (Table 7)")
    assert set(table.columns.get_level_values(0)) == {"paper (Table 7)", "ours"}
    s_row = next(row for row in table.index if row.startswith("s "))
    assert table.loc[s_row, ("paper (Table 7)", "bar 1")] == TABLE7["s"][0]
    assert table.loc[s_row, ("ours", "bar 1")] == TABLE7_S1_TRANSPOSED


def test_fit_error_table_matches_error_summary():
    track, band = st.slab_track(), FIT_BANDS["slab"]
    table = fit_error_table(track, {"paper (Table 4)": st.paper_table4()}, band, df=60.0)
    assert list(table["against"]) == list(FIT_ERROR_TARGETS)
    grid = st.error_band_grid(band, df=60.0)
    e = st.error_summary(st.paper_table4().receptance(grid), st.semi_infinite_receptance(track, grid))
    assert table.loc[0, "median error (%)"] == pytest.approx(100 * e.median)
    assert table.loc[0, "max error (%)"] == pytest.approx(100 * e.max)


def test_mirrored_pair_and_its_table():
    track, band = st.ballasted_track(), FIT_BANDS["ballasted"]
    f = np.arange(3.0, 1000.0, 30.0)
    pair = mirrored_pair(track, {"paper system": st.paper_table7()}, f, band)
    w1 = st.central_response(track, f).w1
    w = st.paper_table7().mirrored_receptance(f)[:, 0, 0]
    np.testing.assert_allclose(pair.errors["paper system"], np.abs(w - w1) / np.abs(w1))
    table = mirrored_pair_table({"ballasted": pair})
    inside = f <= band[1]
    assert table.loc[0, "band (Hz)"] == "3-750"
    assert table.loc[0, "max error (%)"] == pytest.approx(100 * (np.abs(w - w1) / np.abs(w1))[inside].max())


def test_inversion_amplifies_errors():
    table = inversion_error_table(st.slab_track(), {"paper": st.paper_table4()}, FIT_BANDS["slab"], df=30.0)
    assert table.loc[0, "median |a11 a22|/|det a|"] > 1.0
    assert table.loc[0, "median error of K11 (%)"] > 0.0


def test_audit_tables_of_the_derivation_chapter():
    f = [183.0]
    errors = element_error_table([st.slab_track()], f)
    assert list(errors.columns) == ["alpha11 error (%)", "alpha12 error (%)", "alpha22 error (%)"]
    assert errors.index.names == ["track", "f (Hz)"]
    study = convergence_study(st.slab_track(), f, beta_factors=(1, 2), dxs=(0.04, 0.01))
    gains = settings_gain_table({"slab": study}, refined_factor=2, refined_dx=0.01)
    paper = study[(study["beta factor"] == 1) & (study["dx (m)"] == 0.04)]["error"].item()
    assert gains.loc[0, "paper's settings (%)"] == pytest.approx(100 * paper)
    limit = continuous_limit_study(st.slab_track(), [183.0], refinements=(4, 16))
    assert isinstance(limit, pd.DataFrame) and limit["183 Hz"].iloc[1] < limit["183 Hz"].iloc[0] / 10
