"""Run a function over many cases: in this process, on every core, or on a dask cluster; one table out.

:func:`run_study` runs ``func(**case)`` for each case and gives a :class:`pandas.DataFrame`, one
row per case in the order given. Where the cases run does not change the table: every case runs
with BLAS on one thread (in this process and on every worker), its outcome is placed by its index,
never by when it finished, and a number goes through the study's records bit for bit. With a
``cache_dir`` each finished case is stored at once (:mod:`.cases`), so a study interrupted in any
way, even killed, resumes with the cases it had not finished.

Parallel runs use dask's distributed scheduler, the established engine for this in scientific
Python: ``client=n`` starts a local cluster of ``n`` worker processes on the loopback (one thread
each, the dashboard on a free port) for the study and closes it after; a ``dask.distributed.Client``
made by the user runs the study on whatever cluster it is connected to and is left open. The local workers
start without the nanny's ``MALLOC_TRIM_THRESHOLD_=65536`` (it made the package's workloads 1.5-1.9
times slower per case: the many mid-sized arrays of a run were returned to the system and asked
for again) and without the worker's statistical profiler (it samples the running task's stack
every 10 ms, and took a run on a WindowTrack from 2.0 to 2.3-2.6 s a case). A cluster of your own
gains the same from ``DASK_DISTRIBUTED__WORKER__PROFILE__ENABLED=False`` in its workers' environment.

A script that starts a local cluster must guard its entry point with ``if __name__ == "__main__":``
(the workers are new Python processes that import the script's module).
"""

from __future__ import annotations

import logging
import time
import warnings
from collections.abc import Callable, Sequence
from contextlib import contextmanager

import numpy as np

from ..base.checks import brief, check_flag, check_int_at_least
from ..base.errors import InputError, InputTypeError
from ..base.files import check_cache_folder
from ..base.progress import Progress, silenced
from ..base.threads import serial_blas
from .cases import ERROR, case_key, check_cases, error_text, read_record, result_error, study_name, write_record

__all__ = ["run_study", "run_case", "MAX_LOCAL_WORKERS"]

#: Most worker processes of a local cluster (``client=n``).
MAX_LOCAL_WORKERS = 256
#: The workers' environment: BLAS on one thread each, and no ``MALLOC_TRIM_THRESHOLD_`` (module docstring).
WORKER_ENVIRONMENT = {"OMP_NUM_THREADS": 1, "MKL_NUM_THREADS": 1, "OPENBLAS_NUM_THREADS": 1,
                      "SEMITRACK_PROGRESS": "0"}  # a worker's bars would write over the study's line


def run_case(func: Callable, case: dict, inputs: frozenset = frozenset()) -> tuple[dict | None, str, float]:
    """``(result, error, seconds)`` of ``func(**case)``, with BLAS on one thread (where it runs, here or on a worker).

    An exception of the case is its outcome (``error`` says it, ``result`` is None); an interruption
    (Ctrl-C, a worker shut down) is not, and goes through. ``inputs``: every input name of the
    study, which a result may not reuse.
    """
    start = time.perf_counter()
    try:
        with serial_blas(), silenced():  # the study's own bar counts the cases
            out = func(**case)
        result, error = result_error(out, inputs | set(case))
    except Exception as err:  # noqa: BLE001 - a failing case is recorded, and the study goes on
        result, error = None, error_text(err)
    return result, error, time.perf_counter() - start


def _check_client(client: object):
    """None, a number of local workers, or a client (anything with dask's ``submit`` and ``gather``)."""
    if client is None:
        return None
    if isinstance(client, (bool, np.bool_)) or isinstance(client, (int, np.integer)):
        n = check_int_at_least("client", client, 1)
        if n > MAX_LOCAL_WORKERS:
            raise InputError(f"client={n} asks for more than {MAX_LOCAL_WORKERS} local workers: for a larger "
                             "cluster connect a dask.distributed.Client to its scheduler and pass it")
        return n
    if callable(getattr(client, "submit", None)) and callable(getattr(client, "gather", None)):
        return client
    raise InputTypeError(f"client must be None (this process), a number of local workers or a "
                         f"dask.distributed.Client, got {brief(client)} ({type(client).__name__})")


@contextmanager
def local_client(n_workers: int):
    """A dask client of a local cluster of ``n_workers`` processes on the loopback, closed after the block."""
    try:
        import dask
        from distributed import Client, LocalCluster
    except ImportError:  # pragma: no cover - dask[distributed] is in requirements.txt
        raise InputError("client=n needs dask.distributed: pip install 'dask[distributed]'") from None
    # not daemonic: a case may start processes of its own, as it may in this process
    with dask.config.set({"distributed.nanny.pre-spawn-environ": dict(WORKER_ENVIRONMENT),
                          "distributed.worker.daemon": False, "distributed.worker.profile.enabled": False}):
        cluster = LocalCluster(n_workers=n_workers, threads_per_worker=1, processes=True, host="127.0.0.1",
                               dashboard_address="127.0.0.1:0", silence_logs=logging.ERROR)
        try:
            with Client(cluster) as client:
                yield client
        finally:
            cluster.close()


