"""Tests of the equivalent multi-rigid-body systems, their constraints, the paper tables and metrics."""

from __future__ import annotations

import pickle

import numpy as np
import pytest

from semitrack.equivalent.assembly import (
    IllConditionedError,
    assembly,
    dynamic_stiffness,
    end_loads,
    scaled_solve,
)
from semitrack.equivalent.constraints import (
    ballasted_constraints,
    ballasted_from_free,
    cell_frequencies,
    slab_constraints,
    slab_from_free,
    support_mass_frequency,
    unit_cell_frequencies,
)
from semitrack.equivalent.metrics import error_band_grid, error_summary, receptance_errors
from semitrack.equivalent.systems import PARAMETER_UNITS, BallastedEquivalent, EquivalentSystem, SlabEquivalent
from semitrack.paper.systems import paper_consistency_report, paper_table4, paper_table7

TWO_PI = 2 * np.pi
F_BAND = np.arange(3.0, 3001.0, 3.0)  # the paper's plotting range, 3 Hz steps

# Matrices built two ways differ only by rounding in sums of products of numbers spanning
# ~1e-3..1e9; relative to the largest entry that is a few 1e-16, so 1e-12 leaves ample margin
# while any wrong term (O(1) relative) fails.
ASSEMBLY_RTOL = 1e-12
# Receptances from a batched solve vs. a hand inversion: the scaled condition number of the
# dynamic stiffness is below ~1e4 here, so ~1e-12 relative error at most; 1e-9 is safe.
SOLVE_RTOL = 1e-9


def random_slab(n, seed=0):
    rng = np.random.default_rng(seed)
    return SlabEquivalent(
        m=rng.uniform(5, 200, n), J=rng.uniform(0.01, 5, n), L=rng.uniform(0.1, 0.7, n),
        k=rng.uniform(1e6, 1e8, n), c_l=rng.uniform(0, 1e4, n), c_r=rng.uniform(0, 1e4, n),
        k_phi=rng.uniform(1e5, 1e7, n - 1), c_phi=rng.uniform(0, 1e3, n - 1),
    )


def random_ballasted(n, seed=0):
    rng = np.random.default_rng(seed + 100)
    base = random_slab(n, seed).parameters()
    return BallastedEquivalent(
        **base, mu=rng.uniform(10, 300, n), s=rng.uniform(1e6, 1e8, n),
        d_l=rng.uniform(0, 1e4, n), d_r=rng.uniform(0, 1e4, n),
    )


# --- direct Lagrangian: energies evaluated point by point, independent of the matrix assembly ----
def _walk(system, q):
    """Left end, centre and right end displacement of each bar, walking along the chain."""
    N = system.n_bars
    w = q[0]
    left, centre, right = [], [], []
    for j in range(N):
        phi = q[1 + j]
        left.append(w)
        centre.append(w + 0.5 * system.L[j] * phi)
        w = w + system.L[j] * phi
        right.append(w)
    return np.array(left), np.array(centre), np.array(right)


def _energies(system, q):
    """(2T, 2D, 2U) for the generalised velocities/displacements q (T kinetic, D Rayleigh)."""
    N = system.n_bars
    left, centre, right = _walk(system, q)
    phi = q[1 : N + 1]
    rel = np.diff(phi)
    T2 = np.sum(system.m * centre**2) + np.sum(system.J * phi**2)
    U2 = np.sum(system.k_phi * rel**2)
    D2 = np.sum(system.c_phi * rel**2)
    if isinstance(system, BallastedEquivalent):
        wl, wr = q[N + 1 : 2 * N + 1], q[2 * N + 1 :]
        T2 += np.sum(system.mu * wl**2) + np.sum(system.mu * wr**2)
        U2 += np.sum(system.k * (left - wl) ** 2 + system.s * wl**2 + system.k * (right - wr) ** 2 + system.s * wr**2)
        D2 += np.sum(system.c_l * (left - wl) ** 2 + system.d_l * wl**2
                     + system.c_r * (right - wr) ** 2 + system.d_r * wr**2)
    else:
        U2 += np.sum(system.k * (left**2 + right**2))
        D2 += np.sum(system.c_l * left**2 + system.c_r * right**2)
    return T2, D2, U2


