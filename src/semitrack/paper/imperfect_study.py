"""What truncated models are for: an imperfect track under several wheels, in the frequency and time domains.

The computations of the book's chapter "Beyond the paper: an imperfect track under a bogie";
each returns a table (:class:`pandas.DataFrame`) or runs that the chapter shows or draws with
:mod:`semitrack.plotting.imperfect`, so the notebook only calls them.

* Frequency domain (:func:`imperfect_receptance_table`): a 10-bay truncated track with broadband
  ends and a failed fastener, hanging sleepers, a slab-to-ballast transition or a rail joint,
  against the exact :class:`semitrack.InfiniteTrack` with the same changes; beside it the same
  model with pinned ends, and with exact ends (the mesh alone).
* Several wheels (:func:`several_wheel_table`): two wheels 2.5 m apart and a bogie standing on a
  small roughness, the time domain against the several-wheel linear theory, band by band.
* A dipped weld rolled over (:func:`weld_runs`, :func:`weld_table`, :func:`weld_convergence`):
  the 10-bay broadband-ended model against a pinned model long enough that no reflection returns
  (:func:`reflection_free_bays`, from the track decay rate), the P1 and P2 forces beside
  Jenkins' closed-form P2 (:func:`semitrack.methods.impact.jenkins_p2`), rail-seat and ballast
  forces around the weld and the rail's bending at it.
* A hanging sleeper over a gap (:func:`gap_runs`): the gap closing under the wheel and opening
  behind it, the ballast force, the wheel's force.

Errors are relative (``|approx - reference| / |reference|``); tables give them in per cent.
"""

from __future__ import annotations

import functools
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike
from scipy.signal import butter, sosfiltfilt

from ..base.parallel import thread_map
from ..boundary.fitting import BroadbandBoundary
from ..fe.ends import EXACT, PINNED, BoundaryEnd
from ..fe.models import TruncatedTrack
from ..interaction.fe_model import wheel_rail_response
from ..interaction.infinite_convolution import convolution_response
from ..interaction.response import ContactResponse
from ..interaction.transfer import contact_transfer
from ..methods.decay import track_decay_rate
from ..methods.impact import jenkins_p2, lumped_track
from ..methods.receptance import point_receptance
from ..model.irregularity import DippedWeld, RailProfile
from ..model.roughness import Roughness
from ..model.tracks import Track
from ..model.vehicle import Vehicle
from ..model.wheel import Wheel

__all__ = ["CASE_BAYS", "imperfect_cases", "imperfect_receptance_table", "floating_slab_table", "jenkins_table",
           "several_wheel_table", "fe_and_exact_runs",
           "reflection_free_bays", "WeldRun", "weld_runs", "p1_p2", "weld_table", "weld_convergence", "gap_runs",
           "change_rolling_table", "slope_change", "slope_change_table", "weld_entry_table", "hanging_sleeper_table"]

#: Bays each side of the centre of the short models.
CASE_BAYS = 10


def imperfect_cases(slab: Track, ballasted: Track) -> dict[str, tuple[Track, dict, tuple[str, ...], float]]:
    """The local changes of the chapter: ``{name: (track, TruncatedTrack keywords, boundaries, load point)}``.

    Parameters
    ----------
    slab, ballasted : Track
        The two tracks (viscous damping for a causal comparison).

    Returns
    -------
    dict
        ``boundaries`` names the track of each end's boundary (left, right); the load point (m)
        is at the change, its receptance read there and a bay further on.
    """
    d1, d2 = slab.spacing, ballasted.spacing
    return {
        "failed fastener (slab)": (slab, {"changes": {0: None}}, ("slab", "slab"), 0.5 * d1),
        "three hanging sleepers": (ballasted, {"changes": {k: {"kb": 0.0} for k in (-1, 0, 1)}},
                                   ("ballasted", "ballasted"), 0.5 * d2),
        "slab-to-ballast transition": (slab, {"right": ballasted, "transition": 0}, ("slab", "ballasted"), 0.5 * d2),
        "rail joint (hinge, ballasted)": (ballasted, {"joints": {0.0: 0.0}}, ("ballasted", "ballasted"), 0.5 * d2),
    }


