"""Roughness inputs of the wheel-rail contact: broadband from a band spectrum, or one corrugation.

A roughness r(x) of the running surface (downward, so r > 0 is a dip, the convention of
:func:`semitrack.wheel_rail_force`) is passed at a speed v: at the contact it is the time signal
r(t) = r(v t), a wavelength lambda becoming the frequency f = v / lambda. Roughness spectra are
stated as levels in one-third-octave bands of wavelength, ``L = 20 log10(r_rms / 1 um)`` dB
(EN 15610, ISO 3095). :class:`Roughness` holds such a signal as a multisine,

    r(t) = sum_k a_k cos(2 pi f_k t + phi_k),   f_k = j_k / period (integers j_k),

which is periodic in ``period``: a record of whole periods has all its power on the lines f_k,
so that the force per roughness on those lines follows from one discrete Fourier transform
without leakage (:func:`semitrack.contact_transfer`).

:func:`roughness_from_spectrum` spreads each band's mean square over the lines in that band, in
equal parts, with random phases from a ``seed``; the band levels of the result equal the
spectrum's exactly. The default spectrum is the rail roughness limit of ISO 3095:2013 (its
Figure 2, 0.4 m to 3.15 mm; the limit a test track for pass-by noise must stay below),
:data:`ISO3095_ROUGHNESS_LIMIT`. :func:`corrugation` is a single wavelength. Neither includes
the contact filter (the averaging of short wavelengths over the contact patch).
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field, replace
from types import MappingProxyType

import numpy as np
from numpy.typing import ArrayLike

from ..base.bands import HALF_BAND as _HALF_BAND
from ..base.bands import third_octave_bands
from ..base.checks import (
    as_real_array,
    check_in_range,
    check_int_at_least,
    check_nonnegative,
    check_positive,
    check_real,
    check_rolling_speed,
    check_string,
    check_time_step,
    check_work,
    shown,
)
from ..base.errors import InputError, InputTypeError
from ..base.notices import warn_user
from ..dynamics.signals import sin2_ramp
from .irregularity import RailProfile

__all__ = ["ISO3095_ROUGHNESS_LIMIT", "Roughness", "roughness_from_spectrum", "corrugation",
           "third_octave_bands", "MAX_LINES"]

#: The rail roughness limit of ISO 3095:2013 ("Acoustics - Railway applications - Measurement of
#: noise emitted by railbound vehicles"), Figure 2: one-third-octave band level (dB re 1 um) by
#: nominal band-centre wavelength (m), 0.4 m to 3.15 mm. The same 22 values are listed as the
#: "2007 TSI limit" in EN 15610:2009, Annex B. Transcribed as printed beside the figure's points.
ISO3095_ROUGHNESS_LIMIT = MappingProxyType({
    0.4: 17.1, 0.315: 15.0, 0.25: 13.0, 0.2: 11.0, 0.16: 9.0, 0.125: 7.0, 0.1: 4.9, 0.08: 2.9,
    0.063: 0.9, 0.05: -1.1, 0.04: -3.2, 0.0315: -5.0, 0.025: -5.6, 0.02: -6.2, 0.016: -6.8,
    0.0125: -7.4, 0.01: -8.0, 0.008: -8.6, 0.0063: -9.2, 0.005: -9.8, 0.004: -10.4, 0.00315: -11.0,
})
#: Reference of the roughness levels (m): 1 um.
REFERENCE_ROUGHNESS = 1e-6
#: Most lines of a multisine (each costs one cosine per time step).
MAX_LINES = 100_000
#: Largest roughness band level (dB re 1 um) in magnitude.
MAX_LEVEL = 100.0
#: Most samples of one call of :meth:`Roughness.sampled` (8 bytes each).
MAX_SAMPLES = 20_000_000
#: Longest period and time a roughness is read at (s): beyond it the phases 2 pi f t lose their digits.
MAX_PERIOD = 1e7
#: Band-centre wavelengths a roughness spectrum may hold (m): from 1 um (far below a contact patch) to 10 km.
BAND_WAVELENGTHS = (1e-6, 1e4)
#: Largest amplitude of a roughness line (m): a metre is far beyond any rail's (their sum stays finite).
MAX_AMPLITUDE = 1.0
#: Highest line frequency (Hz): far above any a time step resolves, and low enough that ``f t`` over a
#: period stays finite (``frequencies=1e308`` over 2000 s made the signal NaN).
MAX_LINE_FREQUENCY = 1e9
#: Farthest a roughness is shifted along the rail (m): the Earth's circumference 250 times.
MAX_DISTANCE = 1e10
#: Most samples x lines summed as cosines by :meth:`Roughness.sampled` when its period is no whole
#: number of steps (~10 ns each: 2e9 ~ 20 s); the inverse FFT of the other case costs milliseconds.
MAX_COSINE_WORK = 2_000_000_000
#: Most samples of a roughness laid along the rail (:meth:`Roughness.along_rail`): 8 bytes each,
#: 10 km at 40 samples per 3 cm wavelength (1.3e7).
MAX_PROFILE_SAMPLES = 20_000_000
#: Samples per shortest wavelength of a roughness laid along the rail: its linear interpolation
#: is then within 0.3 % of the cosine there (1 - cos(pi / 40)), far less at longer wavelengths.
PROFILE_SAMPLES_PER_WAVELENGTH = 40
#: Times x lines evaluated at once by :meth:`Roughness.__call__` (memory of one chunk, 8 bytes each).
_CHUNK = 2_000_000


@dataclass(frozen=True, eq=False)
class Roughness:
    """A periodic roughness signal at the contact, ``r(t) = sum_k a_k cos(2 pi f_k t + phi_k)``.

    Parameters
    ----------
    frequencies : array_like
        Line frequencies f_k (Hz), positive, each a whole multiple of ``1 / period``.
    amplitudes : array_like
        Amplitudes a_k (m), non-negative, one per line.
    phases : array_like
        Phases phi_k (rad), one per line.
    speed : float
        The speed (m/s) at which the roughness passes the contact; the line of wavelength
        lambda sits at ``speed / lambda``.
    period : float
        The signal's period (s).
    label : str
        A description (for tables and figures).

    Examples
    --------
    >>> r = corrugation(speed=100.0, wavelength=0.05, amplitude=1e-6)
    >>> float(r.frequencies[0]), round(float(r.rms) * 1e6, 4)
    (2000.0, 0.7071)
    """

    frequencies: np.ndarray
    amplitudes: np.ndarray
    phases: np.ndarray
    speed: float
    period: float
    label: str = field(default="", compare=False)

    def __post_init__(self):
        speed = check_rolling_speed("speed", self.speed)
        period = check_in_range("period", check_positive("period", self.period), (0.0, MAX_PERIOD),
                                "s, a roughness of at most 10 million seconds")
        check_string("label", self.label)
        arrays = [np.atleast_1d(as_real_array(getattr(self, k), k, finite=False))
                  for k in ("frequencies", "amplitudes", "phases")]
        f, a, phi = arrays
        if f.ndim != 1 or a.shape != f.shape or phi.shape != f.shape:
            raise InputError(f"frequencies, amplitudes and phases must be 1-D arrays of one length, got shapes "
                             f"{f.shape}, {a.shape}, {phi.shape}")
        check_work(f.size, MAX_LINES, f"the roughness holds {f.size} lines", "use a shorter period or fewer bands")
        if not (np.all(np.isfinite(f)) and np.all(f > 0) and np.all(f <= MAX_LINE_FREQUENCY)):
            bad = f[~(np.isfinite(f) & (f > 0) & (f <= MAX_LINE_FREQUENCY))][:3]
            raise InputError(f"frequencies must be positive and at most {MAX_LINE_FREQUENCY:g} Hz, got {bad}")
        j = f * period
        if np.any(np.abs(j - np.round(j)) > 1e-6 * np.maximum(j, 1.0)):
            raise InputError(f"frequencies must be whole multiples of 1/period = {1 / period:.6g} Hz, "
                             f"got e.g. {f[np.argmax(np.abs(j - np.round(j)))]!r}")
        if not (np.all(np.isfinite(a)) and np.all(a >= 0) and np.all(np.isfinite(phi))):
            raise InputError("amplitudes must be non-negative and finite (m) and phases finite (rad)")
        if np.any(a > MAX_AMPLITUDE):
            raise InputError(f"amplitudes must be at most {MAX_AMPLITUDE:g} m (a roughness of the rail), got "
                             f"{a.max()!r}")
        for key, value in (("frequencies", f), ("amplitudes", a), ("phases", phi), ("speed", speed),
                           ("period", period)):
            object.__setattr__(self, key, value)
        for value in (f, a, phi):
            value.setflags(write=False)

    @property
    def wavelengths(self) -> np.ndarray:
        """``speed / frequencies``: the wavelength of each line (m)."""
        return self.speed / self.frequencies

    @property
    def rms(self) -> float:
        """Root-mean-square roughness ``sqrt(sum a_k^2 / 2)`` (m)."""
        return float(np.sqrt(0.5 * np.sum(self.amplitudes**2)))

    def scaled(self, factor: float) -> Roughness:
        """The same roughness with every amplitude times ``factor``.

        Parameters
        ----------
        factor : float
            Non-negative scale factor (-).

        Returns
        -------
        Roughness
        """
        factor = check_nonnegative("factor", factor)
        largest = float(self.amplitudes.max(initial=0.0)) * factor
        if largest > MAX_AMPLITUDE:
            raise InputError(f"factor={factor!r} makes the largest amplitude {largest:.3g} m, more than "
                             f"{MAX_AMPLITUDE:g} m (a roughness of the rail)")
        return replace(self, amplitudes=self.amplitudes * factor)

    def band_levels(self, centres: ArrayLike) -> np.ndarray:
        """Levels in one-third-octave bands of wavelength (dB re 1 um); -inf where a band holds no line.

        Parameters
        ----------
        centres : array_like
            Band-centre wavelengths (m), each within 3 % of a base-10 centre ``10^(n/10)``
            (nominal values such as 0.0315 m are accepted).

        Returns
        -------
        ndarray
            ``10 log10(sum over the band's lines of a_k^2 / 2 / (1 um)^2)``, one per centre.
        """
        n = _band_numbers(centres)
        lam = 10 * np.log10(self.wavelengths)
        power = np.array([np.sum(self.amplitudes[np.abs(lam - k) <= 10 * _HALF_BAND] ** 2) / 2 for k in n])
        with np.errstate(divide="ignore"):
            return 10 * np.log10(power / REFERENCE_ROUGHNESS**2)

    def shifted(self, distance: float) -> Roughness:
        """The roughness a ``distance`` (m) further along the rail: ``r_s(t) = r(t + distance / speed)``.

        Parameters
        ----------
        distance : float
            How far ahead (m); negative behind.

        Returns
        -------
        Roughness
            The same lines, their phases advanced by ``2 pi f distance / speed``.
        """
        distance = check_in_range("distance", check_real("distance", distance), (-MAX_DISTANCE, MAX_DISTANCE),
                                  "m along the rail")
        return replace(self, phases=np.mod(self.phases + 2 * np.pi * self.frequencies * distance / self.speed,
                                           2 * np.pi))

    def at_speed(self, speed: float) -> Roughness:
        """The same roughness on the rail passed at another ``speed`` (m/s): its wavelengths kept.

        Parameters
        ----------
        speed : float
            The new speed (m/s), positive.

        Returns
        -------
        Roughness
            Lines at ``f speed / self.speed``, the period ``self.period self.speed / speed``.
        """
        ratio = check_rolling_speed("speed", speed) / self.speed
        return replace(self, frequencies=self.frequencies * ratio, period=self.period / ratio, speed=float(speed))

    def sampled(self, dt: float, n: int) -> np.ndarray:
        """The roughness at the times ``k dt``, ``k = 0 .. n - 1`` (m): what a time-stepping run reads.

        When the period is a whole number N of steps the samples repeat every N steps and one
        period is one inverse real FFT of the lines (each line ``j / period`` at bin ``j mod N``,
        folded onto its mirror above N/2: the samples of a line above the Nyquist frequency are
        those of its alias, exactly as the cosines give them); measured 2-3 ms for a 1-s run at
        10 us where the cosine sums take 3-4 s, equal to 1e-12. Otherwise the sums of cosines.

        Parameters
        ----------
        dt : float
            Time step (s), positive.
        n : int
            Number of samples.

        Returns
        -------
        ndarray, shape (n,)
            r(k dt) (m).

        Examples
        --------
        >>> r = corrugation(speed=100.0, wavelength=0.05, amplitude=1e-6)
        >>> bool(np.allclose(r.sampled(1e-5, 101), r(1e-5 * np.arange(101)), rtol=0, atol=1e-18))
        True
        """
        dt, n = check_time_step("dt", dt), check_int_at_least("n", n, 1)
        check_work(n, MAX_SAMPLES, f"n={n} samples", "sample a shorter record, or in parts")
        self.warn_aliasing(dt)
        steps = self.period / dt
        N = int(round(steps))
        if N < 2 or N > MAX_SAMPLES or abs(steps - N) > 1e-9 * steps:  # else one period's FFT: N numbers
            work = n * self.frequencies.size
            check_work(work, MAX_COSINE_WORK, f"{n} samples x {self.frequencies.size} roughness lines give {work} "
                       f"cosines (the period {self.period!r} s is no whole number of steps dt={dt!r} s)",
                       "use a period of whole steps, a larger dt, a shorter run or fewer lines")
            return self._on_grid(dt, n)
        m = np.round(self.frequencies * self.period).astype(np.int64) % N
        mirrored = m > N - m  # cos(2 pi m k / N + phi) = cos(2 pi (N - m) k / N - phi)
        m, phases = np.where(mirrored, N - m, m), np.where(mirrored, -self.phases, self.phases)
        edge = (m == 0) | (2 * m == N)  # irfft keeps the real part of bins 0 and N/2
        weight = np.where(edge, N * self.amplitudes, 0.5 * N * self.amplitudes)
        spectrum = np.zeros(N // 2 + 1, dtype=complex)
        np.add.at(spectrum, m, np.where(edge, weight * np.cos(phases), weight * np.exp(1j * phases)))
        period = np.fft.irfft(spectrum, N)
        return np.resize(period, n)

    def _on_grid(self, dt: float, n: int) -> np.ndarray:
        """The sums of cosines at ``k dt``, ``k < n``, as one complex matrix product (m).

        With ``k = b B + j`` (blocks of B steps), ``cos(w k dt + phi) = Re(exp(i (w b B dt + phi)) exp(i w j dt))``:
        the exponentials of the blocks' starts and of one block's steps, ``(n / B + B)`` per line, and the sum over
        lines a product, where :meth:`__call__` takes one cosine per sample and line (measured 8-12x slower).
        """
        block = max(1, int(math.isqrt(n)))
        starts = np.arange(0, n, block) * dt
        omega = 2 * np.pi * self.frequencies
        rows = max(1, _CHUNK // max(1, block * omega.size))  # bounds the exponentials held at once
        steps = np.exp(1j * np.outer(omega, np.arange(block) * dt))  # (lines, B)
        out = np.empty((starts.size, block))
        for i in range(0, starts.size, rows):
            heads = self.amplitudes * np.exp(1j * (np.outer(starts[i:i + rows], omega) + self.phases))
            out[i:i + rows] = (heads @ steps).real
        return out.ravel()[:n]

    def along_rail(self, start: float, length: float, *, fade: float = 1.0) -> RailProfile:
        """The roughness laid along the rail from ``start``: the profile a wheel meets at any speed.

        The roughness is a signal at its ``speed``; along the rail its line ``f`` is the
        wavelength ``speed / f``, and ``r(x) = r_t((x - start) / speed)``. A vehicle whose speed
        varies (``speed=speed(t)`` of :func:`semitrack.wheel_rail_response`) meets it as a
        profile (``profile=``). Sampled every shortest wavelength / 40 (the spatial period a whole
        number of samples, so that one inverse FFT gives them, :meth:`sampled`), linearly
        interpolated, faded in and out by ``sin^2`` over ``fade`` at both ends.

        Parameters
        ----------
        start : float
            Where it begins (m, at or ahead of the wheels' start).
        length : float
            Its length along the rail (m), more than ``2 fade``.
        fade : float
            The length of each ``sin^2`` fade (m), positive.

        Returns
        -------
        RailProfile

        Examples
        --------
        >>> r = corrugation(speed=50.0, wavelength=0.05, amplitude=1e-6)
        >>> p = r.along_rail(0.0, 5.0)
        >>> bool(abs(p(2.5125) - r(2.5125 / 50.0)) < 1e-8)
        True
        """
        start, length, fade = check_real("start", start), check_positive("length", length), check_positive("fade", fade)
        check_in_range("start", start, (-MAX_DISTANCE, MAX_DISTANCE), "m along the rail")
        check_in_range("length", length, (0.0, MAX_DISTANCE), "m along the rail")
        if not length > 2 * fade:
            raise InputError(f"length must exceed 2 fade = {2 * fade!r} m (a fade at each end), got {length!r}")
        spatial_period = self.speed * self.period
        per_period = math.ceil(spatial_period / float(np.min(self.wavelengths)) * PROFILE_SAMPLES_PER_WAVELENGTH)
        dx = spatial_period / per_period
        n = math.floor(length / dx) + 1  # the last sample within the length
        check_work(n, MAX_PROFILE_SAMPLES, f"length={length!r} m at {dx:.3g} m a sample gives {n} samples",
                   "lay a shorter stretch, or drop the shortest wavelengths")
        if n < 2:
            raise InputError(f"length={length!r} m holds fewer than two samples {dx:.3g} m apart: lay a longer stretch")
        s = dx * np.arange(n)
        with warnings.catch_warnings():  # in space, the samples resolve every line: no aliasing
            warnings.simplefilter("ignore", RuntimeWarning)
            r = self.sampled(dx / self.speed, n)
        envelope = sin2_ramp(s, fade) * sin2_ramp(s[-1] - s, fade)
        return RailProfile(start + s, r * envelope)

    def warn_aliasing(self, dt: float) -> None:
        """Warn when lines lie above the Nyquist frequency ``1 / (2 dt)``: sampled at ``dt`` they alias.

        A 40 kHz corrugation sampled at dt = 20 us (Nyquist 25 kHz) acts as a 10 kHz one; the
        warning names the lines and where they land, at the user's line that asked for the
        sampling (once there, however many of the package's calls sample the same roughness).

        Parameters
        ----------
        dt : float
            Time step (s).
        """
        nyquist = 0.5 / dt
        above = self.frequencies[self.frequencies > nyquist]
        if above.size:
            alias = np.abs(above - np.round(above * dt) / dt)
            warn_user(f"{above.size} roughness line(s) from {above[0]:.6g} to {above[-1]:.6g} Hz lie above the "
                      f"Nyquist frequency {nyquist:.6g} Hz of dt={shown(dt)} s and alias (e.g. {above[0]:.6g} Hz "
                      f"acts as {alias[0]:.6g} Hz): use dt < {0.5 / above[-1]:.3g} s or drop those wavelengths",
                      RuntimeWarning)

    def __call__(self, t: ArrayLike) -> np.ndarray:
        """The roughness at times ``t`` (s): ``sum_k a_k cos(2 pi f_k t + phi_k)`` (m).

        Parameters
        ----------
        t : array_like
            Times (s), any shape.

        Returns
        -------
        ndarray
            r(t) (m), the shape of ``t``.
        """
        t = as_real_array(t, "t")
        if t.size and np.abs(t).max() > MAX_PERIOD:
            raise InputError(f"t must be within {MAX_PERIOD:g} s of the start, got {np.abs(t).max()!r}")
        flat = t.ravel()
        out = np.empty(flat.size)
        step = max(1, _CHUNK // max(1, self.frequencies.size))
        omega = 2 * np.pi * self.frequencies
        for i in range(0, flat.size, step):
            out[i:i + step] = np.cos(np.outer(flat[i:i + step], omega) + self.phases) @ self.amplitudes
        return out.reshape(t.shape)


def _numbers(values: ArrayLike, name: str) -> np.ndarray:
    """``values`` as a float array, or a one-line refusal naming ``name`` (text, None, ragged lists)."""
    try:
        raw = np.asarray(values)
    except (TypeError, ValueError):
        raw = np.asarray(None)
    if raw.dtype.kind not in "iuf":
        raise InputTypeError(f"{name} must be numbers, got {values!r:.60}")
    return raw.astype(float)


def _band_numbers(centres: ArrayLike, name: str = "centres") -> np.ndarray:
    """The integers n of base-10 one-third-octave centres 10^(n/10) (within 3 %), checked."""
    c = np.atleast_1d(_numbers(centres, name))
    if c.ndim != 1 or c.size == 0 or not np.all(np.isfinite(c) & (c > 0)):
        raise InputError(f"{name} must be a non-empty 1-D array of positive band-centre wavelengths (m), "
                         f"got {centres!r}")
    lo, hi = BAND_WAVELENGTHS
    if not np.all((c >= lo) & (c <= hi)):
        raise InputError(f"{name} must be band centres from {lo:g} to {hi:g} m (a rail's roughness), got "
                         f"{c[~((c >= lo) & (c <= hi))][0]!r}")
    n = np.round(10 * np.log10(c)).astype(int)
    off = np.abs(c / 10.0 ** (n / 10) - 1) > 0.03
    if np.any(off):
        raise InputError(f"{name} must be one-third-octave band centres 10^(n/10) m (within 3 %, e.g. 0.0315), "
                         f"got {c[off][0]!r}")
    if np.unique(n).size != n.size:
        raise InputError(f"{name} must name each band once, got {centres!r}")
    return n


def roughness_from_spectrum(speed: float, wavelengths: ArrayLike | None = None, levels: ArrayLike | None = None,
                            *, period: float = 0.1, seed: int = 0, dt: float | None = None) -> Roughness:
    """A broadband roughness with given one-third-octave band levels, random phases.

    Each band of wavelength, passed at ``speed``, covers a band of frequency; its mean square
    ``(1 um)^2 10^(L/10)`` is shared equally by the lines ``j / period`` that fall in it, each
    with a phase drawn uniformly from [0, 2 pi) (``numpy.random.default_rng(seed)``). The band
    levels of the result are the given ones exactly (:meth:`Roughness.band_levels`).

    Parameters
    ----------
    speed : float
        Speed (m/s), e.g. ``300 / 3.6``.
    wavelengths : array_like, optional
        Band-centre wavelengths (m) of the spectrum (one-third-octave, base 10, nominal values
        accepted). Default: those of :data:`ISO3095_ROUGHNESS_LIMIT`.
    levels : array_like, optional
        Band levels (dB re 1 um), one per wavelength; required with ``wavelengths``.
    period : float
        Period of the signal (s): the line spacing is ``1 / period``; every band must hold at
        least one line.
    seed : int
        Seed of the random phases (>= 0).
    dt : float, optional
        The time step the roughness will be sampled at (s): lines above its Nyquist frequency
        are warned about at once (:meth:`Roughness.warn_aliasing`), as sampling them warns.

    Returns
    -------
    Roughness

    Examples
    --------
    The ISO 3095 limit at 100 m/s spans 250 Hz (0.4 m) to 31.7 kHz (3.15 mm):

    >>> r = roughness_from_spectrum(100.0)
    >>> bool(np.allclose(r.band_levels(list(ISO3095_ROUGHNESS_LIMIT)), list(ISO3095_ROUGHNESS_LIMIT.values())))
    True
    """
    speed, period = check_positive("speed", speed), check_positive("period", period)
    seed = check_int_at_least("seed", seed, 0)
    if wavelengths is None and levels is None:
        wavelengths, levels = list(ISO3095_ROUGHNESS_LIMIT), list(ISO3095_ROUGHNESS_LIMIT.values())
    elif wavelengths is None or levels is None:
        raise InputError("wavelengths and levels must be given together (or neither, for the ISO 3095 limit)")
    n = _band_numbers(wavelengths, "wavelengths")
    levels = np.atleast_1d(_numbers(levels, "levels"))
    if levels.shape != n.shape or not np.all(np.isfinite(levels)):
        raise InputError(f"levels must be finite, one per wavelength ({n.size}), got {levels!r}")
    if np.any(np.abs(levels) > MAX_LEVEL):
        raise InputError(f"levels must lie within +-{MAX_LEVEL:g} dB re 1 um (+{MAX_LEVEL:g} dB is a 10 cm "
                         f"roughness), got {levels[np.abs(levels) > MAX_LEVEL][0]!r}")
    lines, amplitudes = [], []
    for k, level in zip(n, levels):
        lam_lo, lam_hi = 10.0 ** (k / 10 - _HALF_BAND), 10.0 ** (k / 10 + _HALF_BAND)
        first, last = np.ceil(speed / lam_hi * period), np.floor(speed / lam_lo * period)
        count = len(lines) + max(last - first + 1, 0)
        check_work(count, MAX_LINES, f"speed={shown(speed)} m/s and period={shown(period)} s give {count:.4g} lines",
                   "use a lower speed, a shorter period or fewer bands")  # counted before any array exists
        j = np.arange(first, last + 1)
        if j.size == 0:
            raise InputError(f"period={period!r} s leaves no line (spacing {1 / period:.4g} Hz) in the band of "
                             f"wavelength {10 ** (k / 10):.4g} m, {speed / lam_hi:.4g}-{speed / lam_lo:.4g} Hz at "
                             f"speed {speed:.4g} m/s; use a longer period")
        lines.extend(j / period)
        amplitudes.extend(np.full(j.size, REFERENCE_ROUGHNESS * 10 ** (level / 20) * np.sqrt(2.0 / j.size)))
    order = np.argsort(lines)
    phases = np.random.default_rng(seed).uniform(0.0, 2 * np.pi, len(lines))
    return _checked_for(dt, Roughness(np.asarray(lines)[order], np.asarray(amplitudes)[order], phases, speed, period,
                                      label=f"{n.size}-band spectrum at {speed:.4g} m/s, seed {seed}"))


def _checked_for(dt: float | None, roughness: Roughness) -> Roughness:
    """``roughness``, warned about when it has lines that a step ``dt`` (if given) cannot resolve."""
    if dt is not None:
        roughness.warn_aliasing(check_positive("dt", dt))
    return roughness


def corrugation(speed: float, wavelength: float, amplitude: float, *, phase: float = 0.0,
                dt: float | None = None) -> Roughness:
    """A single-wavelength roughness ``amplitude cos(2 pi speed t / wavelength + phase)``.

    Parameters
    ----------
    speed : float
        Speed (m/s).
    wavelength : float
        Corrugation wavelength (m).
    amplitude : float
        Amplitude (m), half the peak-to-trough depth; non-negative.
    phase : float
        Phase (rad) at t = 0.
    dt : float, optional
        The time step it will be sampled at (s): a line above its Nyquist frequency is warned
        about at once (:meth:`Roughness.warn_aliasing`).

    Returns
    -------
    Roughness
        One line at ``speed / wavelength`` (Hz); its period is one cycle.

    Examples
    --------
    >>> corrugation(100.0, 0.05, 1e-5).period
    0.0005
    """
    speed, wavelength = check_rolling_speed("speed", speed), check_positive("wavelength", wavelength)
    amplitude, phase = check_nonnegative("amplitude", amplitude), check_real("phase", phase)
    if not math.isfinite(phase):
        raise InputError(f"phase must be finite (rad), got {phase!r}")
    check_in_range("amplitude", amplitude, (0.0, MAX_AMPLITUDE), "m, a roughness of the rail")
    check_in_range("wavelength", wavelength, (0.0, speed * MAX_PERIOD), f"m: one cycle in at most {MAX_PERIOD:g} s")
    f = speed / wavelength
    if f > MAX_LINE_FREQUENCY:  # on the line itself: a bound on the wavelength can round past it
        raise InputError(f"wavelength must be at least {speed / MAX_LINE_FREQUENCY:.6g} m at {speed:.6g} m/s (a line "
                         f"of at most {MAX_LINE_FREQUENCY:g} Hz), got {wavelength!r} m")
    return _checked_for(dt, Roughness(np.array([f]), np.array([amplitude]), np.array([phase]), speed, 1.0 / f,
                                      label=f"corrugation {wavelength:.4g} m at {speed:.4g} m/s"))