def lagrangian_matrices(system):
    """M, C, K by polarisation of the quadratic forms: X_ij = (Q(e_i + e_j) - Q(e_i) - Q(e_j)) / 2."""
    n = system.n_dof
    E = np.eye(n)
    single = [np.array(_energies(system, E[i])) for i in range(n)]
    out = np.zeros((3, n, n))
    for i in range(n):
        for j in range(n):
            both = np.array(_energies(system, E[i] + E[j]))
            out[:, i, j] = 0.5 * (both - single[i] - single[j])
    return out[0], out[1], out[2]


def assert_matrix_close(A, B):
    scale = np.max(np.abs(B))
    np.testing.assert_allclose(A, B, rtol=0, atol=ASSEMBLY_RTOL * scale)


# --- structure ------------------------------------------------------------------------------
@pytest.mark.parametrize("system", [paper_table4(), paper_table7(), random_slab(3), random_ballasted(4)],
                         ids=["table4", "table7", "slab3", "ballasted4"])
def test_matrices_symmetric_psd_and_sized(system):
    M, C, K = system.matrices()
    N = system.n_bars
    n_expected = N + 1 if system.layout == "slab" else 3 * N + 1
    assert system.n_dof == n_expected == len(system.dof_names())
    for X in (M, C, K):
        assert X.shape == (n_expected, n_expected) and X.dtype == float
        np.testing.assert_array_equal(X, X.T)  # symmetrised exactly after the assembly check
        ev = np.linalg.eigvalsh(X)
        # PSD up to rounding: eigenvalues >= -1e-12 of the largest (eigvalsh is backward stable).
        assert ev[0] >= -1e-12 * np.max(np.abs(ev))


def test_dof_names():
    assert paper_table4().dof_names() == ["w1 (m)"] + [f"phi_{j} (rad)" for j in range(1, 6)]
    names = random_ballasted(2).dof_names()
    assert names == ["w1 (m)", "phi_1 (rad)", "phi_2 (rad)", "w_l1 (m)", "w_l2 (m)", "w_r1 (m)", "w_r2 (m)"]


def test_slab_single_bar_by_hand():
    m, J, L, k, cl, cr = 12.0, 0.3, 0.6, 3e7, 150.0, 400.0
    sys1 = SlabEquivalent(m=[m], J=[J], L=[L], k=[k], c_l=[cl], c_r=[cr], k_phi=[], c_phi=[])
    # DOFs (w1 at the left end, phi): centre at w1 + phi L/2, springs at w1 and w1 + phi L.
    M_hand = np.array([[m, m * L / 2], [m * L / 2, m * L**2 / 4 + J]])
    K_hand = np.array([[2 * k, k * L], [k * L, k * L**2]])
    C_hand = np.array([[cl + cr, cr * L], [cr * L, cr * L**2]])
    for A, B in zip(sys1.matrices(), (M_hand, C_hand, K_hand)):
        assert_matrix_close(A, B)
    # Receptance by explicit 2x2 inversion.
    f = np.array([10.0, 183.0, 700.0])
    w = TWO_PI * f
    Z = K_hand + 1j * w[:, None, None] * C_hand - w[:, None, None] ** 2 * M_hand
    det = Z[:, 0, 0] * Z[:, 1, 1] - Z[:, 0, 1] * Z[:, 1, 0]
    alpha_hand = np.stack([np.stack([Z[:, 1, 1], -Z[:, 0, 1]], -1), np.stack([-Z[:, 1, 0], Z[:, 0, 0]], -1)], -2)
    alpha_hand /= det[:, None, None]
    np.testing.assert_allclose(sys1.receptance(f), alpha_hand, rtol=SOLVE_RTOL)


def test_ballasted_single_bar_by_hand():
    m, J, L, k, cl, cr, mu, s, dl, dr = 20.0, 0.5, 0.5, 5e7, 100.0, 300.0, 40.0, 2e7, 2e3, 5e3
    sys1 = BallastedEquivalent(m=m, J=J, L=L, k=k, c_l=cl, c_r=cr, k_phi=[], c_phi=[],
                               mu=mu, s=s, d_l=dl, d_r=dr)
    # DOFs (w1, phi, w_l, w_r); upper springs stretched by w1 - w_l and w1 + phi L - w_r.
    M_hand = np.array([[m, m * L / 2, 0, 0], [m * L / 2, m * L**2 / 4 + J, 0, 0], [0, 0, mu, 0], [0, 0, 0, mu]])
    K_hand = np.array([[2 * k, k * L, -k, -k], [k * L, k * L**2, 0, -k * L],
                       [-k, 0, k + s, 0], [-k, -k * L, 0, k + s]])
    C_hand = np.array([[cl + cr, cr * L, -cl, -cr], [cr * L, cr * L**2, 0, -cr * L],
                       [-cl, 0, cl + dl, 0], [-cr, -cr * L, 0, cr + dr]])
    for A, B in zip(sys1.matrices(), (M_hand, C_hand, K_hand)):
        assert_matrix_close(A, B)


