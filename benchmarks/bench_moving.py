"""Moving Green's functions against the truncated model that holds the path (printed, not asserted).

Run: ``python benchmarks/bench_moving.py [--duration 1.0] [--cases ...] [--dt DT] [--fresh] [--tail-rank R]``
(one run of each case; about 8 minutes on a 2-core machine for the default cases at 1 s; ``madeup-bogie-250``
is a ballasted track that is not the paper's at 30 us, ``--fresh`` adds the first and second run's step
in a new process that reads the kernels and the compiled loop from their caches, ``--tail-rank R`` a run with
the kernels' tails in rank R, its time and its agreement with both references). For each case a vehicle rolls
over a rough rail (the ISO 3095 limit over 40 Hz - 3 kHz at the speed) on a periodic track with
viscous damping, by :func:`semitrack.moving_green_response` and by the truncated FE model with
broadband ends that holds its whole path with 40 bays to spare
(:func:`semitrack.paper.moving_study.compare_runs`), the same mesh (the default for 3 kHz), time
step (40 us on the slab track, 20 us on the ballasted), start and roughness. Printed per wheel:
the rms of the force difference over the reference's fluctuation (%), the worst one-third-octave
band level difference 50 Hz - 2.5 kHz (dB) and the worst band level of the difference under the
reference's (dB); per case: the kernels' set-up, their reading back from a cache folder, the
step of the compiled and of the Python loop (us), the 1-s run and the truncated model's size
and run. Timings are of one run on a shared machine: the set-up, the cache's read, the truncated run and the
run from the kernels are CPU times of the thread that ran them (one BLAS thread), the steps wall times.
"""

from __future__ import annotations

import argparse
import dataclasses
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import pandas as pd

import semitrack as st
from semitrack.interaction.moving_green import DEFAULT_TAIL_START
from semitrack.paper.moving_study import compare_runs, force_agreement, moving_table, rolling_roughness


def made_up_track(damping: str = "viscous") -> st.Track:
    """A ballasted track that is not the paper's (nothing was tuned to it): wider spacing, stiffer pads, softer
    ballast, heavier sleepers."""
    base = st.ballasted_track(damping=damping)
    return dataclasses.replace(base, spacing=0.65, kv=1.5 * base.kv, kb=0.7 * base.kb,
                               sleeper_mass=1.2 * base.sleeper_mass, name="made-up ballasted")


TRACKS = {"slab": (st.slab_track, 4e-5), "ballasted": (st.ballasted_track, 2e-5), "madeup": (made_up_track, 3e-5)}
VEHICLES = {"wheel": st.Wheel, "bogie": st.Bogie,
            "three": lambda: st.WheelGroup((st.Wheel(),) * 3, spacing=(0.0, -2.0, -4.0))}
CASES = ("slab-wheel-300", "slab-bogie-300", "ballasted-wheel-300", "ballasted-bogie-300", "ballasted-wheel-400",
         "slab-wheel-400", "madeup-bogie-250", "ballasted-three-300")

# Runs in a fresh process: kernels read from the cache folder, the compiled loop from numba's cache; prints the
# first run's step (us).
_FRESH = r"""
import sys, warnings
import semitrack as st
sys.path.insert(0, sys.argv[1])
import bench_moving as b
warnings.simplefilter("ignore")
name, vehicle, kmh, dt, duration, x0, folder = sys.argv[2:9]
make, _ = b.TRACKS[name]
track, wheels = make(damping="viscous"), b.VEHICLES[vehicle]()
speed, dt = float(kmh) / 3.6, float(dt)
grid = st.moving_green_kernels(track, speed, dt, wheels.offsets, x=float(x0), cache=folder).grid
rough = b.rolling_roughness(grid.speed)
runs = [st.moving_green_response(track, wheels, rough, x=float(x0), speed=speed, dt=dt, duration=float(duration),
                                cache=folder) for _ in range(2)]
print(*(1e6 * res.elapsed / (res.t.size - 1) for res in runs))
"""


