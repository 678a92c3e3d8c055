"""Public entry points: shapes, input checks, and the continuous-foundation limit."""

import numpy as np
import pytest

import semitrack as st


def test_shapes():
    t = st.slab_track()
    assert st.semi_infinite_receptance(t, 100.0).shape == (2, 2)
    assert st.semi_infinite_receptance(t, [100.0, 200.0, 300.0]).shape == (3, 2, 2)
    assert st.point_receptance(t, np.array([[10.0, 20.0]]), x=0.1, origin="support").shape == (1, 2, 2, 2)
    r = st.central_response(t, [10.0, 20.0])
    assert r.w1.shape == r.psi2.shape == r.Q2.shape == r.M1.shape == r.det.shape == (2,)


@pytest.mark.parametrize("f", [0.0, -3.0, np.nan, np.inf, [10.0, 0.0]])
def test_bad_frequencies_refused(f):
    with pytest.raises(ValueError, match="positive and finite"):
        st.semi_infinite_receptance(st.slab_track(), f)


def test_bad_arguments():
    t = st.slab_track()
    with pytest.raises(TypeError, match="frequencies|Hz"):
        st.semi_infinite_receptance(t, "fast")
    with pytest.raises(ValueError, match="method"):
        st.semi_infinite_receptance(t, 10.0, method="fft")
    with pytest.raises(TypeError, match="no discretisation"):
        st.semi_infinite_receptance(t, 10.0, dx=0.01)
    with pytest.raises(TypeError, match="unknown wavenumber setting"):
        st.semi_infinite_receptance(t, 10.0, method="wavenumber", dz=0.01)
    with pytest.raises(TypeError, match="Track or PeriodicCell"):
        st.semi_infinite_receptance({"kv": 1}, 10.0)
    with pytest.raises(TypeError, match="x"):
        st.point_receptance(t, 10.0, x="mid", origin="support")


def test_closed_form_matches_quadrature():
    """The residue formula against a brute-force Riemann sum of the same inverse Fourier integral."""
    t = st.slab_track()
    kv, kphi = t.pad_stiffness()
    k_f, k_r = kv / t.spacing, kphi / t.spacing
    f = np.array([3.0, 183.0, 945.0])
    ref = st.continuous_foundation_receptance(t, f, k_f, k_r)
    beta = np.linspace(-4000.0, 4000.0, 800_001)
    for fi, r in zip(f, ref):
        w2 = (2 * np.pi * fi) ** 2
        a = t.kAG * beta**2 - w2 * t.mass_per_length + k_f
        b = t.EI * beta**2 + t.kAG - w2 * t.rotary_inertia + k_r
        det = a * b - (t.kAG * beta) ** 2
        step = (beta[1] - beta[0]) / (2 * np.pi)
        # The tails beyond |beta| = 4000 rad/m hold ~1e-3 of the integral.
        assert np.sum(b / det) * step == pytest.approx(r[0, 0], rel=2e-3)
        assert np.sum(a / det) * step == pytest.approx(r[1, 1], rel=2e-3)


def test_dense_supports_tend_to_continuous_foundation():
    """Spacing d/n with kv/n, kphi/n: the periodic track tends to the continuous foundation."""
    base = st.slab_track()
    kv, kphi = base.pad_stiffness()
    f = np.array([3.0, 183.0, 945.0, 2000.0])
    ref = st.continuous_foundation_receptance(base, f, kv / base.spacing, kphi / base.spacing)
    errors = []
    for n in (4, 16, 64):
        t = base.replace(spacing=base.spacing / n, kv=base.kv / n, kphi=base.kphi / n)
        h = st.point_receptance(t, f, x=0.5 * t.spacing, origin="support")
        errors.append(np.max(np.abs(h - ref) / np.abs(ref).max(axis=(1, 2))[:, None, None]))
    # Second-order convergence in d (measured 16x per 4x refinement); 1e-4 at n = 64.
    assert errors[0] / errors[1] > 10 and errors[1] / errors[2] > 10
    assert errors[2] < 1e-4


def test_eq14_refused_for_a_cell_without_mirror_symmetry():
    """Eq. (14) holds only at a mirror plane; an asymmetric cell must not get a silently wrong alpha."""
    t = st.slab_track()
    skew = st.PeriodicCell(t, 1.95, (0.0, 0.2, 0.9))
    assert not skew.is_symmetric_about(skew.mid_span) and t.cell(2).is_symmetric_about(t.cell(2).mid_span)
    with pytest.raises(ValueError, match="symmetric about its central cross-section"):
        st.central_response(skew, 100.0)
    with pytest.raises(ValueError, match="symmetric about its central cross-section"):
        st.semi_infinite_receptance(skew, 100.0, method="wavenumber")
    # The transfer method's alpha = K_R^-1 needs no symmetry: still reciprocal and passive.
    a = st.semi_infinite_receptance(skew, [100.0, 500.0])
    np.testing.assert_allclose(a[:, 0, 1], a[:, 1, 0], rtol=1e-10)


def test_closed_form_takes_any_passive_foundation_and_refuses_an_active_one():
    """Passivity is Im(k) >= 0: a foundation with a negative real part (a mass above its resonance)
    is passive and taken; a negative imaginary part (negative damping) is refused, naming the frequency."""
    t = st.slab_track()
    st.continuous_foundation_receptance(t, 100.0, -8e7)
    st.continuous_foundation_receptance(t, 100.0, 8e7, -1.0)
    with pytest.raises(ValueError, match="k_f is not passive at 100 Hz"):
        st.continuous_foundation_receptance(t, 100.0, 8e7 * (1 - 0.1j))  # negative damping
    with pytest.raises(ValueError, match="k_r is not passive at 250 Hz"):
        st.continuous_foundation_receptance(t, [100.0, 250.0], 8e7, lambda f: 1e4 * (1 - 1j * (f > 200)))
    with pytest.raises(ValueError, match="k_f is not finite"):
        st.continuous_foundation_receptance(t, 100.0, np.inf)
    st.continuous_foundation_receptance(t, 100.0, 8e7, 0.0)  # no rotational foundation is fine