def _fe_receptance(model: TruncatedTrack, f: np.ndarray, x_load: float, points: Sequence[float]) -> np.ndarray:
    """The model's w at nodes ``points`` per unit force at the node ``x_load`` (m/N), (n_f, len(points))."""
    rhs = np.zeros((model.n_dof, 1))
    rhs[model.dof(x_load)] = 1.0
    return model.solve(f, rhs)[:, [model.dof(x) for x in points], 0]


def _point_errors(model: TruncatedTrack, f: np.ndarray, x_load: float, x_away: float) -> np.ndarray:
    """Relative error of w/F at the load and a bay away against the model's infinite track, (n_f, 2)."""
    points = [x_load, x_away]
    ref = model.infinite_track().receptance(f, x_load, points)[:, :, 0, 0]
    return np.abs(_fe_receptance(model, f, x_load, points) - ref) / np.abs(ref)


def floating_slab_table(track: Track, boundary: BroadbandBoundary, f: ArrayLike, elements_per_bay: int = 48
                        ) -> pd.DataFrame:
    """A flexible-slab track cut at a slab joint: w/F there on 10-bay models against the exact method.

    The reference is :func:`semitrack.point_receptance` (the periodic-structure method with the
    slab's exact receptance) at the joint, half a bay before a support; InfiniteTrack does not
    hold a flexible slab.

    Parameters
    ----------
    track : Track
        A flexible-slab track whose slab joint lies at a mid-span (the models' x = 0).
    boundary : BroadbandBoundary
        Its broadband end.
    f : array_like
        Frequencies (Hz).
    elements_per_bay : int
        The mesh.

    Returns
    -------
    pandas.DataFrame
        Rows by ends (broadband, pinned): the median and largest error at the joint (%).
    """
    f = np.asarray(f, dtype=float)
    exact = point_receptance(track, f, 0.0, origin="midspan")[:, 0, 0]
    rows = {}
    for ends in (BoundaryEnd.name, PINNED.name):
        model = TruncatedTrack(track, CASE_BAYS, ends, system=boundary if ends == BoundaryEnd.name else None,
                               elements_per_bay=elements_per_bay)
        e = 100 * np.abs(_fe_receptance(model, f, 0.0, [0.0])[:, 0] / exact - 1)
        rows[ends] = {"median at the joint (%)": np.median(e), "max at the joint (%)": e.max()}
    return pd.DataFrame.from_dict(rows, orient="index").rename_axis("ends")


def imperfect_receptance_table(cases: Mapping[str, tuple], boundaries: Mapping[str, BroadbandBoundary],
                               f: ArrayLike, elements_per_bay: int = 48) -> pd.DataFrame:
    """10-bay models of each case against InfiniteTrack: median and max error at the change and a bay away.

    Parameters
    ----------
    cases : mapping
        :func:`imperfect_cases`.
    boundaries : mapping of str to BroadbandBoundary
        ``{"slab": ..., "ballasted": ...}``, fitted to the cases' tracks.
    f : array_like
        Frequencies (Hz).
    elements_per_bay : int
        The mesh of every model.

    Returns
    -------
    DataFrame
        Rows (case, ends) for ends broadband, pinned and exact (the mesh alone); columns the
        median and max error (%) at the change and a bay away.
    """
    f = np.asarray(f, dtype=float)
    rows = {}
    for name, (track, keywords, which, x) in cases.items():
        d = keywords["right"].spacing if "right" in keywords else track.spacing  # the cases load right of 0
        for ends in (BoundaryEnd.name, PINNED.name, EXACT.name):
            system = tuple(boundaries[w] for w in which) if ends == BoundaryEnd.name else None
            model = TruncatedTrack(track, CASE_BAYS, ends, system=system, elements_per_bay=elements_per_bay,
                                   **keywords)
            e = 100 * _point_errors(model, f, x, x + d)
            rows[name, ends] = {"median at (%)": np.median(e[:, 0]), "max at (%)": e[:, 0].max(),
                                "median a bay away (%)": np.median(e[:, 1]), "max a bay away (%)": e[:, 1].max()}
    return pd.DataFrame.from_dict(rows, orient="index").rename_axis(["case", "ends"])


