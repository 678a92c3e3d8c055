"""Every time-domain entry of the package on one case: set-up, cost per step and agreement (printed, not asserted).

Run: ``python benchmarks/bench_routes.py [--track slab|ballasted] [--dt 4e-5] [--duration 0.1]``
(about 20 s on a 2-core machine for the slab track). The same study as the book's page "Which
route when" (:func:`semitrack.paper.routes_study.route_runs`): a wheel rolling at 300 km/h by the
truncated model that holds its path and by moving Green's functions, a standing wheel by the
10-bay model and by convolution on the exact track (at dt and dt / 2), and a pulse, a moving load
and ``newmark`` on the 10-bay model. Timings are wall times of one run on a shared machine.
"""

from __future__ import annotations

import argparse

import pandas as pd

import semitrack as st
from semitrack.paper.routes_study import route_runs, route_table

TRACKS = {"slab": st.slab_track, "ballasted": st.ballasted_track}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--track", choices=sorted(TRACKS), default="slab")
    parser.add_argument("--dt", type=float, default=4e-5)
    parser.add_argument("--duration", type=float, default=0.1)
    args = parser.parse_args()
    track = TRACKS[args.track](damping="viscous")
    table = route_table(route_runs(track, st.fit_boundary(track), dt=args.dt, duration=args.duration))
    with pd.option_context("display.width", 200, "display.max_colwidth", 80):
        print(table.drop(columns="case").to_string(float_format=lambda v: f"{v:.4g}"))
        print()
        print(table[["entry", "case"]].to_string())


if __name__ == "__main__":
    main()
