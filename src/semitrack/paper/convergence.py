"""Audit of the paper's numerics: error of the wavenumber method against the exact method.

The paper evaluates Eq. (12) on a truncated wavenumber grid and takes the slopes of Eq. (15)-(16)
by finite differences. This module measures, for chosen frequencies, how far the resulting
alpha is from the exact (transfer-method) alpha as the wavenumber range and the finite-difference
step are refined.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike

from ..base.checks import as_frequencies
from ..base.conventions import ELEMENTS
from ..base.paper_values import PAPER_BETA_MAX, PAPER_DX
from ..methods.receptance import CentralResponse, semi_infinite_receptance
from ..methods.wavenumber import WavenumberSettings, central_quantities
from ..model.tracks import PeriodicCell, Track, require_cell


def alpha_relative_error(alpha: ArrayLike, exact: ArrayLike) -> np.ndarray:
    """Largest element-wise relative error ``max_ij |alpha_ij - exact_ij| / |exact_ij|``.

    Both arrays have shape ``(..., 2, 2)``; the result has shape ``(...)``.
    """
    alpha, exact = np.asarray(alpha), np.asarray(exact)
    return (np.abs(alpha - exact) / np.abs(exact)).max(axis=(-2, -1))


def convergence_study(track: Track | PeriodicCell, f: ArrayLike, beta_factors=(1, 2, 5, 10, 20),
                      dxs=(PAPER_DX, 0.02, 0.01, 0.005, 0.002, 0.001), **settings) -> pd.DataFrame:
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
