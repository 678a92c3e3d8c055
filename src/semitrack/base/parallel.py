"""Independent runs side by side on threads of this process, each number bit for bit the serial one.

The chapters' studies run many independent time-domain runs (a wheel at several speeds, on two
models, over several gaps). A run's step loop is compiled with ``nogil``
(:mod:`semitrack.dynamics.compiled`) and dominates it, so on a machine with two cores two runs on
two threads take about the time of one: measured, six weld runs of the imperfect-track chapter took
2.4 s on two threads against 4.5 s in turn, with every force equal bit for bit. Threads, not
processes: nothing is pickled or imported again, the compiled loops are already loaded, and a run
keeps its Python objects.

A run's arithmetic does not depend on the thread it runs on; BLAS is held on one thread for the
whole map (:func:`~.threads.serial_blas`, whose limit is process-wide, entered once here so that no
run's own entry and exit can change it under another). Progress bars of the runs are silenced (two
would write over each other); an exception of a run is raised in the caller, the first one in the
order of ``items``, once the runs already started have ended (a Ctrl-C too: the runs under way
finish, those not started are cancelled).
"""

from __future__ import annotations

import contextvars
import os
from collections.abc import Callable, Iterable, Iterator
from concurrent.futures import ThreadPoolExecutor
from contextlib import contextmanager
from typing import TypeVar

from .notices import user_line, warnings_from
from .progress import silenced
from .threads import serial_blas

__all__ = ["available_cores", "in_worker", "one_thread", "thread_map", "MAX_THREADS"]

T = TypeVar("T")
R = TypeVar("R")

#: Most threads :func:`thread_map` starts (more would only contend for the memory bus).
MAX_THREADS = 8
_WORKER = contextvars.ContextVar("semitrack_thread_map_worker", default=False)


def in_worker() -> bool:
    """Whether this code runs inside a :func:`thread_map` item (whose map already holds the cores), or
    inside :func:`one_thread`."""
    return _WORKER.get()


@contextmanager
def one_thread() -> Iterator[None]:
    """Every :func:`thread_map` inside runs its items in turn, in this thread: for timing a computation by
    its thread's CPU time (:func:`time.thread_time`), which a helper thread's work would escape."""
    token = _WORKER.set(True)
    try:
        yield
    finally:
        _WORKER.reset(token)


def available_cores() -> int:
    """Cores this process may run on (its CPU affinity where the system has one)."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # not on Linux
        return max(1, os.cpu_count() or 1)


def thread_map(func: Callable[[T], R], items: Iterable[T], workers: int | None = None) -> list[R]:
    """``[func(item) for item in items]``, the items run on up to ``workers`` threads at once.

    Parameters
    ----------
    func : callable
        Called once per item; it must not depend on the others' side effects (the runs are
        independent: a study's cases).
    items : iterable
        The items, in the order of the results; they start in this order (an item may wait for one
        before it, never for one after).
    workers : int, optional
        Threads at most; default :func:`available_cores` (at most :data:`MAX_THREADS`). One runs
        the items in turn in this thread, and so does a map inside another's item
        (:func:`in_worker`): the outer map already holds the cores.

    Returns
    -------
    list
        The results in the order of ``items``.

    Examples
    --------
    >>> thread_map(lambda x: x * x, range(5))
    [0, 1, 4, 9, 16]
    """
    items = list(items)
    n = min(len(items), MAX_THREADS, available_cores() if workers is None else max(1, int(workers)))
    n = 1 if in_worker() else n
    with serial_blas():
        if n <= 1:
            return [func(item) for item in items]
        pool = ThreadPoolExecutor(n, thread_name_prefix="semitrack-run")
        line = user_line()  # the package's warnings on the threads name the line that called the map
        try:
            futures = [pool.submit(_silenced_call, func, item, line) for item in items]
            return [future.result() for future in futures]
        finally:
            pool.shutdown(wait=True, cancel_futures=True)


def _silenced_call(func: Callable[[T], R], item: T, line: tuple[str, int, dict] | None) -> R:
    """``func(item)`` without progress bars, its warnings naming the caller's ``line`` (a new thread
    starts with a fresh context: the caller's silencing does not reach it)."""
    _WORKER.set(True)  # this thread's own context: the flag goes with the thread
    with silenced(), warnings_from(line):
        return func(item)