@pytest.mark.parametrize("system", [random_slab(4, 1), random_ballasted(3, 2), paper_table4(), paper_table7()],
                         ids=["slab4", "ballasted3", "table4", "table7"])
def test_assembly_matches_direct_lagrangian(system):
    """Appendix A/B assembly vs. energies written point by point (Eq. A.13, A.17, B.13, B.16, B.21)."""
    for A, B in zip(system.matrices(), lagrangian_matrices(system)):
        assert_matrix_close(A, B)


def test_static_limit_is_condensed_flexibility():
    system = random_slab(4, 3)
    M, C, K = system.matrices()
    # At 1e-9 Hz the inertia and damping terms are ~1e-16 and ~1e-11 of K: 1e-9 is generous.
    np.testing.assert_allclose(system.receptance(1e-9), np.linalg.inv(K)[:2, :2], rtol=1e-9)


def test_receptance_shapes_and_end_stiffness():
    system = paper_table7()
    assert system.receptance(100.0).shape == (2, 2)
    assert system.receptance([100.0]).shape == (1, 2, 2)
    a = system.receptance(F_BAND)
    assert a.shape == (F_BAND.size, 2, 2) and a.dtype == complex
    # Inverse of a well-conditioned 2x2: rounding only.
    np.testing.assert_allclose(system.end_stiffness(F_BAND) @ a, np.broadcast_to(np.eye(2), a.shape), atol=1e-10)


@pytest.mark.parametrize("system", [paper_table4(), paper_table7()], ids=["table4", "table7"])
def test_reciprocity_and_passivity(system):
    a = system.receptance(F_BAND)
    # The dynamic stiffness is symmetric, so alpha12 = alpha21 up to solver rounding.
    np.testing.assert_allclose(a[:, 0, 1], a[:, 1, 0], rtol=1e-10)
    report = system.is_passive(F_BAND)
    assert report, f"not passive: worst at {report.worst_frequency} Hz"
    assert report.min_eig_mobility.shape == F_BAND.shape


def test_passivity_detects_negative_damping():
    # Bypass validation to build an active system: its mobility must fail the check.
    system = random_slab(2, 4)
    object.__setattr__(system, "c_l", np.array([-5e4, 0.0]))
    report = system.is_passive(F_BAND)
    assert not report and report.min_eig_C < 0


def test_singular_dynamic_stiffness_raises():
    zeros = SlabEquivalent(m=[0, 0], J=[0, 0], L=[1, 1], k=[0, 0], c_l=[0, 0], c_r=[0, 0], k_phi=[0], c_phi=[0])
    with pytest.raises(ValueError, match="singular"):
        zeros.receptance(50.0)
    # An undamped bar at its repeated natural frequency is singular too.
    undamped = slab_from_free(m=[10.0], L=[0.5], c_l=[0], c_r=[0], k_phi=[], c_phi=[], f_n=183.0)
    with pytest.raises(ValueError, match="singular"):
        undamped.receptance(183.0)


# --- mirrored system (Sec. 5.3) -------------------------------------------------------------------
def test_mirrored_single_slab_bar_closed_form():
    """Two mirrored copies of one slab bar form a bar of length 2L centred on the junction with
    springs 2k (both left ends) at the centre and k at each outer end."""
    m, J, L, k, cl, cr = 15.0, 0.4, 0.6, 4e7, 300.0, 800.0
    sys1 = SlabEquivalent(m=m, J=J, L=L, k=k, c_l=cl, c_r=cr, k_phi=[], c_phi=[])
    f = np.array([20.0, 150.0, 900.0])
    w = TWO_PI * f
    z_w = 4 * k + 1j * w * (2 * cl + 2 * cr) - w**2 * 2 * m
    z_phi = 2 * k * L**2 + 1j * w * 2 * cr * L**2 - w**2 * 2 * (J + m * L**2 / 4)
    a = sys1.mirrored_receptance(f)
    np.testing.assert_allclose(a[:, 0, 0], 1 / z_w, rtol=SOLVE_RTOL)
    np.testing.assert_allclose(a[:, 1, 1], 1 / z_phi, rtol=SOLVE_RTOL)
    # Symmetry: a vertical force does not rotate the junction. Off-diagonals are the cancellation
    # of two equal terms, so compare with the diagonal magnitude.
    assert np.max(np.abs(a[:, 0, 1])) < 1e-10 * np.max(np.abs(a[:, 0, 0]))


