"""Time a 500-frequency sweep of alpha per track, by both methods, and the paper-settings error.

Run: python benchmarks/bench_receptance.py
Prints timings, their ratio, and the error of the wavenumber alpha against the exact alpha at the
paper's settings and at a refined setting; then the exact sweep of the two flexible-slab example
tracks (ten coupled fasteners per period), with the cut at the joint and inside the slab.
Nothing is asserted: the numbers go into the notes.
"""

from __future__ import annotations

import dataclasses
import time

import numpy as np

import semitrack as st
from semitrack.base.paper_values import PAPER_BETA_MAX, PAPER_GRID
from semitrack.paper.convergence import alpha_relative_error

REFINED = dict(beta_max=10 * PAPER_BETA_MAX, dx=0.002)


def best_time(func, repeat: int) -> tuple[float, object]:
    """Shortest wall time of ``repeat`` calls (s), and the last result."""
    best, out = np.inf, None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = func()
        best = min(best, time.perf_counter() - t0)
    return best, out


def main() -> None:
    f = PAPER_GRID  # 500 frequencies, 3-2997 Hz
    check = np.array([3.0, 183.0, 945.0])
    print("500-frequency sweep of alpha (3-2997 Hz, 6 Hz steps); best of repeated runs")
    print(f"{'track':<10} {'transfer (s)':>13} {'wavenumber (s)':>15} {'ratio':>8}")
    for track in (st.slab_track(), st.ballasted_track()):
        t_tr, exact = best_time(lambda: st.semi_infinite_receptance(track, f), 5)
        t_wn, approx = best_time(lambda: st.semi_infinite_receptance(track, f, method="wavenumber"), 2)
        print(f"{track.name:<10} {t_tr:13.4f} {t_wn:15.2f} {t_wn / t_tr:8.0f}")
        err = alpha_relative_error(approx, exact)
        print(f"{'':<10} wavenumber error over the sweep (paper settings): "
              f"median {np.median(err):.3f}, max {err.max():.3f}")
    print()
    print("max element error of the wavenumber alpha against the exact alpha")
    print(f"{'track':<10} {'f (Hz)':>7} {'paper settings':>15} {'refined':>9} {'ratio':>7}   refined = {REFINED}")
    for track in (st.slab_track(), st.ballasted_track()):
        exact = st.semi_infinite_receptance(track, check)
        e_paper = alpha_relative_error(st.semi_infinite_receptance(track, check, method="wavenumber"), exact)
        t_ref, refined = best_time(lambda: st.semi_infinite_receptance(track, check, method="wavenumber", **REFINED), 1)
        e_ref = alpha_relative_error(refined, exact)
        for fi, a, b in zip(check, e_paper, e_ref):
            print(f"{track.name:<10} {fi:7.0f} {a:15.4f} {b:9.4f} {a / b:7.1f}")
        print(f"{'':<10} (refined evaluation of 3 frequencies: {t_ref:.2f} s)")
    print()
    print("500-frequency exact sweep of alpha on the flexible-slab examples (10 fasteners per slab)")
    print(f"{'track':<16} {'joint cut (s)':>14} {'centre cut (s)':>15} {'rigid slab (s)':>15}")
    t_rigid, _ = best_time(lambda: st.semi_infinite_receptance(st.slab_track(), f), 5)
    for name in ("mortar-slab", "floating-slab"):
        track = st.example_track(name)
        centre = track.replace(slab=dataclasses.replace(track.slab, cut="centre"))
        t_joint, _ = best_time(lambda: st.semi_infinite_receptance(track, f), 5)
        t_centre, _ = best_time(lambda: st.semi_infinite_receptance(centre, f), 5)
        print(f"{name:<16} {t_joint:14.4f} {t_centre:15.4f} {t_rigid:15.4f}")


if __name__ == "__main__":
    main()
