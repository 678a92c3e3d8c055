"""Benchmark of fit_equivalent on the paper's two tracks (printed, not asserted).

For each track: the error of the paper's own system (Table 4 / Table 7) against the exact
receptance over the paper's band (``FIT_BANDS``: 3-900 Hz slab, 3-750 Hz ballasted; 3 Hz
grid), the error of our fit over the same grid, the ratios (paper / ours), the wall-clock time
of one fit and the characteristic frequencies used by the constraints.

Usage::

    python benchmarks/bench_fit.py                 # N = 5, seed 0, both tracks
    python benchmarks/bench_fit.py --n-bars 5 6 --seeds 0 1 --unconstrained
"""

from __future__ import annotations

import argparse
import os
import platform
import time
import warnings

import numpy as np

import semitrack as st
from semitrack.base.paper_values import FIT_BANDS
from semitrack.equivalent.fitting import fit_equivalent
from semitrack.equivalent.metrics import error_band_grid, error_summary
from semitrack.paper.systems import paper_table4, paper_table7

CASES = {
    "slab": (st.slab_track, paper_table4, FIT_BANDS["slab"], "Table 4"),
    "ballasted": (st.ballasted_track, paper_table7, FIT_BANDS["ballasted"], "Table 7"),
}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--tracks", nargs="+", default=list(CASES), choices=list(CASES))
    parser.add_argument("--n-bars", nargs="+", type=int, default=[5])
    parser.add_argument("--seeds", nargs="+", type=int, default=[0])
    parser.add_argument("--n-starts", type=int, default=20)
    parser.add_argument("--unconstrained", action="store_true", help="also fit without the constraints")
    args = parser.parse_args()

    print(f"semitrack {st.__version__}, numpy {np.__version__}, Python {platform.python_version()}, "
          f"{os.cpu_count()} CPUs, load average {os.getloadavg()[0]:.2f}")
    for layout in args.tracks:
        make_track, make_paper, band, table = CASES[layout]
        track = make_track()
        f = error_band_grid(band, 3.0)
        alpha = st.semi_infinite_receptance(track, f)
        paper = error_summary(make_paper().receptance(f), alpha)
        print(f"\n== {layout} track, band {band[0]:g}-{band[1]:g} Hz, {f.size} frequencies (3 Hz grid)")
        print(f"paper {table}: median {paper.median:.4f}  max {paper.max:.4f}")
        for constrained in (True, False) if args.unconstrained else (True,):
            for n_bars in args.n_bars:
                for seed in args.seeds:
                    t0 = time.perf_counter()
                    with warnings.catch_warnings(record=True) as caught:
                        warnings.simplefilter("always")
                        fit = fit_equivalent(track, layout, n_bars, band=band, seed=seed,
                                             constrained=constrained, n_starts=args.n_starts)
                    elapsed = time.perf_counter() - t0
                    label = "constrained" if constrained else "free"
                    chars = ", ".join(f"{k} = {v:.2f} Hz" for k, v in fit.characteristic_frequencies.items())
                    print(f"ours N = {n_bars} {label:11s} seed {seed}: median {fit.median_error:.4f}  "
                          f"max {fit.max_error:.4f}  ratio paper/ours: median {paper.median / fit.median_error:.2f}x "
                          f"max {paper.max / fit.max_error:.2f}x  time {elapsed:.1f} s  "
                          f"({fit.n_starts} starts, best {fit.best_start}, status {fit.status}, nfev {fit.nfev}, "
                          f"{fit.fit_freqs.size} fit frequencies)")
                    print(f"    characteristic frequencies: {chars}")
                    for w in caught:
                        print(f"    warning: {w.message}")


if __name__ == "__main__":
    main()
