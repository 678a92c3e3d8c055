"""The exact (Bloch-wave) method: reciprocity, passivity, symmetry, periodicity, limits."""

import numpy as np
import pytest

import semitrack as st
from semitrack.base.paper_values import PAPER_GRID
from semitrack.methods import transfer
from semitrack.methods.transfer import end_stiffness
from semitrack.model.timoshenko import field_transfer, segment_dynamic_stiffness

MIRROR = np.diag([1.0, -1.0])  # w is even, psi odd under x -> -x


def _hermitian_part_of_mobility(f, alpha):
    y = 1j * 2 * np.pi * f[:, None, None] * alpha
    return 0.5 * (y + np.conj(np.swapaxes(y, -1, -2)))


def test_reciprocity(track, paper_grid):
    a = st.semi_infinite_receptance(track, paper_grid)
    # Reciprocity is exact in theory; 1e-10 relative leaves room for eigen-solver rounding.
    np.testing.assert_allclose(a[:, 0, 1], a[:, 1, 0], rtol=1e-10)


def test_passivity(track, paper_grid):
    a = st.semi_infinite_receptance(track, paper_grid)
    herm = _hermitian_part_of_mobility(paper_grid, a)
    eig = np.linalg.eigvalsh(herm)
    scale = np.abs(herm).max(axis=(1, 2))
    # A damped track absorbs power: eigenvalues >= 0 up to rounding (1e-12 of the largest entry).
    assert np.all(eig.min(axis=1) >= -1e-12 * scale)
    assert np.all(a[:, 0, 0].imag < 0)  # point receptance of a damped structure lags


def test_left_part_is_mirror_of_right(track):
    cell = track.cell()
    omega = 2 * np.pi * np.array([3.0, 183.0, 945.0, 2500.0])
    k_right, k_left = end_stiffness(cell, omega, cell.mid_span)
    np.testing.assert_allclose(k_left, MIRROR @ k_right @ MIRROR, rtol=1e-10, atol=1e-10 * np.abs(k_right).max())


def test_eq14_from_central_responses_equals_direct_inverse(track, paper_grid):
    """Eq. (14) applied to exact w1, psi2, Q2, M1 must reproduce alpha = K_R^-1 (an identity)."""
    r = st.central_response(track, paper_grid)
    np.testing.assert_allclose(r.alpha, st.semi_infinite_receptance(track, paper_grid), rtol=1e-10, atol=0)
    # Eq. (17)/(18): det(alpha^-1) is the determinant of the inverse receptance.
    np.testing.assert_allclose(r.det, np.linalg.det(np.linalg.inv(r.alpha)), rtol=1e-9)


def test_two_supports_per_period_equal_one(track, paper_grid):
    a1 = st.semi_infinite_receptance(track, paper_grid)
    a2 = st.semi_infinite_receptance(track.cell(2), paper_grid)
    np.testing.assert_allclose(a2, a1, rtol=1e-9)


def test_point_receptance_periodic_and_symmetric(track):
    f = np.array([50.0, 183.0, 700.0, 1500.0])
    d = track.spacing
    for x in (0.0, 0.13, 0.5 * d):
        h = st.point_receptance(track, f, x, origin="support")
        # Off-diagonal terms vanish at a support and at mid-span, so compare against the largest
        # entry per frequency: 1e-9 of it is far above rounding and far below any real asymmetry.
        tol = 1e-9 * np.abs(h).max()
        np.testing.assert_allclose(st.point_receptance(track, f, x + 3 * d, origin="support"), h, rtol=1e-9, atol=tol)
        # Mirror symmetry about a support: H(d - x) = P H(x) P.
        mirrored = st.point_receptance(track, f, d - x, origin="support")
        np.testing.assert_allclose(mirrored, MIRROR @ h @ MIRROR, rtol=1e-8, atol=tol)
    # At mid-span the point receptance holds the central responses w1 and psi2.
    r = st.central_response(track, f)
    h = st.point_receptance(track, f, 0.5 * d, origin="support")
    np.testing.assert_allclose(h[:, 0, 0], r.w1, rtol=1e-10)
    np.testing.assert_allclose(h[:, 1, 1], r.psi2, rtol=1e-10)
    np.testing.assert_allclose(h[:, 0, 1], 0, atol=1e-9 * np.abs(r.w1).max())


