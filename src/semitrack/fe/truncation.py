"""How long must a truncated track be? Error of the central receptance against the infinite track.

For each end condition of :class:`semitrack.fe.models.TruncatedTrack` and each number of bays, the
vertical receptance at the central cross-section is compared with the exact infinite-track w1
(:func:`semitrack.central_response`). The error measures are the median and maximum relative
error over a band.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ..base.checks import as_frequencies
from ..methods.receptance import central_response
from .models import TruncatedTrack


def truncation_study(track, f, n_bays=(1, 2, 5, 10, 20, 40, 80), ends: dict | None = None,
                     elements_per_bay: int = 12) -> pd.DataFrame:
    """Median and maximum relative error of w1 of truncated tracks over the frequencies ``f``.

    Parameters
    ----------
    track : Track
        The track.
    f : array_like
        Frequencies (Hz) over which the errors are taken.
    n_bays : sequence of int
        Bays on each side of the centre.
    ends : dict, optional
        Label -> ``(ends, system)`` for :class:`TruncatedTrack`, e.g.
        ``{"pinned": ("pinned", None), "paper system": ("equivalent", paper_table4())}``.
        Default: pinned, free and exact ends.
    elements_per_bay : int
        FE mesh (12 gives about 0.5 % discretisation error up to 3 kHz).

    Returns
    -------
    pandas.DataFrame
        Columns ``ends, n_bays, median error, max error`` (fractions).
    """
    f = np.atleast_1d(as_frequencies(f))
    ends = ends or {"pinned": ("pinned", None), "free": ("free", None), "exact": ("exact", None)}
    w1 = central_response(track, f).w1
    rows = []
    for label, (kind, system) in ends.items():
        for n in n_bays:
            model = TruncatedTrack(track, n, kind, system=system, elements_per_bay=elements_per_bay)
            err = np.abs(model.central_receptance(f)[:, 0, 0] - w1) / np.abs(w1)
            rows.append((label, n, float(np.median(err)), float(err.max())))
    return pd.DataFrame(rows, columns=["ends", "n_bays", "median error", "max error"])


def bays_needed(study: pd.DataFrame, median: float = 0.05, maximum: float = 0.10) -> pd.Series:
    """Fewest bays (each side) in ``study`` meeting both error targets, per end condition.

    NaN where no length in the study meets them.
    """
    ok = study[(study["median error"] <= median) & (study["max error"] <= maximum)]
    needed = ok.groupby("ends", sort=False)["n_bays"].min()
    return needed.reindex(study["ends"].unique())
