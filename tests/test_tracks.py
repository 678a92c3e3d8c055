"""Track presets (paper Tables 2 and 5), validation, and the support dynamic stiffness."""

import numpy as np
import pytest

import semitrack as st


def test_slab_preset_is_paper_table2():
    t = st.slab_track()
    assert (t.rho, t.E, t.G, t.A, t.I, t.kappa, t.eta_rail) == (7850.0, 2.1e11, 0.81e11, 7.69e-3, 30.55e-6, 0.4, 0.01)
    assert (t.kv, t.kphi, t.eta_pad, t.spacing) == (5.44e7, 2.83e5, 0.1, 0.65)
    assert not t.is_ballasted
    # The paper's kphi = kv b^2 / 12 with b = 0.25 m, printed rounded to three digits.
    assert t.kphi == pytest.approx(t.kv * 0.25**2 / 12, rel=2e-3)


def test_ballasted_preset_is_paper_table5():
    t = st.ballasted_track()
    assert (t.kv, t.kphi, t.eta_pad, t.sleeper_mass, t.spacing, t.kb, t.eta_ballast) == (
        3.5e8, 1.82e6, 0.1, 150.0, 0.6, 100e6, 0.3)
    assert t.E == st.slab_track().E and t.is_ballasted


def test_overrides_and_replace():
    t = st.slab_track(kv=1e8, spacing=0.6)
    assert (t.kv, t.spacing) == (1e8, 0.6)
    assert t.replace(kphi=0.0).kphi == 0.0  # kphi may be zero


@pytest.mark.parametrize("key,value,rule", [
    ("kv", -5e7, "positive and finite"),
    ("spacing", 0.0, "positive and finite"),
    ("E", float("nan"), "positive and finite"),
    ("A", float("inf"), "positive and finite"),
    ("kphi", -1.0, "non-negative"),
    ("eta_pad", -0.1, "non-negative"),
])
def test_bad_parameters_are_named(key, value, rule):
    with pytest.raises(ValueError) as err:
        st.slab_track(**{key: value})
    assert key in str(err.value) and rule in str(err.value) and repr(value) in str(err.value)


def test_bad_types_and_keys():
    with pytest.raises(TypeError, match="kv"):
        st.slab_track(kv="stiff")
    with pytest.raises(TypeError, match="unknown track parameter"):
        st.slab_track(k_v=1e8)
    with pytest.raises(TypeError, match="unknown track parameter"):
        st.slab_track(sleeper_mass=150.0)  # the slab preset has a rigid foundation
    with pytest.raises(ValueError, match="sleeper_mass and kb"):
        st.Track(**{**st.slab_track().__dict__, "sleeper_mass": 150.0})
    with pytest.raises(ValueError, match="sleeper_mass"):
        st.ballasted_track(sleeper_mass=-1.0)


def test_slab_support_is_damped_pad():
    t = st.slab_track()
    kv, kphi = t.support_stiffness([10.0, 1000.0])
    np.testing.assert_allclose(kv, 5.44e7 * (1 + 0.1j), rtol=1e-14)
    np.testing.assert_allclose(kphi, 2.83e5 * (1 + 0.1j), rtol=1e-14)


def test_ballasted_support_matches_two_dof_solve():
    """Pad in series with sleeper mass on ballast, against a direct 2-DOF dynamic solve."""
    t = st.ballasted_track()
    f = np.array([3.0, 117.0, 243.0, 900.0])
    kv_dyn, _ = t.support_stiffness(f)
    kp, kb = 3.5e8 * (1 + 0.1j), 100e6 * (1 + 0.3j)
    for fi, k in zip(f, kv_dyn):
        w = 2 * np.pi * fi
        # DOFs (rail seat w, sleeper z); unit displacement imposed at the rail seat.
        z = kp / (kp + kb - w**2 * 150.0)
        force = kp * (1 - z)
        assert k == pytest.approx(force, rel=1e-12)
    # Static limit: springs in series.
    assert t.support_stiffness(1e-6)[0] == pytest.approx(kp * kb / (kp + kb), rel=1e-9)


def test_bouncing_estimate_is_papers_formula():
    t = st.slab_track()
    assert t.bouncing_frequency_estimate == pytest.approx(np.sqrt(5.44e7 / (7850 * 7.69e-3 * 0.65)) / (2 * np.pi))


def test_periodic_cell_checks():
    t = st.slab_track()
    cell = t.cell(2)
    assert cell.period == pytest.approx(1.3) and cell.positions == (0.0, 0.65) and cell.mid_span == pytest.approx(0.325)
    with pytest.raises(ValueError, match="positions"):
        st.PeriodicCell(t, 1.0, (0.5, 0.2))
    with pytest.raises(ValueError, match="0 <= x_s < period"):
        st.PeriodicCell(t, 1.0, (1.0,))
    with pytest.raises(TypeError, match="supports_per_period"):
        t.cell(1.5)
