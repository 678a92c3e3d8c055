"""The classic closed-form estimate of the P2 force at a dipped weld or joint, and the lumped track it needs.

A wheel running down a V-shaped dip of total angle 2 alpha at speed V has its vertical speed
changed by ``2 alpha V`` at the bottom. Jenkins et al. (1974) modelled the wheel's unsprung mass
``M_u`` on a lumped track (mass ``M_t``, stiffness ``K_t``, damping ``C_t`` under the wheel) and
gave the lower-frequency peak of the force that follows:

    P2 = P0 + 2 alpha V sqrt(M_u / (M_u + M_t)) (1 - C_t pi / (4 sqrt(K_t (M_u + M_t)))) sqrt(K_t M_u)

(H. H. Jenkins, J. E. Stephenson, G. A. Clayton, G. W. Morland, D. Lyon, "The effect of track
and vehicle parameters on wheel/rail vertical dynamic forces", Railway Engineering Journal 3
(1974) 2-16; quoted so in Esveld, *Modern Railway Track*, 2001, and most texts on track forces).
The first, higher-frequency peak P1 (the contact spring and the rail's local mass) has no such
formula of comparable standing: it is left to the time domain.

The lumped track comes from the exact receptance (:func:`lumped_track`): ``K_t`` the static
point stiffness, ``M_t`` and ``C_t`` fitted to the dynamic stiffness ``1 / alpha_R`` over the
P2 band. Where it does not apply: a track whose dynamic stiffness is not mass-spring-damper-like
over that band (a ballasted track's sleeper resonance inside it makes ``M_t`` a compromise),
loss of contact (the formula is linear), dips short enough that P1 and P2 merge, a primary
suspension soft enough to matter below the P2 frequency is ignored (the formula has none), and
the dip's position against the supports (the receptance there is used).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ..base.checks import check_band, check_positive, check_real
from ..model.tracks import Track
from ..model.wheel import Wheel
from .infinite import InfiniteTrack

__all__ = ["LumpedTrack", "lumped_track", "jenkins_p2"]


@dataclass(frozen=True)
class LumpedTrack:
    """A mass-spring-damper track under one wheel.

    Attributes
    ----------
    stiffness : float
        K_t (N/m).
    damping : float
        C_t (N s/m).
    mass : float
        M_t (kg).
    band : tuple of float
        The band it was fitted over (Hz).
    """

    stiffness: float
    damping: float
    mass: float
    band: tuple[float, float]

    def receptance(self, f: ArrayLike) -> np.ndarray:
        """``1 / (K_t + i omega C_t - omega^2 M_t)`` (m/N).

        Parameters
        ----------
        f : array_like
            Frequencies (Hz).

        Returns
        -------
        ndarray of complex
        """
        omega = 2 * np.pi * np.asarray(f, dtype=float)
        return 1.0 / (self.stiffness + 1j * omega * self.damping - omega**2 * self.mass)


def lumped_track(track: Track | InfiniteTrack, x: float = 0.0, band: tuple[float, float] = (10.0, 150.0)
                 ) -> LumpedTrack:
    """The lumped track of Jenkins' P2 formula from the exact receptance at x.

    Parameters
    ----------
    track : Track or InfiniteTrack
        The track (an InfiniteTrack may hold local changes).
    x : float
        The position (m, from the central mid-span, as InfiniteTrack takes it).
    band : tuple of float
        Where ``M_t`` and ``C_t`` are fitted (Hz): around the P2 frequency.

    Returns
    -------
    LumpedTrack
        ``K_t`` from 0.05 Hz (static), ``M_t`` from ``K_t - Re(1/alpha)`` over omega^2 and
        ``C_t`` from ``Im(1/alpha)`` over omega, least squares over the band.

    Examples
    --------
    >>> import semitrack as st
    >>> lumped = lumped_track(st.ballasted_track())
    >>> 5e7 < lumped.stiffness < 5e8 and lumped.mass > 0
    True
    """
    lo, hi = check_band(band)
    x = check_real("x", x)
    infinite = track if isinstance(track, InfiniteTrack) else InfiniteTrack(track)
    f = np.concatenate([[0.05], np.linspace(lo, hi, 60)])
    k = 1.0 / infinite.receptance(f, x, [x])[:, 0, 0, 0]
    omega = 2 * np.pi * f[1:]
    k_t = float(k[0].real)
    m_t = float(np.sum((k_t - k[1:].real) * omega**2) / np.sum(omega**4))
    c_t = float(np.sum(k[1:].imag * omega) / np.sum(omega**2))
    return LumpedTrack(stiffness=k_t, damping=c_t, mass=m_t, band=(lo, hi))


def jenkins_p2(wheel: Wheel, angle: float, speed: float, lumped: LumpedTrack) -> float:
    """Jenkins' P2 force (N) at a dip of total angle ``angle`` (rad) passed at ``speed`` (m/s).

    Parameters
    ----------
    wheel : Wheel
        Its unsprung mass M_u and static load P0 (the preload).
    angle : float
        Total dip angle 2 alpha (rad).
    speed : float
        V (m/s).
    lumped : LumpedTrack
        The track under the wheel (:func:`lumped_track`).

    Returns
    -------
    float
        P2 (N), the static load included.

    Examples
    --------
    >>> import semitrack as st
    >>> p2 = jenkins_p2(st.Wheel(), 0.01, 50.0, LumpedTrack(1e8, 5e4, 200.0, (10, 150)))
    >>> round(p2 / 1e3)
    191
    """
    angle, speed = check_positive("angle", angle), check_positive("speed", speed)
    m_u, m_t, k_t, c_t = wheel.mass, lumped.mass, lumped.stiffness, lumped.damping
    factor = 1 - c_t * np.pi / (4 * np.sqrt(k_t * (m_u + m_t)))
    return float(wheel.preload + angle * speed * np.sqrt(m_u / (m_u + m_t)) * factor * np.sqrt(k_t * m_u))
