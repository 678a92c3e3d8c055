"""The truncated track that travels with the train: the window beside the model that holds the path."""

from __future__ import annotations

import numpy as np

from .moving import force_comparison_figure
from .style import house_figure, panels


def window_force_figure(run, window: tuple[float, float] = (0.20, 0.24), title: str = ""):
    """A stretch of the first wheel's force on both models, and every wheel's band levels of the difference.

    Parameters
    ----------
    run : WindowRun
        :func:`semitrack.paper.window_study.window_against_path`.
    window : (float, float)
        The stretch of time drawn (s).
    title : str
        Figure title.

    Returns
    -------
    fig, axes
    """
    return force_comparison_figure(run.window, run.path, run.agreement,
                                   ("travelling window", "model that holds the path"), window, title)


@house_figure
def long_run_figure(response, pad_stiffness: np.ndarray, supports: np.ndarray, spacing: float,
                    failed: tuple[int, ...] = (), title: str = ""):
    """A long run's force along the track, its envelope per bay, above the pads' stiffness it met.

    Parameters
    ----------
    response : ContactResponse
        The run (its first wheel drawn).
    pad_stiffness : ndarray
        Each support's pad stiffness (N/m).
    supports : ndarray of int
        Their indices k (at ``(k + 1/2) d``).
    spacing : float
        The support spacing d (m).
    failed : tuple of int
        Supports without a pad, marked.
    title : str
        Figure title.

    Returns
    -------
    fig, axes
    """
    fig, axes = panels(2, figsize=(10.0, 3.8))
    x = response.x if response.x.ndim == 1 else response.x[:, 0]
    force = response.force if response.force.ndim == 1 else response.force[:, 0]
    bay = np.floor(x / spacing).astype(int)
    edges = np.flatnonzero(np.diff(bay)) + 1
    lo = np.minimum.reduceat(force, np.r_[0, edges]) / 1e3
    hi = np.maximum.reduceat(force, np.r_[0, edges]) / 1e3
    centre = spacing * (bay[np.r_[0, edges]] + 0.5)
    axes[0].fill_between(centre, lo, hi, color="tab:blue", alpha=0.35, lw=0, label="range within each bay")
    axes[0].plot(centre, 0.5 * (lo + hi), color="tab:blue", lw=0.8)
    for k in failed:
        axes[0].axvline((k + 0.5) * spacing, color="tab:red", lw=0.8, ls=":")
    axes[0].set_xlabel("Position of the first wheel (m)")
    axes[0].set_ylabel("Contact force (kN)")
    shown = (x.min() <= (supports + 0.5) * spacing) & ((supports + 0.5) * spacing <= x.max())
    axes[1].plot((supports[shown] + 0.5) * spacing, pad_stiffness[shown] / 1e6, color="0.3", lw=0.6)
    axes[1].set_xlabel("Support position (m)")
    axes[1].set_ylabel("Pad stiffness (MN/m)")
    axes[0].legend(loc="upper right")
    if title:
        fig.suptitle(title)
    return fig, axes
