"""The periodic track in time without truncation: moving Green's functions beside the truncated model."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from .style import house_figure, legend_below, panels


@house_figure
def moving_force_figure(comparison, agreements: Sequence[dict], window: tuple[float, float] = (0.30, 0.34),
                        title: str = ""):
    """A stretch of the first wheel's force by both routes, and every wheel's band levels of the difference.

    Parameters
    ----------
    comparison : Comparison
        :func:`semitrack.paper.moving_study.compare_runs`.
    agreements : sequence of dict
        :func:`semitrack.paper.moving_study.force_agreement` of each wheel.
    window : (float, float)
        The stretch of time drawn (s).
    title : str
        Figure title.

    Returns
    -------
    fig, axes
    """
    return force_comparison_figure(comparison.green, comparison.truncated, agreements,
                                   ("moving Green's functions", "truncated model, broadband ends"), window, title)


@house_figure
def force_comparison_figure(run, reference, agreements: Sequence[dict], labels: tuple[str, str],
                            window: tuple[float, float], title: str = ""):
    """A stretch of the first wheel's force by a run and its reference, and every wheel's band levels of the difference.

    Parameters
    ----------
    run, reference : ContactResponse
        The two runs, on the same time steps.
    agreements : sequence of dict
        :func:`semitrack.paper.moving_study.force_agreement` of each wheel.
    labels : (str, str)
        The run's and the reference's names.
    window : (float, float)
        The stretch of time drawn (s).
    title : str
        Figure title.

    Returns
    -------
    fig, axes
    """
    fig, axes = panels(2, figsize=(10.0, 3.8))
    first = (lambda a: a) if run.force.ndim == 1 else (lambda a: a[:, 0])  # noqa: E731
    shown = (run.t >= window[0]) & (run.t <= window[1])
    axes[0].plot(1e3 * run.t[shown], first(reference.force)[shown] / 1e3, color="0.65", lw=3.2, label=labels[1],
                 zorder=1)
    axes[0].plot(1e3 * run.t[shown], first(run.force)[shown] / 1e3, color="tab:red", lw=1.1, ls="--",
                 label=labels[0], zorder=2)
    axes[0].set_xlabel("Time (ms)")
    axes[0].set_ylabel("Contact force, first wheel (kN)")
    markers = ("o", "s", "^", "v")
    names = run.vehicle.wheel_names if run.vehicle is not None else tuple(
        f"wheel {i + 1}" for i in range(len(agreements)))  # as the vehicle names them: "leading wheel", ...
    for i, a in enumerate(agreements):
        axes[1].semilogx(a["centres"], a["error_level"], marker=markers[i % len(markers)], lw=1.0,
                         label=names[i] if len(agreements) > 1 else "the wheel")
    axes[1].axhline(-45.0, color="k", lw=0.8, ls=":", label="-45 dB")
    axes[1].set_xlabel("One-third-octave band centre (Hz)")
    axes[1].set_ylabel("Difference under the force (dB)")
    top = max(-45.0, float(np.max([a["error_level"].max() for a in agreements])))
    axes[1].set_ylim(top=top + 25)  # room above the -45 dB line for the legend
    legend_below(fig, axes[0])
    axes[1].legend(loc="upper right", ncol=3)
    if title:
        fig.suptitle(title)
    return fig, axes