def several_wheel_table(model: TruncatedTrack, vehicles: Mapping[str, tuple[Vehicle | Sequence[Wheel], ArrayLike]],
                        roughness: Roughness, dt: float, duration: float,
                        band: tuple[float, float] = (50.0, 2500.0)) -> pd.DataFrame:
    """Stationary vehicles on a small roughness: each wheel's band levels against the several-wheel theory.

    Parameters
    ----------
    model : TruncatedTrack
        The track model (broadband ends).
    vehicles : mapping
        ``{label: (vehicle or wheels, x)}``.
    roughness : Roughness
        A small roughness (the contacts must stay linear).
    dt, duration : float
        Time step and duration (s).
    band : tuple of float
        The one-third-octave bands (Hz).

    Returns
    -------
    DataFrame
        Rows (vehicle, wheel); the largest band error (dB) and the band where it is.
    """
    runs = thread_map(lambda case: wheel_rail_response(model, case[0], roughness, x=case[1], dt=dt, duration=duration),
                      vehicles.values())
    rows = {}
    for label, res in zip(vehicles, runs):
        for i in range(len(res.wheels)):
            transfer = contact_transfer(res, band=band, wheel=i)
            j = int(np.argmax(np.abs(transfer.error_db)))
            rows[label, i] = {"largest band error (dB)": float(np.abs(transfer.error_db).max()),
                              "in the band of (Hz)": float(transfer.centres[j]), "bands": transfer.centres.size,
                              "lost contact": res.lost_contact}
    return pd.DataFrame.from_dict(rows, orient="index").rename_axis(["vehicle", "wheel"])


def fe_and_exact_runs(track: Track, boundary: BroadbandBoundary, vehicle: Vehicle, roughness: Roughness, x: float,
                      dt: float, duration: float) -> tuple[ContactResponse, ContactResponse]:
    """A vehicle standing on a small roughness by the 10-bay model with broadband ends and by the
    convolution on the exact track (:func:`semitrack.convolution_response`), the two side by side.

    Parameters
    ----------
    track : Track
        A periodic track (viscous damping).
    boundary : BroadbandBoundary
        Its broadband end.
    vehicle : Vehicle
        The vehicle (a bogie in the chapter).
    roughness : Roughness
        The roughness passing under it.
    x : float
        Where the vehicle stands (m).
    dt, duration : float
        Time step and duration (s).

    Returns
    -------
    (ContactResponse, ContactResponse)
        The truncated model's run and the convolution's.
    """
    model = TruncatedTrack(track, CASE_BAYS, BoundaryEnd.name, system=boundary)
    runs = (lambda: wheel_rail_response(model, vehicle, roughness, x=x, dt=dt, duration=duration),
            lambda: convolution_response(track, vehicle, roughness, x=x, dt=dt, duration=duration))
    fe, exact = thread_map(lambda run: run(), runs)
    return fe, exact


def reflection_free_bays(track: Track, reach: float, attenuation: float = 40.0,
                         band: tuple[float, float] = (50.0, 2500.0)) -> tuple[int, float]:
    """Bays each side of a pinned model so that a wave's round trip to its ends loses ``attenuation`` dB.

    Parameters
    ----------
    track : Track
        The track.
    reach : float
        How far from the centre the wheels go (m).
    attenuation : float
        Round-trip attenuation (dB) of the least attenuated band.
    band : tuple of float
        The bands of the decay rate (Hz).

    Returns
    -------
    bays : int
        ``ceil((reach + attenuation / (2 A_min)) / d)``.
    a_min : float
        The least attenuation of the track's free wave over the bands (dB/m,
        :attr:`semitrack.TrackDecayRate.wave_attenuation`).
    """
    a_min = _least_attenuation(track, tuple(float(b) for b in band))
    return int(np.ceil((reach + attenuation / (2 * a_min)) / track.spacing)), a_min


@functools.lru_cache(maxsize=32)
def _least_attenuation(track: Track, band: tuple[float, float]) -> float:
    """The least attenuation of ``track``'s free wave over ``band`` (dB/m), once per track and band for the process
    (every run of the chapter on a track asks for it)."""
    return float(np.min(track_decay_rate(track, band=band).wave_attenuation))


@dataclass(frozen=True, eq=False)
class WeldRun:
    """A wheel rolled over a dipped weld on one model: the run, its cost and the model's size.

    ``seconds`` is the CPU time of the run's thread (s), which a run on another core beside it does
    not inflate (:func:`weld_runs` runs them side by side); memory traffic shared with it, or a second
    hardware thread on the same core, still can, a little.
    """

    response: ContactResponse
    seconds: float
    n_dof: int


