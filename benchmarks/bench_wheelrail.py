"""Wheel-rail interaction in time: the step's cost, and what the broadband boundary saves (printed, not asserted).

Run: ``python benchmarks/bench_wheelrail.py [--part steps accuracy scenario] [--track slab ballasted]``
(all parts by default; a few minutes on a 2-core machine). Timings are wall times, the best of
``--repeat`` runs (default 2) on a shared machine; ratios are taken within one run.

``steps``
    The cost of a time step: the 10-bay slab model with broadband-boundary ends and one wheel
    under a broadband roughness, end to end (``wheel_rail_response``: set-up, roughness and the
    loop) and the loop alone, compiled and NumPy side by side; the cost per DOF and step at
    10, 40 and 120 bays; the compiled kernel's first compilation in a fresh process with an empty
    cache, and its load from the on-disk cache in the next process.
``accuracy``
    The 10-bay model with broadband-boundary ends against pinned models of growing length, for a
    stationary wheel under a small broadband roughness (one-third-octave bands of wavelength
    2 m - 4 cm at -10 dB re 1 um, passed at 100 m/s: 50 Hz - 2.5 kHz), by the contact force's
    band errors against the linear theory on the exact infinite track: the pinned length that
    reaches 1 dB and 0.3 dB in every band, its size and wall time against the boundary model's,
    and the speed-up as a fraction of the size ratio (the issue asks for at least 0.8).
``scenario``
    The paper's case for long models: wheels at 300 km/h for 1 s over a rough rail (the ISO 3095
    limit, wavelengths 8 mm and longer), one wheel and four (0, 2.5, 17.5 and 20 m: two bogies'
    wheelsets, independent), on the paper's 266 m pinned model and on a boundary-ended model
    that holds the wheels' path with 5 bays to spare at each end. Set-up (assembly, the boundary
    fit, the step's factorisation and arrays) is reported apart from the step loop.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

import semitrack as st
from semitrack.fe.timedomain import SPEED_300_KMH

ROOT = Path(__file__).resolve().parents[1]
SPEED = 100.0
BANDS = (50.0, 2500.0)
#: Elements per bay of every model here: the mesh the earlier measurements used (the default follows f_max).
ELEMENTS = 12
#: Time step and simulated time per track: the slab track's wheel bounce (64 Hz, 1.1 % damping)
#: needs 0.7 s after the fade-in to leave under 0.3 dB; the ballasted one is better damped, and its
#: sharp pinned-pinned peak wants the finer step (0.3 dB at 1 kHz with 40 us).
RUNS = {"slab": (4e-5, 0.82), "ballasted": (2e-5, 0.42)}
PINNED_BAYS = (10, 15, 20, 30, 40, 60, 80, 120, 160, 240, 320)
TRACKS = {"slab": st.slab_track, "ballasted": st.ballasted_track}


def small_roughness():
    lam = st.third_octave_bands(0.04, 2.0)[0]
    return st.roughness_from_spectrum(SPEED, lam, np.full(lam.size, -10.0), period=0.1, seed=1)


def best(repeat: int, call):
    """(wall time, result) of the fastest of ``repeat`` calls."""
    wall, out = np.inf, None
    for _ in range(repeat):
        start = time.perf_counter()
        result = call()
        elapsed = time.perf_counter() - start
        if elapsed < wall:
            wall, out = elapsed, result
    return wall, out


def boundary_of(name: str):
    start = time.perf_counter()
    # 24 poles on both tracks (tests/test_contact.py): the order search keeps 24 on the slab track
    # and 48 on the ballasted one, where 24 move the contact force by 0.001 dB at half the states
    bnd = st.fit_boundary(TRACKS[name](damping="viscous"), band=(3.0, 3000.0), n_poles=24)
    return bnd, time.perf_counter() - start


# ------------------------------------------------------------------------------------------------
def part_steps(repeat: int) -> None:
    print("\n== the time step (slab track, viscous, dt 40 us, 0.82 s, one wheel, broadband roughness)")
    bnd, _ = boundary_of("slab")
    track = st.slab_track(damping="viscous")
    rough = small_roughness()
    dt, duration = RUNS["slab"]
    print(f"{'model':>22} {'DOFs+states':>12} {'loop':>8} {'end to end':>11} {'per step, loop':>15} "
          f"{'end to end':>11} {'ns/DOF/step':>12}")
    for bays in (10, 40, 120):
        model = st.TruncatedTrack(track, bays, "boundary", system=bnd, elements_per_bay=ELEMENTS)
        size = model_size(model, 1)
        for compiled in (True, False):
            if not compiled and bays > 10:
                continue  # the NumPy loop at 120 bays takes minutes; its per-DOF cost shows at 10 already
            wall, res = best(repeat, lambda: st.wheel_rail_response(model, st.Wheel(), rough, dt=dt, duration=duration,
                                                                    compiled=compiled))
            n = res.t.size - 1
            label = f"{bays} bays, {'compiled' if compiled else 'NumPy'}"
            print(f"{label:>22} {size:12d} {res.elapsed:7.2f}s {wall:10.2f}s {1e6 * res.elapsed / n:12.2f} us "
                  f"{1e6 * wall / n:8.2f} us {1e9 * res.elapsed / n / size:12.1f}")
    compile_times()


_CHILD = """
import time, numpy as np, semitrack as st
m = st.TruncatedTrack(st.slab_track(), 2, elements_per_bay=4)
start = time.perf_counter()
st.wheel_rail_response(m, st.Wheel(), dt=1e-4, duration=0.002, ramp=0.001, compiled=True)
print(time.perf_counter() - start)
"""


def compile_times() -> None:
    """First call in a fresh process with an empty kernel cache, then the next process (cache on disk)."""
    with tempfile.TemporaryDirectory() as cache:
        env = dict(os.environ, NUMBA_CACHE_DIR=cache)  # this measurement only: the package never needs it
        times = [float(subprocess.run([sys.executable, "-c", _CHILD], env=env, capture_output=True, text=True,
                                      check=True).stdout) for _ in range(2)]
    print(f"compiled kernel: first call {times[0]:.2f} s (compiling, empty cache), next process {times[1]:.2f} s "
          "(from the on-disk cache), a tiny run included")


# ------------------------------------------------------------------------------------------------
def run_stationary(model, roughness, dt, duration, repeat):
    wall, res = best(repeat, lambda: st.wheel_rail_response(model, st.Wheel(), roughness, dt=dt, duration=duration))
    size = model_size(model, 1)
    return wall, size, st.contact_transfer(res, band=BANDS)


def part_accuracy(names, repeat: int, max_bays: int) -> None:
    rough = small_roughness()
    for name in names:
        track = TRACKS[name](damping="viscous")
        dt, duration = RUNS[name]
        bnd, fit_time = boundary_of(name)
        print(f"\n== {name} track (viscous), dt {dt * 1e6:g} us, {duration:g} s; boundary fit {bnd.n_poles} poles "
              f"in {fit_time:.1f} s (once per track)")
        print(f"{'model':>20} {'DOFs+states':>12} {'time (s)':>9} {'max err (dB)':>12} {'band (Hz)':>10}")
        boundary_model = st.TruncatedTrack(track, 10, "boundary", system=bnd, elements_per_bay=ELEMENTS)
        wall_b, size_b, transfer = run_stationary(boundary_model, rough, dt, duration, repeat)
        row("boundary, 10 bays", wall_b, size_b, transfer)
        targets, found = (1.0, 0.3), {}
        for n in (n for n in PINNED_BAYS if n <= max_bays):
            pinned = st.TruncatedTrack(track, n, "pinned", elements_per_bay=ELEMENTS)
            wall, size, transfer = run_stationary(pinned, rough, dt, duration, repeat)
            err = row(f"pinned, {n} bays", wall, size, transfer)
            found.update({limit: (n, size, wall) for limit in targets if err <= limit and limit not in found})
            if len(found) == len(targets):
                break
        for limit in targets:
            if limit not in found:
                print(f"-> no pinned model up to {max_bays} bays reaches {limit:g} dB")
                continue
            n, size, wall = found[limit]
            size_ratio, speed_up = size / size_b, wall / wall_b
            print(f"-> within {limit:g} dB: pinned needs {n} bays each side ({2 * n * track.spacing:.1f} m): "
                  f"{size_ratio:.1f} x the size, {speed_up:.1f} x the time of the 10-bay boundary model "
                  f"(speed-up / size ratio {speed_up / size_ratio:.2f}; +{fit_time:.1f} s fit, once)")


def row(label: str, wall: float, size: int, transfer) -> float:
    err = np.abs(transfer.error_db)
    worst = int(np.argmax(err))
    print(f"{label:>20} {size:12d} {wall:9.2f} {err[worst]:12.2f} {transfer.centres[worst]:10.0f}")
    return float(err[worst])


def model_size(model, n_wheels: int) -> int:
    """What a time step solves for: the FE DOFs, one per wheel, and the boundary ends' states."""
    return model.n_dof + n_wheels + sum(b.n_states for b in model.boundary_states())


