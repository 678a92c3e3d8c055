"""The linear wheel-rail force per unit roughness: the classical frequency-domain result.

A roughness r(x) on the running surfaces, passed at speed v, excites wheel and rail at
f = v / wavelength. Wheel, contact and rail act in series: with the receptances alpha_W of the
wheel (:meth:`semitrack.Wheel.receptance`), alpha_C = 1 / k_H of the contact linearised at the
preload and alpha_R(x) of the infinite rail at the contact point (:func:`point_receptance`,
exact), the dynamic contact force is

    F / r = -1 / (alpha_W + alpha_C + alpha_R(x)).

Sign convention: r is the rail surface's displacement, downward like w, so r > 0 is a dip that
relieves the contact; F is the compression, positive when wheel and rail press together. The
rail's receptance is that of a stationary load at x (the moving-irregularity model): the
wheel's speed is small beside the track's wave speeds.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from ..base.checks import as_frequencies
from ..base.errors import InputTypeError
from ..model.tracks import PeriodicCell, Track
from ..model.wheel import Wheel
from .receptance import point_receptance


def wheel_rail_force(track: Track | PeriodicCell, f: ArrayLike, wheel: Wheel, x: float = 0.0) -> np.ndarray:
    """Dynamic wheel-rail contact force per unit roughness, linear (N/m).

    Parameters
    ----------
    track : Track or PeriodicCell
        The infinite periodic track.
    f : array_like
        Frequencies (Hz), positive and finite.
    wheel : Wheel
        Unsprung mass, primary suspension, preload and Hertz constant.
    x : float
        Contact position measured from a support (m); ``spacing / 2`` is mid-span.

    Returns
    -------
    ndarray of complex, the shape of ``f``
        F / r = -1 / (alpha_W + alpha_C + alpha_R(x)) in N/m: compression per unit roughness,
        r positive downward (a dip).

    Examples
    --------
    >>> import semitrack as st
    >>> force = st.wheel_rail_force(st.slab_track(), [100.0, 1000.0], st.Wheel())
    >>> force.shape
    (2,)
    """
    if not isinstance(wheel, Wheel):
        raise InputTypeError(f"wheel must be a semitrack Wheel (e.g. st.Wheel()), got {type(wheel).__name__}")
    f = as_frequencies(f)
    alpha_r = point_receptance(track, f, x)[..., 0, 0]
    # -1 / (1/z_W + alpha_C + alpha_R) written with the wheel's dynamic stiffness z_W, which is 0
    # (not its receptance infinite) at an undamped primary suspension's resonance: the force is 0 there
    z_w = wheel.dynamic_stiffness(f)
    return -z_w / (1.0 + z_w * (1.0 / wheel.contact_stiffness + alpha_r))