@pytest.mark.parametrize("system", [random_slab(3, 5), paper_table7()], ids=["slab3", "table7"])
def test_mirrored_matches_doubled_assembly(system):
    """Assemble both copies as one system: the left copy uses its own (mirrored) coordinates,
    joined by w1' = w1 and phi_1' = -phi_1 (clockwise seen in the mirror is anticlockwise)."""
    n = system.n_dof
    T = np.zeros((2 * n, 2 * n - 2))
    T[:n, :n] = np.eye(n)
    T[n, 0] = 1.0
    T[n + 1, 1] = -1.0
    T[n + 2 :, n:] = np.eye(n - 2)
    f = np.array([30.0, 117.0, 243.0, 600.0])
    Z = system.dynamic_stiffness(f)
    Z2 = np.zeros((f.size, 2 * n, 2 * n), dtype=complex)
    Z2[:, :n, :n] = Z
    Z2[:, n:, n:] = Z
    Zt = T.T @ Z2 @ T
    expected = np.linalg.inv(Zt)[:, :2, :2]
    got = system.mirrored_receptance(f)
    # Two different solves agree to rounding, relative to the largest entry at each frequency.
    dev = np.max(np.abs(got - expected), axis=(1, 2)) / np.max(np.abs(expected), axis=(1, 2))
    assert np.all(dev < 1e-9), dev
    # Vertical junction receptance = 1 / (2 K_R[0, 0]).
    np.testing.assert_allclose(got[:, 0, 0], 0.5 / system.end_stiffness(f)[:, 0, 0], rtol=SOLVE_RTOL)


# --- constraint relations --------------------------------------------------------------------------
# The cell frequencies come from an eigen-solution in other coordinates; agreement is limited by
# eigh's rounding (~1e-15 relative on omega^2), so 1e-9 is a strict but safe bound.
CELL_RTOL = 1e-9


def test_slab_constraints_give_repeated_cell_frequency():
    m, L = np.array([10.0, 67.0, 257.0]), np.array([0.09, 0.43, 0.12])
    system = slab_from_free(m, L, c_l=[0, 1, 2], c_r=[3, 4, 5], k_phi=[1e7, 2e7], c_phi=[1, 2], f_n=183.0)
    np.testing.assert_allclose(cell_frequencies(system), 183.0, rtol=CELL_RTOL)
    d = slab_constraints(m, L, 183.0)
    np.testing.assert_allclose(system.k, d["k"])
    np.testing.assert_allclose(system.J, m * L**2 / 4)
    # For N = 1 the whole system is one cell: its own matrices give the same repeated frequency.
    one = slab_from_free([8.0], [0.3], [0], [0], [], [], f_n=200.0)
    M, _, K = one.matrices()
    lam = np.linalg.eigvals(np.linalg.solve(M, K)).real
    np.testing.assert_allclose(np.sqrt(lam) / TWO_PI, 200.0, rtol=CELL_RTOL)


def test_ballasted_constraints_give_two_repeated_pairs_and_anti_resonance():
    f1, f2, fa = 117.0, 465.0, 243.0
    m, L = np.array([7.5, 28.4, 246.0]), np.array([0.19, 0.40, 0.35])
    system = ballasted_from_free(m, L, c_l=[0, 0, 0], c_r=[0, 0, 0], k_phi=[1e7, 1e7], c_phi=[0, 0],
                                 d_l=[1, 1, 1], d_r=[1, 1, 1], f_n1=f1, f_n2=f2, f_anti=fa)
    np.testing.assert_allclose(cell_frequencies(system), np.tile([f1, f1, f2, f2], (3, 1)), rtol=CELL_RTOL)
    np.testing.assert_allclose(support_mass_frequency(system.k, system.s, system.mu), fa, rtol=CELL_RTOL)
    d = ballasted_constraints(m, L, f1, f2, fa)
    for key in ("k", "J", "s", "mu"):
        np.testing.assert_allclose(getattr(system, key), d[key])
    # N = 1: the class's own matrices reproduce the cell frequencies.
    one = ballasted_from_free([20.0], [0.4], [0], [0], [], [], [0], [0], f_n1=f1, f_n2=f2, f_anti=fa)
    M, _, K = one.matrices()
    lam = np.sort(np.linalg.eigvals(np.linalg.solve(M, K)).real)
    np.testing.assert_allclose(np.sqrt(lam) / TWO_PI, [f1, f1, f2, f2], rtol=CELL_RTOL)


