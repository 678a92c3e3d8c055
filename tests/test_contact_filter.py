"""The contact filter: a roughness averaged under the Hertzian pressure of the contact patch.

Independent checks: the filter against a quadrature of a sinusoid weighted by the semi-elliptic
pressure ``sqrt(1 - x^2 / a^2)``; the contact's radius against Hertz's ``a^3 = 3 P0 R / (4 E*)``
for a wheel built from its radii; the filtered roughness line by line.
"""

import numpy as np
import pytest
from scipy.integrate import quad

import semitrack as st
from semitrack.model.contact_filter import STEEL_E, STEEL_POISSON


@pytest.mark.parametrize("wavelength", [0.2, 0.03, 0.0125, 0.008, 0.004])
def test_the_filter_is_the_average_of_a_sinusoid_under_the_hertzian_pressure(wavelength):
    a = 6e-3
    k = 2 * np.pi / wavelength
    weight = quad(lambda x: np.sqrt(1 - (x / a) ** 2), -a, a)[0]
    average = quad(lambda x: np.sqrt(1 - (x / a) ** 2) * np.cos(k * x), -a, a, limit=200)[0] / weight
    assert st.contact_filter([wavelength], a)[0] == pytest.approx(average, abs=1e-9)


def test_its_long_wavelength_limit_and_first_zero():
    a = 6e-3
    h = st.contact_filter([1e3, 2 * np.pi * a / 3.8317059702075125, 2 * np.pi * a / 1e-6], a)
    assert h[0] == pytest.approx(1.0, abs=1e-9) and abs(h[1]) < 1e-9 and h[2] == pytest.approx(1.0, abs=1e-12)
    lam = np.geomspace(2e-3, 0.5, 200)
    h = st.contact_filter(lam, a)
    assert np.all(np.abs(h) <= 1.0 + 1e-12) and np.all(np.diff(h[lam > 2 * np.pi * a / 3.83]) > 0)


def test_the_contact_radius_is_hertz_s():
    wheel = st.Wheel.from_radii(0.46, 0.3, preload=1.2e5)
    e_star = STEEL_E / (2 * (1 - STEEL_POISSON**2))
    hertz = (3 * wheel.preload * np.sqrt(0.46 * 0.3) / (4 * e_star)) ** (1 / 3)
    assert st.contact_semi_length(wheel) == pytest.approx(hertz, rel=1e-12)
    assert 5e-3 < st.contact_semi_length(st.Wheel()) < 8e-3  # the 10-15 mm patch of a loaded wheel


def test_a_filtered_roughness_scales_each_line_and_turns_the_negative_ones():
    rough = st.roughness_from_spectrum(30.0, np.array([0.1, 0.02, 0.01, 0.005]), np.zeros(4), period=0.2, seed=3)
    wheel = st.Wheel()
    out = st.contact_filtered(rough, wheel)
    h = st.contact_filter(rough.wavelengths, st.contact_semi_length(wheel))
    np.testing.assert_allclose(out.amplitudes, rough.amplitudes * np.abs(h), rtol=1e-12)
    assert np.any(h < 0) and np.any(h > 0.9)
    turned = np.mod(out.phases - rough.phases, 2 * np.pi)
    np.testing.assert_allclose(np.where(h < 0, np.abs(turned - np.pi), np.minimum(turned, 2 * np.pi - turned)), 0,
                               atol=1e-12)
    assert out.speed == rough.speed and out.period == rough.period and "contact-filtered" in out.label


@pytest.mark.parametrize("call, name", [
    (lambda: st.contact_filter([0.0], 6e-3), "wavelength"),
    (lambda: st.contact_filter([np.nan], 6e-3), "wavelength"),
    (lambda: st.contact_filter([0.01], 0.0), "semi_length"),
    (lambda: st.contact_filter([0.01], 1.0), "semi_length"),
    (lambda: st.contact_semi_length(st.Wheel(), poisson=0.5), "poisson"),
    (lambda: st.contact_semi_length(st.Wheel(), E=-1.0), "E"),
    (lambda: st.contact_filtered(st.roughness_from_spectrum(30.0, [0.1, 0.01], [0.0, 0.0], period=0.2), st.Wheel(),
                                 poisson=-0.0, E=1e6),
     r"E=1e\+06 N/m\^2 and poisson=-0 give"),  # the radius these imply is refused by them, not by semi_length
])
def test_bad_input_is_refused_by_name(call, name):
    with pytest.raises(st.BadInput, match=name):
        call()
    with pytest.raises(TypeError, match="wheel must be a Wheel"):
        st.contact_semi_length(0.46)
    with pytest.raises(TypeError, match="roughness must be a Roughness"):
        st.contact_filtered(0.46, st.Wheel())
