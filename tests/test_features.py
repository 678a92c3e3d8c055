"""Characteristic frequencies: detection, refinement, and the paper's Tables 3 and 6."""

import numpy as np
import pytest

import semitrack as st
from semitrack.base.paper_values import TABLE3_SLAB_FREQUENCIES, TABLE6_BALLASTED_FREQUENCIES
from semitrack.methods.features import grid_extrema, parabolic_refine, refine_extremum


def test_grid_extrema_and_parabola():
    f = np.linspace(0.0, 10.0, 101)
    y = np.exp(-((f - 3.33) ** 2)) + 0.5 * np.exp(-((f - 7.0) ** 2) / 0.5)
    peaks, dips = grid_extrema(y)
    assert len(peaks) == 2 and len(dips) == 1
    # log|y| of a Gaussian is an exact parabola: the vertex is recovered to rounding.
    assert parabolic_refine(f, y, peaks[0]) == pytest.approx(3.33, abs=1e-9)


def test_brent_refinement_of_a_resonance():
    f0, zeta = 183.7, 0.05
    h = lambda f: 1.0 / (f0**2 - f**2 + 2j * zeta * f0 * f)  # noqa: E731
    exact_peak = f0 * np.sqrt(1 - 2 * zeta**2)
    assert refine_extremum(h, 177.0, 189.0, "peak") == pytest.approx(exact_peak, abs=2e-3)
    with pytest.raises(ValueError, match="kind"):
        refine_extremum(h, 1.0, 2.0, "max")


@pytest.mark.parametrize("maker,entries", [
    (st.slab_track, TABLE3_SLAB_FREQUENCIES),        # 183 and 940 Hz
    (st.ballasted_track, TABLE6_BALLASTED_FREQUENCIES),  # 117 and 1077 Hz
])
def test_bouncing_and_pinned_pinned_within_2_percent(maker, entries):
    ex = st.characteristic_frequencies(maker())
    peaks = ex[(ex.quantity == "w1") & (ex.kind == "peak")]["f"].to_numpy()
    paper = [next(f for f, quantity, kind, _, mode in entries if quantity == "w1" and kind == "peak" and word in mode)
             for word in ("bouncing", "first pinned-pinned")]
    for f_paper in paper:
        nearest = peaks[np.argmin(np.abs(peaks - f_paper))]
        # 183 and 117 Hz are points of the paper's 6 Hz grid (+-3 Hz); the required agreement is 2 %.
        assert abs(nearest - f_paper) / f_paper < 0.02, (f_paper, nearest)


def test_refined_frequencies_do_not_depend_on_grid():
    t = st.slab_track()
    a = st.characteristic_frequencies(t, band=(3.0, 1200.0), df=6.0)
    b = st.characteristic_frequencies(t, band=(3.0, 1200.0), df=4.0)
    fa = a[(a.quantity == "w1")]["f"].to_numpy()
    fb = b[(b.quantity == "w1")]["f"].to_numpy()
    np.testing.assert_allclose(fa, fb, atol=0.01)


def test_paper_table_lists_every_entry(track):
    table = st.paper_frequency_table(track, with_wavenumber=False)
    assert len(table) == (19 if not track.is_ballasted else 21)
    assert table["exact (Hz)"].notna().all(), table[table["exact (Hz)"].isna()]
    # Every stated feature is found within 6 % (the largest, alpha22's anti-resonance dip, 5.3 %).
    assert table["exact dev. (%)"].abs().max() < 6.0


def test_characteristic_frequencies_checks_its_grid():
    with pytest.raises(ValueError, match="band"):
        st.characteristic_frequencies(st.slab_track(), band=(1000.0, 3.0))
    with pytest.raises(ValueError, match="df"):
        st.characteristic_frequencies(st.slab_track(), band=(3.0, 1000.0), df=0.0)
    with pytest.raises(ValueError, match="fewer than 3"):
        st.characteristic_frequencies(st.slab_track(), band=(3.0, 10.0), df=6.0)


def test_paper_table_refuses_a_response_from_another_grid():
    """A precomputed paper-method sweep is only reused if it is on the paper's grid."""
    other = st.central_response(st.slab_track(), [3.0, 9.0, 15.0], method="wavenumber")
    with pytest.raises(ValueError, match="PAPER_GRID"):
        st.paper_frequency_table(st.slab_track(), wavenumber_response=other)
