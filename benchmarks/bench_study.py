"""A study's wall time in this process against a local dask cluster of two workers (printed, not asserted).

Run: ``python benchmarks/bench_study.py [--cases 16] [--duration 4.0] [--workers 2] [--trivial 200]``.
The cases are those of the book's Monte Carlo (:mod:`semitrack.paper.random_track_study`: a bogie
at 200 km/h over a random ballasted track with a share of hanging sleepers, on a
:class:`semitrack.WindowTrack`), each run for ``--duration`` s of track time so that a case takes
a few seconds (the boundary fitted once here and passed to the workers with the function). The
study runs serially, then through ``run_study(client=workers)``, side by side in one process after
a warm-up case (the parallel time includes the cluster's start and each worker's first case);
printed: both wall times, their ratio, the seconds per case, and whether the tables are equal bit
for bit. Then dask's overhead per case: ``--trivial`` cases that do
nothing, on a cluster already running (a user's ``Client``; the cluster ``client=n`` starts, kept open),
the same study on it once its workers have run a case, and the local cluster's start and close.
"""

from __future__ import annotations

import argparse
import functools
import time

import semitrack as st
from semitrack.paper.random_track_study import bogie_over_random_track, monte_carlo_cases, study_track
from semitrack.studies.runner import local_client


def nothing(i: int) -> dict:
    """A case that costs nothing: what is left is the scheduler's overhead."""
    return {"i2": 2 * i}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", type=int, default=16)
    parser.add_argument("--duration", type=float, default=4.0, help="track time of each case (s)")
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--trivial", type=int, default=200, help="empty cases for the overhead")
    args = parser.parse_args()
    cases = monte_carlo_cases([0.0, 0.1, 0.2, 0.3], realisations=-(-args.cases // 4), duration=args.duration)
    cases = cases[: args.cases]
    track, system = study_track()
    lengths = st.WindowTrack(track, system=system)  # the lengths from the decay rate, once
    one_case = functools.partial(bogie_over_random_track, system=system, behind=lengths.behind, ahead=lengths.ahead)
    one_case(0.1, 0, duration=0.05)  # the compiled loop, once
    start = time.perf_counter()
    serial = st.run_study(one_case, cases, progress=False)
    serial_s = time.perf_counter() - start
    start = time.perf_counter()
    parallel = st.run_study(one_case, cases, client=args.workers, progress=False)
    parallel_s = time.perf_counter() - start
    per_case = sum(serial.attrs["seconds"]) / len(cases)
    print(f"{len(cases)} cases of {args.duration:g} s of track ({per_case:.2f} s each): serial {serial_s:.1f} s, "
          f"{args.workers} workers {parallel_s:.1f} s, ratio {parallel_s / serial_s:.2f}; "
          f"tables equal bit for bit: {serial.equals(parallel)}")

    start = time.perf_counter()
    local = local_client(args.workers)  # the cluster client=n starts, kept open here: a user's running cluster
    client = local.__enter__()
    started = time.perf_counter() - start
    trivial = [{"i": i} for i in range(args.trivial)]
    st.run_study(nothing, trivial[:4], client=client, progress=False)  # the workers' imports
    start = time.perf_counter()
    st.run_study(nothing, trivial, client=client, progress=False)
    overhead = (time.perf_counter() - start) / len(trivial)
    one_case(0.1, 0, duration=0.05)
    client.run(lambda: one_case(0.1, 0, duration=0.05))  # every worker's first case, before the clock
    start = time.perf_counter()
    warm = st.run_study(one_case, cases, client=client, progress=False)
    warm_s = time.perf_counter() - start
    start = time.perf_counter()
    local.__exit__(None, None, None)
    closed = time.perf_counter() - start
    print(f"on a running cluster whose workers had run a case ({args.workers} workers): {warm_s:.1f} s, ratio "
          f"{warm_s / serial_s:.2f}, equal: {warm.equals(serial)}")
    print(f"dask: {overhead * 1e3:.1f} ms a case on {args.workers} running workers ({args.trivial} empty cases); "
          f"a local cluster starts in {started:.1f} s and closes in {closed:.1f} s")


if __name__ == "__main__":
    main()
