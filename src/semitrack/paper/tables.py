"""The book's comparison tables: the paper's values beside ours, and the errors of equivalent systems.

Each function returns a :class:`pandas.DataFrame` ready to display; the slab and ballasted
chapters and the validation chapter call the same builders, so a table is computed one way only.
Errors are relative (the complex ``|approx - reference| / |reference|``) and given in per cent.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike

from ..base.checks import as_frequencies, check_band
from ..base.paper_values import TABLE2_SLAB, TABLE5_BALLASTED
from ..equivalent.metrics import error_band_grid, error_summary
from ..equivalent.systems import EquivalentSystem
from ..methods.receptance import central_response, semi_infinite_receptance
from ..model.tracks import PARAMETER_INFO, Track, parameter_table, require_track
from .convergence import alpha_relative_error

__all__ = ["FIT_ERROR_TARGETS", "MirroredPair", "fit_error_table", "inversion_error_table", "mirrored_pair",
           "mirrored_pair_table", "parameter_comparison", "system_comparison"]

#: The two receptances an equivalent system is judged against in :func:`fit_error_table`.
FIT_ERROR_TARGETS = ("exact alpha", "paper's-method alpha")


def parameter_comparison(track: Track) -> pd.DataFrame:
    """The track's parameters beside the paper's Table 2 (slab) or Tables 2 and 5 (ballasted).

    Parameters
    ----------
    track : Track
        A slab track (compared with Table 2) or a ballasted track (Tables 2 and 5).

    Returns
    -------
    pandas.DataFrame
        :func:`semitrack.parameter_table` with two more columns: ``paper (Table 2)`` or
        ``paper (Tables 2, 5)`` (SI units) and ``deviation (%)``.
    """
    track = require_track(track)
    paper, label = (TABLE5_BALLASTED, "paper (Tables 2, 5)") if track.is_ballasted else (TABLE2_SLAB, "paper (Table 2)")
    key_of = {symbol: key for key, symbol, _, _ in PARAMETER_INFO}
    table = parameter_table(track)
    table[label] = [paper[key_of[symbol]] for symbol in table["symbol"]]
    table["deviation (%)"] = 100 * (table["value"] / table[label] - 1)
    return table


def system_comparison(paper: EquivalentSystem, ours: EquivalentSystem, paper_label: str) -> pd.DataFrame:
    """Two equivalent systems' parameters side by side (one row per parameter, one column per bar).

    Parameters
    ----------
    paper, ours : EquivalentSystem
        The paper's system (e.g. ``st.paper_table4()``) and another one of the same layout.
    paper_label : str
        Column group of the paper's system, e.g. ``"paper (Table 4)"``; the other is ``"ours"``.

    Returns
    -------
    pandas.DataFrame
        Columns ``(paper_label, "bar j")`` and ``("ours", "bar j")``; units in the row names.
    """
    return pd.concat({paper_label: paper.to_frame(), "ours": ours.to_frame()}, axis=1)


def fit_error_table(track: Track, systems: Mapping[str, EquivalentSystem], band: tuple[float, float],
                    df: float = 3.0) -> pd.DataFrame:
    """Median and maximum error of equivalent systems against the track over a band.

    Each system's receptance is compared on the grid of :func:`semitrack.error_band_grid` with
    the exact receptance and with the paper's-method (wavenumber) receptance of the track; the
    error is that of :func:`semitrack.error_summary` (elements alpha11, alpha12, alpha22).

    Parameters
    ----------
    track : Track
        The track.
    systems : mapping of str to EquivalentSystem
        The systems to judge, by label.
    band : tuple of float
        ``(f_lo, f_hi)`` (Hz), e.g. ``FIT_BANDS["slab"]``.
    df : float
        Grid step (Hz).

    Returns
    -------
    pandas.DataFrame
        Columns ``system, against, median error (%), max error (%)``; ``against`` is one of
        :data:`FIT_ERROR_TARGETS`.
    """
    grid = error_band_grid(check_band(band), df=df)
    targets = dict(zip(FIT_ERROR_TARGETS, (semi_infinite_receptance(require_track(track), grid),
                                           semi_infinite_receptance(track, grid, method="wavenumber"))))
    rows = []
    for label, system in systems.items():
        approx = system.receptance(grid)
        for against, target in targets.items():
            e = error_summary(approx, target)
            rows.append((label, against, 100 * e.median, 100 * e.max))
    return pd.DataFrame(rows, columns=["system", "against", "median error (%)", "max error (%)"])


@dataclass(frozen=True)
class MirroredPair:
    """The paper's Sec. 5.3 check of equivalent systems on one track.

    Attributes
    ----------
    f : ndarray
        Frequencies (Hz).
    w1 : ndarray
        The complete track's central receptance (m/N), exact method.
    joined : dict of str to ndarray
        Each system's vertical receptance at the junction of it and its mirror image (m/N).
    errors : dict of str to ndarray
        ``|joined - w1| / |w1|`` per system (-).
    band : tuple of float
        The band the systems were fitted over (Hz).
    """

    f: np.ndarray
    w1: np.ndarray
    joined: dict
    errors: dict
    band: tuple

    def summary(self) -> list[tuple]:
        """Rows ``(system, band text, median error (%), max error (%))`` over :attr:`band`."""
        inside = (self.f >= self.band[0]) & (self.f <= self.band[1])
        text = f"{self.band[0]:g}-{self.band[1]:g}"
        return [(label, text, 100 * np.median(e[inside]), 100 * e[inside].max()) for label, e in self.errors.items()]


def mirrored_pair(track: Track, systems: Mapping[str, EquivalentSystem], f: ArrayLike,
                  band: tuple[float, float]) -> MirroredPair:
    """Receptance at the junction of two mirrored copies of each system against the track's w1.

    Parameters
    ----------
    track : Track
        The track; its central receptance w1 (exact method) is the reference.
    systems : mapping of str to EquivalentSystem
        The systems, by label.
    f : array_like
        Frequencies (Hz), 1-D.
    band : tuple of float
        The fitted band (Hz), over which :meth:`MirroredPair.summary` takes its statistics.

    Returns
    -------
    MirroredPair
    """
    f = as_frequencies(f)
    w1 = central_response(require_track(track), f).w1
    joined = {label: system.mirrored_receptance(f)[:, 0, 0] for label, system in systems.items()}
    errors = {label: np.abs(w - w1) / np.abs(w1) for label, w in joined.items()}
    return MirroredPair(f=f, w1=w1, joined=joined, errors=errors, band=check_band(band))


def mirrored_pair_table(pairs: Mapping[str, MirroredPair]) -> pd.DataFrame:
    """The errors of :func:`mirrored_pair` for several tracks as one table.

    Parameters
    ----------
    pairs : mapping of str to MirroredPair
        The results, by track label.

    Returns
    -------
    pandas.DataFrame
        Columns ``track, system, band (Hz), median error (%), max error (%)``.
    """
    rows = [(name, *row) for name, pair in pairs.items() for row in pair.summary()]
    return pd.DataFrame(rows, columns=["track", "system", "band (Hz)", "median error (%)", "max error (%)"])


def inversion_error_table(track: Track, systems: Mapping[str, EquivalentSystem], band: tuple[float, float],
                          df: float = 3.0) -> pd.DataFrame:
    """How relative errors of alpha grow in K = alpha^-1, the quantity the mirrored pair measures.

    Parameters
    ----------
    track : Track
        The track (exact receptance as the reference).
    systems : mapping of str to EquivalentSystem
        The systems, by label.
    band : tuple of float
        ``(f_lo, f_hi)`` (Hz).
    df : float
        Grid step (Hz), as for :func:`fit_error_table`.

    Returns
    -------
    pandas.DataFrame
        One row per system: ``system``, the median of ``|a11 a22| / |det a|`` (-), and the
        median relative errors (%) of alpha (largest element, see
        :func:`semitrack.paper.convergence.alpha_relative_error`) and of K11.
    """
    grid = error_band_grid(check_band(band), df=df)
    alpha = semi_infinite_receptance(require_track(track), grid)
    amplification = np.abs(alpha[:, 0, 0] * alpha[:, 1, 1]) / np.abs(np.linalg.det(alpha))
    k11_ref = np.linalg.inv(alpha)[:, 0, 0]
    rows = []
    for label, system in systems.items():
        approx = system.receptance(grid)
        err_k11 = np.abs(np.linalg.inv(approx)[:, 0, 0] - k11_ref) / np.abs(k11_ref)
        rows.append((label, np.median(amplification), 100 * np.median(alpha_relative_error(approx, alpha)),
                     100 * np.median(err_k11)))
    return pd.DataFrame(rows, columns=["system", "median |a11 a22|/|det a|", "median error of alpha (%)",
                                       "median error of K11 (%)"])
