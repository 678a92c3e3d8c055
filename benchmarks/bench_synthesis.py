"""The broadband end as M, C, K: conversion time, size and accuracy, and the 10-bay time domain
(printed, not asserted).

For the four study fits (the paper's slab and ballasted tracks, hysteretic and viscous damping,
3-3000 Hz, the automatic order): the first-order states, the internal DOFs of
``matrix_system()`` (masses and massless Maxwell DOFs), the conversion's wall time, the largest
element error of its receptance against the rational model from 1 mHz to 1 MHz, the smallest
relative eigenvalue of M, C and K, and a 10-bay track's pulse and moving-load responses with the
M, C, K ends against ``ends="boundary"`` (relative L2).

Run with ``OPENBLAS_NUM_THREADS=1 python benchmarks/bench_synthesis.py``.
"""

from __future__ import annotations

import time

import numpy as np

import semitrack as st
from semitrack.fe.timedomain import moving_load_response, pulse_response, relative_l2_error
from semitrack.paper.boundary_study import study_tracks

F = np.geomspace(1e-3, 1e6, 400)


def main() -> None:
    print(f"{'track':>22} {'states':>7} {'internal':>9} {'masses':>7} {'time (s)':>9} {'max error':>10} "
          f"{'min eig':>9} {'pulse L2':>9} {'moving L2':>10}")
    for (name, damping), track in study_tracks().items():
        bnd = st.fit_boundary(track, band=(3.0, 3000.0))
        start = time.perf_counter()
        mck = bnd.matrix_system()
        wall = time.perf_counter() - start
        error = np.max(np.abs(mck.receptance(F) / bnd.receptance(F) - 1))
        eig = min(np.linalg.eigvalsh(X)[0] / np.max(np.abs(np.linalg.eigvalsh(X))) for X in mck.matrices())
        models = [st.TruncatedTrack(track, 10, ends="boundary", system=bnd),
                  st.TruncatedTrack(track, 10, ends="equivalent", system=mck)]
        l2 = [np.max(relative_l2_error(*(run(m).u for m in models[::-1]))) for run in (pulse_response,
                                                                                       moving_load_response)]
        print(f"{name + ' ' + damping:>22} {bnd.state_space().n_states:7d} {mck.n_internal:9d} "
              f"{int(np.sum(np.diag(mck.M) > 0)):7d} {wall:9.3f} {error:10.1e} {eig:9.1e} {l2[0]:9.1e} {l2[1]:10.1e}")


if __name__ == "__main__":
    main()
