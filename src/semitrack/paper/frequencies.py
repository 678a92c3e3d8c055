"""The paper's reported characteristic frequencies, and tables that put ours beside them.

Each entry names the curve and the kind of extremum in which the paper reports the frequency:
Table 3 (slab) and Table 6 (ballasted) for the complete track, and the statements of Sec. 4.2-4.3
and 5.1-5.2 about det(alpha^-1) and the semi-infinite receptances. The paper read its values off
a 6 Hz grid (3, 9, ..., 2997 Hz). Some values are points of that grid (183, 117 Hz), so they carry
its quantisation of up to +-3 Hz; others are not (940, 980 Hz) and were read off the curves.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ..base.checks import check_flag, check_in_range, check_positive
from ..base.errors import InputError
from ..base.paper_values import PAPER_GRID, TABLE3_SLAB_FREQUENCIES, TABLE6_BALLASTED_FREQUENCIES
from ..methods.features import characteristic_frequencies, curves_of, find_extrema
from ..methods.receptance import CentralResponse, central_response
from ..model.tracks import Track, require_track

__all__ = ["BALLASTED_FREQUENCIES", "PAPER_GRID", "SLAB_FREQUENCIES", "paper_frequencies", "paper_frequency_table"]

#: (paper frequency in Hz, quantity, kind, where the paper states it, mode / remark), from
#: :mod:`semitrack.base.paper_values`.
SLAB_FREQUENCIES = TABLE3_SLAB_FREQUENCIES
BALLASTED_FREQUENCIES = TABLE6_BALLASTED_FREQUENCIES


def paper_frequencies(track: Track) -> tuple:
    """The paper's entries for a track: slab for a rigid foundation, ballasted otherwise."""
    return BALLASTED_FREQUENCIES if track.is_ballasted else SLAB_FREQUENCIES


def nearest_extremum(extrema: pd.DataFrame, quantity: str, kind: str, f_paper: float, rel_window: float) -> float:
    """The frequency of the extremum nearest to one the paper reports, or NaN if none is close.

    Parameters
    ----------
    extrema : pandas.DataFrame
        Peaks and dips as :func:`semitrack.characteristic_frequencies` returns them (columns
        ``quantity``, ``kind``, ``f`` in Hz).
    quantity, kind : str
        The curve (e.g. ``"w1"``) and the kind of extremum (``"peak"`` or ``"dip"``).
    f_paper : float
        The paper's frequency (Hz).
    rel_window : float
        Largest accepted distance, relative to ``f_paper`` (-).

    Returns
    -------
    float
        The nearest extremum's frequency (Hz) of that curve and kind, NaN when none lies within
        ``rel_window * f_paper``.
    """
    cand = extrema[(extrema["quantity"] == quantity) & (extrema["kind"] == kind)]
    if cand.empty:
        return np.nan
    f = cand["f"].to_numpy()
    best = f[np.argmin(np.abs(f - f_paper))]
    return float(best) if abs(best - f_paper) <= rel_window * f_paper else np.nan


def paper_frequency_table(track: Track, with_wavenumber: bool = True, rel_window: float = 0.1,
                          wavenumber_response: CentralResponse | None = None) -> pd.DataFrame:
    """The paper's characteristic frequencies beside ours, with deviations.

    Parameters
    ----------
    track : Track
        ``slab_track()`` or ``ballasted_track()`` (possibly with changed parameters).
    with_wavenumber : bool
        Also locate each extremum with the paper's own method and settings, on the paper's
        6 Hz grid with parabolic refinement (costs a few seconds).
    rel_window : float
        An extremum further than this fraction from the paper's value is not matched (NaN).
    wavenumber_response : CentralResponse, optional
        The paper's-method responses on :data:`PAPER_GRID` if already computed (saves the sweep).

    Returns
    -------
    pandas.DataFrame
        Columns: source, mode, quantity, kind, paper (Hz), exact (Hz), deviation (%) and, with
        ``with_wavenumber``, wavenumber (Hz) and its deviation (%).
    """
    track = require_track(track)
    with_wavenumber = check_flag("with_wavenumber", with_wavenumber)
    rel_window = check_in_range("rel_window", check_positive("rel_window", rel_window), (0.0, 1.0),
                                "of the paper's frequency, a window around it")
    exact = characteristic_frequencies(track)
    wn = None
    if with_wavenumber:
        if wavenumber_response is None:
            wavenumber_response = central_response(track, PAPER_GRID, method="wavenumber")
        elif wavenumber_response.method != "wavenumber" or not np.array_equal(wavenumber_response.f, PAPER_GRID):
            raise InputError("wavenumber_response must come from method='wavenumber' on PAPER_GRID")
        wn = find_extrema(PAPER_GRID, curves_of(wavenumber_response))
    rows = []
    for f_paper, quantity, kind, source, mode in paper_frequencies(track):
        row = {"source": source, "mode": mode, "quantity": quantity, "kind": kind, "paper (Hz)": f_paper}
        f_ex = nearest_extremum(exact, quantity, kind, f_paper, rel_window)
        row["exact (Hz)"] = f_ex
        row["exact dev. (%)"] = 100 * (f_ex - f_paper) / f_paper
        if wn is not None:
            f_wn = nearest_extremum(wn, quantity, kind, f_paper, rel_window)
            row["paper's method (Hz)"] = f_wn
            row["paper's method dev. (%)"] = 100 * (f_wn - f_paper) / f_paper
        rows.append(row)
    return pd.DataFrame(rows)
