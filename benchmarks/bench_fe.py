"""Timoshenko FE track models: timings of frequency sweeps and time integration, and accuracy.

Run: OPENBLAS_NUM_THREADS=1 python benchmarks/bench_fe.py  [--quick]
Prints (nothing is asserted; the numbers go into the notes):

1. time of a 500-frequency sweep (3-2997 Hz, 6 Hz steps) of a 10-bay-each-side truncated track
   (pinned, equivalent and exact ends), of the long FE tracks (semi-infinite for alpha, complete
   for w1) and, for scale, of the exact transfer method;
2. FE long track against the transfer method: median/max error of alpha and w1 over the sweep
   for several meshes (elements per bay) and lengths (bays), pinned far ends;
3. truncated tracks with the paper's equivalent systems (Table 4: slab, 3-900 Hz; Table 7:
   ballasted, 3-750 Hz) against the infinite track's w1, and the number of bays pinned ends need
   to be as accurate as 10 bays with equivalent ends;
4. time domain: run times and relative L2 errors of 10-bay models (pinned / equivalent ends)
   against a long reference, for a Hann pulse and for a load moving at 300 km/h.
"""

from __future__ import annotations

import sys
import time

import numpy as np

import semitrack as st
from semitrack.base.paper_values import FIT_BANDS
from semitrack.equivalent.metrics import error_band_grid, error_summary
from semitrack.fe.models import TruncatedTrack, fe_central_receptance, fe_semi_infinite_receptance
from semitrack.fe.timedomain import moving_load_response, pulse_response, relative_l2_error

QUICK = "--quick" in sys.argv
GRID = np.arange(3.0, 3000.0, 6.0)
CASES = (
    (st.slab_track(), st.paper_table4(), FIT_BANDS["slab"]),
    (st.ballasted_track(), st.paper_table7(), FIT_BANDS["ballasted"]),
)


def timed(func):
    t0 = time.perf_counter()
    out = func()
    return time.perf_counter() - t0, out


def sweep_timings() -> None:
    print("1. 500-frequency sweep (3-2997 Hz), 12 elements per bay; wall time (s)")
    print(f"{'track':<10} {'model':<42} {'n_dof':>6} {'time':>7}")
    for track, system, _ in CASES:
        for ends in ("pinned", "equivalent", "exact"):
            m = TruncatedTrack(track, 10, ends, system=system if ends == "equivalent" else None, elements_per_bay=12)
            t, _ = timed(lambda: m.central_receptance(GRID))
            print(f"{track.name:<10} {'10+10 bays, ' + ends + ' ends':<42} {m.n_dof:6d} {t:7.2f}")
        for nb in (200, 400):
            m = TruncatedTrack(track, nb, "pinned", elements_per_bay=12)
            t, _ = timed(lambda: m.central_receptance(GRID))
            print(f"{track.name:<10} {f'long complete track {nb}+{nb} bays (w1)':<42} {m.n_dof:6d} {t:7.2f}")
            t, _ = timed(lambda: fe_semi_infinite_receptance(track, GRID, n_bays=nb, elements_per_bay=12))
            print(f"{track.name:<10} {f'long semi-infinite track {nb} bays (alpha)':<42} {'':6} {t:7.2f}")
        t, _ = timed(lambda: st.semi_infinite_receptance(track, GRID))
        print(f"{track.name:<10} {'transfer method (alpha), for scale':<42} {'':6} {t:7.2f}")
    print()


def long_track_accuracy() -> None:
    print("2. FE long track vs transfer method over 3-2997 Hz (pinned far end unless stated)")
    print(f"{'track':<10} {'el/bay':>6} {'bays':>5} {'far end':>7} {'alpha med':>9} {'alpha max':>9} "
          f"{'w1 med':>7} {'w1 max':>7} {'psi2 med':>8}")
    meshes = [(8, 100), (8, 200), (12, 100), (12, 200), (12, 400), (24, 400)]
    if QUICK:
        meshes = [(12, 200)]
    for track, _, _ in CASES:
        exact_a = st.semi_infinite_receptance(track, GRID)
        r = st.central_response(track, GRID)
        rows = [(ne, nb, "pinned") for ne, nb in meshes] + [(12, 2, "exact"), (24, 2, "exact")]
        for ne, nb, end in rows:
            a = fe_semi_infinite_receptance(track, GRID, n_bays=nb, elements_per_bay=ne, far_end=end)
            h = fe_central_receptance(track, GRID, n_bays=nb, elements_per_bay=ne, far_end=end)
            s = error_summary(a, exact_a)
            e1 = np.abs(h[:, 0, 0] / r.w1 - 1)
            e2 = np.abs(h[:, 1, 1] / r.psi2 - 1)
            print(f"{track.name:<10} {ne:6d} {nb:5d} {end:>7} {100 * s.median:8.2f}% {100 * s.max:8.1f}% "
                  f"{100 * np.median(e1):6.2f}% {100 * e1.max():6.1f}% {100 * np.median(e2):7.2f}%")
    print()


