"""The wheel, its Hertzian contact and the linear wheel-rail force per unit roughness."""

import numpy as np
import pytest

import semitrack as st
from semitrack.methods.wheelrail import wheel_rail_force
from semitrack.model.wheel import DEFAULT_HERTZ_CONSTANT, Wheel

F = np.array([20.0, 100.0, 245.0, 600.0, 945.0, 2500.0])


def test_the_force_is_the_series_formula_of_the_three_receptances(track):
    wheel = Wheel(mass=600.0, preload=1e5, primary_stiffness=1e6, primary_damping=1e4)
    x = 0.2
    alpha_r = st.point_receptance(track, F, x, origin="midspan")[:, 0, 0]
    omega = 2 * np.pi * F
    alpha_w = 1 / (1e6 + 1j * omega * 1e4 - omega**2 * 600.0)
    k_h = 1.5 * DEFAULT_HERTZ_CONSTANT ** (2 / 3) * 1e5 ** (1 / 3)
    expected = -1 / (alpha_w + 1 / k_h + alpha_r)
    np.testing.assert_allclose(wheel_rail_force(track, F, wheel, x, origin="midspan"), expected, rtol=1e-13)


def test_on_a_rigid_track_the_wheel_bounces_on_its_contact_spring():
    """Rail and pads 1e6 stiffer: F/r -> m w^2 k_H / (k_H - m w^2), the closed form of the
    wheel mass on the contact spring, resonant at sqrt(k_H / m) (245 Hz, left out: there the
    residual rail receptance is all that bounds the force)."""
    base = st.slab_track()
    rigid = base.replace(E=base.E * 1e6, G=base.G * 1e6, kv=base.kv * 1e6, kphi=base.kphi * 1e6)
    wheel = Wheel()
    f = F[F != 245.0]
    omega2, k_h = (2 * np.pi * f) ** 2, wheel.contact_stiffness
    closed = wheel.mass * omega2 * k_h / (k_h - wheel.mass * omega2)
    force = wheel_rail_force(rigid, f, wheel, origin="midspan")
    np.testing.assert_allclose(force, closed, rtol=1e-4)  # measured 1.4e-5
    assert np.sqrt(k_h / wheel.mass) / (2 * np.pi) == pytest.approx(245.6, abs=0.1)


def test_a_stiff_contact_and_an_immovable_wheel_impose_the_roughness_on_the_rail(track):
    """alpha_W -> 0 (a wheel 1e12 times heavier) and alpha_C -> 0 (C_H x 1e12): F/r -> -1/alpha_R."""
    wheel = Wheel(mass=6e14, hertz_constant=DEFAULT_HERTZ_CONSTANT * 1e12)
    alpha_r = st.point_receptance(track, F, origin="midspan")[:, 0, 0]
    np.testing.assert_allclose(wheel_rail_force(track, F, wheel, origin="midspan"), -1 / alpha_r, rtol=1e-6)


def test_a_massless_free_wheel_transmits_no_force(track):
    """With nothing behind the contact (no mass, no suspension) the roughness only moves the wheel."""
    force = wheel_rail_force(track, F, Wheel(mass=1e-9), origin="midspan")
    assert np.all(np.abs(force) < 1e-3 * np.abs(wheel_rail_force(track, F, Wheel(), origin="midspan")))


def test_the_force_follows_the_rail_between_and_over_the_supports():
    """At the pinned-pinned frequency the rail is soft at mid-span and stiff over a support."""
    track, wheel = st.slab_track(), Wheel()
    over, mid = (abs(wheel_rail_force(track, [945.0], wheel, x, origin="midspan")[0]) for x in (0.325, 0.0))
    assert over > 2 * mid  # measured 2.6x


def test_a_flexible_slab_track_takes_the_wheel_too():
    slab = st.Slab(length=6.45, fasteners=10, E=3.6e10, I=2.869e-3, mass_per_length=956.25,
                   support_stiffness=2.55e7, eta_support=0.15, eta_slab=0.02)
    force = wheel_rail_force(st.slab_track(slab=slab), F, Wheel(), x=1.3, origin="midspan")
    assert force.shape == F.shape and np.all(np.isfinite(force))


def test_hertz_law_and_its_linearisation():
    wheel = Wheel(preload=8e4)
    delta0 = wheel.static_approach
    assert wheel.contact_force(delta0) == pytest.approx(8e4, rel=1e-12)
    step = 1e-6 * delta0
    slope = (wheel.contact_force(delta0 + step) - wheel.contact_force(delta0 - step)) / (2 * step)
    assert wheel.contact_stiffness == pytest.approx(slope, rel=1e-8)  # dF/ddelta at the preload
    np.testing.assert_array_equal(wheel.contact_force([-1e-5, 0.0]), [0.0, 0.0])  # loss of contact


def test_hertz_constant_from_the_radii():
    """A 0.46 m wheel on a 0.3 m rail head gives about the default C_H (9.3e10 N/m^1.5)."""
    wheel = Wheel.from_radii(0.46, 0.3, mass=500.0)
    assert wheel.hertz_constant == pytest.approx(DEFAULT_HERTZ_CONSTANT, rel=0.01)  # measured 9.38e10
    assert wheel.mass == 500.0
    assert Wheel.from_radii(0.46, 0.6).hertz_constant > wheel.hertz_constant  # flatter head, stiffer


def test_the_primary_suspension_holds_the_wheel_at_low_frequency():
    wheel = Wheel(primary_stiffness=1.2e6, primary_damping=2e3)
    assert wheel.receptance(0.01) == pytest.approx(1 / 1.2e6, rel=1e-3)
    assert wheel.receptance(1000.0) == pytest.approx(-1 / (600.0 * (2 * np.pi * 1000.0) ** 2), rel=1e-3)


@pytest.mark.parametrize("kwargs,err,match", [
    (dict(mass=0.0), ValueError, "mass must be positive"),
    (dict(preload=-1e5), ValueError, "preload must be positive"),
    (dict(hertz_constant=float("inf")), ValueError, "hertz_constant must be positive"),
    (dict(primary_damping=-1.0), ValueError, "primary_damping must be non-negative"),
    (dict(mass="600"), TypeError, "mass must be a real number"),
])
def test_bad_wheels_are_refused_by_name(kwargs, err, match):
    with pytest.raises(err, match=match):
        Wheel(**kwargs)


def test_bad_radii_and_non_wheels_are_refused():
    with pytest.raises(ValueError, match=r"poisson must be in \[0, 0.5\)"):
        Wheel.from_radii(poisson=0.5)
    with pytest.raises(ValueError, match="rail_radius must be positive"):
        Wheel.from_radii(rail_radius=0.0)
    with pytest.raises(TypeError, match="wheel must be a semitrack Wheel"):
        wheel_rail_force(st.slab_track(), F, {"mass": 600.0})