def weld_runs(track: Track, boundary: BroadbandBoundary, speeds: Sequence[float], weld: DippedWeld, wheel: Wheel,
              *, start: float = -3.0, stop: float = 2.0, dt: float = 2e-5, pinned_bays: int | None = None,
              watch: Sequence[int] = (-2, -1, 0, 1)) -> dict[tuple[float, str], WeldRun]:
    """The wheel rolled from ``start`` to ``stop`` (m) over the weld at each speed (km/h), on both models.

    Parameters
    ----------
    track : Track
        The track (viscous damping).
    boundary : BroadbandBoundary
        Its broadband end, for the 10-bay model.
    speeds : sequence of float
        Speeds (km/h).
    weld : DippedWeld
        The weld, between ``start`` and ``stop``.
    wheel : Wheel
        The wheel.
    start, stop : float
        Where the wheel starts and stops (m).
    dt : float
        Time step (s); P1 and P2 move by under 0.05 % from 20 us to 5 us (:func:`weld_convergence`, the
        chapter's table).
    pinned_bays : int, optional
        Bays each side of the pinned reference; default :func:`reflection_free_bays`.
    watch : sequence of int
        Supports whose rail-seat and ballast forces are recorded.

    Returns
    -------
    dict
        ``{(speed, "broadband ends" | "pinned, long"): WeldRun}``.
    """
    bays = pinned_bays or reflection_free_bays(track, max(abs(start), abs(stop)))[0]
    models = {"broadband ends": TruncatedTrack(track, CASE_BAYS, BoundaryEnd.name, system=boundary),
              "pinned, long": TruncatedTrack(track, bays, PINNED.name)}
    def run(key):
        kmh, name = key
        v, model = kmh / 3.6, models[name]
        t0 = time.thread_time()
        res = wheel_rail_response(model, wheel, profile=weld, x=start, speed=v, dt=dt,
                                  duration=(stop - start) / v, watch_supports=watch, bending_at=[weld.x])
        return WeldRun(res, time.thread_time() - t0, model.n_dof)

    keys = [(kmh, name) for kmh in speeds for name in models]
    return dict(zip(keys, thread_map(run, keys)))


def p1_p2(response: ContactResponse, weld: DippedWeld, f_low: float = 200.0) -> tuple[float, float]:
    """The P1 and P2 forces (N) of a wheel's passage over the weld.

    P1: the largest force within 2 ms after the wheel reaches the dip's bottom (the contact and the
    rail's local mass, ~1 kHz). P2: the largest force in the 25 ms after it, the force low-passed
    at ``f_low`` Hz (zero-phase, 4th order): the unsprung mass on the track, ~50-100 Hz.

    Parameters
    ----------
    response : ContactResponse
        A rolling run over the weld.
    weld : DippedWeld
        The weld.
    f_low : float
        The low-pass frequency (Hz) that separates P2 from P1.

    Returns
    -------
    P1, P2 : float
    """
    return _p1_p2_at(response, weld.x, f_low)


def _p1_p2_at(response: ContactResponse, x: float, f_low: float = 200.0) -> tuple[float, float]:
    """P1 and P2 (N) after the wheel passes ``x`` (m), as :func:`p1_p2` defines them."""
    t_bottom = float(np.interp(x, response.x, response.t))
    after = (response.t >= t_bottom) & (response.t <= t_bottom + 2e-3)
    sos = butter(4, f_low, fs=1.0 / response.dt, output="sos")
    low = sosfiltfilt(sos, response.force)
    later = (response.t >= t_bottom) & (response.t <= t_bottom + 25e-3)
    return float(response.force[after].max()), float(low[later].max())


