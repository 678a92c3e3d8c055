"""Broadband boundary: fit time and accuracy against the number of poles, and what it saves in
the time domain (printed, not asserted).

1. For the paper's two tracks over 3-3000 Hz, hysteretic (the paper's) and viscous (causal)
   damping: the element-wise relative error of alpha (median and maximum on the 3 Hz grid),
   the passivity proof, the enforcement rounds and the wall time of each fit.
2. A 0.1 s time-domain run (Hann pulse, f_max 6 kHz, dt 10 us, 8 elements per bay) of the 10-bay
   model with boundary ends against pinned-end models of growing length, all compared with a
   400-bay reference: wall time, model size and relative L2 error at the centre and 3 bays away.

Run with ``OPENBLAS_NUM_THREADS=1 python benchmarks/bench_boundary.py``.
"""

from __future__ import annotations

import time

import semitrack as st
from semitrack.fe.timedomain import pulse_response, relative_l2_error

BAND = (3.0, 3000.0)
ORDERS = (12, 24, 36, 48, 60)


def fit_table() -> None:
    for name, make in (("slab", st.slab_track), ("ballasted", st.ballasted_track)):
        for damping in ("hysteretic", "viscous"):
            track = make(damping=damping)
            print(f"\n{name} track, {damping} damping, band {BAND[0]:g}-{BAND[1]:g} Hz")
            print(f"{'n_poles':>8} {'median':>8} {'max':>8} {'passive':>8} {'rounds':>7} {'time (s)':>9}")
            for n in ORDERS:
                start = time.perf_counter()
                bnd = st.fit_boundary(track, band=BAND, n_poles=n)
                wall = time.perf_counter() - start
                print(f"{n:8d} {bnd.median_error:8.4f} {bnd.max_error:8.4f} {str(bool(bnd.is_passive())):>8} "
                      f"{bnd.enforcement_rounds:7d} {wall:9.1f}")
            start = time.perf_counter()
            bnd = st.fit_boundary(track, band=BAND)
            print(f"automatic order: {bnd!r}, {time.perf_counter() - start:.1f} s")


def time_domain_speedup() -> None:
    for name, make in (("slab", st.slab_track), ("ballasted", st.ballasted_track)):
        track = make(damping="viscous")  # the time-domain rail is viscously damped
        bnd = st.fit_boundary(track, band=BAND)
        kw = dict(x=(0.0, 3 * track.spacing), f_max=6000.0, dt=1e-5, duration=0.1)
        ref = pulse_response(st.TruncatedTrack(track, 400, "pinned", elements_per_bay=8), **kw)
        print(f"\n{name} track (viscous), 0.1 s pulse run against a 400-bay reference")
        print(f"{'model':>22} {'DOFs+states':>12} {'time (s)':>9} {'L2 err centre':>14} {'L2 err 3 bays':>14}")
        cases = [("boundary, 10 bays", st.TruncatedTrack(track, 10, "boundary", system=bnd, elements_per_bay=8))]
        cases += [(f"pinned, {n} bays", st.TruncatedTrack(track, n, "pinned", elements_per_bay=8))
                  for n in (10, 20, 40, 80, 160)]
        for label, model in cases:
            start = time.perf_counter()
            hist = pulse_response(model, **kw)
            wall = time.perf_counter() - start
            size = model.n_dof + sum(a.A.shape[0] for a in model.boundary_states())
            err = 100 * relative_l2_error(hist.u, ref.u)
            print(f"{label:>22} {size:12d} {wall:9.2f} {err[0]:13.3f}% {err[1]:13.3f}%")


def main() -> None:
    fit_table()
    time_domain_speedup()


if __name__ == "__main__":
    main()
