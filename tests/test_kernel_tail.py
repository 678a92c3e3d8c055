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


@pytest.mark.filterwarnings("ignore:tail_start=")  # at full rank the FFTs cost more than they save: warned of
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


@pytest.mark.filterwarnings("ignore:tail_start=")
def test_the_default_start_is_the_documented_one(kernels):
    """No tail_start: the tail starts at DEFAULT_TAIL_START (0.1 s, 1000 steps), and over 0.15 s it does take part."""
    P = kernels.grid.positions
    whole = _run(kernels, duration=0.15)
    tailed = _run(kernels, duration=0.15, tail_rank=P)
    assert (int(round(DEFAULT_TAIL_START / DT)), P) in _memo_keys(kernels)
    assert _rms(tailed, whole) <= 1e-9
    assert not np.array_equal(tailed.force, whole.force)  # the tail's FFTs, not the whole kernels, past 0.1 s


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
    ({"tail_rank": 3, "tail_start": 0.2}, "tail_start=0.2 s must lie within"),
    ({"tail_rank": 3, "tail_start": 1e-6}, "tail_start=1e-06 s must lie within"),
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
        _run(kernels, duration=0.03, tail_rank=1, tail_start=0.006)


def test_a_block_longer_than_the_tail_s_start_is_refused(kernels):
    tail = kernel_tail(kernels, 50, 2)
    pair = np.zeros((1, 1), dtype=np.int64)
    with pytest.raises(InputError, match="first <= last < first"):
        tail.response(np.zeros((200, 1)), pair, np.zeros(1, dtype=np.int64), 1, 60)


@pytest.mark.parametrize("compiled, wheels", [(False, THREE), (True, THREE), (False, st.Wheel())])
def test_the_loop_in_pieces_is_the_one_run_bit_for_bit(kernels, monkeypatch, compiled, wheels):
    """The step loop run in blocks of 70 steps with the whole kernels and a tail that adds nothing gives the one
    call's numbers exactly: every step starts from what the arrays hold (the general loops, and the Python loop of
    one wheel in floats)."""
    if compiled:
        pytest.importorskip("numba")
    from semitrack.fe.kerneltail import KernelTail
    from semitrack.interaction import moving_green

    n = len(kernels.grid.lags)
    nothing = KernelTail(70, 1, kernels.loop, np.zeros((n, kernels.grid.positions, 1)), np.zeros((n, 1, 1)), 0.0)

    def run(**tail):
        return st.moving_green_response(SLAB, wheels, _rough(SPEED), speed=SPEED, dt=DT, duration=0.05,
                                        kernels=kernels, compiled=compiled, **tail)

    whole = run()
    monkeypatch.setattr(moving_green, "_tail_of", lambda *args: nothing)
    pieces = run(tail_rank=1)
    assert np.array_equal(pieces.force, whole.force) and np.array_equal(pieces.w_rail, whole.w_rail)
    assert np.array_equal(pieces.w_wheel, whole.w_wheel)


def test_the_tail_s_own_arguments_are_checked_before_any_set_up(monkeypatch):
    """A rank that is no whole number, or a start without a rank, is refused before the kernels are made (a set-up
    of a minute for three wheels)."""
    from semitrack.interaction import moving_green

    def no_set_up(*args):
        raise AssertionError("the kernels were made before the tail's arguments were checked")

    monkeypatch.setattr(moving_green, "_kernels_for", no_set_up)
    run = {"speed": SPEED, "dt": DT, "duration": 0.03, "memory": 0.15, "elements_per_bay": NE}
    with pytest.raises(InputTypeError, match="tail_rank"):
        st.moving_green_response(SLAB, THREE, tail_rank=2.5, **run)
    with pytest.raises(InputError, match="give tail_rank"):
        st.moving_green_response(SLAB, THREE, tail_start=0.05, **run)
    with pytest.raises(InputError, match="tail_start"):
        st.moving_green_response(SLAB, THREE, tail_rank=2, tail_start=float("nan"), **run)


@pytest.mark.filterwarnings("ignore:memory=0.05")  # kernels cut short: warned of where they are made
def test_a_default_start_beyond_a_short_memory_is_named_as_the_default():
    short = st.moving_green_kernels(SLAB, SPEED, DT, THREE.offsets, memory=0.05, elements_per_bay=NE)
    with pytest.raises(InputError, match="tail_start, by default 0.1 s, must lie within"):
        _run(short, duration=0.03, tail_rank=2)


@pytest.mark.filterwarnings("ignore:tail_rank=4")  # this early the factors are also far from the kernels
def test_a_start_too_early_to_save_is_warned_of(kernels):
    with pytest.warns(RuntimeWarning, match="cost more than the dot products it saves"):
        _run(kernels, duration=0.03, tail_rank=4, tail_start=0.01)


@pytest.mark.parametrize("start, rank", [(0, 2), (1500, 2), (2.5, 2), (100, 0), (100, 10_000), (100, 1.5)])
def test_kernel_tail_refuses_a_start_or_rank_that_does_not_fit(kernels, start, rank):
    with pytest.raises(InputError, match="start|rank"):
        kernel_tail(kernels, start, rank)


def test_the_kernels_by_phase_from_a_step_on_are_the_impulse_kernels_columns(kernels):
    for lag in kernels.grid.lags:
        assert np.array_equal(kernels.by_phase(lag, 250), kernels.impulse[lag][:, 250:])
