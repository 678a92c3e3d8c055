"""The one input check of a vehicle's run on the rail, shared by every route.

:func:`check_run` takes what every route takes (the vehicle or its wheels, the roughness, where
the wheels start, their speed, the step, the duration and the fade-in) and gives them back
checked, as a :class:`RunInputs`: the vehicle, the scalars, the number of steps and every
wheel's path along the rail. A route adds only the checks of what it alone takes.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from ..base.checks import check_nonnegative, check_positive, check_steps, check_time_step, check_work, shown
from ..base.errors import InputError, InputTypeError
from ..dynamics.simulate import MAX_RECORDED
from ..model.roughness import Roughness
from ..model.vehicle import Vehicle, as_vehicle
from ..model.wheel import Wheel

__all__ = ["RunInputs", "check_run", "check_roughness_speed", "DEFAULT_DT"]

#: The time step of every route when none is given (s): the average-acceleration rule shifts a
#: frequency f to ``tan(pi f dt) / (pi dt)``, +0.8 % at 2.5 kHz.
DEFAULT_DT = 2e-5


@dataclass(frozen=True)
class RunInputs:
    """What every route of a vehicle's run takes, checked.

    Attributes
    ----------
    vehicle : Vehicle
        The vehicle (a list of wheels becomes a :class:`semitrack.WheelGroup`).
    speed : float
        The wheels' speed along +x (m/s), >= 0.
    dt, duration, ramp : float
        Time step, run length and the roughness's fade-in (s).
    n_steps : int
        Steps of the run (bounded by :func:`semitrack.base.checks.check_steps`).
    x0 : ndarray, shape (k,)
        Where the wheels start (m from the central mid-span).
    speeds : ndarray, shape (n_steps + 1,), optional
        The speed at each step (m/s) when it varies (``speed`` is then the first).
    """

    vehicle: Vehicle
    speed: float
    dt: float
    duration: float
    ramp: float
    n_steps: int
    x0: np.ndarray
    speeds: np.ndarray | None = None

    @property
    def t(self) -> np.ndarray:
        """Times of the steps (s), from 0."""
        return self.dt * np.arange(self.n_steps + 1)

    def path(self) -> np.ndarray:
        """Every wheel's position at every step (m), shape ``(n_steps + 1, k)``: ``x0 + speed t``, or
        ``x0`` plus the speed's integral by the trapezoidal rule (the average-acceleration rule's
        own, so that a constant ``speed(t)`` gives the constant speed's path to round-off)."""
        if self.speeds is None:
            return self.x0[None, :] + self.speed * self.dt * np.arange(self.n_steps + 1)[:, None]
        travelled = np.r_[0.0, np.cumsum(0.5 * self.dt * (self.speeds[1:] + self.speeds[:-1]))]
        return self.x0[None, :] + travelled[:, None]

    @property
    def moving(self) -> bool:
        """Whether the wheels roll along the rail."""
        return self.speed > 0 or self.speeds is not None

    @property
    def k(self) -> int:
        """Number of wheels."""
        return len(self.vehicle.wheels)


def check_roughness_speed(roughness: Roughness | None, speed: float, rounded: float | None = None) -> None:
    """A rolling wheel meets a roughness at its own speed: ``roughness.speed`` must be ``speed`` (or ``rounded``).

    Parameters
    ----------
    roughness : Roughness or None
        The roughness (None: a smooth rail, nothing to check).
    speed : float
        The wheels' speed (m/s); 0 (stationary wheels) accepts any roughness.
    rounded : float, optional
        A route's speed as it runs it (the moving Green's functions round it), also accepted.
    """
    if roughness is None or speed == 0:
        return
    accepted = (speed,) if rounded is None else (speed, rounded)
    if not any(math.isclose(roughness.speed, v, rel_tol=1e-9) for v in accepted):
        also = "" if rounded is None else f" (or the rounded {shown(rounded)} m/s)"
        raise InputError(f"a rolling wheel passes the roughness at its own speed: roughness.speed must equal "
                         f"speed={shown(speed)} m/s{also}, got {shown(roughness.speed)} m/s")


