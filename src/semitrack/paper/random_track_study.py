"""Monte Carlo of random ballasted tracks under a bogie: the force distributions against the share of hanging sleepers.

One case is one realisation (:func:`bogie_over_random_track`): a stretch of ballasted track whose
pads and ballast scatter log-normal about the paper's values and a share of whose sleepers hang
over gaps (:func:`semitrack.random_track`), rolled over by a bogie on a
:class:`semitrack.WindowTrack` (the rest of the infinite track nominal). It returns the peak and
least wheel-rail forces and the peak rail-seat and sleeper-ballast forces over the watched
supports, which both wheels cross at full speed. :func:`monte_carlo_cases` lists the cases of a
study, every realisation its own seed ``(seed, fraction index, realisation)``, so that any row can be
recomputed alone. The cases run through :func:`semitrack.run_study`, serially or on a dask cluster.
"""

from __future__ import annotations

import math
from functools import cache

import numpy as np
import pandas as pd

from ..boundary.fitting import BroadbandBoundary, fit_boundary
from ..fe.window import WindowTrack
from ..interaction.fe_model import wheel_rail_response
from ..model.random_track import RandomTrack, random_track
from ..model.tracks import Track, ballasted_track
from ..model.vehicle import Bogie
from ..studies.statistics import percentile_table

__all__ = ["DRAWN", "WATCHED", "bogie_over_random_track", "monte_carlo_cases", "study_track",
           "drawn_statistics", "FORCES", "force_percentiles"]

#: The supports drawn at random (the rest of the infinite track is nominal): the bogie's path with margins.
DRAWN = (-10, 18)
#: The supports whose forces are read: crossed by both wheels of a bogie that starts with its
#: leading wheel at x = 0 and runs 8.3 m (200 km/h for 0.15 s; the trailing wheel 2.5 m behind).
WATCHED = (0, 8)
#: The study's coefficients of variation (-): pads 0.25 and ballast 0.4, log-normal with the track's means.
STUDY_COV = {"kv": 0.25, "kb": 0.4}
#: The range of the gaps under a hanging sleeper (m).
STUDY_GAP = (0.5e-3, 2e-3)


@cache
def study_track() -> tuple[Track, BroadbandBoundary]:
    """The paper's ballasted track with viscous damping and its broadband boundary (fitted once per process)."""
    track = ballasted_track(damping="viscous")
    return track, fit_boundary(track)


def bogie_over_random_track(void_fraction: float, realisation: int, *, seed: int = 2026, fraction_index: int = 0,
                            speed: float = 200 / 3.6, duration: float = 0.15, dt: float = 1e-4,
                            elements_per_bay: int = 6, system: BroadbandBoundary | None = None,
                            behind: int | None = None, ahead: int | None = None) -> dict:
    """One realisation: a bogie over a random ballasted track with a share of hanging sleepers.

    Parameters
    ----------
    void_fraction : float
        The share of the drawn supports whose sleeper hangs over a gap (:data:`STUDY_GAP`).
    realisation : int
        The realisation's number (part of its seed).
    seed : int
        The study's seed; the realisation's is ``(seed, fraction_index, realisation)``.
    fraction_index : int
        The void fraction's place in the study (part of the seed, so that each fraction draws anew).
    speed : float
        The bogie's speed (m/s).
    duration : float
        The run (s); the leading wheel starts at x = 0.
    dt : float
        Time step (s).
    elements_per_bay : int
        The window's mesh.
    system : BroadbandBoundary, optional
        The track's broadband boundary (default fitted once per process, 1.8 s: a study on a
        cluster passes it, ``functools.partial(bogie_over_random_track, system=...)``, so that no
        worker fits it again).
    behind, ahead : int, optional
        The window's lengths (bays); default from the track's least decay rate (0.5 s once per
        process), which a study may compute once and pass as it passes ``system``.

    Returns
    -------
    dict
        ``peak_contact_force``, ``least_contact_force`` (N, over both wheels and the run),
        ``peak_rail_seat_force``, ``peak_ballast_force`` (N, over the watched supports, the hanging
        sleepers' contact with the ballast included), ``voided_watched`` (hanging sleepers among the
        watched supports) and ``lost_contact`` (whether a wheel left the rail).
    """
    if system is None:
        track, system = study_track()
    else:  # checked against the track by the window
        track = ballasted_track(damping="viscous")
    drawn = random_track(track, *DRAWN, cov=STUDY_COV, voids=dict(fraction=void_fraction, gap=STUDY_GAP),
                         seed=(seed, fraction_index, realisation))
    window = WindowTrack(track, drawn.changes, elements_per_bay=elements_per_bay, system=system, behind=behind,
                         ahead=ahead)
    watched = list(range(WATCHED[0], WATCHED[1] + 1))
    run = wheel_rail_response(window, Bogie(), speed=speed, dt=dt, duration=duration, x=0.0,
                              ballast_gaps=drawn.ballast_gaps or None, watch_supports=watched)
    forces = run.track_forces
    ballast = forces.ballast[:, np.isin(forces.supports, drawn.voided, invert=True)]
    peak_ballast = np.nanmax(ballast) if ballast.size else 0.0
    if run.gaps is not None:
        in_watch = np.isin(run.gaps.supports, watched)
        if in_watch.any():
            peak_ballast = max(peak_ballast, float(np.nanmax(run.gaps.force[:, in_watch])))
    return {"peak_contact_force": float(run.force.max()), "least_contact_force": float(run.force.min()),
            "peak_rail_seat_force": float(np.nanmax(forces.rail_seat)), "peak_ballast_force": float(peak_ballast),
            "voided_watched": int(np.isin(drawn.voided, watched).sum()), "lost_contact": bool(run.lost_contact)}