def jenkins_table(track: Track, boundary: BroadbandBoundary, wheel: Wheel,
                  dips: Sequence[tuple[float, float, float]]) -> pd.DataFrame:
    """P2 from the time domain beside Jenkins' closed form, for dips rolled over on the 10-bay broadband-ended model.

    Parameters
    ----------
    track : Track
        The track.
    boundary : BroadbandBoundary
        Its broadband end.
    wheel : Wheel
        The wheel.
    dips : sequence of (float, float, float)
        ``(length (m), angle (rad), speed (km/h))`` of each dip (:class:`semitrack.DippedWeld` at x = 0).

    Returns
    -------
    pandas.DataFrame
        One row per dip: P2 of the time domain (:func:`p1_p2`) and of Jenkins' formula with the lumped track fitted
        to the exact receptance (:func:`semitrack.methods.impact.jenkins_p2`), kN, and whether contact was lost.
    """
    lumped = lumped_track(track)
    model = TruncatedTrack(track, CASE_BAYS, BoundaryEnd.name, system=boundary)
    def run(case):
        length, angle, kmh = case
        return wheel_rail_response(model, wheel, profile=DippedWeld(angle, length, 0.0), x=-2.0, speed=kmh / 3.6,
                                   dt=2e-5, duration=4.0 / (kmh / 3.6))

    rows = {}
    for (length, angle, kmh), res in zip(dips, thread_map(run, dips)):
        dip, v = DippedWeld(angle, length, 0.0), kmh / 3.6
        rows[f"{length:g} m, {1e3 * angle:g} mrad, {kmh:g} km/h"] = {
            "P2, time domain (kN)": p1_p2(res, dip)[1] / 1e3, "Jenkins (kN)": jenkins_p2(wheel, angle, v, lumped) / 1e3,
            "lost contact": res.lost_contact}
    return pd.DataFrame.from_dict(rows, orient="index").rename_axis("dip")


def slope_change(angle: float, run: float = 4.0) -> RailProfile:
    """Jenkins' own case: the rail turns upward by ``angle`` (rad) at x = 0 and climbs straight.

    It climbs for ``run`` m (long enough that P2 is over before the rail turns again) and returns
    to the undisturbed level over the next ``10 run`` m, the returns too far on to matter.

    Parameters
    ----------
    angle : float
        The change of slope 2 alpha (rad), the rail rising after it.
    run : float
        The straight climb after the change (m).

    Returns
    -------
    RailProfile
    """
    return RailProfile([-1.0, 0.0, run, 11.0 * run], [0.0, 0.0, -angle * run, 0.0])


def slope_change_table(track: Track, boundary: BroadbandBoundary, wheel: Wheel, angle: float,
                       speeds: Sequence[float], start: float = -2.0, dt: float = 2e-5) -> pd.DataFrame:
    """P1 and P2 after a single change of slope (:func:`slope_change`) beside Jenkins' P2, per speed.

    This is the case Jenkins et al.'s formula was derived for: a change of slope once, the rail
    straight after it, on the 10-bay broadband-ended model.

    Parameters
    ----------
    track : Track
        The track (viscous damping).
    boundary : BroadbandBoundary
        Its broadband end.
    wheel : Wheel
        The wheel.
    angle : float
        The change of slope (rad).
    speeds : sequence of float
        Speeds (km/h).
    start : float
        Where the wheel starts (m).
    dt : float
        Time step (s).

    Returns
    -------
    pandas.DataFrame
        One row per speed: P1 and P2 of the time domain, Jenkins' P2 (kN), their difference (%),
        and whether contact was lost.
    """
    lumped = lumped_track(track)
    model = TruncatedTrack(track, CASE_BAYS, BoundaryEnd.name, system=boundary)
    profile, rows = slope_change(angle), {}
    runs = thread_map(lambda kmh: wheel_rail_response(model, wheel, profile=profile, x=start, speed=kmh / 3.6, dt=dt,
                                                      duration=(3.0 - start) / (kmh / 3.6)), speeds)
    for kmh, res in zip(speeds, runs):
        v = kmh / 3.6
        p1, p2 = _p1_p2_at(res, 0.0)
        jenkins = jenkins_p2(wheel, angle, v, lumped)
        rows[kmh] = {"P1 (kN)": p1 / 1e3, "P2, time domain (kN)": p2 / 1e3, "Jenkins (kN)": jenkins / 1e3,
                     "Jenkins against the time domain (%)": 100 * (jenkins / p2 - 1), "lost contact": res.lost_contact}
    return pd.DataFrame.from_dict(rows, orient="index").rename_axis("speed (km/h)")


