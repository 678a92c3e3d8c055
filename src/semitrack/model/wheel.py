"""A wheel on the rail: unsprung mass, optional primary suspension, static preload, Hertzian contact.

The paper's motivation (its Sec. 1) is the time-domain interaction of wheels and track at high
frequencies; this is the wheel side of it. Conventions follow the track's: displacements
downward, time factor exp(i omega t). The contact force F is the compression between wheel and
rail (positive when they press together). The Hertzian law for two elastic bodies of revolution
is F = C_H max(delta, 0)^(3/2) with delta the approach of the two bodies; wheel and rail lose
contact where delta < 0.

Linearised about the static preload P0 (the wheel's share of the vehicle's weight), the contact
is a spring of stiffness k_H = dF/ddelta = 1.5 C_H^(2/3) P0^(1/3).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ..base.checks import (
    as_frequencies,
    as_real_array,
    brief,
    check_choice,
    check_in_range,
    check_nonnegative,
    check_positive,
)
from ..base.errors import BadInput, InputError, InputTypeError
from .wheel_defects import RADIUS_RANGE, WheelDefect

#: Largest approach of wheel and rail read by the contact law (m): a real one is below 0.1 mm.
MAX_APPROACH = 0.1
#: A Hertz constant typical of a 0.46 m wheel on a 0.3 m rail head (N/m^1.5), the Wheel default.
DEFAULT_HERTZ_CONSTANT = 9.3e10


#: The masses a Wheel may have (kg): from 1e-9 kg, a massless wheel (the limit case of the linear
#: theory), to 1e15 kg, an immovable one, around every real unsprung mass (~300-1500 kg). Beyond,
#: the wheel's omega^2 m and a time step's M / dt^2 over- or underflow beside the contact stiffness
#: (at 1e300 or 1e-300 kg the contact forces were NaN).
MASS_RANGE = (1e-9, 1e15)
#: The other fields' physical ranges, each far around the real values (a preload of 50-150 kN, a
#: Hertz constant of 0.5-2e11 N/m^1.5, a primary suspension of about 1e6 N/m and 1e4 N s/m); beyond
#: them the contact's and the suspension's terms over- or underflow beside each other.
PRELOAD_RANGE = (1e-3, 1e9)  # N
HERTZ_RANGE = (1e5, 1e24)  # N/m^1.5 (the stiff-contact limit case takes 1e23)
PRIMARY_STIFFNESS_RANGE = (0.0, 1e13)  # N/m
PRIMARY_DAMPING_RANGE = (0.0, 1e10)  # N s/m
#: The radius of the rail head and the Young's modulus :meth:`Wheel.from_radii` takes (m, N/m^2).
RAIL_RADIUS_RANGE = (1e-3, 1e3)
MODULUS_RANGE = (1e6, 1e13)
#: How the wheel meets the rail's profile and its own defects: its centre's path over them
#: (:func:`semitrack.wheel_centre_path`, the wheel's radius in the contact) or the profile under
#: its centre (a point contact, the model before 0.3).
CONTACT_GEOMETRIES = ("centre_path", "point")
#: Most defects one wheel carries.
MAX_DEFECTS = 100


@dataclass(frozen=True)
class Wheel:
    """A wheel: its unsprung mass, an optional primary suspension to a fixed bogie, a preload.

    Parameters
    ----------
    mass : float
        Unsprung mass of the wheel (half a wheelset) (kg), within :data:`MASS_RANGE`.
    preload : float
        Static wheel load P0 (N), pressing the wheel onto the rail.
    hertz_constant : float
        C_H of the Hertzian contact F = C_H delta^(3/2) (N/m^1.5); see :meth:`from_radii`.
    primary_stiffness : float
        Stiffness of the primary suspension between the wheel and a bogie held still (N/m); 0
        (default) for a free unsprung mass, which the suspension barely changes above ~20 Hz.
    primary_damping : float
        Viscous damping of the primary suspension (N s/m).
    radius : float
        Rolling radius R (m), within :data:`RADIUS_RANGE`: the circle its defects lie on and its
        centre's path rolls (the Hertz constant is given apart, or by :meth:`from_radii`).
    defects : sequence of WheelFlat or WheelPolygon
        Defects of the tread (:mod:`semitrack.model.wheel_defects`); their deviations add up.
        Each route meets them once per revolution of the rolling wheel.
    contact : {"centre_path", "point"}
        How the wheel meets the rail's profile (a :class:`semitrack.DippedWeld`, a
        :class:`semitrack.RailProfile`) and its own defects: "centre_path" (default), by the path
        of its centre rolled over them (:func:`semitrack.wheel_centre_path`); "point", by the
        profile under its centre and the tread's deviation at the point in contact, as before 0.3.
        A roughness (:class:`semitrack.Roughness`) enters as given either way: it is a signal
        already met by a wheel.

    Examples
    --------
    >>> import semitrack as st
    >>> wheel = st.Wheel(mass=600.0, preload=1e5)
    >>> round(wheel.contact_stiffness / 1e9, 2)  # linearised Hertz stiffness, GN/m
    1.43
    """

    mass: float = 600.0
    preload: float = 1e5
    hertz_constant: float = DEFAULT_HERTZ_CONSTANT
    primary_stiffness: float = 0.0
    primary_damping: float = 0.0
    radius: float = 0.46
    defects: Sequence[WheelDefect] = ()
    contact: str = "centre_path"

    def __post_init__(self):
        for key in ("mass", "preload", "hertz_constant"):
            object.__setattr__(self, key, check_positive(key, getattr(self, key)))
        check_in_range("mass", self.mass, MASS_RANGE, "kg, from the massless limit to the immovable one; "
                       "beyond, omega^2 m over- or underflows beside the contact stiffness")
        check_in_range("preload", self.preload, PRELOAD_RANGE, "N, around a wheel's static load")
        check_in_range("hertz_constant", self.hertz_constant, HERTZ_RANGE, "N/m^1.5, around a steel contact's")
        for key, bounds, unit in (("primary_stiffness", PRIMARY_STIFFNESS_RANGE, "N/m"),
                                  ("primary_damping", PRIMARY_DAMPING_RANGE, "N s/m")):
            value = check_nonnegative(key, getattr(self, key))
            object.__setattr__(self, key, check_in_range(key, value, bounds, f"{unit}, around a primary suspension's"))
        radius = check_in_range("radius", check_positive("radius", self.radius), RADIUS_RANGE,
                                "m, a wheel's rolling radius")
        object.__setattr__(self, "radius", radius)
        object.__setattr__(self, "defects", _checked_defects(self.defects, self.radius))
        check_choice("contact", self.contact, CONTACT_GEOMETRIES)

    @classmethod
    def from_radii(cls, wheel_radius: float = 0.46, rail_radius: float = 0.3, E: float = 2.1e11,
                   poisson: float = 0.3, **wheel) -> Wheel:
        """A wheel whose Hertz constant follows from the radii of wheel and rail head.

        Both bodies of steel (``E``, ``poisson``); the contact ellipse is approximated by a circle
        of the geometric-mean radius R = sqrt(R_wheel R_rail), so that
        C_H = (4/3) E* sqrt(R) with E* = E / (2 (1 - nu^2)) (within a few per cent of the
        elliptic solution for the usual ratio of radii).

        Parameters
        ----------
        wheel_radius : float
            Rolling radius of the wheel (m).
        rail_radius : float
            Transverse radius of the rail head (m).
        E : float
            Young's modulus of both (N/m^2).
        poisson : float
            Poisson's ratio of both (-), in [0, 0.5).
        **wheel
            The other :class:`Wheel` fields (``mass``, ``preload``, ...).

        Returns
        -------
        Wheel
        """
        r_w, r_r, e = (check_positive(k, v) for k, v in
                       (("wheel_radius", wheel_radius), ("rail_radius", rail_radius), ("E", E)))
        check_in_range("wheel_radius", r_w, RADIUS_RANGE, "m, a wheel's rolling radius")
        check_in_range("rail_radius", r_r, RAIL_RADIUS_RANGE, "m, a rail head's transverse radius")
        check_in_range("E", e, MODULUS_RANGE, "N/m^2, a solid's Young's modulus")
        nu = check_nonnegative("poisson", poisson)
        if not nu < 0.5:
            raise InputError(f"poisson must be in [0, 0.5), got {poisson!r}")
        e_star = e / (2 * (1 - nu**2))
        if "radius" in wheel:
            raise InputError("radius: from_radii takes the wheel's radius as wheel_radius")
        return cls(hertz_constant=4.0 / 3.0 * e_star * np.sqrt(np.sqrt(r_w * r_r)), radius=r_w, **wheel)

    @property
    def circumference(self) -> float:
        """2 pi R (m)."""
        return 2 * np.pi * self.radius

    def tread_profile(self, arc_length: ArrayLike) -> np.ndarray:
        """The tread's radial deviation at ``arc_length`` (m): positive where material is missing (m).

        The sum of the defects' deviations (:mod:`semitrack.model.wheel_defects`); the arc length
        from the point in contact at the run's start, periodic in the circumference.

        Parameters
        ----------
        arc_length : array_like
            Arc lengths along the tread (m).

        Returns
        -------
        ndarray
            The deviation (m), the shape of ``arc_length``.
        """
        s = as_real_array(arc_length, "arc_length")
        if s.size and np.abs(s).max() > 1e7:
            raise InputError(f"arc_length must be within 1e7 m (arc lengths on a tread keep their micrometres), got "
                             f"{np.abs(s).max()!r}")
        out = np.zeros(s.shape)
        for defect in self.defects:
            out = out + defect._deviation(s, self.radius)
        return out

    @property
    def contact_stiffness(self) -> float:
        """k_H = 1.5 C_H^(2/3) P0^(1/3), the contact linearised at the preload (N/m)."""
        return 1.5 * self.hertz_constant ** (2 / 3) * self.preload ** (1 / 3)

    @property
    def static_approach(self) -> float:
        """delta_0 = (P0 / C_H)^(2/3), the contact's compression under the preload alone (m)."""
        return (self.preload / self.hertz_constant) ** (2 / 3)

    def contact_force(self, approach: ArrayLike) -> np.ndarray:
        """Hertzian contact force C_H max(delta, 0)^(3/2) (N), zero out of contact.

        Parameters
        ----------
        approach : array_like
            The approach delta of wheel and rail (m), positive in contact.

        Returns
        -------
        ndarray
            The force (N), the shape of ``approach``.
        """
        approach = as_real_array(approach, "approach")
        if approach.size and np.abs(approach).max() > MAX_APPROACH:
            raise InputError(f"approach must be within {MAX_APPROACH:g} m (a contact, not a collision), got "
                             f"{np.abs(approach).max()!r}")
        return self.hertz_constant * np.maximum(approach, 0.0) ** 1.5

    def receptance(self, f: ArrayLike) -> np.ndarray:
        """Vertical receptance of the wheel, downward displacement per downward force (m/N).

        ``1 / (k_1 + i omega c_1 - omega^2 m)``: -1/(omega^2 m) for a free unsprung mass.

        Parameters
        ----------
        f : array_like
            Frequencies (Hz), positive and finite.

        Returns
        -------
        ndarray of complex, the shape of ``f``
        """
        return 1.0 / self.dynamic_stiffness(f)

    def dynamic_stiffness(self, f: ArrayLike) -> np.ndarray:
        """Vertical dynamic stiffness of the wheel, ``k_1 + i omega c_1 - omega^2 m`` (N/m).

        The inverse of :meth:`receptance`, finite everywhere: it is 0 at the resonance of an
        undamped primary suspension, where the receptance is infinite.

        Parameters
        ----------
        f : array_like
            Frequencies (Hz), positive and finite.

        Returns
        -------
        ndarray of complex, the shape of ``f``
        """
        omega = 2 * np.pi * as_frequencies(f)
        return self.primary_stiffness + 1j * omega * self.primary_damping - omega**2 * self.mass


def _checked_defects(defects: object, radius: float) -> tuple[WheelDefect, ...]:
    """The wheel's defects as a tuple, each checked on a wheel of ``radius`` (m)."""
    if isinstance(defects, WheelDefect) or isinstance(defects, (str, bytes, np.ndarray)) or \
            not isinstance(defects, Sequence):
        raise InputTypeError(f"defects must be a sequence of WheelFlat or WheelPolygon, got {brief(defects)}")
    if len(defects) > MAX_DEFECTS:
        raise InputError(f"defects must be at most {MAX_DEFECTS} on one wheel, got {len(defects)}")
    for k, defect in enumerate(defects):
        if not isinstance(defect, WheelDefect):
            raise InputTypeError(f"defects[{k}] must be a WheelFlat or a WheelPolygon, got {type(defect).__name__}")
        try:
            defect._check_on(radius)
        except BadInput as err:  # the defect's own rule, said as the wheel's argument
            raise type(err)(f"defects[{k}] on a wheel of radius {radius:g} m: {err}") from None
    return tuple(defects)
