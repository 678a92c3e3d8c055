"""The default mesh follows the frequencies asked: its own error under 1 %, measured, and a warning when too coarse."""

import warnings

import numpy as np
import pytest

import semitrack as st
from semitrack.fe.meshsize import MIN_ELEMENTS, elements_for, valid_frequency
from semitrack.fe.models import mesh_probe


def _elements(tracks, f_max):
    return elements_for([mesh_probe(t, f_max) for t in tracks], f_max)


def _mesh_only_error(track, elements_per_bay, f):
    """Largest relative error of w/F at a mid-span, a quarter span and a support: exact ends leave only the mesh."""
    model = st.FETrack(track, 3, 3, "exact", "exact", elements_per_bay=elements_per_bay)
    exact = st.InfiniteTrack(track)
    d, out = track.spacing, 0.0
    for x in (0.0, 0.25 * d, 0.5 * d):
        if elements_per_bay % 4 and x == 0.25 * d:
            continue  # not a node
        rhs = np.zeros((model.n_dof, 1))
        rhs[model.dof(x)] = 1.0
        u = model.solve(f, rhs, check_mesh=False)[:, model.dof(x), 0]
        ref = exact.receptance(f, x, [x])[:, 0, 0, 0]
        out = max(out, float(np.max(np.abs(u - ref) / np.abs(ref))))
    return out


@pytest.mark.parametrize("track, f_max", [
    (st.ballasted_track(), 3000.0), (st.slab_track(damping="viscous"), 3000.0),
    (st.ballasted_track(eta_rail=0.005, kv=1.5e8, spacing=0.65), 1500.0), (st.slab_track(kv=2e8, spacing=0.6), 800.0),
], ids=["ballasted", "slab-viscous", "made-up-ballasted", "made-up-slab"])
def test_the_default_mesh_keeps_its_own_error_under_one_percent(track, f_max):
    """On a 1 Hz grid (finer than the probe's 2 Hz) and at a quarter span too (the probe reads two points);
    and not wastefully fine: above the floor, the error is within a factor 3 of the tolerance."""
    ne = _elements((track,), f_max)
    error = _mesh_only_error(track, ne, np.arange(1.0, f_max + 0.5, 1.0))
    assert error < 0.01
    assert ne == MIN_ELEMENTS or error > 0.01 / 3


def test_the_error_law_predicts_other_meshes():
    """The probe's error at 24 elements, scaled by (24 / n)^2, is the measured error at n within 15 %."""
    track = st.ballasted_track()
    f = np.arange(2.0, 3000.5, 2.0)
    for n in (16, 48):
        measured = _mesh_only_error(track, n, f)
        assert mesh_probe(track, 3000.0).error_at(n, 3000.0) == pytest.approx(measured, rel=0.15)


def test_mesh_grows_with_the_frequency_and_has_a_floor():
    slab = st.slab_track()
    sizes = [_elements((slab,), f) for f in (200.0, 1000.0, 3000.0, 6000.0)]
    assert sizes == sorted(sizes) and sizes[0] == MIN_ELEMENTS and sizes[-1] > sizes[1]
    assert all(n % 2 == 0 for n in sizes)
    both = _elements((slab, st.ballasted_track()), 3000.0)
    assert both == max(_elements((slab,), 3000.0), _elements((st.ballasted_track(),), 3000.0))


def test_models_take_the_default_and_warn_when_too_coarse():
    slab = st.slab_track()
    model = st.TruncatedTrack(slab, 2, f_max=1000.0)
    assert model.elements_per_bay == _elements((slab,), 1000.0) and model.f_max == 1000.0
    assert st.TruncatedTrack(slab, 2).elements_per_bay == _elements((slab,), 3000.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        model.receptance([100.0, 900.0])  # within f_max: no warning
    coarse = st.TruncatedTrack(slab, 2, elements_per_bay=8)
    need = _elements((slab,), 2000.0)
    with pytest.warns(RuntimeWarning, match=f"8 elements per bay .* up to .* Hz only.* >= {need}"):
        coarse.receptance(np.linspace(10.0, 2000.0, 50))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        coarse.receptance([1500.0])  # warned once for this range
    probe = [mesh_probe(slab, 2000.0)]
    assert valid_frequency(probe, 8) < 1000.0 < valid_frequency(probe, 48)


def test_long_tracks_mesh_from_the_frequencies_asked():
    """fe_semi_infinite_receptance takes its default mesh from max(f), so its second pinned-pinned peak is right."""
    slab = st.slab_track(damping="viscous")
    f = np.arange(2500.0, 2650.0, 3.0)
    exact = st.semi_infinite_receptance(slab, f)[:, 0, 0]
    auto = st.fe_semi_infinite_receptance(slab, f, n_bays=4, far_end="exact")[:, 0, 0]
    with pytest.warns(RuntimeWarning, match="12 elements per bay"):
        coarse = st.fe_semi_infinite_receptance(slab, f, n_bays=4, far_end="exact", elements_per_bay=12)[:, 0, 0]
    assert np.max(np.abs(auto / exact - 1)) < 0.01 < np.max(np.abs(coarse / exact - 1))


def test_a_stated_f_max_checks_an_explicit_mesh_at_once():
    """The time domain's case: no frequencies are asked later, so a stated f_max is checked on construction."""
    slab = st.slab_track()
    with pytest.warns(RuntimeWarning, match="8 elements per bay"):
        st.TruncatedTrack(slab, 2, elements_per_bay=8, f_max=2500.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        st.TruncatedTrack(slab, 2, elements_per_bay=48, f_max=2500.0)
