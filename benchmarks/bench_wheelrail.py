"""Wheel-rail interaction in time: what the broadband boundary saves (printed, not asserted).

For the paper's two tracks with viscous damping (the time-domain model's), a stationary wheel
(600 kg, 100 kN, C_H 9.3e10 N/m^1.5) at the central mid-span under a small broadband roughness
(one-third-octave bands of wavelength 2 m - 4 cm at -10 dB re 1 um, passed at 100 m/s: 50 Hz -
2.5 kHz, period 0.1 s). The contact force per unit roughness of each model is compared band by
band with the linear frequency-domain theory on the exact infinite track
(:func:`semitrack.contact_transfer`). The 10-bay model with broadband-boundary ends is set
against pinned-end models of growing length, with the same time step, record and mesh (12
elements per bay), until one is as accurate in every band (the boundary model's largest error
+ 0.1 dB); the summaries give the length, size and time needed for 1 dB (the issue's criterion)
and for that accuracy. Printed per model: DOFs (plus the
boundary's states), wall time of the run (the best of two), the largest band error and its band.

Run with ``OPENBLAS_NUM_THREADS=1 python benchmarks/bench_wheelrail.py`` (a few minutes).
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import semitrack as st

SPEED = 100.0
BANDS = (50.0, 2500.0)
#: Time step and simulated time per track: the slab track's wheel bounce (64 Hz, 1.1 % damping)
#: needs 0.7 s after the fade-in to leave under 0.3 dB; the ballasted one is better damped, and its
#: sharp pinned-pinned peak wants the finer step (0.3 dB at 1 kHz with 40 us).
RUNS = {"slab": (4e-5, 0.82), "ballasted": (2e-5, 0.42)}
PINNED_BAYS = (10, 15, 20, 30, 40, 60, 80, 120, 160, 240, 320)


def run(model, roughness, dt: float, duration: float, repeat: int = 2):
    """Wall time (s, the best of ``repeat`` runs on a shared machine), size and band errors (dB) of one model."""
    wall = np.inf
    for _ in range(repeat):
        start = time.perf_counter()
        res = st.wheel_rail_response(model, st.Wheel(), roughness, dt=dt, duration=duration)
        wall = min(wall, time.perf_counter() - start)
    transfer = st.contact_transfer(res, band=BANDS)
    size = model.n_dof + 1 + sum(a.A.shape[0] for a in model.boundary_states())
    return wall, size, transfer


def row(label: str, wall: float, size: int, transfer) -> float:
    err = np.abs(transfer.error_db)
    worst = int(np.argmax(err))
    print(f"{label:>20} {size:12d} {wall:9.2f} {err[worst]:12.2f} {transfer.centres[worst]:10.0f}")
    return float(err[worst])


def summary(what: str, n: int, track, size: int, wall: float, size_b: int, wall_b: float, fit_time: float) -> None:
    print(f"-> within {what}: pinned needs {n} bays each side ({2 * n * track.spacing:.1f} m), {size / size_b:.1f} x "
          f"the size and {wall / wall_b:.1f} x the time of the 10-bay boundary model (+{fit_time:.1f} s fit, once)")


def study(name: str, roughness, max_bays: int) -> None:
    """The boundary model, then pinned models of growing length until one is as accurate as the
    boundary model (its largest band error + 0.1 dB); summaries at 1 dB and at that accuracy."""
    track = (st.slab_track if name == "slab" else st.ballasted_track)(damping="viscous")
    dt, duration = RUNS[name]
    start = time.perf_counter()
    # 24 poles on both tracks (tests/test_contact.py): the order search keeps 24 on the slab track
    # and 48 on the ballasted one, where 24 move the contact force by 0.001 dB at half the states
    bnd = st.fit_boundary(track, band=(3.0, 3000.0), n_poles=24)
    fit_time = time.perf_counter() - start
    print(f"\n{name} track (viscous), dt {dt * 1e6:g} us, {duration:g} s; boundary fit {bnd.n_poles} poles "
          f"in {fit_time:.1f} s (once per track)")
    print(f"{'model':>20} {'DOFs+states':>12} {'time (s)':>9} {'max err (dB)':>12} {'band (Hz)':>10}")
    wall_b, size_b, transfer = run(st.TruncatedTrack(track, 10, "boundary", system=bnd), roughness, dt, duration)
    strict = row("boundary, 10 bays", wall_b, size_b, transfer) + 0.1
    found = {}
    for n in (n for n in PINNED_BAYS if n <= max_bays):
        wall, size, transfer = run(st.TruncatedTrack(track, n, "pinned"), roughness, dt, duration)
        err = row(f"pinned, {n} bays", wall, size, transfer)
        for what, limit in (("1 dB", 1.0), (f"{strict:.2f} dB (the boundary model's + 0.1)", strict)):
            if err <= limit and what not in found:
                found[what] = (n, size, wall)
        if err <= strict:
            break
    for what, (n, size, wall) in found.items():
        summary(what, n, track, size, wall, size_b, wall_b, fit_time)
    if len(found) < 2:
        print(f"-> no pinned model up to {max_bays} bays reaches {strict:.2f} dB")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--max-bays", type=int, default=PINNED_BAYS[-1], help="longest pinned model (bays each side)")
    parser.add_argument("--track", choices=("slab", "ballasted", "both"), default="both")
    args = parser.parse_args()
    lam = st.third_octave_bands(0.04, 2.0)[0]
    roughness = st.roughness_from_spectrum(SPEED, lam, np.full(lam.size, -10.0), period=0.1, seed=1)
    for name in ("slab", "ballasted") if args.track == "both" else (args.track,):
        study(name, roughness, args.max_bays)


if __name__ == "__main__":
    main()
