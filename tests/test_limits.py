"""Runaway work and wrong-typed input are refused at once, with a message naming the parameter.

Each case was found by trying the package as a careless user would (a mistyped step, a huge
model); before the limits some of them grew to tens of GB or ran for hours.
"""

import re
import time

import numpy as np
import pytest

import semitrack as st
from semitrack.base.checks import MAX_FREQUENCIES, check_band
from semitrack.fe.timedomain import newmark
from semitrack.methods import transfer

SLAB = st.slab_track()


def _no_load(t):
    return np.zeros(1)


RUNAWAY = {
    "search grid df=1e-5": (lambda: st.characteristic_frequencies(SLAB, band=(3, 3000), df=1e-5),
                            r"df=1e-05 over band \(3.0, 3000.0\) gives 299700001 grid frequencies"),
    "too many frequencies": (lambda: st.semi_infinite_receptance(SLAB, np.arange(1.0, MAX_FREQUENCIES + 2)),
                             r"f holds 200001 frequencies"),
    "wavenumber beta_max x1000": (lambda: st.semi_infinite_receptance(SLAB, [100.0], method="wavenumber",
                                                                      beta_max=78540.0),
                                 r"beta_max/dbeta/j_max = 78540.0/.* terms per frequency"),
    "wavenumber sweep too long": (lambda: st.semi_infinite_receptance(SLAB, np.arange(1.0, 30001.0),
                                                                       method="wavenumber", beta_max=785.4),
                                  r"30000 frequencies x 4100000 terms"),
    "50 bars": (lambda: st.fit_equivalent(SLAB, layout="slab", n_bars=50), r"n_bars=50 asks for a fit of 50 bars"),
    "100000 bays": (lambda: st.TruncatedTrack(SLAB, 100_000), r"200000 bays \(n_bays, or n_left \+ n_right\)"),
    "1e10 time steps": (lambda: newmark([[1.0]], [[0.0]], [[1.0]], _no_load, 1e-9, 10**10),
                        r"n_steps = 10000000000 steps x 1 DOFs"),
    "recording 3e8 values": (lambda: newmark(np.eye(1000), np.zeros((1000, 1000)), np.eye(1000),
                                             lambda t: np.zeros(1000), 1e-3, 300_000),
                             r"n_steps = 300000 steps x 1000 outputs"),
}


@pytest.mark.parametrize("case", RUNAWAY)
def test_runaway_work_is_refused_at_once(case):
    call, message = RUNAWAY[case]
    start = time.perf_counter()
    with pytest.raises(ValueError, match=message + r".*more than the limit of \d+ \(time and memory\); "):
        call()
    assert time.perf_counter() - start < 2.0  # refused before any of the work (generous for a busy CI)


@pytest.mark.parametrize("f", [True, [True, False], "100", ["3", "900"], None, [None], object(), [1.0, [2.0, 3.0]]])
def test_frequencies_must_be_numbers_as_track_parameters_are(f):
    with pytest.raises(TypeError, match=r"f must be a number or an array of numbers in Hz, got "):
        st.semi_infinite_receptance(SLAB, f)


@pytest.mark.parametrize("band", [("3", "900"), (True, 900.0), 900.0, (3.0,), None])
def test_bands_must_be_pairs_of_numbers(band):
    with pytest.raises(TypeError, match=r"band must be a pair of frequencies \(f_lo, f_hi\) in Hz"):
        check_band(band)
    assert check_band((np.float64(3.0), 900)) == (3.0, 900.0)


@pytest.mark.parametrize("x", [np.nan, np.inf, -np.inf, 1e308])
def test_point_receptance_refuses_positions_it_cannot_resolve(x):
    with pytest.raises(ValueError, match=r"x must be finite and within 1e9 periods"):
        st.point_receptance(SLAB, [100.0], x=x, origin="support")
    # Far but resolvable positions are periodic images.
    far = 1e6 * SLAB.spacing + 0.1
    np.testing.assert_allclose(st.point_receptance(SLAB, [100.0], x=far, origin="support"),
                               st.point_receptance(SLAB, [100.0], x=far % SLAB.spacing, origin="support"), rtol=1e-6)


@pytest.mark.parametrize("case", [dict(kappa=1e300), dict(E=2e211), dict(A=1e-300), dict(G=1e-300)])
def test_a_track_refuses_moduli_that_overflow_the_algebra(case):
    """Absurd moduli overflowed the exact method's algebra (it refused them there); the track now
    refuses them where it is made, naming the field and its physical range."""
    (key, value), = case.items()
    rule = rf"^{key} must be from .* \(.*around every real track\), got {re.escape(repr(value))}$"
    with pytest.raises(st.BadInput, match=rule):
        st.slab_track(**case)


def test_exact_method_refuses_what_it_cannot_resolve(monkeypatch):
    """Inside the track's ranges, a case the doubling cannot resolve: a clear ValueError, never a
    LinAlgError or a silently wrong alpha."""
    monkeypatch.setattr(transfer, "_MAX_DOUBLINGS", 1)
    with pytest.raises(ValueError, match=r"the exact method cannot resolve 'slab' at 2 frequencies from 100 Hz"):
        st.semi_infinite_receptance(st.slab_track(), [100.0, 1000.0])


@pytest.mark.parametrize("spacing", [1000.5, 1e300])
def test_track_refuses_a_spacing_no_railway_comes_near(spacing):
    with pytest.raises(ValueError, match=r"spacing must be at most 1000 m \(no railway track comes near\)"):
        st.slab_track(spacing=spacing)
    assert st.slab_track(spacing=1000.0).spacing == 1000.0
