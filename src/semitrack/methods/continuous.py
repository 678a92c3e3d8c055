"""Closed form: Timoshenko beam on a continuous (Winkler) foundation, by residues.

This is the limit of the periodic track when the support spacing d shrinks with the support
stiffness per length kept fixed (``k_f = kv / d``, ``k_r = kphi / d``); it serves as an
independent check of the periodic-structure methods.

With D_c(beta) = D(beta) + diag(k_f, k_r), det D_c is a quadratic in u = beta^2,

    P(u) = kAG EI u^2 + (kAG B0 + EI A0 - kAG^2) u + A0 B0,
    A0 = k_f - omega^2 rho A,   B0 = kAG + k_r - omega^2 rho I,

and for x >= 0 the inverse Fourier transform closes in the upper half-plane:

    q(x) = i sum_{p: Im beta_p > 0} adj D_c(beta_p) e^{i beta_p x} / (2 beta_p P'(u_p)).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from ..base.checks import as_frequencies, check_in_range, check_nonnegative
from ..base.errors import InputError, InputTypeError
from ..model.curves import FrequencyCurve, as_curve, check_passive
from ..model.tracks import Track, require_track


def continuous_foundation_receptance(track: Track, f: ArrayLike, k_f: complex, k_r: complex = 0.0,
                                     x: float = 0.0) -> np.ndarray:
    """2x2 receptance of an infinite Timoshenko beam on a continuous elastic foundation.

    Parameters
    ----------
    track : Track
        Supplies the rail properties only (rho, E, G, A, I, kappa, eta_rail); with
        ``damping="viscous"`` also the rail's reference frequency, which depends on ``spacing``.
    f : array_like
        Frequencies (Hz).
    k_f : float or complex or FrequencyCurve or callable
        Vertical foundation stiffness per unit length (N/m^2); complex to include damping; a
        stiffness curve or a callable ``k_f(f)`` (Hz) for a frequency-dependent one. Passive:
        ``Im k_f >= 0`` at every frequency. The real part may be negative (a foundation above
        its own resonance, such as a mass on a spring, is still passive).
    k_r : float or complex or FrequencyCurve or callable
        Rotational foundation stiffness per unit length (N m/rad/m), the same rules.
    x : float
        Distance from the load to the response point (m), x >= 0.

    Returns
    -------
    ndarray of complex, shape ``f.shape + (2, 2)``
        Response (w, psi) at x per load (F, M) at 0.
    """
    track = require_track(track)
    f = as_frequencies(f)
    k_f, k_r = (_stiffness_per_length(name, value, f.ravel()) for name, value in (("k_f", k_f), ("k_r", k_r)))
    check_in_range("x", check_nonnegative("x", x), (0.0, MAX_DISTANCE), "m, as far as the exact track's solves reach")
    omega2 = (2 * np.pi * f.ravel()) ** 2
    ei, kag = track.rail_moduli(f.ravel())
    a0 = k_f - omega2 * track.mass_per_length
    b0 = kag + k_r - omega2 * track.rotary_inertia
    c2, c1, c0 = kag * ei, kag * b0 + ei * a0 - kag**2, a0 * b0
    disc = np.sqrt(c1 * c1 - 4 * c2 * c0)
    out = np.zeros((f.size, 2, 2), dtype=complex)
    for u in ((-c1 + disc) / (2 * c2), (-c1 - disc) / (2 * c2)):
        beta = np.sqrt(u + 0j)
        # the pole in the upper half-plane; on the real axis (no damping at all) the limit of a
        # vanishing damping, the wave that carries energy away: e^{i beta x} with beta < 0
        beta = np.where((beta.imag > 0) | ((beta.imag == 0) & (beta.real < 0)), beta, -beta)
        dp = 2 * beta * (2 * c2 * u + c1)  # d det / d beta
        a = kag * beta**2 + a0
        b = ei * beta**2 + b0
        c = 1j * kag * beta
        adj = np.stack([np.stack([b, -c], -1), np.stack([c, a], -1)], -2)
        out += 1j * adj * (np.exp(1j * beta * x) / dp)[:, None, None]
    return out.reshape(f.shape + (2, 2))


#: The farthest response point (m), as :class:`~semitrack.InfiniteTrack` takes them; at 1e308 m the
#: decaying waves' exponentials gave 0 * inf = NaN.
MAX_DISTANCE = 1e6
#: The largest foundation stiffness per length taken (N/m^2, N/rad): some 1e7 times a real track's
#: (1e8 N/m over 0.6 m); at 1e308 the fourth root of the characteristic equation overflowed into NaN.
MAX_FOUNDATION_STIFFNESS = 1e16


def _stiffness_per_length(name: str, value: object, f: np.ndarray) -> np.ndarray:
    """A foundation stiffness at the frequencies ``f``: a number, or a curve evaluated, checked passive."""
    curve = as_curve(name, value, "stiffness")
    if isinstance(curve, FrequencyCurve):
        k = curve(f, name)
    elif isinstance(curve, bool) or not isinstance(curve, (int, float, complex, np.number)):
        raise InputTypeError(f"{name} must be a number, a stiffness curve or a function of f, got {value!r}")
    else:
        k = np.full(f.shape, complex(curve))
        check_passive(name, "stiffness", f, k, allow_zero=True)  # zero: no foundation in that direction
    if np.abs(k).max() > MAX_FOUNDATION_STIFFNESS:
        raise InputError(f"{name} must be at most {MAX_FOUNDATION_STIFFNESS:g} in magnitude (N/m^2 or N/rad): beyond, "
                         f"the beam's wavenumbers overflow; got {k.ravel()[np.argmax(np.abs(k))]!r}")
    return k
