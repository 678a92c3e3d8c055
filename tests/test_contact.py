"""The wheel on an FE track in time: Hertzian contact, roughness inputs, loss of contact.

Independent checks: the closed form of a wheel on its contact spring over a rigid track; the
linear frequency-domain force per unit roughness (``wheel_rail_force``, exact infinite track) for
small roughness on a 10-bay truncated track with broadband-boundary ends; the contact law at
every step; convergence as the time step halves; the support-passing frequency v / d.
"""

import dataclasses

import numpy as np
import pytest

import semitrack as st
from semitrack.dynamics.contact import hertz_contact_force

#: The flat test spectrum: one-third-octave bands of wavelength 2 m to 4 cm, which at 100 m/s
#: cover the frequency bands 50 Hz - 2.5 kHz, each at -10 dB re 1 um (1.3 um rms in all).
SPEED = 100.0
BANDS = (50.0, 2500.0)


@pytest.fixture(scope="module")
def boundaries():
    """Broadband boundaries of the viscous tracks (the time-domain model's damping), fitted once
    at 24 poles (0.6 s and 1.0 s): the order search keeps 24 on the slab track; on the ballasted
    one 24 poles (alpha within 2.1 %) move the contact force by 0.001 dB from 48 (within 0.28 %)."""
    return {name: st.fit_boundary(make(damping="viscous"), band=(3, 3000), n_poles=24)
            for name, make in (("slab", st.slab_track), ("ballasted", st.ballasted_track))}


@pytest.fixture(scope="module")
def small_roughness():
    lam = st.third_octave_bands(0.04, 2.0)[0]
    return st.roughness_from_spectrum(SPEED, lam, np.full(lam.size, -10.0), period=0.1, seed=1)


# ------------------------------------------------------------------------------------------------
# Roughness inputs
# ------------------------------------------------------------------------------------------------
def test_third_octave_bands_are_the_base_ten_series():
    centres, lower, upper = st.third_octave_bands(50.0, 2500.0)
    assert centres.size == 18 and centres[0] == pytest.approx(50.12, abs=0.01)
    assert centres[-1] == pytest.approx(2511.9, abs=0.1)
    np.testing.assert_allclose(upper[:-1], lower[1:], rtol=1e-12)  # contiguous
    np.testing.assert_allclose(np.sqrt(lower * upper), centres, rtol=1e-12)


def test_synthesised_roughness_has_the_spectrum_s_band_levels_in_its_samples():
    """An independent route to the band levels: sample one period, take the FFT, sum each
    wavelength band's power (ISO 3095 limit at 10 m/s: 25 Hz - 3.17 kHz)."""
    speed = 10.0
    rough = st.roughness_from_spectrum(speed, period=0.2, seed=3)
    n = 2**13  # 41 kHz sampling over one period: above twice the highest line
    t = np.arange(n) * rough.period / n
    spectrum = np.fft.rfft(rough(t)) * 2 / n
    f = np.fft.rfftfreq(n, rough.period / n)
    lam_c = np.array(list(st.ISO3095_ROUGHNESS_LIMIT))
    levels = np.array(list(st.ISO3095_ROUGHNESS_LIMIT.values()))
    for lam, level in zip(lam_c, levels):
        n_band = np.round(10 * np.log10(lam))
        in_band = (f > 0) & (np.abs(10 * np.log10(speed / np.maximum(f, 1e-9)) - n_band) <= 0.5)
        measured = 10 * np.log10(np.sum(np.abs(spectrum[in_band]) ** 2 / 2) / 1e-12)
        assert measured == pytest.approx(level, abs=1e-6)
    assert np.sqrt(np.mean(rough(t) ** 2)) == pytest.approx(rough.rms, rel=1e-9)
    again = st.roughness_from_spectrum(speed, period=0.2, seed=3)
    np.testing.assert_array_equal(again.phases, rough.phases)  # the seed fixes the phases
    assert not np.array_equal(st.roughness_from_spectrum(speed, period=0.2, seed=4).phases, rough.phases)


@pytest.mark.parametrize("speed, dt, period", [(100.0, 1e-5, 0.1), (10.0, 4e-5, 0.2), (300 / 3.6, 2e-5, 0.1),
                                               (100.0, 3e-5, 0.1)])