def weld_entry_table(runs: Mapping[tuple[float, str], WeldRun], weld: DippedWeld, single: pd.DataFrame,
                     model: str = "broadband ends") -> pd.DataFrame:
    """Why a dip's P1 need not grow with speed: what the entry kink did to the wheel before the bottom.

    Parameters
    ----------
    runs : mapping
        :func:`weld_runs`.
    weld : DippedWeld
        The weld.
    single : pandas.DataFrame
        :func:`slope_change_table` for the weld's angle at the same speeds: the bottom kink alone.
    model : str
        Which of the runs' models is read.

    Returns
    -------
    pandas.DataFrame
        One row per speed: the least force on the entry ramp (kN), the time without contact there
        (ms), the force as the wheel reaches the bottom (kN), the dip's P1 and the single change's.
    """
    rows = {}
    for kmh in sorted({k for k, _ in runs}):
        res = runs[kmh, model].response
        entry, bottom = weld.x - 0.5 * weld.length, weld.x
        ramp = (res.x >= entry) & (res.x <= bottom)
        rows[kmh] = {"least force on the entry ramp (kN)": res.force[ramp].min() / 1e3,
                     "without contact there (ms)": 1e3 * res.dt * np.count_nonzero(res.force[ramp] <= 0.0),
                     "force at the bottom (kN)": float(np.interp(bottom, res.x, res.force)) / 1e3,
                     "P1, the dip (kN)": _p1_p2_at(res, bottom)[0] / 1e3,
                     "P1, its bottom kink alone (kN)": single.loc[kmh, "P1 (kN)"]}
    return pd.DataFrame.from_dict(rows, orient="index").rename_axis("speed (km/h)")


def weld_table(runs: Mapping[tuple[float, str], WeldRun], weld: DippedWeld, track: Track, wheel: Wheel
               ) -> pd.DataFrame:
    """Per speed: P1, P2 and Jenkins' P2; the broadband model against the long pinned one; sizes and times.

    Parameters
    ----------
    runs : mapping
        :func:`weld_runs`.
    weld : DippedWeld
        The weld.
    track : Track
        The track (for Jenkins' lumped track at the weld).
    wheel : Wheel
        The wheel.

    Returns
    -------
    DataFrame
        One row per speed.
    """
    lumped = lumped_track(track, weld.x)
    rows = {}
    for kmh in sorted({k for k, _ in runs}):
        b, p = runs[kmh, "broadband ends"], runs[kmh, "pinned, long"]
        fb, fp = b.response.force, p.response.force
        p1, p2 = p1_p2(p.response, weld)
        forces = p.response.track_forces
        rows[kmh] = {"P1 (kN)": p1 / 1e3, "P2 (kN)": p2 / 1e3,
                     "Jenkins P2 (kN)": jenkins_p2(wheel, weld.angle, kmh / 3.6, lumped) / 1e3,
                     "peak, broadband vs pinned (% of peak)": 100 * abs(fb.max() - fp.max()) / fp.max(),
                     "history, largest difference (% of range)": 100 * np.abs(fb - fp).max() / (fp.max() - fp.min()),
                     "largest rail-seat force (kN)": forces.rail_seat.max() / 1e3,
                     "largest ballast force (kN)": (forces.ballast.max() / 1e3 if forces.ballast is not None
                                                    else np.nan),
                     "largest bending at the weld (kN m)": forces.bending.max() / 1e3,
                     "lost contact": p.response.lost_contact,
                     "DOFs broadband / pinned": f"{b.n_dof} / {p.n_dof}",
                     "CPU time broadband / pinned (s)": f"{b.seconds:.1f} / {p.seconds:.1f}"}
    return pd.DataFrame.from_dict(rows, orient="index").rename_axis("speed (km/h)")