def fresh_process_step(case: str, dt: float, duration: float, x0: float, kernels) -> tuple[float, float]:
    """The first and the second run's step (us) in a new process that reads the kernels (written here) and the
    compiled loop from their caches: the first holds numba's reading of the loop at its first call."""
    name, vehicle, kmh = case.split("-")
    with tempfile.TemporaryDirectory() as folder:
        from semitrack.fe.kernelcache import _digest, _write  # the kernels as the cache would have written them

        _write(Path(folder) / f"kernels-{_digest(kernels.key)}.npz", kernels)
        out = subprocess.run([sys.executable, "-c", _FRESH, str(Path(__file__).parent), name, vehicle, kmh, str(dt),
                              str(duration), str(x0), folder], capture_output=True, text=True, check=True)
    first, second = (float(value) for value in out.stdout.strip().splitlines()[-1].split())
    return first, second


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=1.0)
    parser.add_argument("--cases", nargs="+", default=list(CASES[:6]), choices=CASES,
                        help="track-vehicle-km/h; madeup: a ballasted track that is not the paper's (3e-5 s); three: "
                             "three wheels 2 m apart")
    parser.add_argument("--dt", type=float, default=None, help="time step (s) instead of the track's")
    parser.add_argument("--fresh", action="store_true", help="also the first run's step in a fresh process")
    parser.add_argument("--tail-rank", type=int, default=None,
                        help="also a run with the kernels past --tail-start in this rank (semitrack.fe.kerneltail)")
    parser.add_argument("--tail-start", type=float, default=None, help="where the low-rank tail starts (s)")
    args = parser.parse_args()
    boundaries, comparisons = {}, []
    for case in args.cases:
        name, vehicle, kmh = case.split("-")
        make, dt = TRACKS[name]
        dt = args.dt or dt
        track = make(damping="viscous")
        if name not in boundaries:
            boundaries[name] = st.fit_boundary(track)
        wheels = VEHICLES[vehicle]()
        c = compare_runs(f"{name}, {vehicle}", track, boundaries[name], wheels, float(kmh), dt, args.duration)
        comparisons.append(c)
        x0 = float(c.green.x[0, 0])
        run = {"x": x0, "speed": float(kmh) / 3.6, "dt": dt, "duration": args.duration, "kernels": c.kernels}
        start = time.thread_time()  # a whole call with the kernels at hand, side by side with the truncated run
        st.moving_green_response(track, wheels, rolling_roughness(c.kernels.grid.speed), **run)
        wall = time.thread_time() - start
        print(f"{case} (dt {dt:g} s, {args.duration:g} s, P = {c.kernels.grid.positions}, "
              f"{len(c.kernels.grid.lags)} lags): set-up {c.setup:.1f} s ({c.setup / c.truncated_time:.2f}x the "
              f"truncated run), from cache {c.from_cache:.2f} s; a run from the kernels {wall:.3f} s, the truncated "
              f"run {c.truncated_time:.2f} s ({c.truncated_dofs} DOFs): {c.truncated_time / wall:.1f}x; step "
              f"{c.step_compiled:.2f} us compiled, {c.step_numpy:.2f} us Python", flush=True)
        if args.tail_rank is not None:
            tail = {"tail_rank": args.tail_rank, "tail_start": args.tail_start}
            st.moving_green_response(track, wheels, rolling_roughness(c.kernels.grid.speed), **run, **tail)  # factors
            start = time.thread_time()
            tailed = st.moving_green_response(track, wheels, rolling_roughness(c.kernels.grid.speed), **run, **tail)
            low = time.thread_time() - start
            steps = tailed.t.size - 1
            print(f"  low-rank tail (rank {args.tail_rank}, from {args.tail_start or DEFAULT_TAIL_START:g} s): a run "
                  f"{low:.3f} s, {c.truncated_time / low:.1f}x the truncated run; step "
                  f"{1e6 * tailed.elapsed / steps:.2f} us", flush=True)
            for i in range(len(wheels.offsets)):
                ref, full = force_agreement(tailed, c.truncated, i), force_agreement(tailed, c.green, i)
                print(f"  wheel {i + 1}: against the truncated model {100 * ref['rms']:.4f} % rms, worst band "
                      f"{ref['worst_level_difference']:.1e} dB; against the whole kernels {100 * full['rms']:.5f} % "
                      f"rms, worst band {full['worst_level_difference']:.1e} dB", flush=True)
        if args.fresh:
            fresh, again = fresh_process_step(case, dt, args.duration, x0, c.kernels)
            print(f"  fresh process: first run's step {fresh:.2f} us ({fresh / c.step_compiled:.2f}x in-process; with "
                  f"numba reading the loop, {1e-6 * (fresh - again) * args.duration / dt:.3f} s), the second run's "
                  f"{again:.2f} us ({again / c.step_compiled:.2f}x)", flush=True)
    with pd.option_context("display.width", 250, "display.max_columns", 20, "display.precision", 4):
        print(moving_table(comparisons))


if __name__ == "__main__":
    main()
