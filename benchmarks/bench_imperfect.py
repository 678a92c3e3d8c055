"""A bogie over an imperfect stretch at 300 km/h for 1 s: the broadband-end model against the pinned one (printed).

Run: ``python benchmarks/bench_imperfect.py [--dt 2e-5]`` (one run; about a minute on a 2-core
machine). The ballasted track (viscous damping) has a 10 m stretch in the middle of the bogie's
path with a hanging sleeper over a 0.5 mm gap and a dipped weld (10 mrad over 0.4 m) 5 m further;
a bogie (``st.Bogie()``, two wheels 2.5 m apart) rolls 83 m at 300 km/h for 1 s on a smooth rail,
its path centred on the stretch.

Two models hold the path: one with broadband ends and 5 bays to spare beyond the wheels at
either end, and a pinned one whose ends are so far (the least attenuated band's round trip loses
40 dB: :func:`semitrack.paper.imperfect_study.reflection_free_bays`) that no reflection returns.
The pinned model is the reference of the same accuracy: the two force histories are compared.
Printed: DOFs, set-up (model, fit) and run wall times, their ratio, the force difference, and
the cost per DOF and step, which is what dominates (the loop over 50 000 steps of the whole
model).
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import semitrack as st
from semitrack.fe.timedomain import SPEED_300_KMH
from semitrack.paper.imperfect_study import reflection_free_bays

HANGING = -8  # the hanging sleeper's support index, at x = -4.5 m
WELD_X = 5.0  # m: the 10 m stretch around the middle of the path


def run(model, bogie, dt: float, x0: float, duration: float) -> tuple[object, float]:
    start = time.perf_counter()
    res = st.wheel_rail_response(model, bogie, x=x0, speed=SPEED_300_KMH, dt=dt, duration=duration,
                                 profile=st.DippedWeld(0.01, 0.4, WELD_X), ballast_gaps={HANGING: 5e-4})
    return res, time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dt", type=float, default=2e-5)
    args = parser.parse_args()
    track = st.ballasted_track(damping="viscous")
    d, bogie, duration = track.spacing, st.Bogie(), 1.0
    x0 = 0.5 * (bogie.wheelbase - SPEED_300_KMH * duration)  # the bogie's path centred on x = 0
    reach = max(abs(x0 - bogie.wheelbase), abs(x0 + SPEED_300_KMH * duration))
    changes = {HANGING: {"kb": 0.0}}
    t = time.perf_counter()
    bnd = st.fit_boundary(track)
    fit = time.perf_counter() - t
    t = time.perf_counter()
    short = st.TruncatedTrack(track, int(np.ceil(reach / d)) + 5, "boundary", system=bnd, changes=changes)
    build_short = time.perf_counter() - t
    bays, a_min = reflection_free_bays(track, reach)
    t = time.perf_counter()
    long = st.TruncatedTrack(track, bays, "pinned", changes=changes)
    build_long = time.perf_counter() - t
    print(f"ballasted track, a bogie at 300 km/h for {duration:g} s (its wheels from {x0:.1f} and {x0 - 2.5:.1f} m), "
          f"dt {args.dt * 1e6:g} us, "
          f"{short.elements_per_bay} elements per bay; least attenuation {a_min:.2f} dB/m")
    results = {}
    for label, model, build in (("broadband ends", short, build_short), ("pinned, reflection-free", long, build_long)):
        res, wall = run(model, bogie, args.dt, x0, duration)
        steps = res.t.size - 1
        results[label] = res
        print(f"{label:>24}: {2 * model.n_bays * d:6.1f} m, {model.n_dof:6d} DOFs; build {build:5.1f} s, run "
              f"{wall:6.1f} s ({1e9 * wall / (steps * model.n_dof):.1f} ns per DOF and step); peak force "
              f"{res.force.max() / 1e3:.1f} kN, hanging sleeper in contact {res.gaps.contact_time[0] * 1e3:.1f} ms")
    a, b = results["broadband ends"].force, results["pinned, reflection-free"].force
    print(f"broadband boundary fit {fit:.1f} s (once per track); force difference "
          f"{np.abs(a - b).max() / (b.max() - b.min()) * 100:.3f} % of the range; size ratio "
          f"{long.n_dof / short.n_dof:.2f}")


if __name__ == "__main__":
    main()
