"""The moving kernels' tail in low rank (semitrack.fe.kerneltail): exact at full rank, close at low rank, refused
where it does not fit, and the same in the compiled and the Python loop."""

from __future__ import annotations

import numpy as np
import pytest

import semitrack as st
from semitrack.base.errors import InputError, InputTypeError
from semitrack.fe.kerneltail import kernel_tail
from semitrack.interaction.moving_green import DEFAULT_TAIL_START

SLAB = st.slab_track(damping="viscous")
NE = 8  # a coarse mesh: the checks are of the method
SPEED, DT = 50.0, 1e-4
THREE = st.WheelGroup((st.Wheel(),) * 3, spacing=(0.0, -1.0, -2.0))


@pytest.fixture(scope="module")
def kernels():
    return st.moving_green_kernels(SLAB, SPEED, DT, THREE.offsets, memory=0.15, elements_per_bay=NE)


def _rough(speed):
    lam = st.third_octave_bands(0.04, 0.5)[0]
    return st.roughness_from_spectrum(speed, lam, np.full(lam.size, 0.0), period=0.05, seed=2)


def _run(kernels, duration=0.12, **tail):
    return st.moving_green_response(SLAB, THREE, _rough(SPEED), speed=SPEED, dt=DT, duration=duration,
                                    kernels=kernels, **tail)


def _rms(a, b):
    """The forces' rms difference over the reference's fluctuation, the worst wheel."""
    fluct = b.force - b.force.mean(axis=0)
    return float((np.sqrt(np.mean((a.force - b.force) ** 2, axis=0)) / np.sqrt(np.mean(fluct**2, axis=0))).max())


def test_a_full_rank_tail_is_the_whole_kernels(kernels):
    """At the rank of the phases the factors are the kernels (an orthonormal basis): the blocks, their FFTs and the
    heads give the whole kernels' run to round-off, over several blocks and a last one cut short."""
    P = kernels.grid.positions
    whole = _run(kernels)
    tailed = _run(kernels, tail_rank=P, tail_start=0.025)  # blocks of 250 steps: 4 whole, the fifth of 200
    assert kernel_tail(kernels, 250, P).error <= 1e-12
    assert _rms(tailed, whole) <= 1e-9
    assert np.abs(tailed.w_rail - whole.w_rail).max() <= 1e-9 * np.abs(whole.w_rail).max()


def test_a_low_rank_tail_keeps_the_forces_and_says_how_far_it_is(kernels):
    """Rank 4 past 0.08 s on three wheels (50 m/s, a coarse mesh: slower to lose the phase than the paper's tracks
    at speed): the factors within 1e-5 of the kernels' peak and the forces within 1e-4 of their fluctuation (rms)
    of the whole kernels' (measured: 8.6e-6 and 2.1e-5); a lower rank and an earlier start are farther."""
    whole = _run(kernels)
    close = _run(kernels, tail_rank=4, tail_start=0.08)
    factors = kernel_tail(kernels, 800, 4)
    assert factors.error <= 1e-5 and factors.head.shape == (len(kernels.grid.lags), kernels.grid.positions, 800)
    assert _rms(close, whole) <= 1e-4
    with pytest.warns(RuntimeWarning, match="tail_rank=1"):
        coarse = _run(kernels, tail_rank=1, tail_start=0.01)
    assert kernel_tail(kernels, 100, 1).error > 100 * factors.error
    assert _rms(coarse, whole) > 100 * _rms(close, whole)


def test_the_default_start_is_the_documented_one(kernels):
    tailed = _run(kernels, duration=0.03, tail_rank=kernels.grid.positions)
    assert tailed.force.shape == (301, 3)
    assert (int(round(DEFAULT_TAIL_START / DT)), kernels.grid.positions) in _memo_keys(kernels)


def _memo_keys(kernels):
    from semitrack.fe.kerneltail import _MEMO
    return set(_MEMO[kernels])


@pytest.mark.filterwarnings("ignore:tail_rank=3")
def test_the_compiled_and_the_python_loop_take_the_tail_alike(kernels):
    """Both loops in the same blocks of 200 steps, the tail's share added between them."""
    pytest.importorskip("numba")
    runs = [_run(kernels, duration=0.07, tail_rank=3, tail_start=0.02, compiled=c) for c in (False, True)]
    assert np.allclose(runs[0].force, runs[1].force, rtol=1e-12, atol=1e-9)


@pytest.mark.parametrize("tail, match", [
    ({"tail_start": 0.05}, "tail_start .*give tail_rank"),
    ({"tail_rank": 0}, "tail_rank"),
    ({"tail_rank": 10_000}, "tail_rank must be at most"),
    ({"tail_rank": 3, "tail_start": 0.2}, "tail_start must lie within"),
    ({"tail_rank": 3, "tail_start": 1e-6}, "tail_start must lie within"),
    ({"tail_rank": 3, "tail_start": -0.01}, "tail_start"),
])
def test_a_tail_that_does_not_fit_is_refused_naming_it(kernels, tail, match):
    with pytest.raises(InputError, match=match):
        _run(kernels, duration=0.03, **tail)


def test_a_rank_that_is_no_integer_is_refused_naming_it(kernels):
    with pytest.raises(InputTypeError, match="tail_rank must be an integer"):
        _run(kernels, duration=0.03, tail_rank=2.5)


def test_a_tail_far_from_the_kernels_is_warned_of(kernels):
    with pytest.warns(RuntimeWarning, match="tail_rank=1 .* holds the kernels to"):
        _run(kernels, duration=0.03, tail_rank=1, tail_start=0.002)


def test_a_block_longer_than_the_tail_s_start_is_refused(kernels):
    tail = kernel_tail(kernels, 50, 2)
    pair = np.zeros((1, 1), dtype=np.int64)
    with pytest.raises(InputError, match="first <= last < first"):
        tail.response(np.zeros((200, 1)), pair, np.zeros(1, dtype=np.int64), 1, 60)


@pytest.mark.parametrize("compiled", [False, True])
def test_the_loop_in_pieces_is_the_one_run_bit_for_bit(kernels, monkeypatch, compiled):
    """The step loop run in blocks of 70 steps with the whole kernels and a tail that adds nothing gives the one
    call's numbers exactly: every step starts from what the arrays hold."""
    if compiled:
        pytest.importorskip("numba")
    from semitrack.fe.kerneltail import KernelTail
    from semitrack.interaction import moving_green

    n = len(kernels.grid.lags)
    nothing = KernelTail(70, 1, kernels.loop, np.zeros((n, kernels.grid.positions, 1)), np.zeros((n, 1, 1)), 0.0)
    whole = _run(kernels, duration=0.05, compiled=compiled)
    monkeypatch.setattr(moving_green, "_tail_of", lambda *args: nothing)
    pieces = _run(kernels, duration=0.05, compiled=compiled, tail_rank=1)
    assert np.array_equal(pieces.force, whole.force) and np.array_equal(pieces.w_rail, whole.w_rail)
    assert np.array_equal(pieces.w_wheel, whole.w_wheel)
