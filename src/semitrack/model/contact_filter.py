"""The contact filter: roughness averaged over the contact patch, the wheel's side of short wavelengths.

The wheel touches the rail over a patch some 10-15 mm long, not at a point, so roughness much
shorter than the patch is averaged out before it reaches the contact spring. The filter here is
the simplest of those used in rolling-noise prediction (Remington 1987; Thompson 2009, Ch. 5):
the roughness is weighted along the rolling direction by the Hertzian pressure of a circular
contact of radius a, ``p(x) ~ sqrt(1 - x^2 / a^2)``, whose normalised Fourier transform is

    H(k a) = 2 J1(k a) / (k a),    k = 2 pi / lambda,

1 at long wavelengths, -3 dB near ``lambda = 3.9 a`` (24 mm for the default wheel's a = 6.2 mm),
first zero at ``k a = 3.83``; the factor multiplies each line of a :class:`semitrack.Roughness`.

What it neglects, and where the literature goes further:

- the roughness is taken as fully correlated across the contact's width (one line of data along
  the rail); roughness that varies across the width is averaged further, and the filters of
  Remington (a two-dimensional average) attenuate more at short wavelengths;
- the contact is circular, of the radius that the wheel's Hertz constant implies (a real
  wheel-rail contact is an ellipse; the rolling-direction semi-axis is what counts);
- the patch keeps its static size: a dynamic load changes it (Ford and Thompson 2006 found that
  this matters for large roughness and dips, not for moderate roughness);
- it is a linear average of the surface, not the elastic contact's own response to it (their
  "distributed point reacting spring" models), and it does not hold the wheel's curvature: a
  wheel bridges a hollow shorter than it can enter, which :func:`semitrack.wheel_centre_path`
  takes for rail profiles and defects, not for a roughness.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike
from scipy.special import j1

from ..base.checks import as_real_array, check_in_range, check_nonnegative, check_positive, shown
from ..base.errors import InputError, InputTypeError
from .roughness import Roughness
from .wheel import Wheel

__all__ = ["STEEL_E", "STEEL_POISSON", "contact_semi_length", "contact_filter", "contact_filtered"]

#: Young's modulus (N/m^2) and Poisson's ratio of wheel and rail steel, as :meth:`Wheel.from_radii` takes them.
STEEL_E, STEEL_POISSON = 2.1e11, 0.3
#: The range a contact's semi-length may take (m): a patch from micrometres to a decimetre.
SEMI_LENGTH_RANGE = (1e-6, 0.1)


def contact_semi_length(wheel: Wheel, *, E: float = STEEL_E, poisson: float = STEEL_POISSON) -> float:
    """The radius a (m) of the circular Hertzian contact of ``wheel`` under its preload.

    The wheel's Hertz constant is that of a circular contact of curvature radius R,
    ``C_H = (4/3) E* sqrt(R)`` with ``E* = E / (2 (1 - nu^2))`` (:meth:`Wheel.from_radii`); under
    the preload the approach is ``delta_0`` and the radius ``a = sqrt(R delta_0)``, the Hertzian
    ``a^3 = 3 P0 R / (4 E*)``.

    Parameters
    ----------
    wheel : Wheel
        The wheel (its ``hertz_constant`` and ``preload``).
    E : float
        Young's modulus of both bodies (N/m^2), 1e6 to 1e13.
    poisson : float
        Poisson's ratio of both (-), in [0, 0.5).

    Returns
    -------
    float
        The contact's radius (m), 6.2 mm for the default wheel under 100 kN.

    Raises
    ------
    InputError
        Naming ``E`` or ``poisson``: out of range, or giving the wheel's Hertz constant a contact
        radius outside :data:`SEMI_LENGTH_RANGE` (constants its constant was not computed with).

    Examples
    --------
    >>> import semitrack as st
    >>> round(1e3 * st.contact_semi_length(st.Wheel()), 2)
    6.19
    """
    if not isinstance(wheel, Wheel):
        raise InputTypeError(f"wheel must be a Wheel, got {type(wheel).__name__}")
    e = check_in_range("E", check_positive("E", E), (1e6, 1e13), "N/m^2, a solid's Young's modulus")
    nu = check_nonnegative("poisson", poisson)
    if not nu < 0.5:
        raise InputError(f"poisson must be in [0, 0.5), got {poisson!r}")
    e_star = e / (2 * (1 - nu**2))
    radius = (0.75 * wheel.hertz_constant / e_star) ** 2
    a = float(np.sqrt(radius * wheel.static_approach))
    lo, hi = SEMI_LENGTH_RANGE
    if not lo <= a <= hi:  # the wheel's Hertz constant and these constants do not belong together
        raise InputError(f"E={shown(e)} N/m^2 and poisson={shown(nu)} give the wheel (hertz_constant="
                         f"{shown(wheel.hertz_constant)} N/m^1.5) a contact of radius {shown(a)} m, outside "
                         f"{lo:g}-{hi:g} m: give the elastic constants its Hertz constant was computed with")
    return a


#: Roughness wavelengths the filter takes (m): from 1 nm (the filter is zero long before) to 1000 km.
WAVELENGTH_RANGE = (1e-9, 1e6)

def contact_filter(wavelength: ArrayLike, semi_length: float) -> np.ndarray:
    """The contact filter ``2 J1(k a) / (k a)`` at each wavelength: the factor on a roughness's amplitude.

    Parameters
    ----------
    wavelength : array_like
        Roughness wavelengths (m), positive.
    semi_length : float
        The contact's semi-length a along the rail (m), :func:`contact_semi_length`.

    Returns
    -------
    ndarray
        The factor (-), the shape of ``wavelength``: 1 at long wavelengths, negative (the average
        in opposite phase) between the zeros of J1 at short ones.

    Examples
    --------
    >>> contact_filter([1.0, 0.0125], 0.006).round(3).tolist()
    [1.0, 0.221]
    """
    lam = as_real_array(wavelength, "wavelength")
    if lam.size and not np.all(lam > 0):
        raise InputError(f"wavelength must be positive (m), got {lam[~(lam > 0)].ravel()[0]!r}")
    if lam.size and not np.all((lam >= WAVELENGTH_RANGE[0]) & (lam <= WAVELENGTH_RANGE[1])):
        bad = lam[~((lam >= WAVELENGTH_RANGE[0]) & (lam <= WAVELENGTH_RANGE[1]))].ravel()[0]
        lo, hi = WAVELENGTH_RANGE
        raise InputError(f"wavelength must be from {lo:g} to {hi:g} m (a roughness's), got {bad!r}")
    a = check_in_range("semi_length", check_positive("semi_length", semi_length), SEMI_LENGTH_RANGE,
                       "m, a contact patch's half length")
    ka = 2 * np.pi * a / lam
    out = np.ones(lam.shape)
    small = ka < 1e-4  # 2 J1(z)/z = 1 - z^2/8 + ...: the series, not 0/0
    out[small] = 1.0 - ka[small] ** 2 / 8
    out[~small] = 2 * j1(ka[~small]) / ka[~small]
    return out


def contact_filtered(roughness: Roughness, wheel: Wheel, *, E: float = STEEL_E,
                     poisson: float = STEEL_POISSON) -> Roughness:
    """``roughness`` as the contact feels it: each line scaled by :func:`contact_filter` of its wavelength.

    A negative factor turns the line's phase by pi; the amplitudes stay non-negative.

    Parameters
    ----------
    roughness : Roughness
        The roughness of the running surface.
    wheel : Wheel
        The wheel whose contact averages it (:func:`contact_semi_length`).
    E, poisson : float
        The steel's elastic constants (N/m^2, -).

    Returns
    -------
    Roughness
        The filtered roughness, its label marked.
    """
    if not isinstance(roughness, Roughness):
        raise InputTypeError(f"roughness must be a Roughness, got {type(roughness).__name__}")
    factor = contact_filter(roughness.wavelengths, contact_semi_length(wheel, E=E, poisson=poisson))
    label = f"{roughness.label} (contact-filtered)" if roughness.label else "contact-filtered"
    return Roughness(roughness.frequencies, roughness.amplitudes * np.abs(factor),
                     np.mod(roughness.phases + np.pi * (factor < 0), 2 * np.pi), roughness.speed, roughness.period,
                     label=label)