@pytest.mark.filterwarnings("ignore:.*Nyquist frequency:RuntimeWarning")  # aliasing on purpose
def test_sampled_roughness_by_fft_equals_its_cosine_sums(speed, dt, period):
    """One period by an inverse FFT, repeated; lines above the step's Nyquist frequency (the ISO
    spectrum at 100 m/s reaches 31.7 kHz) fold onto their aliases as the cosines' samples do; a
    period that is no whole number of steps (0.1 s / 30 us) takes the cosine sums."""
    rough = st.roughness_from_spectrum(speed, period=period, seed=2)
    n = int(2.5 * period / dt)
    ref = rough(dt * np.arange(n))
    np.testing.assert_allclose(rough.sampled(dt, n), ref, rtol=0, atol=1e-12 * np.abs(ref).max())
    line = st.corrugation(speed, 0.05, 1e-6, phase=0.3)
    short = line.sampled(line.period / 4, 9)  # bins 0 and N/2 are real: a quarter-period step still holds
    np.testing.assert_allclose(short, line(line.period / 4 * np.arange(9)), rtol=0, atol=1e-18)


def test_corrugation_is_one_line():
    r = st.corrugation(SPEED, 0.05, 2e-5)
    assert r.frequencies.tolist() == [2000.0] and r.period == pytest.approx(5e-4)
    t = np.linspace(0.0, 1e-3, 7)
    np.testing.assert_allclose(r(t), 2e-5 * np.cos(2 * np.pi * 2000.0 * t), atol=1e-18)


# ------------------------------------------------------------------------------------------------
# The contact equation of one step
# ------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("a, beta", [(1e-4, 1e-14), (1e-4, 1e-9), (3e-5, 1e-6), (1e-12, 1e-9)])
def test_the_contact_force_solves_its_equation(a, beta):
    c_h = 9.3e10
    f = hertz_contact_force(c_h, a, beta)
    assert 0 < f <= a / beta
    assert f == pytest.approx(c_h * (a - beta * f) ** 1.5, rel=1e-12)


def test_no_approach_no_force():
    assert hertz_contact_force(9.3e10, 0.0, 1e-9) == 0.0
    assert hertz_contact_force(9.3e10, -1e-5, 1e-9) == 0.0


# ------------------------------------------------------------------------------------------------
# Against closed forms and the linear frequency-domain theory
# ------------------------------------------------------------------------------------------------
def test_a_quiet_start_in_static_equilibrium():
    """With no roughness the stationary wheel stays on its preload: the run starts in the static
    state (measured: F within 1.4e-8 N of P0 over 0.1 s)."""
    model = st.TruncatedTrack(st.slab_track(damping="viscous"), 4, elements_per_bay=6)
    res = st.wheel_rail_response(model, st.Wheel(primary_stiffness=1e6, primary_damping=1e4), dt=5e-5,
                                 duration=0.05)
    np.testing.assert_allclose(res.force, 1e5, rtol=1e-9)
    np.testing.assert_allclose(res.approach, st.Wheel().static_approach, rtol=1e-9)


@pytest.mark.parametrize("f", [100.0, 250.0, 500.0, 1000.0])
def test_on_a_rigid_track_the_force_is_the_wheel_on_its_contact_spring(f):
    """Rail and pads 1e6 times stiffer: F/r = -1/(alpha_W + 1/k_H) with alpha_W of the mass on
    a primary damper (10 % of critical on the contact spring, so the start's bounce dies out).
    Measured: 1e-5 at 100 Hz to 2.7e-4 at 250 Hz (the 245 Hz bounce), the time step's error."""
    base = st.slab_track(damping="viscous")
    rigid = base.replace(E=base.E * 1e6, G=base.G * 1e6, kv=base.kv * 1e6, kphi=base.kphi * 1e6)
    model = st.TruncatedTrack(rigid, 2, elements_per_bay=4)
    m, k_h = 600.0, st.Wheel().contact_stiffness
    c1 = 0.2 * np.sqrt(k_h * m)
    res = st.wheel_rail_response(model, st.Wheel(mass=m, primary_damping=c1),
                                 st.corrugation(SPEED, SPEED / f, 1e-7), dt=1e-5, duration=0.12)
    transfer = st.contact_transfer(res, band=(f, f))
    omega = 2 * np.pi * f
    closed = -1 / (1 / (1j * omega * c1 - omega**2 * m) + 1 / k_h)
    assert transfer.f.tolist() == [f]
    assert abs(transfer.H[0] / closed - 1) < 1e-3
    assert abs(transfer.linear[0] / closed - 1) < 1e-3  # the linear theory on the same stiff track