def weld_convergence(track: Track, boundary: BroadbandBoundary, speed: float, weld: DippedWeld, wheel: Wheel,
                     dts: Sequence[float] = (2e-5, 1e-5, 5e-6), meshes: Sequence[int | None] = (None,),
                     start: float = -3.0, stop: float = 2.0) -> pd.DataFrame:
    """P1 and P2 on the 10-bay broadband-ended model as the time step halves and the mesh refines.

    Parameters
    ----------
    track : Track
        The track.
    boundary : BroadbandBoundary
        Its broadband end.
    speed : float
        km/h.
    weld : DippedWeld
        The weld.
    wheel : Wheel
        The wheel.
    dts : sequence of float
        Time steps (s).
    meshes : sequence of int or None
        Elements per bay (None: the default for 3 kHz).
    start, stop : float
        The wheel's path (m).

    Returns
    -------
    DataFrame
        Rows (elements per bay, dt in us): P1 and P2 (kN).
    """
    v = speed / 3.6
    models = [TruncatedTrack(track, CASE_BAYS, BoundaryEnd.name, system=boundary, elements_per_bay=ne) for ne in meshes]
    cases = [(model, dt) for model in models for dt in dts]
    runs = thread_map(lambda case: wheel_rail_response(case[0], wheel, profile=weld, x=start, speed=v, dt=case[1],
                                                       duration=(stop - start) / v), cases)
    rows = {}
    for (model, dt), res in zip(cases, runs):
        p1, p2 = p1_p2(res, weld)
        rows[model.elements_per_bay, dt * 1e6] = {"P1 (kN)": p1 / 1e3, "P2 (kN)": p2 / 1e3}
    return pd.DataFrame.from_dict(rows, orient="index").rename_axis(["elements per bay", "dt (us)"])


def gap_runs(track: Track, boundary: BroadbandBoundary, gaps: Sequence[float], kmh: float = 200.0,
             support: int = 0, start: float = -3.0, stop: float = 3.0, dt: float = 2e-5
             ) -> dict[float, ContactResponse]:
    """A wheel rolled over a hanging sleeper with each gap (m), on the 10-bay broadband-ended model.

    Parameters
    ----------
    track : Track
        A ballasted track (viscous damping).
    boundary : BroadbandBoundary
        Its broadband end.
    gaps : sequence of float
        The gaps (m); a gap larger than the sleeper moves is the linear ``kb = 0`` sleeper.
    kmh : float
        Speed (km/h).
    support : int
        The hanging sleeper's support.
    start, stop : float
        The wheel's path (m).
    dt : float
        Time step (s).

    Returns
    -------
    dict
        ``{gap: ContactResponse}``, each with its ``gaps`` (:class:`semitrack.fe.gaps.GapResponse`).
    """
    model = TruncatedTrack(track, CASE_BAYS, BoundaryEnd.name, system=boundary, changes={support: {"kb": 0.0}})
    v = kmh / 3.6
    runs = thread_map(lambda g: wheel_rail_response(model, Wheel(primary_stiffness=1.2e6, primary_damping=1.5e4),
                                                    x=start, speed=v, dt=dt, duration=(stop - start) / v,
                                                    ballast_gaps={support: g}), gaps)
    return dict(zip(gaps, runs))


def change_rolling_table(cases: Mapping[str, tuple], boundaries: Mapping[str, BroadbandBoundary], wheel: Wheel,
                         kmh: float = 400.0, start: float = -3.0, stop: float = 2.0, dt: float = 2e-5
                         ) -> pd.DataFrame:
    """A wheel rolled over each local change (no profile: the change of support alone) at ``kmh``.

    Each case's 10-bay broadband-ended model against a reflection-free pinned model with the same
    change (the longer of its tracks' reflection-free lengths): the largest force and its
    difference, the force history's largest difference, the largest rail-seat force.

    Parameters
    ----------
    cases : mapping
        :func:`imperfect_cases`.
    boundaries : mapping of str to BroadbandBoundary
        ``{"slab": ..., "ballasted": ...}``.
    wheel : Wheel
        The wheel.
    kmh : float
        Speed (km/h).
    start, stop : float
        The wheel's path (m), over the change at the centre.
    dt : float
        Time step (s).

    Returns
    -------
    DataFrame
        One row per case.
    """
    v, rows, pairs = kmh / 3.6, {}, {}
    for name, (track, keywords, which, _) in cases.items():
        own = [track] + ([keywords["right"]] if "right" in keywords else [])
        bays = max(reflection_free_bays(t, max(abs(start), abs(stop)))[0] for t in own)
        pairs[name] = {"short": TruncatedTrack(track, CASE_BAYS, BoundaryEnd.name,
                                               system=tuple(boundaries[w] for w in which), **keywords),
                       "long": TruncatedTrack(track, bays, PINNED.name, **keywords)}
    keys = [(name, label) for name, models in pairs.items() for label in models]
    done = dict(zip(keys, thread_map(lambda key: wheel_rail_response(
        pairs[key[0]][key[1]], wheel, x=start, speed=v, dt=dt, duration=(stop - start) / v, watch_supports=(-1, 0, 1)),
        keys)))
    for name, models in pairs.items():
        runs = {label: done[name, label] for label in models}
        fs, fl = runs["short"].force, runs["long"].force
        rows[name] = {"largest force (kN)": fl.max() / 1e3,
                      "peak, broadband vs pinned (% of peak)": 100 * abs(fs.max() - fl.max()) / fl.max(),
                      "history, largest difference (% of range)": 100 * np.abs(fs - fl).max() / (fl.max() - fl.min()),
                      "largest rail-seat force (kN)": runs["long"].track_forces.rail_seat.max() / 1e3,
                      "DOFs broadband / pinned": f"{models['short'].n_dof} / {models['long'].n_dof}"}
    return pd.DataFrame.from_dict(rows, orient="index").rename_axis("case")


