"""The exact (Bloch-wave) method: reciprocity, passivity, symmetry, periodicity, limits."""

import numpy as np

import semitrack as st
from semitrack.base.paper_values import PAPER_GRID
from semitrack.methods.transfer import end_stiffness

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
        h = st.point_receptance(track, f, x)
        # Off-diagonal terms vanish at a support and at mid-span, so compare against the largest
        # entry per frequency: 1e-9 of it is far above rounding and far below any real asymmetry.
        tol = 1e-9 * np.abs(h).max()
        np.testing.assert_allclose(st.point_receptance(track, f, x + 3 * d), h, rtol=1e-9, atol=tol)
        # Mirror symmetry about a support: H(d - x) = P H(x) P.
        np.testing.assert_allclose(st.point_receptance(track, f, d - x), MIRROR @ h @ MIRROR, rtol=1e-8, atol=tol)
    # At mid-span the point receptance holds the central responses w1 and psi2.
    r = st.central_response(track, f)
    h = st.point_receptance(track, f, 0.5 * d)
    np.testing.assert_allclose(h[:, 0, 0], r.w1, rtol=1e-10)
    np.testing.assert_allclose(h[:, 1, 1], r.psi2, rtol=1e-10)
    np.testing.assert_allclose(h[:, 0, 1], 0, atol=1e-9 * np.abs(r.w1).max())


def test_undamped_limit_uses_power_flow():
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