# ------------------------------------------------------------------------------------------------
SCENARIO_SPEED = SPEED_300_KMH
SCENARIO_DT = 2e-5
WHEELSETS = (0.0, 2.5, 17.5, 20.0)  # m behind the first: two bogies' wheelsets


def part_scenario(names, repeat: int) -> None:
    limit = {lam: level for lam, level in st.ISO3095_ROUGHNESS_LIMIT.items() if lam >= 0.008}
    rough = st.roughness_from_spectrum(SCENARIO_SPEED, list(limit), list(limit.values()), period=0.1, seed=1)
    path = SCENARIO_SPEED * 1.0
    print(f"\n== the paper's scenario: 300 km/h for 1 s (path {path:.1f} m), dt {1e6 * SCENARIO_DT:g} us, "
          "ISO 3095 limit roughness (>= 8 mm)")
    print(f"{'track':>10} {'wheels':>6} {'model':>34} {'DOFs+states':>12} {'set-up (s)':>10} {'loop (s)':>9} "
          f"{'total (s)':>9}")
    for name in names:
        track = TRACKS[name](damping="viscous")
        d = track.spacing
        bnd, fit_time = boundary_of(name)
        pinned_bays = int(round(133.0 / d))
        start = time.perf_counter()
        # the same for every set of wheels
        pinned = st.TruncatedTrack(track, pinned_bays, "pinned", elements_per_bay=ELEMENTS)
        t_pinned = time.perf_counter() - start
        for offsets in ((0.0,), WHEELSETS):
            rear, front = -max(offsets), 0.0
            x_start = -0.5 * path  # the first wheel runs from -path/2 to +path/2
            models = {f"pinned, {2 * pinned_bays * d:.0f} m": pinned}
            reach = max(abs(x_start + rear), abs(x_start + front + path)) + 5 * d
            bays = int(np.ceil(reach / d))
            start = time.perf_counter()
            models[f"boundary, {2 * bays * d:.0f} m"] = st.TruncatedTrack(track, bays, "boundary", system=bnd,
                                                                          elements_per_bay=ELEMENTS)
            t_boundary = time.perf_counter() - start
            walls = {}
            for (label, model), t_model in zip(models.items(), (t_pinned, t_boundary + fit_time)):
                wheels = [st.Wheel()] * len(offsets)
                x0 = [x_start - o for o in offsets]
                wall, res = best(repeat, lambda: st.wheel_rail_response(model, wheels, rough, x=x0,
                                                                        speed=SCENARIO_SPEED, dt=SCENARIO_DT,
                                                                        duration=1.0))
                size = model_size(model, len(offsets))
                set_up = t_model + wall - res.elapsed
                walls[label] = set_up + res.elapsed
                print(f"{name:>10} {len(offsets):6d} {label:>34} {size:12d} {set_up:10.2f} {res.elapsed:9.2f} "
                      f"{walls[label]:9.2f}")
            (p_label, p_wall), (b_label, b_wall) = walls.items()
            print(f"{'':>10} {'':>6} -> the boundary model {p_wall / b_wall:.1f} x faster in all "
                  f"(the boundary fit, {fit_time:.1f} s, counted in its set-up)")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--part", nargs="+", choices=("steps", "accuracy", "scenario"),
                        default=["steps", "accuracy", "scenario"])
    parser.add_argument("--track", nargs="+", choices=tuple(TRACKS), default=list(TRACKS))
    parser.add_argument("--max-bays", type=int, default=PINNED_BAYS[-1], help="longest pinned model (bays each side)")
    parser.add_argument("--repeat", type=int, default=2, help="runs per timing (the best is printed)")
    args = parser.parse_args()
    if "steps" in args.part:
        part_steps(args.repeat)
    if "accuracy" in args.part:
        part_accuracy(args.track, args.repeat, args.max_bays)
    if "scenario" in args.part:
        part_scenario(args.track, args.repeat)


if __name__ == "__main__":
    main()
