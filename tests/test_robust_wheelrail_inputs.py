"""The wheel on the rail under hostile input: physical ranges, limits instead of NaN, bounded runs, aliasing.

Each case asserts the exception (or warning) class, a one-line message naming the parameter, and
a time bound; the runs that would allocate gigabytes are refused before any allocation, which a
subprocess measures (peak RSS, ``VmHWM`` by :mod:`peak_memory`: under 1 GB, under 30 s).
"""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
import warnings
from pathlib import Path

import numpy as np
import pytest
from peak_memory import PEAK_RSS
from refusals import refused

import semitrack as st
from semitrack.base.errors import InputError, InputTypeError
from semitrack.dynamics.simulate import MAX_STEP_DOFS, check_limits
from semitrack.fe.timedomain import moving_load_response, pulse_response
from semitrack.model.roughness import corrugation, roughness_from_spectrum


@pytest.fixture(scope="module")
def model():
    return st.TruncatedTrack(st.slab_track(), 2, elements_per_bay=4)


# --- the wheel ---------------------------------------------------------------------------------------
@pytest.mark.parametrize("mass", [1e300, 1e-300, 1e-10, 1e16])
def test_a_wheel_mass_outside_physics_is_refused(mass):
    refused(lambda: st.Wheel(mass=mass), InputError, "mass", "kg", "1e-09 to 1e+15")


@pytest.mark.parametrize("mass", [1e-9, 600.0, 1e15])
def test_the_range_s_ends_give_finite_forces(model, mass):
    wheel = st.Wheel(mass=mass)
    assert st.Wheel(mass=mass).mass == mass
    assert np.all(np.isfinite(st.wheel_rail_force(st.slab_track(), [10.0, 1000.0, 5000.0], wheel, origin="support")))
    res = st.wheel_rail_response(model, wheel, dt=5e-5, duration=0.03, ramp=0.01)
    assert np.all(np.isfinite(res.force))


def test_the_force_at_an_undamped_suspension_resonance_is_zero_not_nan():
    k1, m = 1e6, 600.0
    wheel = st.Wheel(mass=m, primary_stiffness=k1)  # undamped: the wheel's receptance is infinite at f0
    f0 = np.sqrt(k1 / m) / (2 * np.pi)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no division by zero on the way
        force = st.wheel_rail_force(st.slab_track(), [f0, 100.0], wheel, origin="support")
    assert np.all(np.isfinite(force))
    assert abs(force[0]) < 1e-9 * abs(force[1])  # the limit: no force where the wheel gives way freely
    # away from it, the same as -1 / (alpha_W + alpha_C + alpha_R)
    alpha_r = st.point_receptance(st.slab_track(), [100.0], 0.0, origin="support")[0, 0, 0]
    expected = -1.0 / (wheel.receptance(100.0) + 1.0 / wheel.contact_stiffness + alpha_r)
    assert abs(force[1] - expected) < 1e-12 * abs(expected)


# --- runs refused before they allocate ---------------------------------------------------------------
def test_a_nanosecond_wheel_run_is_refused(model):
    refused(lambda: st.wheel_rail_response(model, st.Wheel(), dt=1e-9, duration=1.0), InputError,
            "duration=1.0 s / dt=1e-09 s", "limit")


def test_a_nanosecond_pulse_is_refused(model):
    refused(lambda: pulse_response(model, (0.0,), dt=1e-9, duration=10.0), InputError, "duration=10.0 s / dt=1e-09 s")


def test_a_load_at_a_millimetre_per_second_is_refused(model):
    refused(lambda: moving_load_response(model, speed=1e-3, x_start=-0.5, x_end=0.5), InputError,
            "(x_end - x_start) / speed", "limit")


def test_the_fixed_cost_of_a_step_is_counted():
    # 1e8 steps of a 33-DOF model: 3.3e9 step-DOFs passed the old limit of 5e9 and allocated 763 MiB
    assert 10**8 * 33 < MAX_STEP_DOFS
    refused(lambda: check_limits(10**8, 33, 3), InputError, "per step", "step-DOFs")
    check_limits(10**5, 33, 3)  # a 1-s run at 10 us is fine


@pytest.mark.parametrize("dt, duration", [(0.2, 0.1), (1.0, 0.05)])
def test_a_step_longer_than_the_run_is_refused(model, dt, duration):
    refused(lambda: st.wheel_rail_response(model, st.Wheel(), dt=dt, duration=duration, ramp=0.01), InputError,
            "dt", "duration", "longer")
    refused(lambda: pulse_response(model, (0.0,), dt=dt, duration=duration), InputError, "dt", "duration")


