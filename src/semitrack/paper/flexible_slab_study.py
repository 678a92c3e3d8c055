"""The chapter on the flexible slab: how far a slab that bends moves the end receptance from the rigid one's.

The chapter's tables computed here: the deviation of alpha on a flexible slab from the rigid
slab's (largest, below and above the slab's modes, and where), with the rail's bouncing peak on
each, and |alpha11| at 50 Hz for the cut placed at each mid-span of the slab.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping

import numpy as np
import pandas as pd

from ..equivalent.metrics import receptance_errors
from ..methods.features import find_extrema
from ..methods.receptance import semi_infinite_receptance
from ..model.slab import Slab
from ..model.tracks import Track, slab_track

__all__ = ["worst_deviation", "bouncing_peaks", "with_cut", "deviation_table", "cut_table"]


def worst_deviation(a: np.ndarray, reference: np.ndarray) -> np.ndarray:
    """The largest element error of alpha11, alpha12, alpha22 at each frequency (-).

    Parameters
    ----------
    a, reference : ndarray, shape (n_f, 2, 2)
        A receptance and its reference.

    Returns
    -------
    ndarray, shape (n_f,)
    """
    return np.max(list(receptance_errors(a, reference).values()), axis=0)


def bouncing_peaks(track: Track, lo: float, hi: float) -> np.ndarray:
    """The peaks of ``|alpha11|`` in ``[lo, hi]`` (Hz) on a 1-Hz grid, each refined by Brent's method.

    Parameters
    ----------
    track : Track
        The track.
    lo, hi : float
        The band searched (Hz).

    Returns
    -------
    ndarray
        The peaks' frequencies (Hz), lowest first.
    """
    grid = np.arange(lo, hi, 1.0)
    found = find_extrema(grid, {"a11": semi_infinite_receptance(track, grid)[:, 0, 0]},
                         evaluate=lambda x: {"a11": semi_infinite_receptance(track, [x])[0, 0, 0]})
    return found.loc[found["kind"] == "peak", "f"].to_numpy()


def with_cut(slab: Slab, cut: str | int) -> Track:
    """The paper's Table 2 rail and pads on ``slab`` with alpha's cut at ``cut`` (``"joint"``, ``"centre"`` or k).

    Parameters
    ----------
    slab : Slab
        The slab.
    cut : str or int
        Where the cut sits (:class:`semitrack.Slab`'s ``cut``).

    Returns
    -------
    Track
    """
    return slab_track(slab=dataclasses.replace(slab, cut=cut))


def deviation_table(f: np.ndarray, alpha: Mapping[str, np.ndarray], alpha_rigid: np.ndarray,
                    tracks: Mapping[str, Track], rigid_track: Track, bounce: tuple[float, float] = (150.0, 220.0),
                    low: float = 150.0, high: float = 300.0) -> pd.DataFrame:
    """alpha on each flexible slab against the rigid slab's: the largest deviation, where, and the bouncing peaks.

    Parameters
    ----------
    f : ndarray
        Frequencies (Hz) of the receptances.
    alpha : mapping of str to ndarray, shape (n_f, 2, 2)
        alpha on each flexible slab, by the track's name.
    alpha_rigid : ndarray, shape (n_f, 2, 2)
        alpha on the rigid slab.
    tracks : mapping of str to Track
        The flexible-slab tracks, by the same names.
    rigid_track : Track
        The rigid-slab track.
    bounce : (float, float)
        The band of the rail's bouncing peak of ``|alpha11|`` (Hz).
    low, high : float
        The table's deviations below ``low`` and above ``high`` (Hz).

    Returns
    -------
    pandas.DataFrame
        A row per track: the largest deviation (%) and its frequency, below ``low`` and above
        ``high``, the rigid slab's and the track's bouncing peak (Hz).
    """
    below, above = f < low, f > high
    rigid_peak = bouncing_peaks(rigid_track, *bounce).item()
    rows = {}
    for name, a in alpha.items():
        e = worst_deviation(a, alpha_rigid)
        rows[name] = {"largest deviation (%)": 100 * e.max(), "at (Hz)": f[e.argmax()],
                      f"largest below {low:g} Hz (%)": 100 * e[below].max(),
                      f"largest above {high:g} Hz (%)": 100 * e[above].max(),
                      f"above {high:g} Hz: at (Hz)": f[above][e[above].argmax()],
                      "rigid slab: bouncing peak (Hz)": rigid_peak,
                      "rail bouncing peak of |a11| (Hz)": bouncing_peaks(tracks[name], *bounce)[-1]}
    return pd.DataFrame(rows).T


def cut_table(slab: Slab, f: float = 50.0) -> pd.DataFrame:
    """``|alpha11|`` at ``f`` with the cut at each mid-span k of the slab (k = 0 its joint), relative to the joint.

    Parameters
    ----------
    slab : Slab
        The slab (on the paper's Table 2 rail and pads).
    f : float
        The frequency (Hz).

    Returns
    -------
    pandas.DataFrame
        A row per mid-span: ``|a11|`` (m/N) and its ratio to the joint's (-).
    """
    values = {k: abs(semi_infinite_receptance(with_cut(slab, k) if k else slab_track(slab=slab), [f])[0, 0, 0])
              for k in range(slab.fasteners)}
    return pd.DataFrame({"mid-span k": list(values), f"|a11| at {f:g} Hz (m/N)": list(values.values()),
                         "relative to the joint (-)": [v / values[0] for v in values.values()]})
