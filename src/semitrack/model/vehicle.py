"""Vehicles on one rail: wheels at fixed spacings, each on its own suspension, or a bogie that carries two.

A vehicle is what the rail meets at its contacts: k wheels at fixed offsets along the track, each
with its Hertzian contact (:class:`semitrack.Wheel`), and a linear mechanical system behind
them, ``M a + C v + K u = f``, whose first k DOFs are the wheels' vertical displacements
(downward, as the rail's). Two kinds:

:class:`WheelGroup`
    independent wheels, each on its primary suspension to a bogie held still (the wheels of
    :func:`semitrack.wheel_rail_response` given as a list);
:class:`Bogie`
    a bogie on one rail: two wheels (half wheelsets) a wheelbase apart under a frame that
    bounces and pitches on the wheels' primary suspensions, and optionally a car-body mass on a
    secondary suspension above the frame's centre.

Each gives its receptance matrix at the wheels (the frequency-domain theory couples it to the
rail's, :func:`semitrack.wheel_rail_force`) and its static state: the run starts in equilibrium
with every contact carrying its wheel's preload P0 as a load on the wheel, the suspensions
unstretched (bogie) or carrying nothing of it (wheels on a still bogie). For a linear vehicle
this is gravity with pre-stressed springs up to a constant offset of every DOF: the motion about
it is the same. The masses above the wheels are the vehicle's dynamics, not its weight.

Positions: ``offsets`` are the wheels' positions along +x (the direction of travel) from the
first wheel; a bogie's first wheel leads (``offsets = (0, -wheelbase)``).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from ..base.checks import (
    as_frequencies,
    as_real_array,
    brief,
    check_in_range,
    check_nonnegative,
    check_positive,
    check_real,
)
from ..base.errors import InputError, InputTypeError
from ..dynamics.newmark import Newmark
from ..dynamics.system import SecondOrderSystem
from .wheel import MASS_RANGE, Wheel

__all__ = ["Vehicle", "WheelGroup", "Bogie", "as_vehicle", "vehicle_step"]

#: Farthest a wheel starts from x = 0 (m): 10 000 km, beyond any line (and where positions keep
#: their millimetres in a double).
MAX_POSITION = 1e7
#: Longest wheelbase of a bogie or group (m): a car's bogie centres are ~20 m apart.
MAX_WHEELBASE = 50.0


class Vehicle:
    """What the package asks of a vehicle (the base of :class:`WheelGroup` and :class:`Bogie`)."""

    @property
    def wheels(self) -> tuple[Wheel, ...]:
        """The wheels in contact, in the order of :attr:`offsets`."""
        raise NotImplementedError

    @property
    def offsets(self) -> np.ndarray:
        """Each wheel's position along +x from the first wheel (m)."""
        raise NotImplementedError

    @property
    def wheel_names(self) -> tuple[str, ...]:
        """How tables and figures name the wheels, in the order of :attr:`wheels`."""
        raise NotImplementedError

    def matrices(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``M, C, K`` of the vehicle (SI), its first k DOFs the wheels'."""
        raise NotImplementedError

    def system(self) -> SecondOrderSystem:
        """The vehicle as a second-order system, its first block ``"wheels"`` (k DOFs).

        Returns
        -------
        SecondOrderSystem
        """
        M, C, K = self.matrices()
        k = len(self.wheels)
        blocks = {"wheels": slice(0, k)}
        if M.shape[0] > k:
            blocks["body"] = slice(k, M.shape[0])
        return SecondOrderSystem(M, C, K, blocks)

    def receptance(self, f: ArrayLike) -> np.ndarray:
        """The vehicle's receptance at its wheels: downward displacement of wheel i per downward force on wheel j.

        Parameters
        ----------
        f : array_like
            Frequencies (Hz), positive and finite.

        Returns
        -------
        ndarray of complex, shape ``f.shape + (k, k)``
            m/N; symmetric (reciprocal).
        """
        f = as_frequencies(f)
        omega = 2 * np.pi * np.atleast_1d(f)
        M, C, K = self.matrices()
        k = len(self.wheels)
        Z = K[None] + 1j * omega[:, None, None] * C[None] - omega[:, None, None] ** 2 * M[None]
        unit = np.zeros((M.shape[0], k))
        unit[:k, :k] = np.eye(k)
        out = np.linalg.solve(Z, np.broadcast_to(unit, Z.shape[:2] + (k,)))[:, :k, :]
        return out.reshape(f.shape + (k, k))

    def static_state(self, w_wheels: ArrayLike) -> np.ndarray:
        """The vehicle's DOFs at the start, given its wheels' static displacements.

        Parameters
        ----------
        w_wheels : array_like
            The wheels' static displacements (m).

        Returns
        -------
        ndarray
        """
        raise NotImplementedError

    def positions(self, x: float | ArrayLike, name: str = "x") -> np.ndarray:
        """The wheels' positions (m) from the first wheel's or from one per wheel.

        Parameters
        ----------
        x : float or array_like
            One position per wheel, or (a vehicle whose wheels have offsets) the first wheel's.
        name : str
            The parameter's name in messages.

        Returns
        -------
        ndarray, shape (k,)
        """
        k = len(self.wheels)
        try:
            xs = np.atleast_1d(as_real_array(x, name, finite=False)).ravel()
        except (TypeError, ValueError):
            raise InputTypeError(f"{name} must be a position (m) or one per wheel, got {brief(x)}") from None
        if not np.all(np.isfinite(xs)):
            raise InputError(f"{name} must be finite (m), got {brief(x)}")
        if xs.size == 0:
            raise InputError(f"{name} must give a position (m), got an empty array")
        if np.abs(xs).max() > MAX_POSITION:
            raise InputError(f"{name} must lie within {MAX_POSITION:g} m of x = 0 (a line's length), got "
                             f"{np.abs(xs).max()!r} m")
        offsets = self.offsets
        if xs.size == 1 and k > 1 and np.any(offsets):
            return xs[0] + offsets
        if xs.size != k:
            raise InputError(f"{name} must give one position per wheel ({k}), got {x!r}")
        if k > 1 and np.any(offsets) and not np.allclose(xs - xs[0], offsets, rtol=0, atol=1e-9):
            raise InputError(f"{name} must follow the vehicle's wheel offsets {offsets.tolist()} m, got {x!r}")
        return xs

    def static_loads(self, u0: np.ndarray) -> np.ndarray:
        """The constant loads on the vehicle's DOFs (N) that hold it in ``u0`` with every contact at its preload.

        Parameters
        ----------
        u0 : ndarray
            The vehicle's static state (:meth:`static_state`).

        Returns
        -------
        ndarray
            ``K u0`` plus each wheel's preload on its wheel.
        """
        loads = self.matrices()[2] @ u0
        loads[: len(self.wheels)] += [w.preload for w in self.wheels]
        return loads


@dataclass(frozen=True)
class WheelGroup(Vehicle):
    """Independent wheels at fixed offsets, each on its primary suspension to a bogie held still.

    Parameters
    ----------
    members : sequence of Wheel
        The wheels.
    spacing : sequence of float, optional
        Each wheel's position along +x from the first (m); default all at one point (their
        positions are given where they are used).
    """

    members: tuple = ()
    spacing: tuple = field(default=())

    def __post_init__(self):
        members = tuple(self.members) if isinstance(self.members, (list, tuple)) else ()
        if not members or not all(isinstance(w, Wheel) for w in members):
            raise InputTypeError(f"wheels must be semitrack Wheels (e.g. st.Wheel()), got {self.members!r}")
        if not isinstance(self.spacing, (list, tuple, np.ndarray)):
            raise InputTypeError(f"spacing must be a sequence of offsets (m), got {type(self.spacing).__name__}")
        offsets = tuple(check_real("spacing", s) for s in self.spacing) or (0.0,) * len(members)
        if not all(np.isfinite(offsets)):
            raise InputError(f"spacing must be finite offsets (m), got {self.spacing!r}")
        if len(offsets) != len(members):
            raise InputError(f"spacing must give one offset per wheel ({len(members)}), got {self.spacing!r}")
        object.__setattr__(self, "members", members)
        object.__setattr__(self, "spacing", offsets)

    @property
    def wheels(self) -> tuple[Wheel, ...]:
        return self.members

    @property
    def offsets(self) -> np.ndarray:
        return np.array(self.spacing)

    @property
    def wheel_names(self) -> tuple[str, ...]:
        """``("wheel",)`` for one wheel, ``("wheel 1", "wheel 2", ...)`` for several, in the order of :attr:`wheels`."""
        return ("wheel",) if len(self.members) == 1 else tuple(f"wheel {i}" for i in range(1, len(self.members) + 1))

    def matrices(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        return (np.diag([w.mass for w in self.members]), np.diag([w.primary_damping for w in self.members]),
                np.diag([w.primary_stiffness for w in self.members]))

    def receptance(self, f: ArrayLike) -> np.ndarray:
        """Diagonal: each wheel's own receptance (:meth:`semitrack.Wheel.receptance`), m/N.

        Parameters
        ----------
        f : array_like
            Frequencies (Hz), positive and finite.

        Returns
        -------
        ndarray of complex, shape ``f.shape + (k, k)``
        """
        f = as_frequencies(f)
        out = np.zeros(f.shape + (len(self.members),) * 2, dtype=complex)
        for i, w in enumerate(self.members):
            out[..., i, i] = w.receptance(f)
        return out

    def static_state(self, w_wheels: ArrayLike) -> np.ndarray:
        """The wheels alone: their own static displacements.

        Parameters
        ----------
        w_wheels : array_like
            The wheels' static displacements (m).

        Returns
        -------
        ndarray
        """
        return as_real_array(w_wheels, "w_wheels")


@dataclass(frozen=True)
class Bogie(Vehicle):
    """A bogie on one rail: two wheels under a frame (bounce and pitch), optionally a car body above.

    Values are per rail (half the bogie's frame, half its pitch inertia, a quarter of a car body
    on two bogies). The defaults are of the order of a passenger bogie, for illustration, not a
    particular vehicle's data.

    Parameters
    ----------
    wheel : Wheel
        Each wheel: unsprung mass (half a wheelset), preload (the static wheel load), Hertz
        constant, and its primary suspension, which here joins it to the frame (N/m, N s/m).
    wheelbase : float
        Distance between the two wheels (m).
    frame_mass : float
        Mass of the frame (kg, per rail).
    frame_inertia : float
        Pitch inertia of the frame about its centre (kg m^2, per rail).
    body_mass : float
        A car-body mass on the secondary suspension (kg, per rail); 0 (default) for none.
    secondary_stiffness, secondary_damping : float
        The secondary suspension between frame centre and body (N/m, N s/m).

    Examples
    --------
    >>> import semitrack as st
    >>> bogie = st.Bogie()
    >>> bogie.offsets.tolist(), bogie.system().n_dof
    ([0.0, -2.5], 4)
    """

    wheel: Wheel = field(default_factory=lambda: Wheel(mass=600.0, preload=1e5, primary_stiffness=1.2e6,
                                                       primary_damping=1.5e4))
    wheelbase: float = 2.5
    frame_mass: float = 1250.0
    frame_inertia: float = 1200.0
    body_mass: float = 0.0
    secondary_stiffness: float = 4e5
    secondary_damping: float = 2e4

    def __post_init__(self):
        if not isinstance(self.wheel, Wheel):
            raise InputTypeError(f"wheel must be a semitrack Wheel, got {type(self.wheel).__name__}")
        if not self.wheel.primary_stiffness > 0:
            raise InputError("a bogie's frame rests on its wheels' primary suspensions: wheel.primary_stiffness "
                             f"must be > 0 N/m, got {self.wheel.primary_stiffness!r}")
        object.__setattr__(self, "wheelbase", check_in_range("wheelbase", check_positive("wheelbase", self.wheelbase),
                                                              (0.0, MAX_WHEELBASE), "m, a bogie's"))
        for key in ("frame_mass", "frame_inertia"):  # the wheel's range: beyond it the matrices overflow
            object.__setattr__(self, key, check_in_range(key, check_positive(key, getattr(self, key)), MASS_RANGE,
                                                         "kg or kg m^2, as a wheel's mass"))
        for key in ("body_mass", "secondary_stiffness", "secondary_damping"):
            object.__setattr__(self, key, check_nonnegative(key, getattr(self, key)))
        if self.body_mass > MASS_RANGE[1]:
            raise InputError(f"body_mass must be at most {MASS_RANGE[1]:g} kg, got {self.body_mass!r}")
        if self.body_mass > 0 and not self.secondary_stiffness > 0:
            raise InputError("a car body rests on the secondary suspension: secondary_stiffness must be > 0 N/m "
                             f"with body_mass={self.body_mass!r} kg")

    @property
    def wheels(self) -> tuple[Wheel, ...]:
        return (self.wheel, self.wheel)

    @property
    def offsets(self) -> np.ndarray:
        return np.array([0.0, -self.wheelbase])

    @property
    def wheel_names(self) -> tuple[str, ...]:
        """The first wheel leads (offset 0, the bogie runs towards +x), the second trails it."""
        return ("leading wheel", "trailing wheel")

    def _lever(self) -> np.ndarray:
        """The frame's (bounce, pitch) motion at each wheel: w = z + s theta, s from the centre along +x."""
        half = 0.5 * self.wheelbase
        return np.array([[1.0, half], [1.0, -half]])

    def matrices(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``M, C, K``: DOFs (wheel 1, wheel 2, frame bounce z, frame pitch theta, [body]).

        Returns
        -------
        M, C, K : ndarray
            kg, kg m^2; N s/m...; N/m... (theta in rad, positive when the leading end dips).
        """
        body = self.body_mass > 0
        n = 5 if body else 4
        # each primary spring stretches by w_i - (z + s_i theta): the map e = T u
        T = np.zeros((2, n))
        T[:, :2] = np.eye(2)
        T[:, 2:4] = -self._lever()
        K = self.wheel.primary_stiffness * T.T @ T
        C = self.wheel.primary_damping * T.T @ T
        M = np.diag([self.wheel.mass, self.wheel.mass, self.frame_mass, self.frame_inertia] + ([self.body_mass] * body))
        if body:
            e = np.zeros(n)
            e[2], e[4] = -1.0, 1.0  # the secondary stretches by z_body - z
            K = K + self.secondary_stiffness * np.outer(e, e)
            C = C + self.secondary_damping * np.outer(e, e)
        return M, C, K

    def static_state(self, w_wheels: ArrayLike) -> np.ndarray:
        """The frame (and body) placed on the wheels with every spring unstretched.

        Parameters
        ----------
        w_wheels : array_like
            The two wheels' static displacements (m).

        Returns
        -------
        ndarray
            ``(w1, w2, z, theta[, z_body])``.
        """
        w = as_real_array(w_wheels, "w_wheels")
        if w.shape != (2,):
            raise InputError(f"w_wheels must be the two wheels' displacements (m), got shape {w.shape}")
        z_theta = np.linalg.solve(self._lever(), w)
        return np.concatenate([w, z_theta, [z_theta[0]] if self.body_mass > 0 else []])


def as_vehicle(vehicle: Vehicle | Wheel | Sequence[Wheel], spacing: Sequence[float] = ()) -> Vehicle:
    """A vehicle from what users give: a Vehicle, one Wheel, or a list of Wheels.

    Parameters
    ----------
    vehicle : Vehicle, Wheel or sequence of Wheel
        The vehicle, or wheels each on its own suspension to a bogie held still.
    spacing : sequence of float
        The wheels' offsets along +x from the first (m), for a list of wheels.

    Returns
    -------
    Vehicle
    """
    if isinstance(vehicle, Vehicle):
        return vehicle
    if isinstance(vehicle, Wheel):
        return WheelGroup((vehicle,), tuple(spacing))
    if isinstance(vehicle, (list, tuple)):
        return WheelGroup(tuple(vehicle), tuple(spacing))
    raise InputTypeError(f"wheel must be a semitrack Wheel (e.g. st.Wheel()), a list of them or a vehicle "
                         f"(st.Bogie()), got {type(vehicle).__name__}")


def vehicle_step(vehicle: Vehicle, stepper: Newmark) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The vehicle's mass, damping and effective stiffness's inverse for a Newmark step.

    The routes that hold no model of the track in the loop step the vehicle alone, with the
    rail under its wheels given by a convolution (:mod:`semitrack.interaction.convolved_run`).

    Parameters
    ----------
    vehicle : Vehicle
        The vehicle.
    stepper : Newmark
        The scheme and its step.

    Returns
    -------
    M, C, inverse : ndarray
        ``(n_v, n_v)`` each (kg, N s/m and m/N).
    """
    M, C, K = vehicle.matrices()
    a0, a1 = stepper.coefficients[:2]
    return M, C, np.linalg.inv(K + a1 * C + a0 * M)