class _Tally:
    """Done, running and failed cases, and the progress line that shows them with the time left."""

    def __init__(self, total: int, cached: int, failed: int, show: bool, slots: int):
        self.total, self.done, self.failed, self.slots = total, cached, failed, slots
        self.computed, self.start = 0, time.perf_counter()
        self.line = Progress("study", total, quiet=not show, unit="case", every=True)
        self.line.update(self.done, self._note())

    def _note(self) -> str:
        left = self.total - self.done
        running = min(self.slots, left)
        note = f"{running} running, {self.failed} failed"
        if self.computed and left:
            rate = (time.perf_counter() - self.start) / self.computed
            note += f", about {rate * left:.0f} s left"
        return note

    def add(self, error: str) -> None:
        self.done, self.computed, self.failed = self.done + 1, self.computed + 1, self.failed + bool(error)
        self.line.update(self.done, self._note())

    def close(self) -> None:
        self.line.close()


def _n_workers(client) -> int:
    """How many cases a client runs at once (its workers' threads), for the progress line."""
    try:
        return max(1, sum(client.nthreads().values()))
    except Exception:  # noqa: BLE001 - a client of another kind: the line then shows one at a time
        return 1


#: Cases handed to a cluster ahead of those running, per worker thread: enough to keep every worker
#: busy, few enough that a study of a million cases does not sit in the scheduler at once.
AHEAD = 4


def _run(func, cases: list[dict], todo: list[int], client, store, inputs: frozenset, slots: int) -> None:
    """Run the cases ``todo``, handing each outcome to ``store(i, outcome)`` as it arrives."""
    if client is None:
        for i in todo:
            store(i, run_case(func, cases[i], inputs))
        return
    from distributed import as_completed

    try:
        shared = client.scatter(func, broadcast=True, hash=False)  # sent to each worker once, not with every case
    except Exception as err:  # noqa: BLE001 - pickling raises whatever the object it met raises
        raise InputError(f"func cannot be sent to the workers ({type(err).__name__}: {str(err).splitlines()[0]}): "
                         "give a function of a module, or a partial of one whose fixed arguments pickle") from None
    waiting = iter(todo)
    futures: dict = {}

    def submit() -> None:
        i = next(waiting, None)
        if i is not None:
            futures[client.submit(run_case, shared, cases[i], inputs, pure=False)] = i

    for _ in range(AHEAD * slots + 8):
        submit()
    running = as_completed(list(futures))
    try:
        for future in running:
            i = futures.pop(future)
            try:
                outcome = future.result()
            except Exception as err:  # noqa: BLE001 - the worker died (KilledWorker), or the case would not pickle
                store(i, (None, f"not run: {error_text(err)}", 0.0), keep=False)
            else:
                store(i, outcome)
            before = set(futures)
            submit()
            for new in set(futures) - before:
                running.add(new)
    finally:
        for future in futures:
            future.cancel()