def equivalent_ends() -> None:
    print("3. Truncated track (12 el/bay) vs the infinite track's w1, paper's equivalent systems")
    print(f"{'track':<10} {'band (Hz)':<10} {'ends':<11} {'bays':>5} {'median':>8} {'max':>8}")
    for track, system, band in CASES:
        f = error_band_grid(band, 3.0)
        w1 = st.central_response(track, f).w1

        def err(n, ends):
            h = TruncatedTrack(track, n, ends, system=system if ends == "equivalent" else None,
                               elements_per_bay=12).central_receptance(f)
            e = np.abs(h[:, 0, 0] / w1 - 1)
            return float(np.median(e)), float(e.max())

        label = f"{band[0]:g}-{band[1]:g}"
        for n in (0, 1, 2, 5, 10, 20):
            med, mx = err(n, "equivalent")
            print(f"{track.name:<10} {label:<10} {'equivalent':<11} {n:5d} {100 * med:7.2f}% {100 * mx:7.1f}%")
        target = err(10, "equivalent")
        needed = None
        for n in (10, 20, 30, 40, 50, 60, 80, 100, 120, 150, 200):
            med, mx = err(n, "pinned")
            print(f"{track.name:<10} {label:<10} {'pinned':<11} {n:5d} {100 * med:7.2f}% {100 * mx:7.1f}%")
            if med <= target[0] and mx <= target[1]:
                needed = n
                break
        print(f"{track.name:<10} pinned ends reach the median and max of 10 bays with equivalent ends at "
              f"{needed} bays each side" if needed else "  (not reached)")
    print()


def time_domain() -> None:
    print("4. Time domain: Newmark average acceleration, dt = 20 us, 8 el/bay; relative L2 error vs a")
    print("   long reference (100 bays each side for the pulse, 60 for the moving load; the change of the")
    print("   reference when its length is doubled is printed)")
    for track, system, _ in CASES:
        d = track.spacing
        pos = (0.0, 3 * d)
        models = {
            "reference": TruncatedTrack(track, 100, "pinned", elements_per_bay=8),
            "pinned": TruncatedTrack(track, 10, "pinned", elements_per_bay=8),
            "equivalent": TruncatedTrack(track, 10, "equivalent", system=system, elements_per_bay=8),
        }
        runs = {}
        for key, m in models.items():
            t, runs[key] = timed(lambda: pulse_response(m, pos, duration=0.03))
            print(f"   {track.name:<10} pulse (f_max 1.5 kHz, 30 ms = 1500 steps) {key:<10} n_dof {m.n_dof:5d}: "
                  f"{t:6.2f} s")
        doubled = pulse_response(TruncatedTrack(track, 200, "pinned", elements_per_bay=8), pos, duration=0.03)
        e = relative_l2_error(runs["reference"].u, doubled.u)
        print(f"   {track.name:<10} pulse reference 100 vs 200 bays: {e.max():.1e}")
        for key in ("pinned", "equivalent"):
            e = relative_l2_error(runs[key].u, runs["reference"].u)
            print(f"   {track.name:<10} pulse, 10 bays, {key:<10} ends: error at x = 0 {100 * e[0]:5.1f} %, "
                  f"at x = 3d {100 * e[1]:5.1f} %")
        for n_bays, span in ((10, 8), (4, 3)):
            kw = dict(x=(0.0,), x_start=-span * d, x_end=span * d)
            ref_m = TruncatedTrack(track, 60, "pinned", elements_per_bay=8)
            t, ref = timed(lambda: moving_load_response(ref_m, **kw))
            doubled = moving_load_response(TruncatedTrack(track, 120, "pinned", elements_per_bay=8), **kw)
            n_steps = ref.t.size - 1
            print(f"   {track.name:<10} moving load 300 km/h from -{span}d to {span}d ({n_steps} steps), reference "
                  f"60 bays: {t:5.2f} s; 60 vs 120 bays: {relative_l2_error(ref.u, doubled.u).max():.1e}")
            for ends in ("pinned", "equivalent"):
                m = TruncatedTrack(track, n_bays, ends, system=system if ends == "equivalent" else None,
                                   elements_per_bay=8)
                t, h = timed(lambda: moving_load_response(m, **kw))
                e = relative_l2_error(h.u, ref.u)
                print(f"   {track.name:<10} moving load, {n_bays:2d} bays, {ends:<10} ends ({t:4.2f} s): error "
                      f"under the load {100 * e[0]:5.2f} %, at x = 0 {100 * e[1]:5.2f} %")
    print()


def main() -> None:
    sweep_timings()
    long_track_accuracy()
    equivalent_ends()
    time_domain()


if __name__ == "__main__":
    main()
