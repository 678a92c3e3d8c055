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
    MISSING,
    fit_error_table,
    fixed,
    inversion_error_table,
    mirrored_pair,
    mirrored_pair_table,
    parameter_comparison,
    readable_number,
    styled,
    system_comparison,
    table4_consistency_table,
    table7_consistency_table,
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
    assert table.loc[0, "median element error (%)"] == pytest.approx(100 * e.median)
    assert table.loc[0, "max element error (%)"] == pytest.approx(100 * e.max)
    assert table.attrs["caption"].startswith("Element error: |α_E − α|/|α| of α11, α12 and α22")


def test_fit_error_table_reuses_a_paper_method_sweep():
    """A sweep on the paper's 6 Hz grid gives half of a 3 Hz grid: the same table, bit for bit;
    a sweep of another track is refused (one shared frequency is recomputed)."""
    track, band, systems = st.slab_track(), (3.0, 30.0), {"paper (Table 4)": st.paper_table4()}
    sweep = st.central_response(track, np.arange(3.0, 20.0, 6.0), method="wavenumber")  # 3-15 Hz: some of the grid
    direct = fit_error_table(track, systems, band)
    pd.testing.assert_frame_equal(fit_error_table(track, systems, band, wavenumber_response=sweep), direct)
    with pytest.raises(ValueError, match="not this track's paper-method sweep"):
        fit_error_table(st.slab_track(kv=1e8), systems, band, wavenumber_response=sweep)
    with pytest.raises(ValueError, match="method='wavenumber'"):
        fit_error_table(track, systems, band, wavenumber_response=st.central_response(track, [3.0]))


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
    assert table.loc[0, "max junction error (%)"] == pytest.approx(100 * (np.abs(w - w1) / np.abs(w1))[inside].max())


def test_inversion_amplifies_errors():
    track, band = st.ballasted_track(), FIT_BANDS["ballasted"]
    table = inversion_error_table(track, {"paper": st.paper_table7()}, band, df=30.0)
    row = table.loc[0]
    assert 1.0 < row["median |α11 α22|/|det α| (-)"] < row["max |α11 α22|/|det α| (-)"]
    grid = st.error_band_grid(band, df=30.0)
    alpha = st.semi_infinite_receptance(track, grid)
    amplification = np.abs(alpha[:, 0, 0] * alpha[:, 1, 1] / np.linalg.det(alpha))
    assert row["max |α11 α22|/|det α| (-)"] == pytest.approx(amplification.max())
    # The two measures of alpha's error, side by side: pooled elements, and the worst element.
    errors = st.error_summary(st.paper_table7().receptance(grid), alpha)
    assert row["median element error of α (%)"] == pytest.approx(100 * errors.median)
    worst = np.max(list(errors.per_element.values()), axis=0)
    assert row["median worst-element error of α (%)"] == pytest.approx(100 * np.median(worst))
    assert row["median worst-element error of α (%)"] > row["median element error of α (%)"]
    assert row["median error of K11 (%)"] > 0.0


def test_audit_tables_of_the_derivation_chapter():
    f = [183.0]
    errors = element_error_table([st.slab_track()], f)
    assert list(errors.columns) == ["alpha11 error (%)", "alpha12 error (%)", "alpha22 error (%)"]
    assert errors.index.names == ["track", "f (Hz)"]
    html = styled(errors, index=True).to_html()
    assert ">183<" in html and "183.0" not in html  # a float index level, written for a reader
    study = convergence_study(st.slab_track(), f, beta_factors=(1, 2), dxs=(0.04, 0.01))
    gains = settings_gain_table({"slab": study}, refined_factor=2, refined_dx=0.01)
    paper = study[(study["beta factor"] == 1) & (study["dx (m)"] == 0.04)]["error"].item()
    assert gains.loc[0, "paper's settings (%)"] == pytest.approx(100 * paper)
    limit = continuous_limit_study(st.slab_track(), [183.0], refinements=(4, 16))
    assert isinstance(limit, pd.DataFrame) and limit["183 Hz"].iloc[1] < limit["183 Hz"].iloc[0] / 10