def test_undamped_track_is_the_limit_of_vanishing_damping():
    """Without damping the Bloch waves sit on the unit circle; the result must equal the limit
    of vanishing damping (1e-7 here), and stay passive and reciprocal."""
    f = PAPER_GRID
    for track in (st.slab_track(), st.ballasted_track()):
        a0 = st.semi_infinite_receptance(track.replace(eta_rail=0.0, eta_pad=0.0, eta_ballast=0.0), f)
        a1 = st.semi_infinite_receptance(track.replace(eta_rail=1e-7, eta_pad=1e-7, eta_ballast=1e-7), f)
        rel = np.abs(a0 - a1) / np.abs(a1)
        # Damping of 1e-7 shifts the result by O(1e-7) except next to band edges (measured 2e-4).
        assert np.median(rel) < 1e-6 and rel.max() < 1e-2
        eig = np.linalg.eigvalsh(_hermitian_part_of_mobility(f, a0))
        assert eig.min() >= -1e-12 * np.abs(eig).max()


def test_static_limit_semi_infinite_winkler_beam():
    """At low frequency and small spacing: the end receptance of a semi-infinite Euler-Bernoulli
    beam on a Winkler foundation, in closed form with b = (k_f / 4EI)^(1/4).

    End receptances (Hetenyi): w = 2 b Q / k_f - 2 b^2 M / k_f, psi = -2 b^2 Q / k_f + 4 b^3 M / k_f
    in the paper's signs (downward w and Q, clockwise psi and M). A stiff shear modulus removes the
    Timoshenko correction; the dense supports approach the continuous foundation.
    """
    base = st.slab_track(eta_rail=0.0, eta_pad=0.0, kphi=0.0, G=1e16)
    n = 32
    t = base.replace(spacing=base.spacing / n, kv=base.kv / n)
    k_f = base.kv / base.spacing
    b = (k_f / (4 * base.E * base.I)) ** 0.25
    expected = np.array([[2 * b, -2 * b**2], [-2 * b**2, 4 * b**3]]) / k_f
    a = st.semi_infinite_receptance(t, 0.01)
    # Residual differences: discrete supports (O((b d)^2) ~ 1e-4 at n = 32) and the half support
    # spacing between cut and first support; 1 % is far below any sign or factor-2 error.
    np.testing.assert_allclose(a.real, expected, rtol=1e-2)


# ------------------------------------------------------------------------------------------------
# Robustness: the period's dynamic stiffness against the transfer matrix it replaced
# ------------------------------------------------------------------------------------------------
def _transfer_matrix_end_stiffness(track, f):
    """K_R at a mid-span by the eigenvectors of the period transfer matrix (the textbook route,
    accurate while the evanescent waves grow by much less than 1e16 over a period)."""
    omega, d = 2 * np.pi * f, track.spacing
    kv, kphi = track.support_stiffness(f)
    point = np.broadcast_to(np.eye(4, dtype=complex), (f.size, 4, 4)).copy()
    point[:, 2, 0], point[:, 3, 1] = -kv, -kphi
    half = field_transfer(track, omega, d / 2)
    lam, vec = np.linalg.eig(half @ point @ half)
    decaying = np.argsort(np.abs(lam), axis=-1)[:, :2]  # damped: |lambda| < 1 decays to the right
    v = np.take_along_axis(vec, decaying[:, None, :], axis=-1)
    return v[:, 2:, :] @ np.linalg.inv(v[:, :2, :])


