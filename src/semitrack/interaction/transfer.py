"""The force per unit roughness of stationary wheels: a run's time domain beside the linear theory.

A periodic roughness (:class:`semitrack.Roughness`) has all its power on the lines of its period;
over whole periods the discrete Fourier transforms of the roughness and the contact force hold
them without leakage, and their ratio is the force per unit roughness on each line
(:func:`contact_transfer`). It takes the run of any route (:class:`ContactResponse`) and sets
beside it the linear theory of :func:`semitrack.wheel_rail_force` on the run's exact infinite
track, on the lines and in one-third-octave bands.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..base.bands import third_octave_bands
from ..base.checks import check_int_at_least, shown
from ..base.errors import InputError, InputTypeError
from ..base.fields import check_fields
from ..methods.wheelrail import wheel_rail_force
from .response import ContactResponse

__all__ = ["ContactTransfer", "contact_transfer"]


@dataclass(frozen=True, eq=False)
class ContactTransfer:
    """The contact force per unit roughness of a stationary wheel, time domain beside linear theory.

    Attributes
    ----------
    f : ndarray
        The roughness's lines in the analysed bands (Hz).
    H : ndarray of complex
        ``H1 = S_rF / S_rr`` on those lines (N/m): the time-domain force per unit roughness.
    linear : ndarray of complex
        :func:`semitrack.wheel_rail_force` on those lines (N/m), for the infinite track at the
        contact point.
    r_amplitude : ndarray
        Roughness amplitude of each line (m), the weights of the band levels.
    centres : ndarray
        Centres of the one-third-octave bands that hold at least one line (Hz).
    level, linear_level : ndarray
        Band levels of the force per unit roughness (dB re 1 N/m):
        ``10 log10(sum |H R|^2 / sum |R|^2)`` over the band's lines, time domain and linear.
    """

    f: np.ndarray
    H: np.ndarray
    linear: np.ndarray
    r_amplitude: np.ndarray
    centres: np.ndarray
    level: np.ndarray
    linear_level: np.ndarray

    def __post_init__(self):
        check_fields(self)  # a record built by hand is refused here, not in a method

    @property
    def error_db(self) -> np.ndarray:
        """``level - linear_level`` per band (dB)."""
        return self.level - self.linear_level


def _band_levels(H: np.ndarray, r: np.ndarray, band_of_line: np.ndarray, n_bands: int) -> np.ndarray:
    power = np.bincount(band_of_line, np.abs(H * r) ** 2, n_bands)
    return 10 * np.log10(power / np.bincount(band_of_line, r**2, n_bands))


def contact_transfer(response: ContactResponse, band: tuple[float, float] = (50.0, 2500.0),
                     periods: int = 1, wheel: int | None = None) -> ContactTransfer:
    """Force per unit roughness from the last whole roughness periods of a stationary wheel's run.

    A periodic roughness (:class:`semitrack.Roughness`) has all its power on lines ``j / period``;
    over whole periods the discrete Fourier transforms of r and F hold them without leakage, and
    ``H1 = sum_p conj(R_p) F_p / sum_p |R_p|^2`` (over the ``periods`` analysed) is the force per
    unit roughness on each line. The window must start after the fade-in (``response.t_full``),
    and the fade-in's transient must have decayed by then: on the viscous slab track the wheel's
    bounce (64 Hz, 1.1 % damping) leaves 1.6 dB in the 50 Hz band 0.3 s after the fade-in and
    0.26 dB after 0.7 s; on the ballasted track (5.5 %) 0.02 dB after 0.3 s (measured). The
    time domain's damping is viscous (:meth:`FETrack.matrices`): compare a track with
    ``damping="viscous"``, whose frequency domain has the same dampers.

    Parameters
    ----------
    response : ContactResponse
        A stationary wheel's run (``speed=0``) with a roughness whose period is a whole
        number of time steps.
    band : tuple of float
        The lowest and highest one-third-octave band centres (Hz) analysed (nominal values
        name their band).
    periods : int
        Number of whole roughness periods at the end of the record to analyse (>= 1).
    wheel : int, optional
        With several wheels, whose force: the transfer is then the force at that wheel per unit
        roughness under the first wheel, ``sum_j H_ij R_j / R_1`` in the linear theory (the
        roughness reaching wheel j earlier or later, :func:`semitrack.wheel_rail_force`'s matrix
        ``H`` on the model's exact infinite track). Required with several wheels.

    Returns
    -------
    ContactTransfer
    """
    if not isinstance(response, ContactResponse):
        raise InputTypeError(f"response must be a ContactResponse (wheel_rail_response), got {type(response).__name__}")
    n_wheels = 1 if response.force.ndim == 1 else response.force.shape[1]
    if wheel is None and n_wheels > 1:
        raise InputError(f"contact_transfer of a run with {n_wheels} wheels needs wheel=i (0 <= i < {n_wheels}): "
                         "the force at wheel i per unit roughness under the first wheel")
    wheel = check_int_at_least("wheel", 0 if wheel is None else wheel, 0)
    if wheel >= n_wheels:
        raise InputError(f"wheel must be below the number of wheels, {n_wheels}, got {wheel}")
    if response.period is None or response.speed != 0:
        raise InputError("contact_transfer needs a stationary wheel (speed=0) driven by a roughness, got "
                         f"speed={shown(response.speed)} m/s and period={shown(response.period)} s")
    try:
        lo, hi = band
    except (TypeError, ValueError):
        raise InputTypeError(f"band must be a pair (lowest, highest) of band centres in Hz, got {band!r}") from None
    periods = check_int_at_least("periods", periods, 1)
    dt, n_per = response.dt, response.period / response.dt
    if abs(n_per - round(n_per)) > 1e-6 * n_per:
        raise InputError(f"the roughness period {response.period!r} s must be a whole number of time steps "
                         f"dt={dt!r} s for a transfer without leakage")
    n_per = int(round(n_per))
    start = response.t.size - periods * n_per
    if start < 0 or response.t[start] < response.t_full - 1e-12:
        raise InputError(f"periods={periods} roughness periods of {response.period:.6g} s must fit after the fade-in "
                         f"(t >= {response.t_full:.6g} s) in a record of {response.t[-1]:.6g} s; simulate longer")
    column = (lambda a: a) if n_wheels == 1 else (lambda a: a[:, wheel])  # noqa: E731
    rough = response.roughness.reshape(response.t.size, -1)
    R_all = np.fft.rfft(rough[start:].T.reshape(n_wheels, periods, n_per), axis=2)  # every wheel's roughness
    R, F = R_all[0], np.fft.rfft(column(response.force)[start:].reshape(periods, n_per), axis=1)
    try:
        centres, lower, upper = third_octave_bands(lo, hi)
    except (TypeError, ValueError) as err:
        raise type(err)(f"band: {err}") from None
    j = np.arange(R.shape[1])
    f = j / response.period
    power = np.sum(np.abs(R) ** 2, axis=0)
    keep = (power > 1e-12 * power.max()) & (f >= lower[0]) & (f < upper[-1]) & (j > 0)
    if not np.any(keep):
        raise InputError(f"band={band!r} Hz holds none of the roughness's lines ({1 / response.period:.4g} Hz "
                         "apart); choose bands the roughness covers")
    f, H = f[keep], (np.sum(np.conj(R) * F, axis=0) / np.where(power > 0, power, 1.0))[keep]
    r_amp = 2 * np.sqrt(power[keep] / periods) / n_per
    band_of_line = np.searchsorted(upper, f, side="right")
    used = np.unique(band_of_line)
    band_of_line = np.searchsorted(used, band_of_line)
    linear = _linear_transfer(response, f, R_all[:, :, keep], wheel)
    return ContactTransfer(f=f, H=H, linear=linear, r_amplitude=r_amp, centres=centres[used],
                           level=_band_levels(H, r_amp, band_of_line, used.size),
                           linear_level=_band_levels(linear, r_amp, band_of_line, used.size))


def _linear_transfer(response: ContactResponse, f: np.ndarray, R: np.ndarray, wheel: int) -> np.ndarray:
    """The linear theory's force at ``wheel`` per unit roughness under the first, on the lines ``f``.

    ``R`` holds every wheel's roughness spectrum on those lines, (wheels, periods, lines): the
    roughness reaches each wheel with its own phase, ``R_j / R_1`` read from the run itself.
    """
    x0 = response.x if response.x.ndim == 1 else response.x[0]
    if response.infinite is None:  # a flexible slab (no InfiniteTrack), or a response made by hand
        if len(response.wheels) > 1:
            raise InputError("the linear theory of several wheels needs the exact InfiniteTrack of the model, which "
                             "a flexible slab does not have: analyse one wheel at a time")
        return wheel_rail_force(response.track, f, response.wheel, float(np.atleast_1d(x0)[0]), origin="midspan")
    H = wheel_rail_force(response.infinite, f, response.vehicle, x=np.atleast_1d(x0)[: len(response.wheels)])
    ratio = R[:, 0, :] / R[0, 0, :]  # (wheels, lines)
    return np.einsum("fj,jf->f", H[:, wheel, :], ratio)
