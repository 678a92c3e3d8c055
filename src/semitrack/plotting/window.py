"""The truncated track that travels with the train: the window beside the model that holds the path."""

from __future__ import annotations

import numpy as np

from .style import house_figure, legend_below, panels


@house_figure
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
    fig, axes = panels(2, figsize=(10.0, 3.8))
    win, path = run.window, run.path
    first = (lambda a: a) if win.force.ndim == 1 else (lambda a: a[:, 0])  # noqa: E731
    shown = (win.t >= window[0]) & (win.t <= window[1])
    axes[0].plot(1e3 * win.t[shown], first(path.force)[shown] / 1e3, color="0.65", lw=3.2,
                 label="model that holds the path", zorder=1)
    axes[0].plot(1e3 * win.t[shown], first(win.force)[shown] / 1e3, color="tab:red", lw=1.1, ls="--",
                 label="travelling window", zorder=2)
    axes[0].set_xlabel("Time (ms)")
    axes[0].set_ylabel("Contact force, first wheel (kN)")
    markers = ("o", "s", "^", "v")
    for i, a in enumerate(run.agreement):
        axes[1].semilogx(a["centres"], a["error_level"], marker=markers[i % len(markers)], lw=1.0,
                         label=f"wheel {i + 1}" if len(run.agreement) > 1 else "the wheel")
    axes[1].axhline(-45.0, color="k", lw=0.8, ls=":", label="-45 dB")
    axes[1].set_xlabel("One-third-octave band centre (Hz)")
    axes[1].set_ylabel("Difference under the force (dB)")
    top = max(-45.0, float(np.max([a["error_level"].max() for a in run.agreement])))
    axes[1].set_ylim(top=top + 25)  # room above the -45 dB line for the legend
    legend_below(fig, axes[0])
    axes[1].legend(loc="upper right", ncol=3)
    if title:
        fig.suptitle(title)
    return fig, axes


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
    shown = (supports + 0.5) * spacing <= x.max()
    axes[1].plot((supports[shown] + 0.5) * spacing, pad_stiffness[shown] / 1e6, color="0.3", lw=0.6)
    axes[1].set_xlabel("Support position (m)")
    axes[1].set_ylabel("Pad stiffness (MN/m)")
    axes[0].legend(loc="upper right")
    if title:
        fig.suptitle(title)
    return fig, axes
