"""The chapter "wheel flats and the wheel's geometry": impacts of flats against speed, and what the wheel's radius does.

Each function runs one of the chapter's studies and returns tables (and runs for the figures of
:mod:`semitrack.plotting.flats`); the chapter asserts the numbers its prose quotes.

The impacts are run by the moving-irregularity model (:func:`semitrack.convolution_response`
with ``speed=``): the wheel stands on the exact infinite track and turns, so its flat comes
round under it; nothing is meshed or truncated, and a run costs milliseconds once the rail's
impulse responses are known (they are kept for the track, :mod:`semitrack.interaction.infinite_convolution`).
The forces in the track around an impact need the track itself, and the wheel rolling along it:
those runs are on the 10-bay model with broadband ends (:func:`semitrack.wheel_rail_response`).

The wheel's geometric input is its centre's path rolled over the rail
(:func:`semitrack.wheel_centre_path`); ``contact="point"`` feeds the tread's profile instead, the
model the field used before the wheel-centre trajectory.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike
from scipy.signal import butter, sosfiltfilt

from ..boundary.fitting import BroadbandBoundary
from ..fe.ends import BoundaryEnd
from ..fe.models import TruncatedTrack
from ..interaction.fe_model import wheel_rail_response
from ..interaction.infinite_convolution import convolution_response
from ..interaction.response import ContactResponse
from ..methods.infinite import InfiniteTrack
from ..model.centre_path import wheel_centre_path
from ..model.irregularity import DippedWeld
from ..model.wheel import Wheel
from ..model.wheel_defects import WheelFlat
from .imperfect_study import CASE_BAYS, p1_p2

__all__ = ["LEAD", "AFTER", "MEMORY", "DT", "flat_wheel", "centre_path_curves", "flat_run", "flat_p1_p2",
           "impact_table", "descent_loss", "kinematic_loss_speed", "loss_speed_table", "contact_model_table",
           "track_force_runs", "track_force_table", "weld_contact_table", "model_of"]

#: Rail rolled before the flat's leading end meets the contact (m), and time run after its trailing
#: end has passed (s): the impact and the wheel's rebound on the track (P2, ~50-100 Hz) within it.
LEAD, AFTER = 0.01, 0.03
#: How long the impact runs remember the rail's response (s): longer than any of them lasts (a
#: 100 mm flat at 5 km/h: 0.11 s), so no lag is cut, and one length for all, so the responses are
#: computed once per track.
MEMORY = 0.15
#: Time step of the impact runs (s): P1 of a new 50 mm flat on the ballasted track moves by under
#: 0.3 % against an independent model at half of it (``tests/test_wheel_flats.py``).
DT = 2e-5


def flat_wheel(length: float, shape: str = "new", *, lead: float = LEAD, contact: str = "centre_path",
               **wheel: float) -> Wheel:
    """A wheel (on the chapter's primary suspension unless told) whose flat meets the rail after rolling ``lead`` m.

    Parameters
    ----------
    length : float
        The flat's length (m).
    shape : {"new", "rounded"}
        Its shape (:class:`semitrack.WheelFlat`).
    lead : float
        Rail rolled before the flat's leading end reaches the contact point (m).
    contact : {"centre_path", "point"}
        The wheel's geometric input.
    **wheel
        Other :class:`semitrack.Wheel` fields (default: primary suspension 1.2 MN/m, 15 kN s/m).

    Returns
    -------
    Wheel
    """
    fields = {"primary_stiffness": 1.2e6, "primary_damping": 1.5e4} | wheel
    flat = WheelFlat(length, shape=shape, position=0.5 * length + lead)
    return Wheel(defects=(flat,), contact=contact, **fields)


def _duration(wheel: Wheel, speed: float) -> float:
    """From the start over the whole flat and ``AFTER`` beyond (s)."""
    flat = wheel.defects[0]
    return (flat.position + 0.5 * flat.length) / speed + AFTER


def centre_path_curves(wheels: Mapping[str, Wheel], x: ArrayLike) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Each wheel's tread profile and its centre's path at the distances ``x`` rolled (m, downward).

    Parameters
    ----------
    wheels : mapping of str to Wheel
        Wheels whose flat is at ``position = 0``, by name.
    x : array_like
        Distances rolled (m; the arc length on the tread for the profile).

    Returns
    -------
    dict
        Name to (profile, centre path), for :func:`semitrack.plotting.centre_path_figure`.
    """
    return {name: (w.tread_profile(x), wheel_centre_path(w, x)) for name, w in wheels.items()}


def flat_run(track: InfiniteTrack, wheel: Wheel, kmh: float, x: float = 0.0) -> ContactResponse:
    """One impact by the moving-irregularity model: the wheel of :func:`flat_wheel` turning at ``kmh`` at ``x``.

    Parameters
    ----------
    track : InfiniteTrack
        The exact track (one object for all runs: its impulse responses are computed once).
    wheel : Wheel
        A wheel of :func:`flat_wheel`.
    kmh : float
        The speed (km/h).
    x : float
        Where the wheel stands (m; 0 a mid-span, ``d/2`` above a support).

    Returns
    -------
    ContactResponse
    """
    v = kmh / 3.6
    return convolution_response(track, wheel, x=x, speed=v, dt=DT, duration=_duration(wheel, v), ramp=1e-3,
                                memory=MEMORY)


def flat_p1_p2(response: ContactResponse, f_low: float = 200.0) -> tuple[float, float]:
    """The impact's P1 (its largest force) and P2 (the largest of the force low-passed at ``f_low``), N.

    Parameters
    ----------
    response : ContactResponse
        An impact run.
    f_low : float
        The low-pass frequency (Hz) that separates P2 (the wheel on the track, ~50-100 Hz) from P1.

    Returns
    -------
    P1, P2 : float
    """
    sos = butter(4, f_low, fs=1.0 / response.dt, output="sos")
    return float(response.force.max()), float(sosfiltfilt(sos, response.force).max())


def descent_loss(response: ContactResponse, wheel: Wheel, kmh: float) -> float:
    """Time without contact (s) before the flat's centre reaches the rail: the wheel left behind on its descent."""
    before = response.t * kmh / 3.6 < wheel.defects[0].position
    return float(np.count_nonzero(response.force[before] <= 0.0) * response.dt)


def impact_table(tracks: Mapping[str, InfiniteTrack], lengths: Sequence[float], shapes: Sequence[str],
                 speeds: Sequence[float], contact: str = "centre_path", **wheel: float) -> pd.DataFrame:
    """P1, P2 and loss of contact of every flat at every speed on every track.

    Parameters
    ----------
    tracks : mapping of str to InfiniteTrack
        The tracks by name.
    lengths : sequence of float
        Flat lengths (m).
    shapes : sequence of str
        Flat shapes.
    speeds : sequence of float
        Speeds (km/h).
    contact : {"centre_path", "point"}
        The wheel's geometric input.
    **wheel
        Wheel fields for :func:`flat_wheel`.

    Returns
    -------
    pandas.DataFrame
        Indexed by (track, shape, length in mm, speed in km/h): P1 and P2 (kN), the time without
        contact (ms), and that of it before the flat's centre (the descent, ms).
    """
    rows = {}
    for name, track in tracks.items():
        for shape in shapes:
            for length in lengths:
                w = flat_wheel(length, shape, contact=contact, **wheel)
                for kmh in speeds:
                    res = flat_run(track, w, kmh)
                    p1, p2 = flat_p1_p2(res)
                    rows[name, shape, round(1e3 * length, 6), kmh] = {
                        "P1 (kN)": p1 / 1e3, "P2 (kN)": p2 / 1e3,
                        "without contact (ms)": 1e3 * np.count_nonzero(res.force <= 0.0) * res.dt,
                        "on the descent (ms)": 1e3 * descent_loss(res, w, kmh)}
    table = pd.DataFrame.from_dict(rows, orient="index")
    table.index = pd.MultiIndex.from_tuples(table.index, names=["track", "shape", "length (mm)", "speed (km/h)"])
    return table


def kinematic_loss_speed(wheel: Wheel, spacing: float = 1e-4) -> float:
    """The speed (km/h) above which a rigid rail would lose a wheel on its flat's descent.

    Rolled at speed v, the centre must follow its path r(x) down with the acceleration
    ``v^2 r''(x)``; only the wheel's load pulls it down, so it leaves the rail once ``v^2 max r''``
    exceeds ``P0 / m`` (gravity on the unsprung mass is part of the static load). A new flat's
    centre turns about the flat's edge, so ``max r'' = 1 / R`` and ``v = sqrt(P0 R / m)``.

    Parameters
    ----------
    wheel : Wheel
        A wheel with one flat.
    spacing : float
        The step of the second difference of the centre path (m).

    Returns
    -------
    float
    """
    flat = wheel.defects[0]
    x = flat.position + np.arange(-0.5 * flat.length - 5 * spacing, 5 * spacing, spacing)  # the descent
    r = wheel_centre_path(wheel, x)
    curvature = float(np.max(np.diff(r, 2)) / spacing**2)
    return 3.6 * float(np.sqrt(wheel.preload / (wheel.mass * curvature)))


def _loses_on_descent(track: InfiniteTrack, wheel: Wheel, kmh: float) -> bool:
    return descent_loss(flat_run(track, wheel, kmh), wheel, kmh) > 0


def loss_speed_table(tracks: Mapping[str, InfiniteTrack], flats: Mapping[str, tuple[float, str]],
                     lo: float = 5.0, hi: float = 300.0, tol: float = 0.25, **wheel: float) -> pd.DataFrame:
    """The lowest speed at which the wheel leaves the rail on its flat's descent, on each track, by bisection.

    Parameters
    ----------
    tracks : mapping of str to InfiniteTrack
        Tracks by name.
    flats : mapping of str to (float, str)
        Name to (length in m, shape).
    lo, hi : float
        The speed range searched (km/h): kept at ``lo``, lost at ``hi``.
    tol : float
        The bisection's width at the end (km/h).
    **wheel
        Wheel fields for :func:`flat_wheel`.

    Returns
    -------
    pandas.DataFrame
        Per flat: the rigid rail's speed (:func:`kinematic_loss_speed`) and each track's (km/h);
        NaN where the wheel keeps contact up to ``hi``.
    """
    rows = {}
    for label, (length, shape) in flats.items():
        w = flat_wheel(length, shape, **wheel)
        row = {"rigid rail (km/h)": kinematic_loss_speed(w)}
        for name, track in tracks.items():
            a, b = lo, hi
            if _loses_on_descent(track, w, a) or not _loses_on_descent(track, w, b):
                row[f"{name} (km/h)"] = np.nan if not _loses_on_descent(track, w, b) else a
                continue
            while b - a > tol:
                mid = 0.5 * (a + b)
                a, b = (a, mid) if _loses_on_descent(track, w, mid) else (mid, b)
            row[f"{name} (km/h)"] = 0.5 * (a + b)
        rows[label] = row
    return pd.DataFrame.from_dict(rows, orient="index").rename_axis("flat")


def _against(centre: tuple[float, float], point: tuple[float, float]) -> dict[str, float]:
    """A row of P1 and P2 (N in, kN out) by the centre path and the point contact, and the point's over it (%)."""
    row = {}
    for i, name in enumerate(("P1", "P2")):
        row |= {f"{name}, centre path (kN)": centre[i] / 1e3, f"{name}, point (kN)": point[i] / 1e3,
                f"{name}, point against centre path (%)": 100 * (point[i] / centre[i] - 1)}
    return row


def contact_model_table(tracks: Mapping[str, InfiniteTrack], flats: Mapping[str, tuple[float, str]],
                        speeds: Sequence[float], **wheel: float) -> pd.DataFrame:
    """P1 and P2 with the wheel's centre path as input against the tread's profile at a point.

    Parameters
    ----------
    tracks : mapping of str to InfiniteTrack
        Tracks by name.
    flats : mapping of str to (float, str)
        Name to (length in m, shape).
    speeds : sequence of float
        Speeds (km/h).
    **wheel
        Wheel fields for :func:`flat_wheel`.

    Returns
    -------
    pandas.DataFrame
        Indexed by (track, flat, speed): P1 and P2 of each input (kN) and the point contact's
        over the centre path's (%).
    """
    rows = {}
    for name, track in tracks.items():
        for label, (length, shape) in flats.items():
            wheels = {c: flat_wheel(length, shape, contact=c, **wheel) for c in ("centre_path", "point")}
            for kmh in speeds:
                rows[name, label, kmh] = _against(*(flat_p1_p2(flat_run(track, w, kmh)) for w in wheels.values()))
    table = pd.DataFrame.from_dict(rows, orient="index")
    table.index = pd.MultiIndex.from_tuples(table.index, names=["track", "flat", "speed (km/h)"])
    return table


def track_force_runs(model: TruncatedTrack, length: float, shape: str, speeds: Sequence[float],
                     at: float, watch: Sequence[int] = (-2, -1, 0, 1, 2), **wheel: float
                     ) -> dict[float, ContactResponse]:
    """A wheel with a flat rolled along the FE model, the flat meeting the rail at ``at``, per speed.

    Parameters
    ----------
    model : TruncatedTrack
        The track model (10 bays with broadband ends in the chapter).
    length : float
        The flat's length (m).
    shape : str
        Its shape.
    speeds : sequence of float
        Speeds (km/h).
    at : float
        Where the flat's leading end meets the rail (m).
    watch : sequence of int
        The supports whose rail-seat and ballast forces are recorded; the rail's bending is read
        where the flat's middle meets the rail.
    **wheel
        Wheel fields for :func:`flat_wheel`.

    Returns
    -------
    dict
        Speed to its run.
    """
    start = at - 1.5  # 1.5 m of rail before the flat: the wheel settles on the moving load's own deflection
    w = flat_wheel(length, shape, lead=1.5, **wheel)
    runs = {}
    for kmh in speeds:
        v = kmh / 3.6
        runs[kmh] = wheel_rail_response(model, w, x=start, speed=v, dt=DT, duration=_duration(w, v),
                                        watch_supports=watch, bending_at=[at + 0.5 * length])
    return runs


def track_force_table(runs: Mapping[float, ContactResponse], reference: Mapping[float, ContactResponse] | None = None
                      ) -> pd.DataFrame:
    """Per speed: the contact's P1 and P2 and the largest rail-seat and ballast forces around the impact.

    Parameters
    ----------
    runs : mapping of float to ContactResponse
        :func:`track_force_runs`.
    reference : mapping of float to ContactResponse, optional
        The same flat by the moving-irregularity model at the same speeds (a wheel standing at the
        impact's place), whose P1 is set beside.

    Returns
    -------
    pandas.DataFrame
        One row per speed (kN; the bending in kN m).
    """
    rows = {}
    for kmh, res in runs.items():
        forces = res.track_forces
        p1, p2 = flat_p1_p2(res)
        row = {"P1 (kN)": p1 / 1e3, "P2 (kN)": p2 / 1e3, "largest rail-seat force (kN)": forces.rail_seat.max() / 1e3}
        if forces.ballast is not None:
            row["largest ballast force (kN)"] = forces.ballast.max() / 1e3
        if forces.x_bending.size:
            row["largest bending at the impact (kN m)"] = forces.bending.max() / 1e3
        if reference is not None:
            row["P1, standing wheel on the exact track (kN)"] = flat_p1_p2(reference[kmh])[0] / 1e3
        rows[kmh] = row
    return pd.DataFrame.from_dict(rows, orient="index").rename_axis("speed (km/h)")


def weld_contact_table(model: TruncatedTrack, weld: DippedWeld, speeds: Sequence[float], start: float = -3.0,
                       stop: float = 2.0, **wheel: float) -> pd.DataFrame:
    """The imperfect chapter's dipped weld rolled over with the wheel's radius in the contact and without.

    Parameters
    ----------
    model : TruncatedTrack
        The track model.
    weld : DippedWeld
        The weld.
    speeds : sequence of float
        Speeds (km/h).
    start, stop : float
        The wheel's path (m).
    **wheel
        Wheel fields (default: the imperfect chapter's primary suspension).

    Returns
    -------
    pandas.DataFrame
        Per speed: P1 and P2 (:func:`semitrack.paper.imperfect_study.p1_p2`) of each input (kN),
        and the point contact's over the centre path's (%).
    """
    fields = {"primary_stiffness": 1.2e6, "primary_damping": 1.5e4} | wheel
    rows = {}
    for kmh in speeds:
        v = kmh / 3.6
        peaks = {c: p1_p2(wheel_rail_response(model, Wheel(contact=c, **fields), profile=weld, x=start, speed=v,
                                              dt=DT, duration=(stop - start) / v), weld)
                 for c in ("centre_path", "point")}
        rows[kmh] = _against(peaks["centre_path"], peaks["point"])
    return pd.DataFrame.from_dict(rows, orient="index").rename_axis("speed (km/h)")


def model_of(track, boundary: BroadbandBoundary) -> TruncatedTrack:
    """The chapter's FE model: 10 bays each side with broadband ends."""
    return TruncatedTrack(track, CASE_BAYS, BoundaryEnd.name, system=boundary)