def test_unit_cell_frequencies_closed_form():
    # Bar of mass m on two springs k: bounce sqrt(2k/m), pitch sqrt(k L^2 / (2 J)).
    m, J, L, k = 10.0, 0.1, 0.4, 1e7
    got = unit_cell_frequencies(m, J, L, k)
    want = np.sort([np.sqrt(2 * k / m), np.sqrt(k * L**2 / (2 * J))]) / TWO_PI
    np.testing.assert_allclose(got, want, rtol=CELL_RTOL)


def test_ballasted_constraints_reject_bad_frequency_order():
    with pytest.raises(ValueError, match="f_anti must lie strictly between"):
        ballasted_constraints([1.0], [0.5], 117.0, 465.0, 500.0)
    with pytest.raises(ValueError, match="f_n must be positive"):
        slab_constraints([1.0], [0.5], -1.0)


def test_paper_consistency_report():
    r = paper_consistency_report()
    t4, t7 = r["table4"], r["table7"]
    massive = t4["m"] > 0
    # Table 4: Eq. (19)/(20) hold within what rounding to the printed digits explains.
    assert np.all(np.abs(t4["k_rel_dev"][massive]) <= t4["k_rounding"][massive])
    assert np.all(np.abs(t4["J_rel_dev"][massive]) <= t4["J_rounding"][massive])
    np.testing.assert_allclose(t4["f_bounce_implied"][massive], 183.0, rtol=5e-4)
    assert np.all(np.isnan(t4["cell_f1"][~massive]))
    # Table 7: Eq. (28) holds within rounding; with either stated f_n2 Eq. (29) is off by the same
    # factor for every bar (so k/m is common to all bars), and the f_n2 implied by k/m lies
    # between the two values the paper states.
    assert np.all(np.abs(t7["J_rel_dev"]) <= t7["J_rounding"])
    for tag in ("465", "489"):
        dev = t7[f"k_rel_dev_{tag}"]
        assert np.ptp(dev) < 1e-3 and np.min(np.abs(dev)) > 10 * np.max(t7["k_rounding"])
    assert np.all((t7["f_n2_from_k"] > 465.0) & (t7["f_n2_from_k"] < 489.0))
    # Eq. (23) holds within rounding for bars 2-5; bar 1 is the outlier the audit reports.
    assert np.all(np.abs(t7["mu_rel_dev"][1:]) <= t7["mu_rounding"][1:])
    assert abs(t7["mu_rel_dev"][0]) > 100 * t7["mu_rounding"][0]


# --- validation and bookkeeping -----------------------------------------------------------------------
def _slab_kwargs(n=2):
    return random_slab(n).parameters()


@pytest.mark.parametrize(
    "change, exc, pattern",
    [
        (dict(m=[10.0, -1.0]), ValueError, r"m\[1\] must be non-negative and finite, got -1\.0"),
        (dict(L=[0.5, 0.0]), ValueError, r"L\[1\] must be positive and finite, got 0\.0"),
        (dict(k=[1e7, np.nan]), ValueError, r"k\[1\] must be non-negative and finite, got nan"),
        (dict(c_r=[1.0, 2.0, 3.0]), ValueError, r"c_r must have one value per bar \(length N = 2"),
        (dict(k_phi=[1.0, 2.0]), ValueError, r"k_phi must have one value per hinge \(length N - 1 = 1\)"),
        (dict(J=[[1.0, 2.0]]), ValueError, r"J must be one-dimensional"),
        (dict(c_phi=["a"]), TypeError, r"c_phi must be an array of real numbers"),
        (dict(m=[1 + 1j, 2.0]), TypeError, r"m must be an array of real numbers"),
    ],
)
def test_bad_parameters_raise(change, exc, pattern):
    kwargs = _slab_kwargs() | change
    with pytest.raises(exc, match=pattern):
        SlabEquivalent(**kwargs)


