"""Track presets (paper Tables 2 and 5), validation, and the support dynamic stiffness."""

import dataclasses

import numpy as np
import pytest

import semitrack as st
from semitrack.base.paper_values import PAD_LENGTH, TABLE2_RAIL, TABLE2_SLAB, TABLE5_BALLASTED
from semitrack.model.tracks import FIELD_RULES, require_cell


def test_slab_preset_is_paper_table2():
    t = st.slab_track()
    assert {key: getattr(t, key) for key in TABLE2_SLAB} == dict(TABLE2_SLAB)
    assert not t.is_ballasted
    # The paper's kphi = kv b^2 / 12 with b = 0.25 m, printed rounded to three digits.
    assert t.kphi == pytest.approx(t.kv * PAD_LENGTH**2 / 12, rel=2e-3)


def test_ballasted_preset_is_paper_table5():
    t = st.ballasted_track()
    assert {key: getattr(t, key) for key in TABLE5_BALLASTED} == dict(TABLE5_BALLASTED)
    assert all(getattr(t, key) == getattr(st.slab_track(), key) for key in TABLE2_RAIL) and t.is_ballasted


def test_every_field_has_one_rule():
    """The rule table covers the Track's fields exactly (the track file reader applies it too)."""
    # ``slab`` is a Slab, which checks its own fields (tests/test_slab.py); ``foundation`` is a curve,
    # checked passive where it is evaluated (tests/test_curves.py).
    assert set(FIELD_RULES) | {"slab", "foundation"} == {f.name for f in dataclasses.fields(st.Track)}


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
    np.testing.assert_allclose(kv, t.kv * (1 + 1j * t.eta_pad), rtol=1e-14)
    np.testing.assert_allclose(kphi, t.kphi * (1 + 1j * t.eta_pad), rtol=1e-14)


def test_ballasted_support_matches_two_dof_solve():
    """Pad in series with sleeper mass on ballast, against a direct 2-DOF dynamic solve."""
    t = st.ballasted_track()
    f = np.array([3.0, 117.0, 243.0, 900.0])
    kv_dyn, _ = t.support_stiffness(f)
    kp, kb = t.kv * (1 + 1j * t.eta_pad), t.kb * (1 + 1j * t.eta_ballast)
    for fi, k in zip(f, kv_dyn):
        w = 2 * np.pi * fi
        # DOFs (rail seat w, sleeper z); unit displacement imposed at the rail seat.
        z = kp / (kp + kb - w**2 * t.sleeper_mass)
        force = kp * (1 - z)
        assert k == pytest.approx(force, rel=1e-12)
    # Static limit: springs in series.
    assert t.support_stiffness(1e-6)[0] == pytest.approx(kp * kb / (kp + kb), rel=1e-9)


def test_bouncing_estimate_is_papers_formula():
    t = st.slab_track()
    assert t.bouncing_frequency_estimate == pytest.approx(np.sqrt(t.kv / (t.rho * t.A * t.spacing)) / (2 * np.pi))


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


def test_one_wording_for_a_value_that_is_not_a_track():
    t = st.slab_track()
    assert require_cell(t) == t.cell() and require_cell(t.cell(2)) == t.cell(2)
    with pytest.raises(TypeError, match="track must be a semitrack Track or PeriodicCell"):
        require_cell({"kv": 1})
    for call in (lambda: st.parameter_table("slab"), lambda: st.continuous_foundation_receptance(None, 1.0, 1e8),
                 lambda: st.PeriodicCell("slab", 1.0, (0.0,)), lambda: st.paper_frequency_table(3)):
        with pytest.raises(TypeError, match="must be a semitrack Track"):
            call()
