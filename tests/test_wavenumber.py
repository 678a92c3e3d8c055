"""The paper's wavenumber method: agreement with and convergence to the exact method."""

import numpy as np
import pytest

import semitrack as st
from semitrack.base.paper_values import PAPER_BETA_MAX, PAPER_DBETA, PAPER_DX, PAPER_J_MAX
from semitrack.methods.wavenumber import WavenumberSettings, displacement_fields

CHECK_F = np.array([3.0, 183.0, 945.0])  # low, bouncing, and near the first pinned-pinned frequency
# Refined setting: ten times the paper's wavenumber range, one twentieth of its dx.
REFINED = dict(beta_max=10 * PAPER_BETA_MAX, dx=0.002)


def _max_rel_error(alpha, ref):
    return (np.abs(alpha - ref) / np.abs(ref)).reshape(len(ref), 4).max(axis=1)


def test_paper_settings_are_the_default():
    s = WavenumberSettings()
    assert (s.beta_max, s.dbeta, s.j_max, s.dx) == (PAPER_BETA_MAX, PAPER_DBETA, PAPER_J_MAX, PAPER_DX)
    assert s.beta.size == 10000 and np.pi / s.beta_max == pytest.approx(s.dx)  # the paper's dx is its FFT x-step


def test_wavenumber_converges_to_exact(track):
    exact = st.semi_infinite_receptance(track, CHECK_F)
    err_paper = _max_rel_error(st.semi_infinite_receptance(track, CHECK_F, method="wavenumber"), exact)
    err_refined = _max_rel_error(st.semi_infinite_receptance(track, CHECK_F, method="wavenumber", **REFINED), exact)
    # Required: a 10x reduction at each frequency; measured 15x-300x.
    ratio = err_paper / err_refined
    assert np.all(ratio >= 10), f"paper error {err_paper}, refined {err_refined}"
    # The book states that the paper's settings are measurably off (measured 9-68 % here): keep
    # that claim true from both sides, and keep the refined setting near 1 % (measured 0.2-1 %).
    assert np.all(err_paper > 0.05) and np.all(err_paper < 0.8) and np.all(err_refined < 0.02)


def test_central_displacement_converges_fast(track):
    """w1 is a value, not a slope: at the paper's settings it is already within 2 %."""
    exact = st.central_response(track, CHECK_F)
    wn = st.central_response(track, CHECK_F, method="wavenumber")
    np.testing.assert_allclose(wn.w1, exact.w1, rtol=0.02)


def test_two_supports_per_period_equal_one(track):
    """Period 2d with two supports (S = 2): the same sum over beta_j when j_max doubles."""
    a1 = st.semi_infinite_receptance(track, CHECK_F, method="wavenumber")
    a2 = st.semi_infinite_receptance(track.cell(2), CHECK_F, method="wavenumber", j_max=40)
    np.testing.assert_allclose(a2, a1, rtol=1e-6)  # measured 5e-8


def test_field_symmetries_table1(track):
    """Force: w1 even, psi1 odd; moment: w2 odd, psi2 even about the load (paper Table 1)."""
    cell = track.cell()
    x = np.array([-0.3, -0.1, 0.0, 0.1, 0.3])
    q = displacement_fields(cell, 2 * np.pi * np.array([100.0, 800.0]), x)
    # The grid [-beta_max, beta_max) has one more negative than positive wavenumber, which breaks
    # the symmetry at the 1e-6 level (measured 4e-6 at most); 2e-5 of the field's peak.
    for (i, k), parity in {(0, 0): 1, (1, 0): -1, (0, 1): -1, (1, 1): 1}.items():
        field = q[:, :, i, k]
        tol = 2e-5 * np.abs(field).max()
        np.testing.assert_allclose(field[:, ::-1], parity * field, atol=tol)
    # psi1 and w2 vanish at the load: the odd fields the slopes of Eq. (15)-(16) are taken from.
    assert np.abs(q[:, 2, 1, 0]).max() < 2e-5 * np.abs(q[:, :, 1, 0]).max()
    assert np.abs(q[:, 2, 0, 1]).max() < 2e-5 * np.abs(q[:, :, 0, 1]).max()


@pytest.mark.parametrize("kw,err", [
    (dict(beta_max=-1.0), ValueError), (dict(dx=0.0), ValueError), (dict(j_max=-1), ValueError),
    (dict(j_max=2.5), TypeError), (dict(beta_max=1.0, dbeta=2.0), ValueError),
])
def test_bad_settings(kw, err):
    with pytest.raises(err):
        st.semi_infinite_receptance(st.slab_track(), 100.0, method="wavenumber", **kw)


def test_undamped_rail_is_refused_by_the_wavenumber_method():
    """Eq. (12) runs through the free rail's poles when the rail has no damping; the method must
    say so instead of returning a non-reciprocal alpha (a11 was > 100 % off at 500 Hz)."""
    track = st.slab_track(eta_rail=0.0)
    with pytest.raises(ValueError, match=r"needs a damped rail \(eta_rail > 0\), got eta_rail=0.0"):
        st.semi_infinite_receptance(track, [500.0], method="wavenumber")
    st.semi_infinite_receptance(track, [500.0])  # the exact method takes the limit instead


def test_summing_the_wavenumbers_in_blocks_changes_nothing(track):
    """A frequency whose terms exceed the memory budget is summed in wavenumber blocks."""
    cell, omega, x = track.cell(), 2 * np.pi * np.array([50.0, 900.0]), np.array([0.0, 0.04, 0.08])
    whole = displacement_fields(cell, omega, x)
    blocks = displacement_fields(cell, omega, x, chunk_bytes=1e6)  # ~240 wavenumbers per block
    np.testing.assert_allclose(blocks, whole, rtol=1e-12, atol=1e-12 * np.abs(whole).max())