def hanging_sleeper_table(track: Track, boundary: BroadbandBoundary, wheel: Wheel, speeds: Sequence[float],
                          gaps: Sequence[float], support: int = 0, start: float = -3.0, stop: float = 3.0,
                          dt: float = 2e-5, slow_dt: float = 1e-4) -> pd.DataFrame:
    """What a hanging sleeper puts on its neighbours' ballast, against the perfect track, per speed and gap.

    Parameters
    ----------
    track : Track
        A ballasted track (viscous damping).
    boundary : BroadbandBoundary
        Its broadband end.
    wheel : Wheel
        The wheel.
    speeds : sequence of float
        Speeds (km/h); below 100 km/h the run is quasi-static and steps by ``slow_dt``.
    gaps : sequence of float
        The sleeper's gaps (m); one larger than the sleeper ever moves never closes.
    support : int
        The hanging sleeper.
    start, stop : float
        The wheel's path (m).
    dt, slow_dt : float
        Time steps (s) from 100 km/h on and below.

    Returns
    -------
    pandas.DataFrame
        Indexed by (speed, gap in mm): the neighbours' largest ballast force (kN) and its increase
        over the perfect track's (%), the hanging sleeper's largest ballast force (kN) and time on
        its ballast (ms), and the perfect track's sleeper deflection (its largest ballast force
        over ``kb``, mm), the depth a gap must have to stay open.
    """
    watch = (support - 1, support, support + 1)
    perfect = TruncatedTrack(track, CASE_BAYS, BoundaryEnd.name, system=boundary)
    hanging = TruncatedTrack(track, CASE_BAYS, BoundaryEnd.name, system=boundary, changes={support: {"kb": 0.0}})
    def run(key):
        kmh, g = key
        v = kmh / 3.6
        kw = {"x": start, "speed": v, "dt": dt if kmh >= 100 else slow_dt, "duration": (stop - start) / v,
              "watch_supports": watch}
        if g is None:
            return wheel_rail_response(perfect, wheel, **kw)
        return wheel_rail_response(hanging, wheel, ballast_gaps={support: g}, **kw)

    keys = [(kmh, g) for kmh in speeds for g in (None, *gaps)]
    done = dict(zip(keys, thread_map(run, keys)))
    rows = {}
    for kmh in speeds:
        ref = done[kmh, None].track_forces.ballast
        reference = ref[:, [0, 2]].max()
        for g in gaps:
            res = done[kmh, g]
            neighbours = res.track_forces.ballast[:, [0, 2]].max()
            rows[kmh, 1e3 * g] = {"neighbours' largest ballast force (kN)": neighbours / 1e3,
                                  "increase over the perfect track (%)": 100 * (neighbours / reference - 1),
                                  "hanging sleeper's largest ballast force (kN)": res.gaps.force.max() / 1e3,
                                  "on its ballast (ms)": 1e3 * float(res.gaps.contact_time[0]),
                                  "perfect track's sleeper deflection (mm)": 1e3 * ref[:, 1].max() / track.kb}
    table = pd.DataFrame.from_dict(rows, orient="index")
    table.index = pd.MultiIndex.from_tuples(table.index, names=["speed (km/h)", "gap (mm)"])
    return table