def check_run(wheel: Wheel | Vehicle | Sequence[Wheel], roughness: Roughness | None, x: float | Sequence[float],
              speed: float | Callable[[float], float], dt: float, duration: float, ramp: float, *, name: str = "x",
              check_speed: bool = True, varying: bool = False) -> RunInputs:
    """The checked inputs of a vehicle's run (see the module docstring).

    Parameters
    ----------
    wheel : Wheel, sequence of Wheel, or Vehicle
        The vehicle, or wheels on their own suspensions.
    roughness : Roughness or None
        The roughness under the first wheel; None: a smooth rail. Rolling wheels must meet it at
        their speed.
    x : float or sequence of float
        Where the wheels start (m): one position per wheel, or a vehicle's first wheel's.
    speed : float or callable
        The wheels' speed (m/s), >= 0; with ``varying``, also a function ``speed(t)`` of the time
        (s), >= 0 at every step (braking or accelerating).
    dt, duration, ramp : float
        Time step, run length and fade-in (s), positive; ``duration > ramp``.
    name : str
        The start's parameter name in messages.
    check_speed : bool
        Check the roughness's speed here (:func:`check_roughness_speed`); False for a route that
        checks it against the speed it rounds to as well.
    varying : bool
        Whether the route takes a speed that varies (the FE routes).

    Returns
    -------
    RunInputs
    """
    vehicle = as_vehicle(wheel)
    if roughness is not None and not isinstance(roughness, Roughness):
        raise InputTypeError(f"roughness must be None (a smooth rail) or a Roughness (roughness_from_spectrum, "
                             f"corrugation), got {type(roughness).__name__}")
    x0 = vehicle.positions(x, name)
    dt, duration, ramp = check_time_step("dt", dt), check_positive("duration", duration), check_positive("ramp", ramp)
    if not duration > ramp:
        raise InputError(f"duration must exceed ramp = {ramp!r} s (the roughness's fade-in), got {duration!r}")
    n_steps = check_steps(dt, duration)
    k = len(x0)  # every route records force, wheel, rail and roughness per wheel per step, and the time
    check_work((n_steps + 1) * (4 * k + 1), MAX_RECORDED, f"duration={duration!r} s / dt={dt!r} s = {n_steps} steps of "
               f"{k} wheel(s) record {(n_steps + 1) * (4 * k + 1)} values", "simulate less, or with a larger dt")
    speeds = None
    if callable(speed):
        if not varying:
            raise InputError("speed: a speed that varies, speed(t), runs on an FE model (TruncatedTrack or "
                             "WindowTrack); this route takes a constant speed")
        speeds = _speeds(speed, dt, n_steps)
        if roughness is not None:
            raise InputError("roughness: a Roughness is a signal in time at one speed; with a varying speed give the "
                             "rail's profile along x instead: profile=roughness.along_rail(start, length)")
        speed = float(speeds[0])
    speed = check_nonnegative("speed", speed)
    if check_speed:
        check_roughness_speed(roughness, speed)
    return RunInputs(vehicle=vehicle, speed=speed, dt=dt, duration=duration, ramp=ramp, n_steps=n_steps, x0=x0,
                     speeds=speeds)


def _speeds(speed: Callable[[float], float], dt: float, n_steps: int) -> np.ndarray:
    """``speed(t)`` at every step (m/s), checked non-negative and finite."""
    t = dt * np.arange(n_steps + 1)
    values = np.empty(t.size)
    for k, tk in enumerate(t):
        value = speed(float(tk))
        try:
            values[k] = float(value)
        except (TypeError, ValueError):
            raise InputTypeError(f"speed(t) must return a real number (m/s), got {value!r} at t = {tk:.6g} s") from None
    bad = ~(np.isfinite(values) & (values >= 0))
    if np.any(bad):
        k = int(np.argmax(bad))
        raise InputError(f"speed(t) must be non-negative and finite at every step of the run (the wheels do not "
                         f"reverse), got {float(values[k])!r} m/s at t = {t[k]:.6g} s of duration={t[-1]:.6g} s")
    return values
