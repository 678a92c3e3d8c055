"""Stationary wheels on the exact infinite track by convolution: the reference that truncates nothing.

Independent checks: the linear theory of coupled wheels (the frequency domain) in every band for
a small roughness; the 10-bay FE model with broadband ends against it in time; contact lost under
a large roughness, the force never negative.
"""

import warnings

import numpy as np
import pytest

import semitrack as st
from semitrack.interaction.infinite_convolution import convolution_response, rail_impulse_responses

TRACK = st.ballasted_track(damping="viscous")


@pytest.fixture(scope="module")
def small():
    lam = st.third_octave_bands(0.04, 2.0)[0]
    return st.roughness_from_spectrum(100.0, lam, np.full(lam.size, -10.0), period=0.1, seed=1)


def test_the_convolution_follows_the_linear_theory(small):
    """One wheel and two wheels 2.5 m apart: every band within 0.05 dB (measured 0.015 and 0.019 dB)."""
    one = convolution_response(TRACK, st.Wheel(), small, dt=2e-5, duration=0.42)
    assert np.max(np.abs(st.contact_transfer(one).error_db)) < 0.05
    two = convolution_response(TRACK, [st.Wheel(), st.Wheel()], small, x=[1.25, -1.25], dt=2e-5,
                               duration=0.42)
    for i in range(2):
        transfer = st.contact_transfer(two, wheel=i)
        assert transfer.centres.size == 18 and np.max(np.abs(transfer.error_db)) < 0.05


def test_the_truncated_model_against_the_reference_that_truncates_nothing(small):
    """The 10-bay FE model with broadband ends and a bogie: the force's fluctuation within 5 % rms of the
    convolution on the exact track (measured 3.2 %), each band within 0.3 dB of it."""
    model = st.TruncatedTrack(TRACK, 10, "boundary", system=st.fit_boundary(TRACK))
    fe = st.wheel_rail_response(model, st.Bogie(), small, x=1.25, dt=2e-5, duration=0.42)
    exact = convolution_response(TRACK, st.Bogie(), small, x=1.25, dt=2e-5, duration=0.42)
    late = fe.t > 0.05
    fluctuation = exact.force[late] - exact.force[late].mean(axis=0)
    rms = np.sqrt(np.mean((fe.force[late] - exact.force[late]) ** 2, axis=0) / np.mean(fluctuation**2, axis=0))
    assert np.all(rms < 0.05), rms
    for i in range(2):
        gap = st.contact_transfer(fe, wheel=i).level - st.contact_transfer(exact, wheel=i).level
        assert np.max(np.abs(gap)) < 0.3


def test_a_large_roughness_loses_contact_and_the_memory_is_long_enough():
    rough = st.corrugation(100.0, 0.1, 1e-4)  # 1 kHz near the pinned-pinned peak: twice the preload, linearly
    res = convolution_response(st.slab_track(damping="viscous"), st.Wheel(), rough, dt=1e-5, duration=0.04,
                               ramp=0.005, memory=0.3)
    assert res.lost_contact and res.force.min() == 0.0 and res.force.max() > 1.5e5
    x = np.array([0.0])
    short, long = (rail_impulse_responses(st.InfiniteTrack(TRACK), x, 2e-5, m)[2] for m in (0.05, 0.4))
    assert long < short and long < 1e-3  # what the memory cuts off shrinks as it grows
    with pytest.warns(RuntimeWarning, match="give a longer memory"):  # the run outlasts the memory: lags are cut
        convolution_response(TRACK, st.Wheel(), rough, dt=2e-5, duration=0.08, ramp=0.005, memory=0.05)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a run within the memory uses every lag it has: nothing is cut
        convolution_response(TRACK, st.Wheel(), rough, dt=2e-5, duration=0.04, ramp=0.005, memory=0.05)


def test_the_rail_s_impulse_responses_are_kept_for_their_track():
    """A second call on the same InfiniteTrack returns the same read-only arrays; another memory or another
    track computes its own, equal to a fresh computation; runs on equal Tracks share one exact track."""
    inf = st.InfiniteTrack(TRACK)
    x = np.array([0.0])
    first, again = (rail_impulse_responses(inf, x, 2e-5, 0.05) for _ in range(2))
    assert first[0] is again[0] and not first[0].flags.writeable and not first[1].flags.writeable
    fresh = rail_impulse_responses(st.InfiniteTrack(TRACK), x, 2e-5, 0.05)
    assert fresh[0] is not first[0]
    np.testing.assert_array_equal(fresh[0], first[0])
    longer = rail_impulse_responses(inf, x, 2e-5, 0.1)
    assert longer[0].shape[0] == 2 * first[0].shape[0]
    from semitrack.interaction.infinite_convolution import _periodic

    assert _periodic(TRACK) is _periodic(TRACK.replace(name=TRACK.name))
