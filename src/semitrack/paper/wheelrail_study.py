"""The wheel-rail chapter's studies: a wheel on the paper's tracks, linear theory and time domain.

Each function runs one of the chapter's studies and returns tables and results for its figures
(:mod:`semitrack.plotting.contact`); the chapter asserts the numbers its prose quotes. The time
domain's damping is viscous (the FE models' own), so the tracks of those studies are the paper's
with ``damping="viscous"``; the broadband boundaries are fitted to them.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
import pandas as pd

from ..base.checks import as_frequencies
from ..base.errors import InputError
from ..boundary.fitting import BroadbandBoundary
from ..fe.ends import BoundaryEnd, End, end_kinds
from ..fe.models import TruncatedTrack
from ..interaction.fe_model import wheel_rail_response
from ..interaction.response import ContactResponse
from ..interaction.transfer import ContactTransfer, contact_transfer
from ..methods.receptance import point_receptance
from ..methods.wheelrail import wheel_rail_force
from ..model.roughness import Roughness, corrugation
from ..model.tracks import Track
from ..model.wheel import Wheel

__all__ = ["linear_limits", "LinearForce", "linear_force", "StationaryRuns", "stationary_runs", "cost_table",
           "corrugation_runs", "loss_of_contact_runs", "halving_change", "rolling_runs", "rolling_lines"]


def linear_limits(track: Track, wheel: Wheel, f: Sequence[float]) -> pd.DataFrame:
    """The linear force per unit roughness against its three closed forms on ``track`` above a support.

    The series of the three receptances ``-1 / (alpha_W + 1/k_H + alpha_R)``; a rigid track (rail
    and pads 1e6 times stiffer: a mass on the contact spring); a stiff contact under an immovable
    wheel (``-1/alpha_R``).

    Parameters
    ----------
    track : Track
        The track.
    wheel : Wheel
        The wheel.
    f : sequence of float
        Frequencies (Hz), away from the contact resonance.

    Returns
    -------
    pandas.DataFrame
        ``largest relative difference`` (-) per check.
    """
    f = np.atleast_1d(as_frequencies(f))
    track.require_constant("linear_limits' rigid track (pads 1e6 times stiffer)", "give constant pads")
    alpha_r = point_receptance(track, f, 0.0, origin="support")[:, 0, 0]
    rigid = track.replace(E=track.E * 1e6, G=track.G * 1e6, kv=track.kv * 1e6, kphi=track.kphi * 1e6)
    w2k = wheel.mass * (2 * np.pi * f) ** 2
    k_h = wheel.contact_stiffness
    immovable = Wheel(mass=wheel.mass * 1e12, hertz_constant=wheel.hertz_constant * 1e12)
    def force(t: Track, w: Wheel) -> np.ndarray:  # over a support, where alpha_r is taken
        return wheel_rail_force(t, f, w, 0.0, origin="support")

    checks = {
        "series of the three receptances": (force(track, wheel),
                                            -1 / (wheel.receptance(f) + 1 / k_h + alpha_r)),
        "rigid track: mass on the contact spring": (force(rigid, wheel), w2k * k_h / (k_h - w2k)),
        "stiff contact, immovable wheel: -1/alpha_R": (force(track, immovable), -1 / alpha_r)}
    return pd.DataFrame({"largest relative difference": [np.max(np.abs(a / b - 1)) for a, b in checks.values()]},
                        index=list(checks))


@dataclass(frozen=True)
class LinearForce:
    """|F / r| of the linear theory on each track, above a support and at mid-span.

    Attributes
    ----------
    f : ndarray
        Frequencies (Hz).
    curves : dict
        ``{(track, where): |F / r| (N/m)}``, ``where`` "above a support" or "at mid-span".
    peaks : pandas.DataFrame
        Indexed by (track, where): the wheel bounce (the peak below 150 Hz) and the largest
        |F / r|, in Hz.
    """

    f: np.ndarray
    curves: dict
    peaks: pd.DataFrame


def linear_force(tracks: Mapping[str, Track], wheel: Wheel, f: Sequence[float]) -> LinearForce:
    """The linear force per unit roughness on the infinite tracks, and where it peaks.

    Parameters
    ----------
    tracks : mapping of str to Track
        The tracks by name.
    wheel : Wheel
        The wheel.
    f : sequence of float
        Frequencies (Hz).

    Returns
    -------
    LinearForce
    """
    f = np.atleast_1d(as_frequencies(f))
    curves, peaks = {}, {}
    for name, track in tracks.items():
        for x, where in ((track.spacing / 2, "above a support"), (0.0, "at mid-span")):
            force = np.abs(wheel_rail_force(track, f, wheel, x=x, origin="midspan"))
            low = f < 150.0
            curves[name, where] = force
            peaks[name, where] = {"wheel bounce (Hz)": f[low][np.argmax(force[low])],
                                  "largest |F / r| (Hz)": f[np.argmax(force)]}
    return LinearForce(f=f, curves=curves, peaks=pd.DataFrame(peaks).T)


@dataclass(frozen=True)
class StationaryRuns:
    """A stationary wheel under a roughness on truncated tracks: runs and their force per unit roughness.

    Attributes
    ----------
    runs : dict
        ``{(track, label): (model, ContactResponse)}``.
    transfers : dict
        ``{(track, label): ContactTransfer}`` over the studied bands.
    """

    runs: dict
    transfers: dict


def stationary_runs(tracks: Mapping[str, Track], boundaries: Mapping[str, BroadbandBoundary], wheel: Wheel,
                    roughness: Roughness, steps: Mapping[str, tuple[float, float]],
                    models: Sequence[tuple[str, End | str, int]], band: tuple[float, float] = (50.0, 2500.0)
                    ) -> StationaryRuns:
    """A stationary wheel on each track's truncated models under ``roughness``.

    Parameters
    ----------
    tracks : mapping of str to Track
        The (viscous) tracks by name.
    boundaries : mapping of str to BroadbandBoundary
        Each track's broadband boundary, for boundary ends.
    wheel : Wheel
        The wheel.
    roughness : Roughness
        The roughness passing under it.
    steps : mapping of str to (float, float)
        Time step and duration (s) per track.
    models : sequence of (label, end, n_bays)
        The truncated models: ``end`` a name ("boundary", "pinned"...) or an End; ``n_bays``
        bays on each side, or a mapping of track name to bays; ``label`` may hold ``{bays}``.
    band : (float, float)
        The one-third-octave bands of the transfer (Hz).

    Returns
    -------
    StationaryRuns
    """
    runs = {}
    for name, track in tracks.items():
        dt, duration = steps[name]
        for label, end, n_bays in models:
            bays = n_bays[name] if isinstance(n_bays, Mapping) else n_bays
            kind = type(end) if isinstance(end, End) else end_kinds(end)[0]
            system = boundaries[name] if kind is BoundaryEnd and not isinstance(end, End) else None
            # 12 elements per bay: the mesh whose band errors the chapter measures (beside a 48-element one)
            model = TruncatedTrack(track, bays, end, system=system, elements_per_bay=12)
            runs[name, label.format(bays=bays)] = model, wheel_rail_response(model, wheel, roughness, dt=dt,
                                                                             duration=duration)
    transfers = {key: contact_transfer(res, band=band) for key, (_, res) in runs.items()}
    return StationaryRuns(runs=runs, transfers=transfers)


def cost_table(study: StationaryRuns) -> pd.DataFrame:
    """Size, wall time and band errors of each model of :func:`stationary_runs`.

    Parameters
    ----------
    study : StationaryRuns
        The runs.

    Returns
    -------
    pandas.DataFrame
        Indexed by (track, model): length (m), DOFs + boundary states, wall time (s), us per
        step, the largest band error (dB) and its band (Hz).
    """
    rows = []
    for (name, label), (model, res) in study.runs.items():
        err = np.abs(study.transfers[name, label].error_db)
        rows.append({"track": name, "model": label, "length (m)": 2 * model.n_bays * model.track.spacing,
                     "DOFs + states": res.n_dof + sum(b.n_states for b in model.boundary_states()),
                     "wall time (s)": res.elapsed, "µs per step": 1e6 * res.elapsed / (res.t.size - 1),
                     "max band error (dB)": err.max(),
                     "worst band (Hz)": study.transfers[name, label].centres[np.argmax(err)]})
    return pd.DataFrame(rows).set_index(["track", "model"])


def corrugation_runs(model: TruncatedTrack, wheel: Wheel, speed: float, wavelength: float,
                     amplitudes: Sequence[float], dt: float = 2e-5, duration: float = 0.15, periods: int = 50
                     ) -> tuple[pd.DataFrame, dict[float, ContactResponse]]:
    """A stationary wheel under one corrugation wavelength at several amplitudes, against the linear theory.

    Parameters
    ----------
    model : TruncatedTrack
        The track model.
    wheel : Wheel
        The wheel.
    speed : float
        Speed (m/s).
    wavelength : float
        Corrugation wavelength (m).
    amplitudes : sequence of float
        Amplitudes (m).
    dt, duration : float
        Time step and simulated time (s).
    periods : int
        Corrugation periods analysed at the end of each run.

    Returns
    -------
    table : pandas.DataFrame
        Per amplitude: the line, |F/r| in time and linear, their ratio, the force swing per
        preload, how much further the peaks rise than the troughs fall, and loss of contact.
    runs : dict
        ``{amplitude: ContactResponse}``.
    """
    rows, runs = [], {}
    for amplitude in amplitudes:
        res = wheel_rail_response(model, wheel, corrugation(speed, wavelength, amplitude), dt=dt, duration=duration)
        line: ContactTransfer = contact_transfer(res, band=(speed / wavelength, speed / wavelength), periods=periods)
        after = res.force[res.t >= res.t_full]
        runs[amplitude] = res
        rows.append({"amplitude (µm)": 1e6 * amplitude, "line (Hz)": line.f[0],
                     "|F/r|, time domain (N/m)": abs(line.H[0]), "|F/r|, linear (N/m)": abs(line.linear[0]),
                     "ratio": abs(line.H[0]) / abs(line.linear[0]),
                     "force swing / preload": (after.max() - after.min()) / 2 / wheel.preload,
                     "peak rise / trough fall": (after.max() - after.mean()) / (after.mean() - after.min()),
                     "lost contact": res.lost_contact})
    return pd.DataFrame(rows), runs


def loss_of_contact_runs(model: TruncatedTrack, wheel: Wheel, roughness: Roughness, steps: Sequence[float],
                         duration: float = 0.04, ramp: float = 0.005
                         ) -> tuple[pd.DataFrame, dict[float, ContactResponse]]:
    """A large roughness that lifts the wheel off the rail, at several time steps.

    Parameters
    ----------
    model : TruncatedTrack
        The track model.
    wheel : Wheel
        The wheel.
    roughness : Roughness
        The roughness (a deep corrugation).
    steps : sequence of float
        Time steps (s), each half the one before, for the convergence.
    duration, ramp : float
        Simulated time and the roughness's fade-in (s).

    Returns
    -------
    summary : pandas.DataFrame
        Per step: the time out of contact (%), the largest force per preload and the change of
        the force when the step is halved (% of its peak; :func:`halving_change`).
    runs : dict
        ``{dt: ContactResponse}``.
    """
    runs = {dt: wheel_rail_response(model, wheel, roughness, dt=dt, duration=duration, ramp=ramp) for dt in steps}
    summary = pd.DataFrame({"time step (µs)": [1e6 * dt for dt in steps],
                            "time out of contact (%)": [100 * np.mean(~runs[dt].in_contact) for dt in steps],
                            "largest force / preload": [runs[dt].force.max() / wheel.preload for dt in steps],
                            "change when halved (%)": [100 * halving_change(runs[a], runs[b])
                                                       for a, b in zip(steps[:-1], steps[1:])] + [np.nan]})
    return summary, runs


def halving_change(coarse: ContactResponse, fine: ContactResponse) -> float:
    """``max |F_dt - F_dt/2| / max F``, on the coarser run's times (``fine`` at half its step)."""
    ratio = coarse.dt / fine.dt
    if abs(ratio - 2) > 1e-9:
        raise InputError(f"fine must have half the time step of coarse, got {fine.dt!r} s and {coarse.dt!r} s")
    sampled = fine.force[::2]
    return float(np.max(np.abs(coarse.force - sampled)) / np.max(sampled))


