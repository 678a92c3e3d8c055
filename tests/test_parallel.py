"""Runs side by side on threads (:mod:`semitrack.base.parallel`): the serial answer, bit for bit."""

from __future__ import annotations

import inspect
import threading
import time

import numpy as np
import pytest
from threadpoolctl import threadpool_info

import semitrack as st
from semitrack.base import parallel
from semitrack.base.notices import warn_user
from semitrack.base.parallel import thread_map
from semitrack.base.progress import progress_shown
from semitrack.paper import imperfect_study as study


def test_results_come_in_the_order_of_the_items_whatever_finishes_first():
    def slow_first(x):
        time.sleep(0.05 if x == 0 else 0.0)
        return x * x
    assert thread_map(slow_first, range(6), workers=3) == [0, 1, 4, 9, 16, 25]
    assert thread_map(slow_first, [], workers=3) == []


def test_the_items_run_on_several_threads_and_blas_on_one():
    seen, blas = set(), []
    barrier = threading.Barrier(2, timeout=5)

    def record(_):
        seen.add(threading.get_ident())
        blas.append([lib["num_threads"] for lib in threadpool_info() if lib["user_api"] == "blas"])
        barrier.wait()  # both items are under way at once, or this times out
        return None

    thread_map(record, range(2), workers=2)
    assert len(seen) == 2 and threading.get_ident() not in seen
    assert all(n == 1 for counts in blas for n in counts)


def test_one_worker_runs_in_this_thread():
    assert thread_map(lambda _: threading.get_ident(), range(3), workers=1) == [threading.get_ident()] * 3


def test_the_first_failing_item_in_order_raises_after_the_others_end():
    ended = []

    def run(x):
        if x in (1, 3):
            raise ValueError(f"item {x}")
        time.sleep(0.02 if x == 0 else 0.3)  # item 2 starts when 1 fails and is still under way when 0 ends
        ended.append(x)
        return x

    with pytest.raises(ValueError, match="item 1"):
        thread_map(run, range(4), workers=2)
    assert 2 in ended  # the run under way when item 1's error was found finished before it reached the caller


def test_bars_of_the_runs_are_silenced(monkeypatch):
    monkeypatch.setenv("SEMITRACK_PROGRESS", "1")  # bars forced on: drawn anywhere not silenced
    assert progress_shown()
    assert thread_map(lambda _: progress_shown(), range(2), workers=2) == [False, False]


def test_a_study_s_runs_on_two_threads_equal_the_serial_ones_bit_for_bit(monkeypatch):
    track = st.ballasted_track(damping="viscous")
    boundary = st.fit_boundary(track, n_poles=24)
    cases = {}
    for cores in (1, 2):
        monkeypatch.setattr(parallel, "available_cores", lambda cores=cores: cores)
        cases[cores] = study.gap_runs(track, boundary, (1.0, 5e-4), start=-0.6, stop=0.6)
    for g in (1.0, 5e-4):
        assert np.array_equal(cases[1][g].force, cases[2][g].force)
        assert np.array_equal(cases[1][g].gaps.force, cases[2][g].gaps.force)


def test_a_map_inside_an_item_runs_in_that_item_s_thread():
    def inner(_):
        outer = threading.get_ident()
        return all(t == outer for t in thread_map(lambda _: threading.get_ident(), range(4), workers=4))

    assert thread_map(inner, range(2), workers=2) == [True, True]


def test_a_warning_on_a_thread_names_the_line_that_called_the_map():
    line = inspect.currentframe().f_lineno + 2
    with pytest.warns(UserWarning, match="from a run") as caught:
        thread_map(warn_user, ["from a run", "from a run"], workers=2)  # warn_user is the package's own frame
    assert {(w.filename, w.lineno) for w in caught} == {(__file__, line)}  # not concurrent/futures/thread.py
