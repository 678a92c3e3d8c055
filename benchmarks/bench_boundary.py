"""Broadband boundary: fit time and accuracy against the number of poles (printed, not asserted).

For the paper's two tracks over 3-3000 Hz: the element-wise relative error of alpha (median and
maximum on the 3 Hz grid), whether passivity had to be enforced and was proven, and the wall
time of each fit. Run with ``OPENBLAS_NUM_THREADS=1 python benchmarks/bench_boundary.py``.
"""

from __future__ import annotations

import time

import semitrack as st

BAND = (3.0, 3000.0)
ORDERS = (12, 24, 36, 48, 60)


def main() -> None:
    for name, make in (("slab", st.slab_track), ("ballasted", st.ballasted_track)):
        track = make()
        print(f"\n{name} track, band {BAND[0]:g}-{BAND[1]:g} Hz")
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


if __name__ == "__main__":
    main()