# --- roughness -----------------------------------------------------------------------------------------
@pytest.mark.parametrize("options, words", [
    ({"speed": 1e10}, ("speed=1e+10", "lines")),
    ({"speed": 100.0, "period": 1e7}, ("period=1e+07", "lines")),
])
def test_roughness_lines_are_counted_before_any_array(options, words):
    refused(lambda: roughness_from_spectrum(**options), InputError, *words)


@pytest.mark.parametrize("options, name", [
    ({"wavelengths": ["a"], "levels": [1.0]}, "wavelengths"),
    ({"wavelengths": [0.1], "levels": ["x"]}, "levels"),
    ({"wavelengths": [None], "levels": [1.0]}, "wavelengths"),
])
def test_roughness_spectra_of_text_are_refused(options, name):
    refused(lambda: roughness_from_spectrum(100.0, **options), InputTypeError, name)


def test_roughness_above_the_nyquist_frequency_is_warned(model):
    speed = 100.0
    r = corrugation(speed, speed / 40_000.0, 1e-7)  # a 40 kHz line; dt = 20 us resolves 25 kHz
    with pytest.warns(RuntimeWarning, match=r"40000 to 40000 Hz.*Nyquist frequency 25000 Hz") as record:
        st.wheel_rail_response(model, st.Wheel(), r, dt=2e-5, duration=0.03, ramp=0.01)
    aliasing = [w for w in record if "Nyquist" in str(w.message)]  # beside it the hysteretic track's own warning
    assert len(aliasing) == 1 and "acts as 10000 Hz" in str(aliasing[0].message)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # resolved: no warning
        r.sampled(1e-5, 10)
    with pytest.warns(RuntimeWarning, match="Nyquist"):
        roughness_from_spectrum(100.0).sampled(2e-5, 10)  # the ISO 3095 spectrum at 100 m/s reaches 31.7 kHz


def test_both_roughness_builders_warn_when_given_the_step():
    with pytest.warns(RuntimeWarning, match=r"40000 to 40000 Hz.*25000 Hz") as record:
        corrugation(100.0, 100.0 / 40_000.0, 1e-7, dt=2e-5)
    assert record[0].filename == __file__  # the warning points at the caller
    with pytest.warns(RuntimeWarning, match=r"from 25\d+ to 3\d+ Hz.*25000 Hz"):
        roughness_from_spectrum(100.0, dt=2e-5)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        corrugation(100.0, 0.05, 1e-7, dt=2e-5)  # 2 kHz: resolved
        roughness_from_spectrum(20.0, dt=2e-5)  # up to 6.3 kHz: resolved
    refused(lambda: corrugation(100.0, 0.05, 1e-7, dt=-1.0), InputError, "dt")


MEASURE = PEAK_RSS + textwrap.dedent("""
    import sys, time
    import semitrack as st
    from semitrack.model.roughness import roughness_from_spectrum
    from semitrack.fe.timedomain import moving_load_response, pulse_response
    model = st.TruncatedTrack(st.slab_track(), 2, elements_per_bay=4)
    calls = {
        "wheel": lambda: st.wheel_rail_response(model, st.Wheel(), dt=1e-9, duration=1.0),
        "pulse": lambda: pulse_response(model, (0.0,), dt=1e-9, duration=10.0),
        "moving": lambda: moving_load_response(model, speed=1e-3, x_start=-0.5, x_end=0.5),
        "speed": lambda: roughness_from_spectrum(1e10),
        "period": lambda: roughness_from_spectrum(100.0, period=1e7),
    }
    for name, call in calls.items():
        start = time.perf_counter()
        try:
            call()
            print(name, "ran")
        except Exception as err:
            print(name, type(err).__name__, time.perf_counter() - start)
    print("rss", peak_rss_kib())
""")


def test_the_refusals_stay_within_1_gb_and_30_s():
    env = {**os.environ, "PYTHONPATH": str(Path(st.__file__).parent.parent)}
    out = subprocess.run([sys.executable, "-c", MEASURE], env=env, capture_output=True, text=True, timeout=120)
    lines = out.stdout.strip().splitlines()
    assert len(lines) == 6, out.stdout + out.stderr
    for line in lines[:-1]:
        name, outcome, seconds = line.split()
        assert outcome == "InputError" and float(seconds) < 30, line
    assert int(lines[-1].split()[1]) < 1_000_000, lines[-1]  # KiB