def test_bad_ballasted_parameters_raise():
    p = random_ballasted(2).parameters()
    with pytest.raises(ValueError, match=r"mu\[0\] must be non-negative"):
        BallastedEquivalent(**(p | dict(mu=[-1.0, 1.0])))
    with pytest.raises(ValueError, match=r"s must have one value per bar"):
        BallastedEquivalent(**(p | dict(s=[1.0])))


@pytest.mark.parametrize("f", [0.0, -3.0, [10.0, 0.0], np.inf, np.nan, [[1.0, 2.0]]])
def test_bad_frequencies_raise(f):
    with pytest.raises(ValueError, match="f must"):
        paper_table4().receptance(f)


def test_abstract_base_and_from_parameters():
    with pytest.raises(TypeError, match="abstract"):
        EquivalentSystem(**_slab_kwargs())
    t7 = paper_table7()
    assert EquivalentSystem.from_parameters(t7.parameters()) == t7
    assert EquivalentSystem.from_parameters(paper_table4().parameters() | {"layout": "slab"}) == paper_table4()
    assert BallastedEquivalent.from_parameters(t7.parameters()) == t7
    with pytest.raises(TypeError, match="unknown parameter"):
        SlabEquivalent.from_parameters(t7.parameters())
    with pytest.raises(TypeError, match="missing parameter"):
        BallastedEquivalent.from_parameters(paper_table4().parameters())
    with pytest.raises(ValueError, match="layout must be one of"):
        EquivalentSystem.from_parameters(t7.parameters() | {"layout": "floating"})


def test_immutability_equality_hash():
    t4 = paper_table4()
    with pytest.raises(ValueError):
        t4.m[0] = 1.0  # read-only array
    p = t4.parameters()
    p["m"][0] = 1.0  # a copy: the system is unchanged
    assert t4.m[0] == 10.080
    assert t4 == paper_table4() and hash(t4) == hash(paper_table4())
    assert t4 != t4.replace(k_phi=[1.0, 1.0, 1.0, 1.0])
    assert paper_table4() != paper_table7()


def test_paper_tables_as_printed():
    t4, t7 = paper_table4(), paper_table7()
    assert t4.n_bars == t7.n_bars == 5
    assert t4.k_phi.size == t4.c_phi.size == 4
    np.testing.assert_array_equal(t4.m[[1, 3]], 0.0)
    np.testing.assert_array_equal(t4.k[[1, 3]], 0.0)
    np.testing.assert_allclose(t7.k_phi, [1.337e7, 0.650e7, 1.103e7, 0.347e7])
    np.testing.assert_allclose(t7.c_phi, [1373.233, 122.498, 3126.892, 16752.988])


# --- metrics ------------------------------------------------------------------------------------------
def test_receptance_errors_and_summary():
    ref = paper_table7().receptance(F_BAND[:50])
    assert all(np.all(e == 0) for e in receptance_errors(ref, ref).values())
    scaled = ref * 1.1  # a 10 % error everywhere, to rounding
    s = error_summary(scaled, ref)
    assert set(s.per_element) == {"alpha11", "alpha12", "alpha22"}
    np.testing.assert_allclose([s.median, s.max], 0.1, rtol=1e-12)
    assert s.element_maxima()["alpha22"] == pytest.approx(0.1, rel=1e-12)
    assert error_summary(ref[0], ref[0]).max == 0  # a single 2x2 is accepted
    with pytest.raises(ValueError, match="same shape"):
        receptance_errors(ref[:3], ref[:4])
    bad = ref.copy()
    bad[2, 1, 1] = 0
    with pytest.raises(ValueError, match="alpha22 must be non-zero"):
        receptance_errors(ref, bad)


def test_error_band_grid():
    g = error_band_grid((3.0, 900.0))
    assert g[0] == 3.0 and g[-1] == 900.0
    assert np.max(np.diff(g)) <= 3.0 * (1 + 1e-12)  # linspace rounding only
    g = error_band_grid((3.0, 10.0), df=3.0)
    assert g.size == 4 and np.max(np.diff(g)) <= 3.0
    with pytest.raises(ValueError, match="band must satisfy"):
        error_band_grid((900.0, 3.0))
    with pytest.raises(ValueError, match="df must be positive"):
        error_band_grid((3.0, 900.0), df=0)