def test_dynamic_stiffness_route_equals_transfer_matrix_route(track):
    f = PAPER_GRID
    k_right, _ = end_stiffness(track.cell(), 2 * np.pi * f, track.spacing / 2)
    np.testing.assert_allclose(k_right, _transfer_matrix_end_stiffness(track, f), rtol=1e-9)


def test_segment_dynamic_stiffness_equals_transfer_matrix_and_is_bounded():
    track = st.slab_track()
    omega = 2 * np.pi * np.array([3.0, 300.0, 3000.0])
    short = segment_dynamic_stiffness(track, omega, [0.3])[0]
    t = field_transfer(track, omega, 0.3)  # s(l) = T s(0); loads on the segment: s_f(0), -s_f(l)
    inv_t12 = np.linalg.inv(t[:, :2, 2:])
    d_aa, d_ab = -inv_t12 @ t[:, :2, :2], inv_t12
    np.testing.assert_allclose(short[:, :2, :2], d_aa, rtol=1e-10)
    np.testing.assert_allclose(short[:, :2, 2:], d_ab, rtol=1e-10)
    # 12 m at 20 kHz: the evanescent wave's e^{kL} ~ 1e400 would overflow a transfer matrix;
    # here every entry is finite and D is symmetric (reciprocity).
    long = segment_dynamic_stiffness(track, [2 * np.pi * 2e4], [12.0])[0, 0]
    assert np.isfinite(long).all()
    np.testing.assert_allclose(long, long.T, rtol=1e-12, atol=1e-12 * np.abs(long).max())


def _assert_reciprocal_and_passive(f, alpha):
    scale = np.sqrt(np.abs(alpha[:, 0, 0] * alpha[:, 1, 1]))
    assert np.all(np.abs(alpha[:, 0, 1] - alpha[:, 1, 0]) <= 1e-9 * scale)
    herm = _hermitian_part_of_mobility(f, alpha)
    # In the balanced scaling of w by sqrt(|a22 / a11|) the eigenvalues are comparable.
    c = np.sqrt(np.abs(alpha[:, 1, 1] / alpha[:, 0, 0]))[:, None, None]
    balance = np.concatenate([np.concatenate([c, np.ones_like(c)], 2)] * 2, 1)
    balance = balance * np.swapaxes(balance, 1, 2)
    eig = np.linalg.eigvalsh(herm * balance)
    assert np.all(eig[:, 0] >= -1e-10 * np.abs(eig).max(axis=1))


@pytest.mark.parametrize("spacing", [0.3, 0.6, 1.0, 2.0, 4.0, 8.0, 12.0])
@pytest.mark.parametrize("make", [st.slab_track, st.ballasted_track])
def test_long_spacings_and_high_frequencies_stay_reciprocal_and_passive(make, spacing):
    """Up to 12 m and 20 kHz the evanescent waves grow by up to e^{500} over a period; the old
    transfer-matrix method returned a12 != a21 from spacing 8 m on."""
    f = np.geomspace(1.0, 2e4, 120)
    _assert_reciprocal_and_passive(f, st.semi_infinite_receptance(make(spacing=spacing), f))


@pytest.mark.parametrize("case", [dict(I=1e-12), dict(G=1e3), dict(kphi=1e20), dict(f=6.7e6), dict(f=5e7),
                                  dict(spacing=10.0, eta_rail=0.0, eta_pad=0.0)])
def test_extreme_but_accepted_inputs_stay_reciprocal_and_passive(case):
    case = dict(case)
    f = np.atleast_1d(case.pop("f", np.geomspace(1.0, 2e4, 60)))
    _assert_reciprocal_and_passive(f, st.semi_infinite_receptance(st.slab_track(**case), f))


def test_unconverged_doubling_is_refused_with_a_clear_message(monkeypatch):
    monkeypatch.setattr(transfer, "_MAX_DOUBLINGS", 1)
    with pytest.raises(ValueError, match="cannot resolve 'slab' at .* frequencies from"):
        st.semi_infinite_receptance(st.slab_track(), [100.0, 1000.0])