def run_study(func: Callable, cases: Sequence[dict], *, client=None, cache_dir=None, progress: bool = True):
    """Run ``func(**case)`` for every case and gather the results in one table.

    Parameters
    ----------
    func : callable
        ``func(**case) -> dict`` of numbers (floats, ints, bools), the same keys for every case as a
        rule. On a cluster it must be picklable: a function of a module (or, in a script, defined at
        its top level), or a :func:`functools.partial` of one with fixed arguments.
    cases : list of dict
        The inputs of each case (keyword arguments of ``func``): numbers, strings, None, tuples of
        them, the package's records (a Track). At most :data:`~semitrack.studies.cases.MAX_CASES`.
    client : None, int or dask.distributed.Client
        None: in this process, one case after the other. An int ``n``: on a local dask cluster of
        ``n`` worker processes started for the study. A ``Client``: on the cluster it is connected
        to (``Client("tcp://scheduler:8786")``), left open.
    cache_dir : str or os.PathLike, optional
        Folder of the study's records, one per case (checked and created before any case runs). A
        case whose record is there and matches is not run again; a record that does not match or
        cannot be read is recomputed. The records are keyed by func's module, name and code (and a
        partial's fixed arguments), the package's version and the case; func must then be a
        function of a module's top level or a partial of one. A change in what func calls is not
        seen: give a new folder then.
    progress : bool
        Show done, running and failed cases and the time left on one line of stderr (on a terminal only).

    Returns
    -------
    pandas.DataFrame
        The same bit for bit wherever the cases ran, on machines of one kind (CPU and libraries: BLAS
        picks its kernels by the CPU). One row per case, in the order of ``cases``: a column per
        input, a column per returned key (NaN where a case did not return it), and ``error``, a
        string ("" where the case ran, else its exception's type and message). ``attrs`` holds
        ``"seconds"`` (each case's time, cached cases their stored time), ``"computed"`` (the
        cases run now) and ``"cached"`` (read back).

    Warns
    -----
    RuntimeWarning
        When records could not be stored (a full disk, something else under a record's name, a
        case too large to keep): those cases' results are in the table and are computed again next time.

    Raises
    ------
    InputTypeError, InputError
        For a ``func`` that is not callable, cases that are not dicts of storable inputs, a
        ``client`` of another kind or an unusable ``cache_dir``, before any case runs.

    Notes
    -----
    A case that raises is recorded with its error and the study goes on. A case whose worker died
    (out of memory, killed) is recorded as ``"not run: ..."`` and not stored, so that a rerun tries
    it again. Ctrl-C stops the study; the stored cases stay.

    Examples
    --------
    >>> def square(x):
    ...     return {"y": x * x}
    >>> run_study(square, [{"x": 1.0}, {"x": 2.0}], progress=False)
         x    y error
    0  1.0  1.0
    1  2.0  4.0
    """
    if not callable(func):
        raise InputTypeError(f"func must be a callable taking the cases' inputs, got {brief(func)}")
    cases = check_cases(cases)
    client = _check_client(client)
    show = check_flag("progress", progress)
    folder = None if cache_dir is None else check_cache_folder(cache_dir, "cache_dir")
    name = study_name(func)
    if folder is not None and name is None:
        raise InputError(f"func={brief(func)}: with cache_dir, func must be a function defined at a module's top "
                         "level, or a functools.partial of one (its records are kept under its name; a lambda, a "
                         "nested function, a method or a callable object has none that tells two of them apart)")
    inputs = frozenset(k for case in cases for k in case)
    keys = [case_key(name, case) for case in cases] if folder is not None else []
    outcomes: list = [None] * len(cases)
    if folder is not None:
        for i, case in enumerate(cases):
            outcomes[i] = read_record(folder, keys[i], name, case, inputs)
    cached = sum(o is not None for o in outcomes)
    todo = [i for i, o in enumerate(outcomes) if o is None]
    unstored: list[str] = []

    def store(i: int, outcome, keep: bool = True) -> None:
        outcomes[i] = outcome
        if folder is not None and keep:
            problem = write_record(folder, keys[i], name, cases[i], *outcome)
            if problem:
                unstored.append(f"case {i}: {problem}")
        tally.add(outcome[1])

    failed = sum(bool(o[1]) for o in outcomes if o is not None)
    try:
        with _where(client, bool(todo)) as (runner, slots):
            tally = _Tally(len(cases), cached, failed, show, slots)
            try:
                _run(func, cases, todo, runner, store, inputs, slots)
            finally:
                tally.close()
    finally:
        if unstored:
            warnings.warn(f"run_study: {len(unstored)} case(s) ran but their records were not stored in cache_dir, "
                          f"so a rerun computes them again ({unstored[0]})", RuntimeWarning, stacklevel=2)
    return _table(cases, outcomes, cached, len(todo))


@contextmanager
def _where(client, work: bool):
    """``(client or None, cases run at once)``: this process, a local cluster for the study, or the user's."""
    if client is None or not work:  # nothing to run: no cluster is started
        yield None, 1
    elif isinstance(client, int):
        with local_client(client) as local:
            yield local, client
    else:
        yield client, _n_workers(client)


def _table(cases: list[dict], outcomes: list, cached: int, computed: int):
    """The study's DataFrame (see :func:`run_study`)."""
    import pandas as pd

    inputs = list(dict.fromkeys(k for case in cases for k in case))
    outputs = list(dict.fromkeys(k for result, _, _ in outcomes if result for k in result))
    rows = []
    for case, (result, error, _) in zip(cases, outcomes):
        row = {k: case.get(k) for k in inputs}
        row.update({k: (result or {}).get(k, np.nan) for k in outputs})
        row[ERROR] = error
        rows.append(row)
    table = pd.DataFrame(rows, columns=[*inputs, *outputs, ERROR])
    table[ERROR] = table[ERROR].astype(str)
    table.attrs.update(seconds=[o[2] for o in outcomes], computed=computed, cached=cached)
    return table

