"""Moving Green's functions against the truncated model that holds the path (printed, not asserted).

Run: ``python benchmarks/bench_moving.py [--duration 1.0] [--cases ...]`` (one run of each case;
about 8 minutes on a 2-core machine for the default cases at 1 s). For each case a vehicle rolls
over a rough rail (the ISO 3095 limit over 40 Hz - 3 kHz at the speed) on a periodic track with
viscous damping, by :func:`semitrack.moving_green_response` and by the truncated FE model with
broadband ends that holds its whole path with 40 bays to spare
(:func:`semitrack.paper.moving_study.compare_runs`), the same mesh (the default for 3 kHz), time
step (40 us on the slab track, 20 us on the ballasted), start and roughness. Printed per wheel:
the rms of the force difference over the reference's fluctuation (%), the worst one-third-octave
band level difference 50 Hz - 2.5 kHz (dB) and the worst band level of the difference under the
reference's (dB); per case: the kernels' set-up, their reading back from a cache folder, the
step of the compiled and of the Python loop (us), the 1-s run and the truncated model's size
and run. Timings are wall times of one run on a shared machine.
"""

from __future__ import annotations

import argparse

import pandas as pd

import semitrack as st
from semitrack.paper.moving_study import compare_runs, moving_table

TRACKS = {"slab": (st.slab_track, 4e-5), "ballasted": (st.ballasted_track, 2e-5)}
CASES = ("slab-wheel-300", "slab-bogie-300", "ballasted-wheel-300", "ballasted-bogie-300", "ballasted-wheel-400",
         "slab-wheel-400")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=1.0)
    parser.add_argument("--cases", nargs="+", default=list(CASES), choices=CASES)
    args = parser.parse_args()
    boundaries, comparisons = {}, []
    for case in args.cases:
        name, vehicle, kmh = case.split("-")
        make, dt = TRACKS[name]
        track = make(damping="viscous")
        if name not in boundaries:
            boundaries[name] = st.fit_boundary(track)
        wheels = st.Bogie() if vehicle == "bogie" else st.Wheel()
        c = compare_runs(f"{name}, {vehicle}", track, boundaries[name], wheels, float(kmh), dt, args.duration)
        comparisons.append(c)
        print(f"{case}: set-up {c.setup:.1f} s, from cache {c.from_cache:.2f} s, step {c.step_compiled:.2f} us "
              f"compiled, {c.step_numpy:.2f} us Python; truncated {c.truncated_dofs} DOFs {c.truncated_time:.1f} s",
              flush=True)
    with pd.option_context("display.width", 250, "display.max_columns", 20, "display.precision", 4):
        print(moving_table(comparisons))


if __name__ == "__main__":
    main()