# Measured band errors (dB) of the 10-bay models, 50 Hz - 2.5 kHz, 12 elements per bay:
#   slab (dt 40 us, 0.82 s): boundary within 0.26 (the 50 Hz band; the fade-in's bounce at 64 Hz
#   decays with 1.1 % damping: 1.6 dB after 0.42 s, 0.1 dB after 1.02 s); pinned 5.9 (501 Hz),
#   above 1 dB from 200 Hz to 1.6 kHz.
#   ballasted (dt 20 us, 0.42 s): boundary within 0.02; pinned 1.86 (794 Hz band).
#   dt 40 us on the ballasted track: 0.3 dB in the 1 kHz band (the sharp pinned-pinned peak
#   shifted by the step's frequency warping, +0.2 %).
TRANSFER_RUNS = {"slab": (4e-5, 0.82), "ballasted": (2e-5, 0.42)}


@pytest.mark.parametrize("name", ["slab", "ballasted"])
def test_small_roughness_matches_the_linear_theory_with_boundary_ends_not_pinned(boundaries, small_roughness, name):
    track = (st.slab_track if name == "slab" else st.ballasted_track)(damping="viscous")
    dt, duration = TRANSFER_RUNS[name]
    errors = {}
    for ends in ("boundary", "pinned"):
        model = st.TruncatedTrack(track, 10, ends, system=boundaries[name] if ends == "boundary" else None)
        res = st.wheel_rail_response(model, st.Wheel(), small_roughness, dt=dt, duration=duration)
        assert not res.lost_contact
        transfer = st.contact_transfer(res, band=BANDS)
        assert transfer.centres.size == 18  # every band from 50 Hz to 2.5 kHz holds lines
        errors[ends] = transfer.error_db
    assert np.max(np.abs(errors["boundary"])) < 1.0
    assert np.max(np.abs(errors["pinned"])) > 1.5


# ------------------------------------------------------------------------------------------------
# Large roughness: loss of contact
# ------------------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def large_runs():
    """A 100 um corrugation of 0.1 m at 100 m/s (1 kHz, near the pinned-pinned resonance where
    the linear force would be ~2e9 N/m x 100 um = twice the preload) on a 10-bay pinned slab track."""
    model = st.TruncatedTrack(st.slab_track(damping="viscous"), 10)
    rough = st.corrugation(SPEED, 0.1, 1e-4)
    return {dt: st.wheel_rail_response(model, st.Wheel(), rough, dt=dt, duration=0.04, ramp=0.005)
            for dt in (2e-5, 1e-5, 5e-6)}


def test_large_roughness_loses_contact_and_the_force_is_never_negative(large_runs):
    res = large_runs[1e-5]
    assert res.lost_contact and 0.05 < np.mean(~res.in_contact) < 0.5  # measured 12 % of the time
    assert np.all(res.force >= 0)
    wheel = res.wheel
    np.testing.assert_allclose(res.force, wheel.contact_force(res.approach), rtol=1e-9, atol=1e-6 * wheel.preload)
    assert res.force.max() > 2 * wheel.preload  # the impacts after the flights (measured 2.7 P0)


def test_large_roughness_converges_as_the_time_step_halves(large_runs):
    """max |F_dt - F_dt/2| / max F at the common times; measured 3.5 % (20 -> 10 us) and 0.87 %
    (10 -> 5 us): second order."""
    def change(dt):
        coarse, fine = large_runs[dt].force, large_runs[dt / 2].force[::2]
        return np.max(np.abs(coarse - fine)) / np.max(fine)

    assert change(1e-5) < 0.02
    assert change(1e-5) < change(2e-5) / 3