#: The forces of a case, as the chapter names them.
FORCES = {"peak_ballast_force": "sleeper-ballast", "peak_rail_seat_force": "rail seat",
          "peak_contact_force": "wheel-rail"}


def force_percentiles(table: pd.DataFrame, q=(50.0, 95.0), confidence: float = 0.9) -> pd.DataFrame:
    """The percentiles of each force of a study per void fraction, as ``"value (low-high)"`` in kN.

    Parameters
    ----------
    table : pandas.DataFrame
        The study's table (:func:`semitrack.run_study` of :func:`bogie_over_random_track`).
    q : sequence of float
        Percentiles.
    confidence : float
        Level of the bootstrap intervals.

    Returns
    -------
    pandas.DataFrame
        One row per force and percentile, one column per void fraction; each cell the percentile
        and its interval, joined by non-breaking spaces so that a narrow page does not split them.
    """
    rows = []
    for name, label in FORCES.items():
        stats = percentile_table(table, name, "void_fraction", q, confidence=confidence)
        for level, part in stats.groupby("q", sort=True):
            row = {"force": label, "percentile": f"{level:g}th"}
            for v, value, lo, hi in zip(part.void_fraction, part.value, part.low, part.high):
                row[f"{100 * v:g} % hanging"] = f"{value / 1e3:.1f}\u00a0({lo / 1e3:.1f}\u2013{hi / 1e3:.1f})"
            rows.append(row)
    return pd.DataFrame(rows)


def monte_carlo_cases(fractions, realisations: int, seed: int = 2026, **run) -> list[dict]:
    """The cases of a study: every void fraction, ``realisations`` times, each with its own seed.

    Parameters
    ----------
    fractions : sequence of float
        The void fractions.
    realisations : int
        Realisations per fraction.
    seed : int
        The study's seed.
    **run
        Further arguments of :func:`bogie_over_random_track` (the same for every case).

    Returns
    -------
    list of dict
        For :func:`semitrack.run_study` with :func:`bogie_over_random_track`.
    """
    return [{"void_fraction": float(v), "realisation": r, "seed": seed, "fraction_index": j, **run}
            for j, v in enumerate(fractions) for r in range(realisations)]


def drawn_statistics(drawn: RandomTrack, cov: dict, correlation_length: float | None) -> pd.DataFrame:
    """What a realisation's fields hold beside what was asked, with the sampling errors to judge them.

    The mean over the nominal value, the coefficient of variation and the correlation length of the
    logs fitted from neighbours (``-d / ln rho_1``), each with its standard error for a sample of
    this many supports correlated as asked (the effective number of independent supports of a
    Gauss-Markov sequence, ``n (1 - rho) / (1 + rho)``; a log-normal's kurtosis for the CoV).

    Parameters
    ----------
    drawn : RandomTrack
        A long realisation (thousands of supports, for small sampling errors).
    cov : dict
        The coefficients of variation asked.
    correlation_length : float or None
        The correlation length asked (m).

    Returns
    -------
    pandas.DataFrame
        One row per field.
    """
    d = drawn.track.spacing
    rows = []
    for name, values in drawn.values.items():
        ratio = values / getattr(drawn.track, name)
        z = np.log(ratio)
        rho = float(np.corrcoef(z[:-1], z[1:])[0, 1])
        asked = math.exp(-d / correlation_length) if correlation_length else 0.0
        n_eff = values.size * (1 - asked) / (1 + asked)
        s2 = math.log1p(cov[name] ** 2)
        kurtosis = math.exp(4 * s2) + 2 * math.exp(3 * s2) + 3 * math.exp(2 * s2) - 6
        row = {"field": name, "supports": values.size, "mean / nominal": float(ratio.mean()),
               "s.e. of the mean": cov[name] / math.sqrt(n_eff), "cov asked": cov[name],
               "cov drawn": float(ratio.std() / ratio.mean()),
               "s.e. of the cov": cov[name] * math.sqrt((kurtosis + 2) / (4 * n_eff))}
        if correlation_length:
            # the lag-1 correlation's standard error, sqrt((1 - rho^2) / n), carried through -d / ln(rho)
            se_rho = math.sqrt((1 - asked**2) / values.size)
            row.update({"correlation length asked (m)": correlation_length,
                        "correlation length drawn (m)": -d / math.log(rho) if 0 < rho < 1 else 0.0,
                        "s.e. of the length (m)": d * se_rho / (asked * math.log(asked) ** 2)})
        rows.append(row)
    return pd.DataFrame(rows)

