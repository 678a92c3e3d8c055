"""The time-domain runs whose results are pinned by ``tests/data/timedomain_reference.npz``.

The reference was written by ``python tests/timedomain_cases.py`` at commit 93d90fd, before the
time-domain engine was rebuilt on :mod:`semitrack.dynamics` (issue 20): the rebuilt engine must
reproduce the old one's contact forces, boundary-end pulses and moving loads to 1e-10 relative.
The broadband boundaries are stored beside it (JSON) so that the reference does not depend on
the boundary fit staying bit for bit the same.

Each case is small (a few hundred DOFs, 1000-3000 steps) and covers one path of the engine:
boundary states, equivalent-system ends, pinned ends, a fixed and a moving load, a stationary
and a rolling wheel, a primary suspension, loss of contact. The rolling cases run without the
rail elements' own flexibility under the contact (``element_flexibility=False``), which the old
engine did not have: the stationary wheels sit on nodes, where it is zero.
"""

from __future__ import annotations

import pathlib

import numpy as np

import semitrack as st
from semitrack.fe.timedomain import moving_load_response, pulse_response

DATA = pathlib.Path(__file__).parent / "data"
REFERENCE = DATA / "timedomain_reference.npz"


def boundary(name: str):
    """The stored broadband boundary of the viscous track ``name`` (24 poles, 3 Hz - 3 kHz)."""
    return st.load_boundary(DATA / f"boundary_{name}_viscous_24.json")


def _tracks():
    return {"slab": st.slab_track(damping="viscous"), "ballasted": st.ballasted_track(damping="viscous")}


def cases() -> dict:
    """``{name: callable() -> {channel: ndarray}}``: every pinned run."""
    tracks = _tracks()
    slab, ballasted = tracks["slab"], tracks["ballasted"]
    d = slab.spacing
    lam = st.third_octave_bands(0.04, 0.5)[0]
    rough = st.roughness_from_spectrum(100.0, lam, np.full(lam.size, -10.0), period=0.02, seed=1)

    def pulse_boundary(name):
        model = st.TruncatedTrack(tracks[name], 3, "boundary", system=boundary(name), elements_per_bay=8)
        h = pulse_response(model, (0.0, 1.2), dt=2e-5, duration=0.03)
        return {"u": h.u}

    def pulse_equivalent():
        model = st.TruncatedTrack(st.ballasted_track(), 4, "equivalent", system=st.paper_table7(),
                                  elements_per_bay=6)
        return {"u": pulse_response(model, (0.0, 0.6), dt=2e-5, duration=0.02).u}

    def moving_boundary():
        model = st.TruncatedTrack(slab, 4, "boundary", system=boundary("slab"), elements_per_bay=8)
        return {"u": moving_load_response(model, (0.0, d), x_start=-2 * d, x_end=2 * d, dt=2e-5).u}

    def moving_pinned():
        model = st.TruncatedTrack(ballasted, 4, "pinned", elements_per_bay=6)
        return {"u": moving_load_response(model, (0.3,), speed=50.0, x_start=-1.0, x_end=1.0, dt=4e-5).u}

    def contact(res):
        return {"force": res.force, "w_wheel": res.w_wheel, "w_rail": res.w_rail}

    def wheel_stationary_boundary(name):
        model = st.TruncatedTrack(tracks[name], 3, "boundary", system=boundary(name), elements_per_bay=8)
        return contact(st.wheel_rail_response(model, st.Wheel(), rough, dt=2e-5, duration=0.06, ramp=0.01))

    def wheel_rolling_pinned():
        model = st.TruncatedTrack(ballasted, 5, "pinned", elements_per_bay=6)
        r = st.roughness_from_spectrum(300 / 3.6, lam, np.full(lam.size, -5.0), period=0.02, seed=2)
        res = st.wheel_rail_response(model, st.Wheel(primary_stiffness=1e6, primary_damping=1e4), r,
                                     x=-1.5, speed=300 / 3.6, dt=2e-5, duration=0.03, ramp=0.01,
                                     element_flexibility=False)
        return contact(res)

    def wheel_rolling_boundary():
        model = st.TruncatedTrack(slab, 4, "boundary", system=boundary("slab"), elements_per_bay=8)
        res = st.wheel_rail_response(model, st.Wheel(), x=-2.0, speed=300 / 3.6, dt=2e-5, duration=0.045,
                                     element_flexibility=False)
        return contact(res)

    def wheel_loses_contact():
        model = st.TruncatedTrack(slab, 3, "pinned", elements_per_bay=6)
        res = st.wheel_rail_response(model, st.Wheel(), st.corrugation(30.0, 0.05, 1.5e-4), dt=2e-5,
                                     duration=0.03, ramp=0.005)
        assert res.lost_contact
        return contact(res)

    return {
        "pulse, slab, boundary ends": lambda: pulse_boundary("slab"),
        "pulse, ballasted, boundary ends": lambda: pulse_boundary("ballasted"),
        "pulse, ballasted, paper Table 7 ends": pulse_equivalent,
        "moving load, slab, boundary ends": moving_boundary,
        "moving load, ballasted, pinned": moving_pinned,
        "wheel, slab, boundary ends": lambda: wheel_stationary_boundary("slab"),
        "wheel, ballasted, boundary ends": lambda: wheel_stationary_boundary("ballasted"),
        "rolling wheel on a suspension, ballasted, pinned": wheel_rolling_pinned,
        "rolling wheel, slab, boundary ends": wheel_rolling_boundary,
        "wheel losing contact, slab, pinned": wheel_loses_contact,
    }


def key(case: str, channel: str) -> str:
    return f"{case} | {channel}"


def write_reference() -> None:
    """Fit and store the boundaries (once), run every case and store its channels."""
    for name, track in _tracks().items():
        path = DATA / f"boundary_{name}_viscous_24.json"
        if not path.exists():
            st.save_boundary(st.fit_boundary(track, band=(3.0, 3000.0), n_poles=24), path)
    arrays = {key(case, ch): v for case, run in cases().items() for ch, v in run().items()}
    np.savez_compressed(REFERENCE, **arrays)
    print(f"wrote {len(arrays)} arrays to {REFERENCE}")


if __name__ == "__main__":
    write_reference()
