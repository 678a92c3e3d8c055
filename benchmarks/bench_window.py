"""The travelling window against the model that holds the path (printed, not asserted).

Run: ``python benchmarks/bench_window.py [--durations 0.4 1.0] [--tracks ballasted slab]
[--window-only 2.0] [--elements 16] [--dt 4e-5]``. A bogie at 250 km/h over a random track (every
support's pad stiffness log-normal with a CoV of 20 %, the ballast's 30 %, a failed fastener; on
the ballasted track two sleepers hanging over gaps of 0.5 and 1 mm) with the ISO 3095 limit
roughness over 40 Hz - 3 kHz, by :class:`semitrack.WindowTrack` at its default lengths and by the
truncated model with broadband ends that holds the whole path with 40 bays to spare
(:func:`semitrack.paper.window_study.window_against_path`), on the same mesh (the default for
3 kHz, or ``--elements``), step (20 us, or ``--dt``), start and roughness, run side by side in
one process after a warm-up of the compiled loop. Printed per run: both wall times and their
ratio, the DOFs each steps, and per wheel the rms difference over the force's fluctuation (%) and
the worst one-third-octave band difference 50 Hz - 2.5 kHz (dB). ``--window-only`` adds runs of
the window alone (the path model's time grows with the run; the window's should not).
"""

from __future__ import annotations

import argparse
import time

import semitrack as st
from semitrack.paper.moving_study import rolling_roughness
from semitrack.paper.window_study import random_supports, window_against_path

KMH = 250.0
DT = 2e-5


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--durations", type=float, nargs="*", default=[0.4, 1.0])
    parser.add_argument("--tracks", nargs="+", default=["ballasted", "slab"], choices=["ballasted", "slab"])
    parser.add_argument("--window-only", type=float, nargs="*", default=[], help="durations run by the window alone")
    parser.add_argument("--elements", type=int, default=None, help="elements per bay (default: the mesh for 3 kHz)")
    parser.add_argument("--dt", type=float, default=DT, help="time step (s)")
    args = parser.parse_args()
    speed = KMH / 3.6
    for name in args.tracks:
        track = (st.ballasted_track if name == "ballasted" else st.slab_track)(damping="viscous")
        start = time.perf_counter()
        boundary = st.fit_boundary(track)
        print(f"{name}: boundary fitted in {time.perf_counter() - start:.1f} s")
        longest = max(args.durations + args.window_only)
        reach = int(speed * longest / track.spacing) + 200
        changes = random_supports(track, range(-reach, reach), seed=1, failed=(3,))
        gaps = {8: 0.5e-3, 14: 1e-3} if track.is_ballasted else None
        changes.update({k: {"kb": 0.0} for k in gaps or {}})
        roughness = rolling_roughness(speed, period=max(1.0, longest))
        window_against_path(track, changes, boundary, st.Bogie(), roughness, speed=speed, dt=args.dt, duration=0.03,
                            path=False, elements_per_bay=args.elements)  # warm-up: compiles or loads the loop
        for duration in args.durations:
            run = window_against_path(track, changes, boundary, st.Bogie(), roughness, speed=speed, dt=args.dt,
                                      duration=duration, ballast_gaps=gaps, elements_per_bay=args.elements)
            print(f"  {duration:.2f} s: window {run.window_time:.2f} s ({run.window_dofs} DOFs, loop "
                  f"{run.window.elapsed:.2f} s), path model {run.path_time:.2f} s ({run.path_dofs} DOFs), "
                  f"ratio {run.path_time / run.window_time:.2f}")
            for i, a in enumerate(run.agreement):
                print(f"    wheel {i}: rms {100 * a['rms']:.3f} %, worst band {a['worst_level_difference']:.4f} dB, "
                      f"worst error level {a['worst_error_level']:.1f} dB")
        for duration in args.window_only:
            run = window_against_path(track, changes, boundary, st.Bogie(), roughness, speed=speed, dt=args.dt,
                                      duration=duration, path=False, ballast_gaps=gaps,
                                      elements_per_bay=args.elements)
            print(f"  {duration:.2f} s window alone: {run.window_time:.2f} s (loop {run.window.elapsed:.2f} s)")


if __name__ == "__main__":
    main()