# --- the shared assembly (assembly.py) ---------------------------------------------------------------
# Central differences with a relative step of 1e-6: truncation ~1e-12, rounding ~1e-10 of the
# largest derivative; a wrong term is O(1).
SENSITIVITY_RTOL = 1e-6


@pytest.mark.parametrize("system", [random_slab(3, 7), random_ballasted(3, 8)], ids=["slab3", "ballasted3"])
def test_receptance_sensitivities_match_finite_differences(system):
    """d alpha / d v and d alpha / d L of the assembly, against differences of the system's receptance."""
    f = np.array([40.0, 180.0, 650.0])
    pairs = ((0, 0), (0, 1), (1, 1))
    params = system.parameters()
    asm = assembly(system.layout, system.n_bars)
    M, C, K = system.matrices()
    X = scaled_solve(dynamic_stiffness(M, C, K, TWO_PI * f), end_loads(system.n_dof))
    d_values, d_lengths = asm.receptance_sensitivities(X, params, TWO_PI * f, pairs)

    def alpha(name, j, h):
        changed = params[name].copy()
        changed[j] += h
        a = system.replace(**{name: changed}).receptance(f)
        return np.stack([a[:, i, k] for i, k in pairs], axis=1)

    for name in ("k", "c_r", "m", "k_phi", "L"):
        for j in range(params[name].size):
            h = 1e-6 * params[name][j]
            fd = (alpha(name, j, h) - alpha(name, j, -h)) / (2 * h)
            if name == "L":
                got = d_lengths[:, :, j]
            else:  # one value enters through every term of its family (k: both ends)
                got = d_values[name][:, j, :]
            np.testing.assert_allclose(got, fd, rtol=0, atol=SENSITIVITY_RTOL * np.max(np.abs(fd)))


def test_scaled_solve_refuses_a_singular_dynamic_stiffness():
    Z = np.zeros((2, 3, 3), complex)
    Z[:, 0, 0] = Z[:, 1, 1] = 1.0  # the third coordinate is free
    with pytest.raises(IllConditionedError) as info:
        scaled_solve(Z, np.eye(3)[:, :2], cond_limit=1e12)
    assert info.value.index == 0 and info.value.n_bad == 2
    with pytest.raises(np.linalg.LinAlgError):  # without the check, numpy's own error
        scaled_solve(Z, np.eye(3)[:, :2])


@pytest.mark.parametrize("system", [paper_table4(), paper_table7()], ids=["table4", "table7"])
def test_pickle_round_trip_keeps_arrays_read_only(system):
    system.matrices()  # the cached matrices travel too
    back = pickle.loads(pickle.dumps(system))
    assert back == system
    assert not back.m.flags.writeable and not back._mck[0].flags.writeable
    with pytest.raises(ValueError):
        back.k[0] = 1.0


# --- natural frequencies, bar motion, repr ----------------------------------------------------------
def test_highest_natural_frequency_of_a_single_mass_spring():
    # A ballasted bar without mass and upper springs leaves each support mass mu on its spring s:
    # two single mass-springs at sqrt(s / mu) / (2 pi); the massless bar is condensed out.
    mu, s = 40.0, 3e7
    oscillator = BallastedEquivalent(m=0.0, J=0.0, L=0.5, k=0.0, c_l=0.0, c_r=0.0, k_phi=[], c_phi=[],
                                     mu=mu, s=s, d_l=0.0, d_r=0.0)
    f_closed = np.sqrt(s / mu) / TWO_PI
    np.testing.assert_allclose(oscillator.natural_frequencies(), [f_closed, f_closed], rtol=1e-12)
    assert oscillator.highest_natural_frequency() == pytest.approx(f_closed, rel=1e-12)
    assert oscillator.central_difference_time_step() == pytest.approx(2 / (TWO_PI * f_closed), rel=1e-12)