# ------------------------------------------------------------------------------------------------
# A rolling wheel on a smooth rail
# ------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("kmh", [300.0, 400.0])
def test_a_rolling_wheel_shows_the_support_passing_frequency(boundaries, kmh):
    """The largest line of the force spectrum in 100 Hz - 1 kHz is v / d (measured: 129.0 Hz for
    128.2 Hz at 300 km/h, 170.4 Hz for 170.9 Hz at 400 km/h; bins of 8-11 Hz). Above, the mesh
    adds its own line at the element-passing frequency v / h (1.5 / 2.1 kHz with 12 elements
    per bay; at 300 km/h 3.2 kN against 2.0 kN at v / d, 0.8 kN with 48 elements per bay)."""
    track = st.slab_track(damping="viscous")
    speed = kmh / 3.6
    model = st.TruncatedTrack(track, 10, "boundary", system=boundaries["slab"])
    res = st.wheel_rail_response(model, st.Wheel(), speed=speed, x=-6.0, dt=2e-5, duration=12.0 / speed)
    assert res.x[-1] == pytest.approx(6.0) and not res.lost_contact
    f, spectrum = res.force_spectrum(after=0.02)  # past the start, where the wheel's bounce (64 Hz) is set off
    band = (f > 100.0) & (f < 1000.0)
    peak = f[band][np.argmax(spectrum[band])]
    assert abs(peak - speed / track.spacing) <= f[1]


# ------------------------------------------------------------------------------------------------
# Input validation
# ------------------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def small_model():
    return st.TruncatedTrack(st.slab_track(), 2, elements_per_bay=4)


@pytest.mark.parametrize("kwargs, error, match", [
    ({"wheel": "wheel"}, TypeError, "wheel must be a semitrack Wheel"),
    ({"roughness": np.zeros(10)}, TypeError, "roughness must be None"),
    ({"dt": 0.0}, ValueError, "dt must be positive"),
    ({"duration": 0.01, "ramp": 0.02}, ValueError, "duration must exceed ramp"),
    ({"x": 5.0}, ValueError, "x must lie on the rail"),
    ({"speed": 100.0, "duration": 0.05}, ValueError, r"x \+ speed \* duration must lie on the rail"),
    ({"speed": -1.0}, ValueError, "speed must be non-negative"),
    ({"speed": 10.0, "roughness": st.corrugation(20.0, 0.1, 1e-6)}, ValueError, "roughness.speed must equal"),
])
def test_wheel_rail_response_refuses_bad_input(small_model, kwargs, error, match):
    args = {"wheel": st.Wheel(), "duration": 0.05, **kwargs}
    with pytest.raises(error, match=match):
        st.wheel_rail_response(small_model, **args)


def test_a_roughness_too_long_to_evaluate_is_refused(small_model):
    """Its samples are one inverse FFT when its period is a whole number of steps (31 600 lines,
    2e6 steps a period: a fraction of a second); otherwise the cosine sums, refused beyond the limit."""
    rough = st.roughness_from_spectrum(SPEED, period=2.0)  # 31 600 lines
    assert rough.sampled(1e-6, 100_001).shape == (100_001,)
    with pytest.raises(ValueError, match="roughness lines give .* cosines .* more than the limit"):
        st.wheel_rail_response(small_model, st.Wheel(), rough, dt=1.1e-6, duration=0.1)


def test_force_spectrum_reads_a_line_s_amplitude():
    """A small 2 kHz corrugation on a short track: the force is nearly one sinusoid, whose amplitude
    the windowed spectrum returns at its line (the Hann window's scalloping is zero on a bin)."""
    model = st.TruncatedTrack(st.slab_track(damping="viscous"), 2, elements_per_bay=4)
    res = st.wheel_rail_response(model, st.Wheel(), st.corrugation(SPEED, SPEED / 2000.0, 1e-8), dt=1e-5,
                                 duration=0.1, ramp=0.01)
    f, amplitude = res.force_spectrum(after=0.05)
    late = res.t >= 0.05
    swing = (res.force[late].max() - res.force[late].min()) / 2
    assert f[np.argmax(amplitude)] == pytest.approx(2000.0, abs=f[1])
    assert amplitude.max() == pytest.approx(swing, rel=0.05)
    with pytest.raises(ValueError, match="fewer than two samples"):
        res.force_spectrum(after=1.0)


def test_wheel_rail_response_needs_an_fe_model():
    with pytest.raises(TypeError, match="track must be an FETrack"):
        st.wheel_rail_response(st.slab_track(), st.Wheel())


