"""The exact infinite track with local changes: timing (printed, not asserted).

Run: python benchmarks/bench_infinite.py

The ballasted track with 20 changed supports (every other one a hanging sleeper, the others a
worn pad), 500 frequencies (the paper's grid) and 30 response points over the changed stretch,
the best of three; and, for scale, the periodic track's point receptance at the same 500
frequencies (st.point_receptance); the decay rate of EN 15461 of each paper track (18 bands,
lines 2 Hz apart, 29 positions); and the same with the slab track's pad given as a curve (a
standard linear solid), the cost of a frequency-dependent support.
"""

from __future__ import annotations

import time

import numpy as np

import semitrack as st


def best(call, repeat=3):
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        call()
        times.append(time.perf_counter() - start)
    return min(times)


def main() -> None:
    track = st.ballasted_track()
    changes = {k: ({"kb": 0.0} if k % 2 else {"kv": 0.3 * track.kv}) for k in range(-10, 10)}
    inf = st.InfiniteTrack(track, changes)
    f = st.PAPER_GRID
    xs = np.linspace(-6.0, 6.0, 30)
    wall = best(lambda: inf.receptance(f, 0.0, xs))
    print(f"InfiniteTrack, 20 changed supports, {f.size} frequencies, {xs.size} response points: {wall:.3f} s")
    periodic = best(lambda: st.point_receptance(track, f, origin="midspan"))
    print(f"point_receptance of the periodic track, {f.size} frequencies: {periodic:.3f} s")
    for name, make in (("slab", st.slab_track), ("ballasted", st.ballasted_track)):
        wall = best(lambda: st.track_decay_rate(make()))
        print(f"track_decay_rate, {name} track, 100 Hz - 5 kHz bands at 2 Hz lines: {wall:.2f} s")
    curved = st.slab_track(kv=st.StandardLinearSolid(4.35e7, 1.1e8, 4e-4))
    wall = best(lambda: st.track_decay_rate(curved))
    print(f"track_decay_rate, slab track with a standard-linear-solid pad: {wall:.2f} s")


if __name__ == "__main__":
    main()