def rolling_runs(models: Mapping[tuple[float, int], TruncatedTrack], wheel: Wheel, x_start: float = -6.0,
                 dt: float = 2e-5) -> dict[tuple[float, int], ContactResponse]:
    """A wheel rolling along each model over a smooth rail, from ``x_start`` to ``-x_start``.

    Parameters
    ----------
    models : mapping of (km/h, elements per bay) to TruncatedTrack
        The models, by the speed to roll at and their mesh (checked against the model's own).
    wheel : Wheel
        The wheel.
    x_start : float
        Start of the roll (m, model coordinates; negative); the wheel stops at ``-x_start``.
    dt : float
        Time step (s).

    Returns
    -------
    dict
        ``{(km/h, elements per bay): ContactResponse}``.
    """
    for (kmh, n_el), model in models.items():
        if n_el != model.elements_per_bay:  # rolling_lines reads the mesh's line v/h from the key
            raise InputError(f"models key ({kmh!r}, {n_el!r}) names {n_el} elements per bay, but the model has "
                             f"{model.elements_per_bay}")
    return {(kmh, n_el): wheel_rail_response(model, wheel, speed=kmh / 3.6, x=x_start, dt=dt,
                                             duration=-2 * x_start / (kmh / 3.6))
            for (kmh, n_el), model in models.items()}


