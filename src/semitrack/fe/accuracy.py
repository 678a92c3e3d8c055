"""The long FE tracks as a third route to alpha and w1: their error against the exact transfer method.

A long semi-infinite FE track (:func:`semitrack.fe.models.fe_semi_infinite_receptance`) gives
the end receptance alpha, a long complete one (:func:`semitrack.fe.models.fe_central_receptance`)
the central w1; both are compared frequency by frequency with the exact transfer method
(:func:`semitrack.semi_infinite_receptance`, :func:`semitrack.central_response`). The errors come
from the mesh (near the sharp second pinned-pinned resonance) and from the length of the model
(weakly damped waves reflected by the far end).
"""

from __future__ import annotations

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike

from ..base.checks import as_frequencies
from ..equivalent.metrics import receptance_errors
from ..methods.receptance import central_response, semi_infinite_receptance
from ..model.tracks import Track
from .models import fe_central_receptance, fe_semi_infinite_receptance

__all__ = ["long_track_errors"]


def long_track_errors(track: Track, f: ArrayLike, n_bays: int = 200, elements_per_bay: int = 12) -> pd.DataFrame:
    """Relative error of the long FE tracks' alpha and w1 against the exact transfer method.

    Parameters
    ----------
    track : Track
        The track.
    f : array_like
        Frequencies (Hz), 1-D.
    n_bays : int
        Bays of the semi-infinite track, and on each side of the centre of the complete one.
    elements_per_bay : int
        Even number of elements per support spacing.

    Returns
    -------
    pandas.DataFrame
        One row per frequency: ``f (Hz)``, ``alpha error`` (the largest of the relative errors
        of alpha11, alpha12 and alpha22, -) and ``w1 error`` (-).

    Examples
    --------
    >>> import semitrack as st
    >>> e = long_track_errors(st.slab_track(), [100.0, 300.0], n_bays=20, elements_per_bay=4)
    >>> list(e.columns), len(e)
    (['f (Hz)', 'alpha error', 'w1 error'], 2)
    """
    f = np.atleast_1d(as_frequencies(f))
    alpha = fe_semi_infinite_receptance(track, f, n_bays=n_bays, elements_per_bay=elements_per_bay)
    w1 = fe_central_receptance(track, f, n_bays=n_bays, elements_per_bay=elements_per_bay)[:, 0, 0]
    err_alpha = np.max(list(receptance_errors(alpha, semi_infinite_receptance(track, f)).values()), axis=0)
    exact_w1 = central_response(track, f).w1
    return pd.DataFrame({"f (Hz)": f, "alpha error": err_alpha, "w1 error": np.abs(w1 - exact_w1) / np.abs(exact_w1)})
