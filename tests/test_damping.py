"""The causal damping option: viscous dampers that equal the loss factors at reference frequencies."""

from __future__ import annotations

import numpy as np
import pytest

import semitrack as st


@pytest.mark.parametrize("make", [st.slab_track, st.ballasted_track])
def test_viscous_loss_factor_grows_with_frequency_and_matches_at_the_reference(make):
    track = make(damping="viscous")
    ref = track.reference_frequencies()
    for family, eta in (("rail", track.eta_rail), ("pad", track.eta_pad), ("ballast", track.eta_ballast)):
        if eta == 0:
            assert np.all(track.loss_factor(family, [1.0, 100.0]) == 0)
            continue
        assert track.loss_factor(family, ref[family]) == pytest.approx(eta, rel=1e-14)
        assert track.loss_factor(family, 2 * ref[family]) == pytest.approx(2 * eta, rel=1e-14)
    hysteretic = make()
    assert np.all(hysteretic.loss_factor("pad", [1.0, 1e3]) == hysteretic.eta_pad)


def test_viscous_and_hysteretic_agree_where_the_one_damper_matches():
    """With the pads the only damping, both models are the same track at the pad's reference
    frequency, so alpha must agree there to round-off and differ elsewhere."""
    hyst = st.slab_track(eta_rail=0.0)
    visc = hyst.replace(damping="viscous")
    f_pad = visc.reference_frequencies()["pad"]
    a_h, a_v = (st.semi_infinite_receptance(t, [f_pad, 3 * f_pad]) for t in (hyst, visc))
    assert np.allclose(a_v[0], a_h[0], rtol=1e-12, atol=0)
    assert not np.allclose(a_v[1], a_h[1], rtol=1e-3, atol=0)


@pytest.mark.parametrize("make", [st.slab_track, st.ballasted_track])
def test_viscous_track_is_reciprocal_passive_and_method_independent(make):
    track = make(damping="viscous")
    f = np.array([3.0, 120.0, 480.0, 1100.0, 2900.0])
    alpha = st.semi_infinite_receptance(track, f)
    assert np.allclose(alpha[:, 0, 1], alpha[:, 1, 0], rtol=1e-9, atol=0)
    mobility = 1j * 2 * np.pi * f[:, None, None] * alpha
    herm = 0.5 * (mobility + np.conj(np.swapaxes(mobility, 1, 2)))
    assert np.all(np.linalg.eigvalsh(herm)[:, 0] > -1e-12 * np.abs(herm).max())
    # Two supports per period describe the same track (exact method).
    assert np.allclose(st.semi_infinite_receptance(track.cell(2), f), alpha, rtol=1e-10, atol=0)
    # The paper's method with refined settings follows the same damping (within its ~1-2 %).
    wn = st.semi_infinite_receptance(track, f[1:3], method="wavenumber", beta_max=785.4, dx=0.002)
    assert np.max(np.abs(wn - alpha[1:3]) / np.abs(alpha[1:3]).max(axis=(1, 2), keepdims=True)) < 0.03


def test_damping_must_be_a_known_model():
    with pytest.raises(ValueError, match=r"damping must be one of \('hysteretic', 'viscous'\)"):
        st.slab_track(damping="coulomb")
    with pytest.raises(ValueError, match="needs the frequencies"):
        st.slab_track(damping="viscous").pad_stiffness()