def test_highest_natural_frequency_of_a_single_bar_bounce_and_pitch():
    m, L, k = 12.0, 0.6, 3e7
    J = m * L**2 / 12  # a slender bar: pitch sqrt(k L^2 / (2 J)) above bounce sqrt(2 k / m)
    bar = SlabEquivalent(m=m, J=J, L=L, k=k, c_l=0.0, c_r=0.0, k_phi=[], c_phi=[])
    # Bounce and pitch about the centre of mass (taken at mid-length) decouple.
    expected = np.sort([np.sqrt(2 * k / m), np.sqrt(k * L**2 / (2 * J))]) / TWO_PI
    np.testing.assert_allclose(bar.natural_frequencies(), expected, rtol=1e-12)
    assert bar.highest_natural_frequency() == pytest.approx(expected[-1], rel=1e-12)


def test_massless_bars_are_condensed_not_infinite():
    one = SlabEquivalent(m=12.0, J=0.3, L=0.6, k=3e7, c_l=0.0, c_r=0.0, k_phi=[], c_phi=[])
    # The same bar with a massless, springless second bar on a hinge: it follows statically.
    two = SlabEquivalent(m=[12.0, 0.0], J=[0.3, 0.0], L=[0.6, 0.4], k=[3e7, 0.0], c_l=[0.0, 0.0],
                         c_r=[0.0, 0.0], k_phi=[1e6], c_phi=[0.0])
    np.testing.assert_allclose(two.natural_frequencies(), one.natural_frequencies(), rtol=1e-10)
    # The paper's Table 4 (bars 2 and 4 massless): finite, above the fitted band.
    assert 900.0 < paper_table4().highest_natural_frequency() < 1e5
    # A light (not massless) bar keeps its own, higher frequency.
    light = two.replace(m=[12.0, 1e-3], J=[0.3, 1e-5])
    assert light.highest_natural_frequency() > 10 * one.highest_natural_frequency()
    # No inertia at all: no natural frequency and no step limit.
    empty = one.replace(m=0.0, J=0.0)
    assert empty.natural_frequencies().size == 0 and empty.highest_natural_frequency() == 0.0
    assert empty.central_difference_time_step() == np.inf


def test_bar_centre_motion_single_bar_closed_form():
    bar = SlabEquivalent(m=10.0, J=0.2, L=0.6, k=1e7, c_l=500.0, c_r=500.0, k_phi=[], c_phi=[])
    f = np.array([50.0, 300.0])
    a = bar.receptance(f)
    # Under an end force: w1 = a11, phi_1 = a21, so the centre moves w1 + (L/2) phi_1.
    np.testing.assert_allclose(bar.bar_centre_motion(f)[:, 0], 1 + 0.3 * a[:, 1, 0] / a[:, 0, 0], rtol=1e-12)
    ratios = np.abs(paper_table7().bar_centre_motion(f))
    assert ratios.shape == (2, 5) and np.all(ratios[:, -1] < ratios[:, 0])


@pytest.mark.parametrize("system", [paper_table4(), paper_table7()], ids=["table4", "table7"])
def test_repr_lists_each_parameter_with_its_unit(system):
    text = repr(system)
    lines = text.splitlines()
    assert lines[0].startswith(f"{type(system).__name__}: N = 5 bars, {system.n_dof} DOFs")
    for name in system.parameter_names():
        unit = f"({PARAMETER_UNITS[name]})"
        assert any(line.split()[0] == name and line.split(unit)[0].strip() == name for line in lines), name
    assert f"highest natural frequency {system.highest_natural_frequency():.0f} Hz" in lines[-1]
    dt = f"dt < {1e6 * system.central_difference_time_step():.3g} µs"
    assert dt in lines[-1]
    assert "array(" not in text and "nan" not in text
    assert max(len(line) for line in lines) <= 90


def test_dynamic_stiffness_is_k_plus_i_omega_c_minus_omega_squared_m():
    """Assembled by real and imaginary parts for real matrices (the fit's hot path), by the
    complex formula otherwise (a complex K keeps its imaginary part); both equal the formula."""
    rng = np.random.default_rng(2)
    M, C, K = (rng.standard_normal((3, 3)) for _ in range(3))
    omega = np.array([0.0, 2.0, 1e3])
    w = omega[:, None, None]
    np.testing.assert_array_equal(dynamic_stiffness(M, C, K, omega), K + 1j * w * C - w**2 * M)
    K_lossy = K * (1 + 0.1j)
    np.testing.assert_array_equal(dynamic_stiffness(M, C, K_lossy, omega), K_lossy + 1j * w * C - w**2 * M)