# --- display: what a reader sees -----------------------------------------------------------------
def _shown(styler) -> str:
    """The HTML a notebook shows for a Styler."""
    return styler.to_html()


def _assert_readable(html: str) -> None:
    for raw in ("e+0", "e+1", "e-0", "e-1", "nan", "NaN", "inf"):
        assert raw not in html, raw


def test_readable_number_and_fixed():
    assert [readable_number(v) for v in (7850.0, 2.1e11, 0.25, 0.01, 5.44e7, 3.055e-5)] == [
        "7850", "2.1×10¹¹", "0.25", "0.01", "5.44×10⁷", "3.055×10⁻⁵"]
    assert [readable_number(v) for v in (0.0, -283000.0, 12345.0, float("nan"), float("inf"))] == [
        "0", "-2.83×10⁵", "12345", MISSING, "∞"]
    assert readable_number(2 / 3, digits=2) == "0.67"
    # Trailing zeros are kept where significant: one number of digits per column.
    assert [readable_number(v) for v in (19.003, 1.9003e7, 1.9e7, 100.0004)] == ["19.00", "1.900×10⁷", "1.9×10⁷",
                                                                                 "100.0"]
    assert fixed(2)(-0.0004) == "0.00" and fixed(2)(-0.006) == "-0.01" and fixed(1)(15.43) == "15.4"


def test_styled_table2_has_readable_numbers_and_no_index(track):
    html = _shown(styled(parameter_comparison(track)))
    _assert_readable(html)
    assert "row_heading" not in html  # no 0..N index column
    assert ">7850<" in html and ">2.1×10¹¹<" in html and ">0.00769<" in html
    assert ">0<" in html and ">0.00<" not in html  # the deviations: exactly zero, and shown so, not rounded
    assert parameter_comparison(track)["value"].dtype == float  # the values stay numbers


def test_styled_system_comparison_shows_missing_hinges_as_a_dash():
    table = system_comparison(st.paper_table4(), st.paper_table4(), "paper (Table 4)")
    html = _shown(styled(table, index=True))
    _assert_readable(html)
    assert f">{MISSING}<" in html and "k_phi (N m/rad)" in html and "no hinge after the last bar" in html
    assert ">1.029×10⁵<" in html  # c_r of bar 5


def test_styled_error_tables_name_their_measure():
    fit = fit_error_table(st.slab_track(), {"paper (Table 4)": st.paper_table4()}, FIT_BANDS["slab"], df=60.0)
    html = _shown(styled(fit))
    _assert_readable(html)
    assert "row_heading" not in html and "median element error (%)" in html and "Element error:" in html
    assert f">{fit.loc[0, 'median element error (%)']:.1f}<" in html


def test_table4_consistency_table_is_readable():
    table = table4_consistency_table()
    assert list(table["bar"]) == [1, 2, 3, 4, 5]
    assert all("(" in label for label in table.columns[1:])  # every quantity with its unit
    # Eq. (19)-(20) hold within what rounding explains, and the massless bars have nothing to check.
    massive = table["m (kg)"] > 0
    assert (table["k deviation (%)"].abs()[massive] <= table["k rounding bound (%)"][massive]).all()
    assert table.loc[~massive, "k rounding bound (%)"].isna().all()
    html = _shown(styled(table))
    _assert_readable(html)
    assert f">{MISSING}<" in html and "row_heading" not in html and "massless bar" in html


def test_table7_consistency_table_is_readable():
    table = table7_consistency_table()
    assert list(table.columns) == [f"bar {j}" for j in range(1, 6)]
    implied = table.loc["f_n2 implied by k, Eq. (29) (Hz)"]
    np.testing.assert_allclose(implied, 471.0, atol=0.05)  # the book's reading of Table 7
    assert table.loc["μ deviation (%)", "bar 1"] == pytest.approx(-16.26, abs=0.01)
    assert table.loc["s making Eq. (23) exact (N/m)", "bar 1"] == pytest.approx(TABLE7_S1_TRANSPOSED, rel=1e-3)
    html = _shown(styled(table, index=True))
    _assert_readable(html)
    assert ">471.00<" in html and ">1.801×10⁷<" in html and ">-16.26<" in html and ">-0.00<" not in html
