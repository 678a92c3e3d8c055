"""Time functions of the loads: the package's one fade-in (a ``sin^2`` ramp) and a Hann pulse.

Both are smooth at their ends, so that a load switched on by them sets off no impulsive start:
the ramp fades roughness and moving loads in, the pulse excites the track up to a chosen frequency.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from ..base.checks import check_positive

__all__ = ["sin2_ramp", "hann_pulse"]


def sin2_ramp(t: ArrayLike, ramp: float) -> np.ndarray:
    """``sin^2(pi t / (2 ramp))`` on ``[0, ramp]``, 0 before, 1 after: the package's one fade-in.

    Parameters
    ----------
    t : array_like
        Times (s).
    ramp : float
        Duration of the rise (s), positive.

    Returns
    -------
    ndarray
        The ramp at ``t`` (-), same shape.

    Examples
    --------
    >>> sin2_ramp([-1.0, 0.5, 1.0, 2.0], 1.0).round(12).tolist()
    [0.0, 0.5, 1.0, 1.0]
    """
    ramp = check_positive("ramp", ramp)
    s = np.asarray(t, dtype=float)
    return np.where(s <= 0, 0.0, np.where(s >= ramp, 1.0, np.sin(0.5 * np.pi * np.clip(s, 0, ramp) / ramp) ** 2))


def hann_pulse(t: ArrayLike, duration: float) -> np.ndarray:
    """Unit Hann (raised-cosine) pulse ``sin^2(pi t / duration)`` on ``0 <= t <= duration``, else 0.

    Its amplitude spectrum is ``duration / 2 |sinc(f T) / (1 - (f T)^2)|`` (T = duration) with
    the first zero at ``f = 2 / T``; choose ``T = 2 / f_max`` for content up to ``f_max``.

    Parameters
    ----------
    t : array_like
        Times (s).
    duration : float
        Length T of the pulse (s), positive.

    Returns
    -------
    ndarray
        The pulse at ``t`` (-), same shape.

    Examples
    --------
    >>> hann_pulse([0.0, 0.5e-3, 1e-3, 2e-3], 1e-3).round(12).tolist()
    [0.0, 1.0, 0.0, 0.0]
    """
    duration = check_positive("duration", duration)
    t = np.asarray(t, dtype=float)
    return np.where((t >= 0) & (t <= duration), np.sin(np.pi * t / duration) ** 2, 0.0)
