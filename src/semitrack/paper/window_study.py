"""The travelling window against the model that holds the whole path: random tracks, accuracy and cost.

A random track (:func:`random_supports`: every support's pad and ballast stiffness drawn
log-normal about the track's, a failed fastener) is run by a vehicle two ways, with the same
mesh, step, start and roughness (:func:`window_against_path`): on a
:class:`semitrack.WindowTrack`, and on a :class:`semitrack.TruncatedTrack` with broadband ends
that holds the path with :data:`MARGIN_BAYS` to spare at each end. The forces are compared by
:func:`semitrack.paper.moving_study.force_agreement` (rms of the difference over the force's
fluctuation, one-third-octave bands 50 Hz - 2.5 kHz); the wall times are taken side by side in
one process, the compiled loop warmed up first.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass

import numpy as np
import pandas as pd

from ..boundary.fitting import BroadbandBoundary
from ..fe.ends import BoundaryEnd
from ..fe.models import TruncatedTrack
from ..fe.window import WindowTrack, least_decay_rate
from ..interaction.fe_model import wheel_rail_response
from ..interaction.response import ContactResponse
from ..model.irregularity import Irregularity
from ..model.random_track import lognormal_factors
from ..model.roughness import Roughness
from ..model.tracks import Track
from ..model.vehicle import as_vehicle
from .moving_study import MARGIN_BAYS, force_agreement

__all__ = ["random_supports", "WindowRun", "window_against_path", "path_model_bays", "agreement_table", "lengths_table",
           "least_decay_rate"]


def random_supports(track: Track, supports: range, *, cov_pad: float = 0.2, cov_ballast: float = 0.3,
                    seed: int = 0, failed: tuple[int, ...] = ()) -> dict[int, dict | None]:
    """Every support of ``supports`` with its own pad (and ballast) stiffness, as a built track has.

    The window chapter's draw order (pads, then ballast, from one stream; the values numpy's own
    log-normal of that stream to an ulp or two); a study draws with :func:`semitrack.random_track`
    (a stream per field, correlation lengths, hanging sleepers, a share of failed fasteners).

    Parameters
    ----------
    track : Track
        The nominal track.
    supports : range
        The supports k that vary.
    cov_pad, cov_ballast : float
        Coefficients of variation of the log-normal factors on ``kv`` and on ``kb`` (ballasted).
    seed : int
        Seed of :func:`numpy.random.default_rng`.
    failed : tuple of int
        Supports whose fastener has failed (no pad: ``{k: None}``).

    Returns
    -------
    dict
        ``changes`` for :class:`semitrack.WindowTrack` and :class:`semitrack.TruncatedTrack`.
    """
    rng = np.random.default_rng(seed)
    pad = track.kv * lognormal_factors(rng, cov_pad, len(supports))
    ballast = track.kb * lognormal_factors(rng, cov_ballast, len(supports)) if track.is_ballasted else None
    changes: dict[int, dict | None] = {}
    for i, k in enumerate(supports):
        changes[k] = {"kv": float(pad[i])} | ({} if ballast is None else {"kb": float(ballast[i])})
    changes.update(dict.fromkeys(failed))
    return changes


@dataclass(frozen=True, eq=False)
class WindowRun:
    """One vehicle over one track by the window and by the model that holds the path.

    Attributes
    ----------
    window, path : ContactResponse
        The two runs (``path`` None when not run).
    window_time, path_time : float
        Their wall times (s), set-up included.
    window_dofs, path_dofs : int
        The DOFs each steps.
    agreement : list of dict
        Per wheel, :func:`~semitrack.paper.moving_study.force_agreement` of the window against the path.
    behind, ahead : int
        The window's lengths (bays).
    """

    window: ContactResponse
    path: ContactResponse | None
    window_time: float
    path_time: float
    window_dofs: int
    path_dofs: int
    agreement: list
    behind: int = 0
    ahead: int = 0


def _timed(track, vehicle, roughness, **run) -> tuple[ContactResponse, float]:
    start = time.perf_counter()
    res = wheel_rail_response(track, vehicle, roughness, **run)
    return res, time.perf_counter() - start


def window_against_path(track: Track, changes: Mapping, boundary: BroadbandBoundary, vehicle,
                        roughness: Roughness | None, *, speed: float | Callable[[float], float], dt: float,
                        duration: float, behind: int | None = None, ahead: int | None = None,
                        elements_per_bay: int | None = None, ballast_gaps: Mapping[int, float] | None = None,
                        profile: Irregularity | None = None, x: float | None = None, after: float = 0.05,
                        path: bool = True) -> WindowRun:
    """A vehicle over a track with changes, on the window and on the model that holds the path.

    Parameters
    ----------
    track : Track
        The nominal track (viscous damping).
    changes : mapping
        Its changes (:func:`random_supports`), covering the path and its margins.
    boundary : BroadbandBoundary
        The track's broadband end, for both models.
    vehicle : Vehicle or Wheel
        The vehicle.
    roughness : Roughness or None
        The roughness at ``speed`` (None with a varying speed: give ``profile``).
    speed : float or callable
        Speed (m/s), or ``speed(t)``.
    dt, duration : float
        Time step and run length (s).
    behind, ahead : int, optional
        The window's lengths (default: :class:`semitrack.WindowTrack`'s).
    elements_per_bay : int, optional
        The mesh of both models (default: the one for 3 kHz).
    ballast_gaps : mapping, optional
        Hanging sleepers, ``{k: gap}`` (their supports held with ``kb = 0`` in ``changes``).
    profile : Irregularity, optional
        A profile fixed on the rail (:meth:`semitrack.Roughness.along_rail`).
    x : float, optional
        The first wheel's start (m); default the path centred on x = 0.
    after : float
        Start of the compared record (s).
    path : bool
        Run the model that holds the path too (False: the window only).

    Returns
    -------
    WindowRun
    """
    vehicle = as_vehicle(vehicle)
    window = WindowTrack(track, changes, behind=behind, ahead=ahead, elements_per_bay=elements_per_bay,
                         system=boundary)
    top = max(speed(t) for t in np.linspace(0.0, duration, 101)) if callable(speed) else speed
    length = top * duration
    x0 = -0.5 * length if x is None else x
    run = dict(x=x0, speed=speed, dt=dt, duration=duration, ballast_gaps=ballast_gaps, profile=profile)
    res_w, t_w = _timed(window, vehicle, roughness, **run)
    if not path:
        return WindowRun(res_w, None, t_w, math.nan, res_w.n_dof, 0, [], window.behind, window.ahead)
    start = vehicle.positions(x0, "x")
    bays = path_model_bays(track, start, length)
    inside = {k: v for k, v in (changes or {}).items() if -bays <= k < bays}  # the path model's own supports
    model = TruncatedTrack(track, bays, BoundaryEnd.name, system=boundary, changes=inside,
                           elements_per_bay=window.elements_per_bay)
    res_p, t_p = _timed(model, vehicle, roughness, **run)
    agreement = [force_agreement(res_w, res_p, wheel=i, after=after) for i in range(len(vehicle.wheels))]
    return WindowRun(res_w, res_p, t_w, t_p, res_w.n_dof, res_p.n_dof, agreement, window.behind, window.ahead)


def path_model_bays(track: Track, start: np.ndarray, length: float) -> int:
    """The bays each side of the truncated model that holds a path: wheels from ``start`` (m) run ``length`` (m).

    The model is centred on x = 0 and keeps :data:`~semitrack.paper.moving_study.MARGIN_BAYS`
    beyond the farthest position of any wheel.

    Parameters
    ----------
    track : Track
        The track.
    start : ndarray
        Every wheel's start (m).
    length : float
        The distance run (m).

    Returns
    -------
    int
    """
    start = np.asarray(start, dtype=float)
    reach = float(max(np.max(np.abs(start)), np.max(np.abs(start + length))))
    return math.ceil(reach / track.spacing) + MARGIN_BAYS


def agreement_table(runs: Mapping[str, WindowRun]) -> pd.DataFrame:
    """Each case's agreement and cost, a row per wheel.

    Parameters
    ----------
    runs : mapping of str to WindowRun
        The cases by label.

    Returns
    -------
    DataFrame
        rms difference (% of the force's fluctuation), worst band difference (dB), worst band
        level of the difference under the force (dB), the two models' DOFs and wall times (s).
    """
    rows = []
    for label, run in runs.items():
        for i, a in enumerate(run.agreement):
            rows.append({"case": label, "wheel": i + 1, "rms (%)": 100 * a["rms"],
                         "worst band (dB)": a["worst_level_difference"], "error level (dB)": a["worst_error_level"],
                         "window DOFs": run.window_dofs, "path DOFs": run.path_dofs,
                         "window (s)": run.window_time, "path model (s)": run.path_time})
    return pd.DataFrame(rows).set_index(["case", "wheel"])


def lengths_table(track: Track, changes: Mapping, boundary: BroadbandBoundary, vehicle, roughness: Roughness, *,
                  lengths: Sequence[int | None], speed: float, dt: float, duration: float,
                  elements_per_bay: int | None = None, after: float = 0.05) -> pd.DataFrame:
    """The window's error as its lengths grow (``behind = ahead``; None: the default), against one path run.

    Parameters
    ----------
    track, changes, boundary, vehicle, roughness, speed, dt, duration, elements_per_bay, after
        As :func:`window_against_path`.
    lengths : sequence of int or None
        Bays behind and ahead of each window.

    Returns
    -------
    DataFrame
        Per length: the bays, each wheel's rms difference (%), the worst band difference (dB),
        the window's DOFs and wall time (s).
    """
    vehicle = as_vehicle(vehicle)
    first = window_against_path(track, changes, boundary, vehicle, roughness, speed=speed, dt=dt, duration=duration,
                                elements_per_bay=elements_per_bay, after=after)  # the default, and the path run
    rows = []
    for bays in lengths:
        run = first if bays is None else window_against_path(
            track, changes, boundary, vehicle, roughness, speed=speed, dt=dt, duration=duration, behind=bays,
            ahead=bays, elements_per_bay=elements_per_bay, after=after, path=False)
        agreement = first.agreement if bays is None else [
            force_agreement(run.window, first.path, wheel=i, after=after) for i in range(len(vehicle.wheels))]
        row = {"bays behind = ahead": f"{first.ahead} (default)" if bays is None else str(bays)}
        row.update({f"rms, {name} (%)": 100 * a["rms"] for name, a in zip(vehicle.wheel_names, agreement)})
        row.update({"worst band (dB)": max(a["worst_level_difference"] for a in agreement),
                    "window DOFs": run.window_dofs, "window (s)": run.window_time})
        rows.append(row)
    return pd.DataFrame(rows).set_index("bays behind = ahead")
