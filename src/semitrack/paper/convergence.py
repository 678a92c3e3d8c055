"""Audit of the paper's numerics: error of the wavenumber method against the exact method.

The paper evaluates Eq. (12) on a truncated wavenumber grid and takes the slopes of Eq. (15)-(16)
by finite differences. This module measures, for chosen frequencies, how far the resulting
alpha is from the exact (transfer-method) alpha as the wavenumber range and the finite-difference
step are refined (:func:`convergence_study`, :func:`element_errors` and the tables built from
them), and how the exact method itself tends to the closed form of a continuous foundation
(:func:`continuous_limit_study`).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike

from ..base.checks import as_frequencies
from ..base.conventions import ELEMENTS
from ..base.paper_values import PAPER_BETA_MAX, PAPER_DX
from ..methods.continuous import continuous_foundation_receptance
from ..methods.receptance import CentralResponse, point_receptance, semi_infinite_receptance
from ..methods.wavenumber import WavenumberSettings, central_quantities
from ..model.tracks import PeriodicCell, Track, require_cell, require_track


def alpha_relative_error(alpha: ArrayLike, exact: ArrayLike) -> np.ndarray:
    """Largest element-wise relative error ``max_ij |alpha_ij - exact_ij| / |exact_ij|``.

    Both arrays have shape ``(..., 2, 2)``; the result has shape ``(...)``.
    """
    alpha, exact = np.asarray(alpha), np.asarray(exact)
    return (np.abs(alpha - exact) / np.abs(exact)).max(axis=(-2, -1))


def convergence_study(track: Track | PeriodicCell, f: ArrayLike, beta_factors: Sequence[float] = (1, 2, 5, 10, 20),
                      dxs: Sequence[float] = (PAPER_DX, 0.02, 0.01, 0.005, 0.002, 0.001), **settings) -> pd.DataFrame:
    """Error of the wavenumber alpha against the exact alpha over a grid of settings.

    Parameters
    ----------
    track : Track or PeriodicCell
        The track.
    f : array_like
        Frequencies (Hz).
    beta_factors : sequence of float
        Wavenumber ranges as multiples of the paper's beta_max = 78.5 rad/m.
    dxs : sequence of float
        Finite-difference steps (m), the paper's 0.04 m first; all are taken from one field
        evaluation per range.
    **settings
        Other :class:`WavenumberSettings` fields (``dbeta``, ``j_max``), the paper's by default.

    Returns
    -------
    pandas.DataFrame
        Columns ``f (Hz), beta_max (rad/m), beta factor, dx (m), error`` with the error as in
        :func:`alpha_relative_error`.
    """
    f = np.atleast_1d(as_frequencies(f))
    cell = require_cell(track)
    exact = semi_infinite_receptance(cell, f)
    dxs = np.asarray(dxs, dtype=float)
    rows = []
    for factor in beta_factors:
        ws = WavenumberSettings(beta_max=factor * PAPER_BETA_MAX, **settings)
        w1, psi2, q2, m1 = central_quantities(cell, 2 * np.pi * f, ws, dxs=dxs)
        for k, dx in enumerate(dxs):
            r = CentralResponse(f=f, w1=w1[:, k], psi2=psi2[:, k], Q2=q2[:, k], M1=m1[:, k], method="wavenumber")
            err = alpha_relative_error(r.alpha, exact)
            for fi, e in zip(f, err):
                rows.append((fi, ws.beta_max, factor, dx, e))
    return pd.DataFrame(rows, columns=["f (Hz)", "beta_max (rad/m)", "beta factor", "dx (m)", "error"])


def element_errors(track: Track | PeriodicCell, f: ArrayLike, method_settings: dict | None = None) -> pd.DataFrame:
    """Relative error of each element of the wavenumber alpha (paper settings by default).

    Parameters
    ----------
    track : Track or PeriodicCell
        The track.
    f : array_like
        Frequencies (Hz).
    method_settings : dict, optional
        Wavenumber settings (``beta_max``, ``dbeta``, ``j_max``, ``dx``); the paper's by default.

    Returns
    -------
    pandas.DataFrame
        One row per frequency: ``f (Hz)`` and the relative error (-) of each element of
        :data:`semitrack.base.conventions.ELEMENTS`.
    """
    f = np.atleast_1d(as_frequencies(f))
    exact = semi_infinite_receptance(track, f)
    approx = semi_infinite_receptance(track, f, method="wavenumber", **(method_settings or {}))
    rel = np.abs(approx - exact) / np.abs(exact)
    return pd.DataFrame({"f (Hz)": f} | {name: rel[:, i, k] for name, (i, k) in ELEMENTS.items()})


def element_error_table(tracks: Sequence[Track], f: ArrayLike) -> pd.DataFrame:
    """:func:`element_errors` at the paper's settings for several tracks, in per cent.

    Parameters
    ----------
    tracks : sequence of Track
        The tracks; their ``name`` labels the rows.
    f : array_like
        Frequencies (Hz).

    Returns
    -------
    pandas.DataFrame
        Indexed by ``(track, f (Hz))``; one column ``"<element> error (%)"`` per element.
    """
    table = pd.concat({t.name: element_errors(t, f).set_index("f (Hz)") for t in tracks}, names=["track", "f (Hz)"])
    return (100 * table).rename(columns=lambda name: f"{name} error (%)")


def settings_gain_table(studies: dict[str, pd.DataFrame], refined_factor: float = 10,
                        refined_dx: float = 0.002) -> pd.DataFrame:
    """Error at the paper's settings and at a refined setting, from :func:`convergence_study` results.

    Parameters
    ----------
    studies : dict of str to pandas.DataFrame
        :func:`convergence_study` tables by track name; each must hold the paper's setting
        (beta factor 1, dx = 0.04 m) and the refined one.
    refined_factor : float
        The refined wavenumber range, as a multiple of the paper's (-).
    refined_dx : float
        The refined finite-difference step (m).

    Returns
    -------
    pandas.DataFrame
        Columns ``track, f (Hz)``, the two errors (%) and their ratio ``improvement (x)``.
    """
    refined = f"{refined_factor:g}x range, dx = {1000 * refined_dx:g} mm (%)"
    rows = []
    for name, study in studies.items():
        for f_hz, s in study.groupby("f (Hz)", sort=False):
            paper = _error_at(s, 1, PAPER_DX)
            better = _error_at(s, refined_factor, refined_dx)
            rows.append((name, f_hz, 100 * paper, 100 * better, paper / better))
    return pd.DataFrame(rows, columns=["track", "f (Hz)", "paper's settings (%)", refined, "improvement (x)"])


def _error_at(study: pd.DataFrame, factor: float, dx: float) -> float:
    """The one error of a convergence study at a beta factor and a step."""
    return study[(study["beta factor"] == factor) & np.isclose(study["dx (m)"], dx)]["error"].item()


def continuous_limit_study(track: Track, f: ArrayLike, refinements: Sequence[int] = (1, 2, 4, 8, 16, 32, 64)
                           ) -> pd.DataFrame:
    """The exact method's approach to a beam on a continuous foundation as the spacing shrinks.

    The spacing d becomes d/n with kv/n and kphi/n, so the foundation stiffness per length
    stays that of ``track``; the mid-span point receptance H11 is compared with
    :func:`semitrack.continuous_foundation_receptance`.

    Parameters
    ----------
    track : Track
        The track (its pads are the foundation; a sleeper and ballast are ignored).
    f : array_like
        Frequencies (Hz), 1-D.
    refinements : sequence of int
        The values of n.

    Returns
    -------
    pandas.DataFrame
        Column ``spacing (m)`` and one column ``"<f> Hz"`` per frequency with the relative
        error of H11 (-).
    """
    track = require_track(track)
    f = np.atleast_1d(as_frequencies(f))
    kv, kphi = track.pad_stiffness()
    reference = continuous_foundation_receptance(track, f, kv / track.spacing, kphi / track.spacing)
    rows = []
    for n in refinements:
        dense = track.replace(spacing=track.spacing / n, kv=track.kv / n, kphi=track.kphi / n,
                              sleeper_mass=None, kb=None)
        h = point_receptance(dense, f, x=0.0, origin="midspan")
        rows.append([dense.spacing, *np.abs(h[:, 0, 0] / reference[:, 0, 0] - 1)])
    return pd.DataFrame(rows, columns=["spacing (m)"] + [f"{fi:g} Hz" for fi in f])