def rolling_lines(runs: Mapping[tuple[float, int], ContactResponse], after: float = 0.02) -> pd.DataFrame:
    """The support-passing line ``v/d`` and the mesh's line ``v/h`` in each rolling run's force.

    Parameters
    ----------
    runs : mapping
        The runs of :func:`rolling_runs`.
    after : float
        Start of the analysed record (s), past the start's bounce.

    Returns
    -------
    pandas.DataFrame
        Per run: speed, mesh, both lines' frequencies and amplitudes (the largest within two bins),
        the largest line above 100 Hz and the bin width.
    """
    rows = []
    for (kmh, n_el), res in runs.items():
        f_line, amp = res.force_spectrum(after=after)

        def line_at(f0, f_line=f_line, amp=amp):
            return amp[np.abs(f_line - f0) <= 2 * f_line[1]].max()

        d = res.track.spacing
        v_d, v_h = res.speed / d, res.speed * n_el / d
        above = f_line > 100.0
        rows.append({"speed (km/h)": kmh, "elements per bay": n_el, "v/d (Hz)": v_d, "line at v/d (N)": line_at(v_d),
                     "v/h (Hz)": v_h, "line at v/h (N)": line_at(v_h),
                     "largest line above 100 Hz (Hz)": f_line[above][np.argmax(amp[above])], "bin (Hz)": f_line[1]})
    return pd.DataFrame(rows)