def test_contact_transfer_refuses_what_it_cannot_analyse(small_model):
    smooth = st.wheel_rail_response(small_model, st.Wheel(), dt=5e-5, duration=0.03)
    with pytest.raises(ValueError, match="needs a stationary wheel"):
        st.contact_transfer(smooth)
    rough = st.wheel_rail_response(small_model, st.Wheel(), st.corrugation(SPEED, SPEED / 300.0, 1e-7),
                                   dt=1e-5, duration=0.03)
    with pytest.raises(ValueError, match="whole number of time steps"):
        st.contact_transfer(rough)
    rough = st.wheel_rail_response(small_model, st.Wheel(), st.corrugation(SPEED, 1.0, 1e-7), dt=1e-4,
                                   duration=0.05)
    with pytest.raises(ValueError, match="must fit after the fade-in"):
        st.contact_transfer(rough, periods=4)
    with pytest.raises(ValueError, match="holds none of the roughness's lines"):
        st.contact_transfer(rough, band=(1000.0, 2000.0))
    with pytest.raises(TypeError, match="response must be a ContactResponse"):
        st.contact_transfer(smooth.force)


@pytest.mark.parametrize("kwargs, match", [
    ({"wavelengths": [0.1, 0.05]}, "wavelengths and levels must be given together"),
    ({"wavelengths": [0.1, 0.07], "levels": [0.0, 0.0]}, "one-third-octave band centres"),
    ({"wavelengths": [0.1], "levels": [0.0, 1.0]}, "one per wavelength"),
    ({"period": 0.001}, "leaves no line"),
    ({"seed": -1}, "seed must be an integer >= 0"),
])
def test_roughness_from_spectrum_refuses_bad_input(kwargs, match):
    with pytest.raises(ValueError, match=match):
        st.roughness_from_spectrum(SPEED, **kwargs)


def test_roughness_refuses_lines_off_its_period():
    with pytest.raises(ValueError, match="whole multiples of 1/period"):
        st.Roughness([15.0], [1e-6], [0.0], speed=SPEED, period=0.1)
    with pytest.raises(ValueError, match="amplitudes must be non-negative"):
        st.Roughness([10.0], [-1e-6], [0.0], speed=SPEED, period=0.1)


def test_several_wheels_start_quietly_and_one_in_a_list_is_one():
    """Two wheels (different preloads) stand still on a smooth rail: the static start holds them
    on their preloads through the rail's coupling (measured 1e-11); a list of one wheel is the
    single-wheel run; a roughness reaches a wheel s ahead s / v earlier."""
    model = st.TruncatedTrack(st.slab_track(damping="viscous"), 4, elements_per_bay=6)
    wheels = [st.Wheel(), st.Wheel(preload=5e4, primary_stiffness=1e6, primary_damping=1e4)]
    res = st.wheel_rail_response(model, wheels, x=[-0.4, 0.9], dt=5e-5, duration=0.05)
    assert res.force.shape == (1001, 2) and res.n_dof == model.n_dof + 2
    np.testing.assert_allclose(res.force, np.tile([1e5, 5e4], (1001, 1)), rtol=1e-9)
    rough = st.corrugation(SPEED, 0.2, 1e-6)
    one = st.wheel_rail_response(model, st.Wheel(), rough, dt=5e-5, duration=0.05)
    listed = st.wheel_rail_response(model, [st.Wheel()], rough, dt=5e-5, duration=0.05)
    np.testing.assert_array_equal(one.force, listed.force)
    two = st.wheel_rail_response(model, [st.Wheel(), st.Wheel()], rough, x=[0.0, 0.05], dt=5e-5,
                                 duration=0.05, ramp=1e-3)
    late = two.t > 2e-3
    ahead = 1e-6 * np.cos(2 * np.pi * SPEED / 0.2 * (two.t[late] + 0.05 / SPEED))
    np.testing.assert_allclose(two.roughness[late, 1], ahead, atol=1e-15)
    with pytest.raises(ValueError, match="contact_transfer of a run with 2 wheels needs wheel=i"):
        st.contact_transfer(two)
    f, amplitude = two.force_spectrum(after=0.01)
    assert amplitude.shape == (f.size, 2)  # a spectrum per wheel, each as one wheel's record gives it
    for j in range(2):
        np.testing.assert_allclose(dataclasses.replace(two, force=two.force[:, j]).force_spectrum(after=0.01)[1],
                                   amplitude[:, j], rtol=0, atol=1e-9 * amplitude.max())
    with pytest.raises(ValueError, match=r"x must give one position per wheel \(2\)"):
        st.wheel_rail_response(model, wheels, dt=5e-5, duration=0.05)
