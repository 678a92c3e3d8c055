"""The package's warnings: each names what it assumed and the unit asked, once, at the user's line.

What is checked: a hysteretic track in the time domain (viscous equivalents named, with the
broadband end's accuracy), implausible magnitudes (a gap in mm typed as m, a pad without
stiffness), an aliasing roughness shown once however many of the package's calls sample it, and
messages that show rounded numbers, never a numpy repr. Beside them, the claim of the README's
table of defects that a failed fastener is ``None``: to the rail, a sleeper it no longer holds
is no sleeper (the exact infinite track, both notations, to round-off).
"""

from __future__ import annotations

import re
import warnings

import numpy as np
import pytest

import semitrack as st


def _caught(call, category=UserWarning):
    """The warnings of ``call`` under the default filters (each location once), of ``category``."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.resetwarnings()
        warnings.simplefilter("default")
        result = call()
    return result, [w for w in caught if issubclass(w.category, category)]


def test_a_hysteretic_track_in_the_time_domain_warns_once_naming_its_viscous_equivalents():
    """A run on the paper's hysteretic slab track: one warning at this file's line, naming each
    family's reference frequency (the viscous dampers that stand in for the loss factors)."""
    track = st.slab_track()
    model = st.TruncatedTrack(track, 2, elements_per_bay=4)
    _, caught = _caught(lambda: st.wheel_rail_response(model, st.Wheel(), dt=1e-4, duration=0.005, ramp=0.002),
                        st.HystereticDampingWarning)
    assert len(caught) == 1 and caught[0].filename == __file__
    fr = track.reference_frequencies()
    text = str(caught[0].message)
    assert f"rail {fr['rail']:.0f} Hz, pads {fr['pad']:.0f} Hz" in text and "damping='viscous'" in text
    assert "broadband end" not in text  # pinned ends: no end's accuracy to name
    _, none = _caught(lambda: st.wheel_rail_response(st.TruncatedTrack(st.slab_track(damping="viscous"), 2,
                                                                       elements_per_bay=4),
                                                     st.Wheel(), dt=1e-4, duration=0.005, ramp=0.002),
                      st.HystereticDampingWarning)
    assert none == []


def test_the_warning_names_the_broadband_end_s_accuracy_and_the_ballast():
    track = st.ballasted_track()
    end = st.fit_boundary(track, n_poles=24)
    model = st.TruncatedTrack(track, 2, "boundary", system=end, elements_per_bay=4)
    _, caught = _caught(model.time_domain_system, st.HystereticDampingWarning)
    text = str(caught[0].message)
    assert f"follows the hysteretic track to {100 * end.max_error:.1f} % at worst" in text
    assert f"ballast {track.reference_frequencies()['ballast']:.0f} Hz" in text
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        warnings.filterwarnings("ignore", category=st.HystereticDampingWarning)  # the class silences it
        model.matrices()


@pytest.mark.parametrize("gap, warned", [(0.5, True), (0.021, True), (0.02, False), (2e-3, False)])
def test_a_gap_above_20_mm_warns_in_the_unit_asked_on_both_fe_routes(gap, warned):
    track = st.ballasted_track(damping="viscous")
    model = st.TruncatedTrack(track, 3, elements_per_bay=4, changes={0: {"kb": 0.0}})
    run = dict(dt=1e-4, duration=0.004, ramp=0.002, ballast_gaps={0: gap})
    _, caught = _caught(lambda: st.wheel_rail_response(model, st.Wheel(), **run), st.ImplausibleValueWarning)
    assert len(caught) == warned
    if warned:
        text = str(caught[0].message)
        assert f"ballast_gaps[0]={gap:g} m is a gap of {1e3 * gap:.0f} mm" in text and "in metres" in text
        assert caught[0].filename == __file__
    window = st.WindowTrack(track, {0: {"kb": 0.0}}, behind=3, ahead=3, elements_per_bay=4,
                            system=st.fit_boundary(track, n_poles=24))
    _, caught = _caught(lambda: st.wheel_rail_response(window, st.Wheel(), **run), st.ImplausibleValueWarning)
    assert len(caught) == warned


def test_a_pad_without_stiffness_warns_and_names_the_failed_fastener_s_notation():
    _, caught = _caught(lambda: st.InfiniteTrack(st.ballasted_track(), {3: {"kv": 0.0}}), st.ImplausibleValueWarning)
    assert len(caught) == 1 and "changes={3: None}" in str(caught[0].message) and caught[0].filename == __file__
    _, none = _caught(lambda: st.InfiniteTrack(st.ballasted_track(), {3: None, 4: {"kv": 1e7}}),
                      st.ImplausibleValueWarning)
    assert none == []


def test_a_failed_fastener_is_none_in_either_notation_to_the_rail():
    """``{k: None}`` (no support) and a fastener that holds nothing (kv = kphi = 0, the sleeper
    still on its ballast) give the rail the same receptance: the README's table of defects."""
    track = st.ballasted_track()
    f = np.array([50.0, 117.0, 400.0, 1000.0])
    x = [0.0, 0.3, 1.2]
    none = st.InfiniteTrack(track, {0: None}).receptance(f, 0.3, x)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", st.ImplausibleValueWarning)
        zero = st.InfiniteTrack(track, {0: {"kv": 0.0, "kphi": 0.0}}).receptance(f, 0.3, x)
    np.testing.assert_allclose(zero, none, rtol=1e-10, atol=1e-12 * np.abs(none).max())
    perfect = st.InfiniteTrack(track).receptance(f, 0.3, x)
    assert np.abs(none[:, 0, 0, 0] / perfect[:, 0, 0, 0] - 1).max() > 0.05  # the defect shows


def test_an_aliasing_roughness_warns_once_per_run():
    """Sampled by the run's input and by its transfer, the same roughness warns once, at this line."""
    rough = st.corrugation(10.0, 0.0004, 1e-6)  # 25 kHz at 10 m/s, above the 5 kHz Nyquist of dt = 0.1 ms
    model = st.TruncatedTrack(st.slab_track(damping="viscous"), 2, elements_per_bay=4)
    _, caught = _caught(lambda: st.wheel_rail_response(model, st.Wheel(), rough, dt=1e-4, duration=0.005,
                                                       ramp=0.002), RuntimeWarning)
    aliasing = [w for w in caught if "Nyquist" in str(w.message)]
    assert len(aliasing) == 1 and aliasing[0].filename == __file__
    assert "dt=0.0001 s" in str(aliasing[0].message)


def test_messages_show_rounded_numbers_not_numpy_reprs():
    speed = np.float64(23.777777777777782)
    with pytest.raises(st.BadInput) as caught:
        st.moving_green_kernels(st.slab_track(damping="viscous"), speed, dt=0.01)
    text = str(caught.value)
    assert "speed=23.7778 m/s and dt=0.01 s" in text and "np.float64" not in text
    rough = st.corrugation(np.float64(20.123456789), 0.05, 1e-6)
    with pytest.raises(st.BadInput) as caught:
        st.convolution_response(st.slab_track(), st.Wheel(), rough, speed=np.float64(10.987654321), dt=1e-4,
                                duration=0.004, ramp=0.002)
    text = str(caught.value)
    assert re.search(r"speed=10.9877 m/s, got 20.1235 m/s", text) and "np.float64" not in text
