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

from ..methods.features import characteristic_frequencies, curves_of, find_extrema
from ..methods.receptance import central_response

# (paper frequency in Hz, quantity, kind, where the paper states it, mode / remark)
SLAB_FREQUENCIES = (
    (183, "w1", "peak", "Table 3", "rail bouncing on the fastener stiffness"),
    (940, "w1", "peak", "Table 3", "first pinned-pinned mode"),
    (980, "psi2", "peak", "Table 3", "sliding-pinned-sliding* mode"),
    (2577, "det", "peak", "Table 3", "second pinned-pinned mode"),
    (2607, "w1", "peak", "Table 3", "sliding-sliding*-sliding mode"),
    (183, "psi2", "peak", "Sec. 4.2", "pitching frequency"),
    (183, "Q2", "dip", "Sec. 4.2", "pitching frequency"),
    (980, "Q2", "dip", "Sec. 4.2", "sliding-pinned-sliding*"),
    (183, "M1", "peak", "Sec. 4.2", "bouncing frequency"),
    (940, "M1", "peak", "Sec. 4.2", "first pinned-pinned"),
    (183, "det", "dip", "Sec. 4.2", "resonance of the semi-infinite track"),
    (2607, "det", "dip", "Sec. 4.2", "sliding-sliding*-sliding"),
    (183, "alpha11", "peak", "Sec. 4.3", "omega_n"),
    (183, "alpha12", "peak", "Sec. 4.3", "omega_n"),
    (183, "alpha22", "peak", "Sec. 4.3", "omega_n"),
    (940, "alpha11", "peak", "Sec. 4.3", "first pinned-pinned"),
    (940, "alpha22", "dip", "Sec. 4.3", "first pinned-pinned"),
    (2577, "alpha11", "dip", "Sec. 4.3", "second pinned-pinned"),
    (2577, "alpha22", "peak", "Sec. 4.3", "second pinned-pinned"),
)

BALLASTED_FREQUENCIES = (
    (117, "w1", "peak", "Table 6", "rail and sleeper bouncing together on the ballast"),
    (243, "w1", "dip", "Table 6", "sleeper acting as a vibration absorber"),
    (531, "w1", "peak", "Table 6", "rail and sleeper bouncing out of phase"),
    (1077, "w1", "peak", "Table 6", "first pinned-pinned mode"),
    (1269, "psi2", "peak", "Table 6", "sliding-pinned-sliding* mode"),
    (2871, "w1", "dip", "Table 6", "second pinned-pinned mode"),
    (2955, "w1", "peak", "Table 6", "sliding*-sliding mode"),
    (117, "det", "dip", "Sec. 5.1", "resonance omega_n1 of the semi-infinite track"),
    (489, "det", "dip", "Sec. 5.1", "resonance omega_n2 of the semi-infinite track"),
    (2925, "det", "dip", "Sec. 5.1", "third resonance of the semi-infinite track"),
    (243, "det", "peak", "Sec. 5.1", "anti-resonance"),
    (2871, "det", "peak", "Sec. 5.1", "second pinned-pinned"),
    (117, "alpha11", "peak", "Sec. 5.2", "omega_n1"),
    (117, "alpha12", "peak", "Sec. 5.2", "omega_n1"),
    (117, "alpha22", "peak", "Sec. 5.2", "omega_n1"),
    (489, "alpha11", "peak", "Sec. 5.2", "omega_n2"),
    (489, "alpha12", "peak", "Sec. 5.2", "omega_n2"),
    (489, "alpha22", "peak", "Sec. 5.2", "omega_n2"),
    (243, "alpha11", "dip", "Sec. 5.2", "omega_anti"),
    (243, "alpha12", "dip", "Sec. 5.2", "omega_anti"),
    (243, "alpha22", "dip", "Sec. 5.2", "omega_anti"),
)

#: The paper's frequency grid (Sec. 4.1): 3 Hz to 3000 Hz in steps of 6 Hz.
PAPER_GRID = np.arange(3.0, 3000.0, 6.0)


def paper_frequencies(track) -> tuple:
    """The paper's entries for a track: slab for a rigid foundation, ballasted otherwise."""
    return BALLASTED_FREQUENCIES if track.is_ballasted else SLAB_FREQUENCIES


def _nearest(extrema: pd.DataFrame, quantity: str, kind: str, f_paper: float, rel_window: float) -> float:
    cand = extrema[(extrema["quantity"] == quantity) & (extrema["kind"] == kind)]
    if cand.empty:
        return np.nan
    f = cand["f"].to_numpy()
    best = f[np.argmin(np.abs(f - f_paper))]
    return float(best) if abs(best - f_paper) <= rel_window * f_paper else np.nan


def paper_frequency_table(track, with_wavenumber: bool = True, rel_window: float = 0.1,
                          wavenumber_response=None) -> pd.DataFrame:
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
    exact = characteristic_frequencies(track)
    wn = None
    if with_wavenumber:
        if wavenumber_response is None:
            wavenumber_response = central_response(track, PAPER_GRID, method="wavenumber")
        elif wavenumber_response.method != "wavenumber" or not np.array_equal(wavenumber_response.f, PAPER_GRID):
            raise ValueError("wavenumber_response must come from method='wavenumber' on PAPER_GRID")
        wn = find_extrema(PAPER_GRID, curves_of(wavenumber_response))
    rows = []
    for f_paper, quantity, kind, source, mode in paper_frequencies(track):
        row = {"source": source, "mode": mode, "quantity": quantity, "kind": kind, "paper (Hz)": f_paper}
        f_ex = _nearest(exact, quantity, kind, f_paper, rel_window)
        row["exact (Hz)"] = f_ex
        row["exact dev. (%)"] = 100 * (f_ex - f_paper) / f_paper
        if wn is not None:
            f_wn = _nearest(wn, quantity, kind, f_paper, rel_window)
            row["paper's method (Hz)"] = f_wn
            row["paper's method dev. (%)"] = 100 * (f_wn - f_paper) / f_paper
        rows.append(row)
    return pd.DataFrame(rows)
