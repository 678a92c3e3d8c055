"""Track parameters (paper Tables 2 and 5), their validation, and the support dynamic stiffness.

A :class:`Track` holds the rail (a Timoshenko beam), the rail pad and, for a ballasted track, the
sleeper mass and the ballast stiffness. Damping is by loss factors, entered as complex stiffness:
``E(1 + i eta_rail)``, ``G(1 + i eta_rail)``, ``kv(1 + i eta_pad)``, ``kphi(1 + i eta_pad)`` and
``kb(1 + i eta_ballast)``; the harmonic time factor is ``exp(i omega t)``.

A measured pad or foundation depends on frequency: ``kv`` and ``kphi`` may be a
:class:`~semitrack.model.curves.FrequencyCurve` of stiffness (a table, a function, a standard
linear solid) that holds its own damping, and ``foundation`` a curve of the receptance under the
pad (a measured sleeper or slab) in place of the rigid ground or the sleeper on ballast. Every
frequency-domain method reads the supports through :meth:`Track.pad_stiffness` and
:meth:`Track.foundation_receptance`, so all of them take such a track; the time-domain models
refuse it.

That hysteretic model (the paper's, ``damping="hysteretic"``) is not causal: no stable
time-domain system has a loss factor that is constant down to zero frequency. The causal
alternative ``damping="viscous"`` gives each family a viscous damper that equals its loss factor
at the family's reference frequency (:meth:`Track.reference_frequencies`), i.e. the loss factor
``eta f / f_ref`` grows in proportion to frequency: ``E(1 + i eta_rail f / f_rail)`` and so on.
It is the damping the time-domain finite-element model uses, so frequency- and time-domain
results of a viscous track agree exactly.

A :class:`PeriodicCell` is the repeating unit that the wavenumber and transfer methods work on:
one period ``L`` of the track holding ``S`` supports (paper Sec. 2.1, Eq. 3). Both paper tracks
have ``S = 1``; ``S = 2`` (two identical supports per period) is the same track and serves as a
check of the general formulation.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from ..base.checks import (
    as_frequencies,
    as_real_array,
    check_choice,
    check_in_range,
    check_int_at_least,
    check_nonnegative,
    check_positive,
    check_string,
)
from ..base.errors import InputError, InputTypeError
from ..base.paper_values import TABLE2_SLAB, TABLE5_BALLASTED
from .curves import FrequencyCurve, as_curve, stiffness_values
from .slab import Slab

if TYPE_CHECKING:
    import pandas as pd

#: Damping models of a Track: the paper's loss factors, or their causal viscous equivalents.
DAMPING_MODELS = ("hysteretic", "viscous")

#: The rule every Track field obeys, one check of :mod:`semitrack.base.checks` per field. The
#: Track itself and the track file reader (:mod:`semitrack.model.trackfile`) both apply this
#: table, through :func:`check_track_field`. ``sleeper_mass`` and ``kb`` may also be None together.
#: Largest support spacing (m): kilometres are no railway track (the paper's is 0.65 m), and from
#: ~1e150 m the exact method's scaling (spacing squared) overflows.
MAX_SPACING = 1000.0


def _check_spacing(key: str, value: object) -> float:
    spacing = check_positive(key, value)
    if spacing > MAX_SPACING:
        raise InputError(f"{key} must be at most {MAX_SPACING:g} m (no railway track comes near), got {value!r}")
    return spacing


#: Each number field's physical range (SI units), wide around every real rail and support (and the
#: limit cases the tests take: a rail with I = 1e-12 m^4, one 1e6 times stiffer, kphi = 1e20 N m/rad, a
#: sleeper of 1e-9 kg); beyond them the algebra over- or underflows (kappa = 1e300, E = 2e211, a loss
#: factor of 1e308 made singular matrices), so they are refused where the track is made.
FIELD_RANGES: dict[str, tuple[float, float, str]] = {
    "rho": (1.0, 1e6, "kg/m^3"), "E": (1e3, 1e19, "N/m^2"), "G": (1e3, 1e19, "N/m^2"),
    "A": (1e-7, 10.0, "m^2"), "I": (1e-13, 10.0, "m^4"), "kappa": (1e-3, 1e3, "-"),
    "sleeper_mass": (1e-12, 1e8, "kg"), "kb": (1e-3, 1e17, "N/m"), "kv": (1e-3, 1e17, "N/m"),
    "kphi": (0.0, 1e21, "N m/rad"), **dict.fromkeys(("eta_rail", "eta_pad", "eta_ballast"), (0.0, 10.0, "-")),
}


def _within(rule: Callable) -> Callable:
    """A number field's rule, then its :data:`FIELD_RANGES` range."""
    def check(key: str, value: object) -> float:
        lo, hi, unit = FIELD_RANGES[key]
        return check_in_range(key, rule(key, value), (lo, hi), f"{unit}, around every real track")
    return check


def _or_a_curve(rule: Callable) -> Callable:
    """A pad stiffness's rule: a number by ``rule``; the type error also names the curves it may be."""
    def check(key: str, value: object) -> float:
        try:
            return rule(key, value)
        except InputTypeError as err:
            raise InputTypeError(f"{err}; or a stiffness curve of frequency (st.FrequencyTable, "
                                 "st.StandardLinearSolid, a function of f)") from None
    return check


FIELD_RULES: dict[str, Callable] = {
    **dict.fromkeys(("rho", "E", "G", "A", "I", "kappa", "sleeper_mass", "kb"), _within(check_positive)),
    "kv": _or_a_curve(_within(check_positive)),
    "kphi": _or_a_curve(_within(check_nonnegative)),
    "spacing": _check_spacing,
    **dict.fromkeys(("eta_rail", "eta_pad", "eta_ballast"), _within(check_nonnegative)),
    "name": check_string,
    "damping": lambda key, value: check_choice(key, value, DAMPING_MODELS),
}


#: The fields of one support that a local change may set (:class:`semitrack.InfiniteTrack`'s
#: ``changes``, a track file's ``[[changes]]``).
SUPPORT_FIELDS = ("kv", "kphi", "eta_pad", "sleeper_mass", "kb", "eta_ballast")
#: The only fields that may be None (together): a pad on a rigid foundation has no sleeper.
OPTIONAL_FIELDS = ("sleeper_mass", "kb")


def check_track_field(key: str, value: object) -> float | str:
    """Check one Track field against its rule in :data:`FIELD_RULES` and return it converted.

    Parameters
    ----------
    key : str
        The field name, e.g. ``"kv"``.
    value : object
        Its value (SI units).

    Returns
    -------
    float or str
        The value as a float (a str for ``name``).

    Raises
    ------
    TypeError, ValueError
        As the rule does, naming the field, the value and the rule.
    """
    return FIELD_RULES[key](key, value)


@dataclass(frozen=True)
class Track:
    """A periodically supported rail: Timoshenko beam on discrete supports.

    All quantities in SI units. The presets :func:`slab_track` and :func:`ballasted_track` give
    the paper's parameters; every field can be overridden by keyword there.

    Parameters
    ----------
    rho : float
        Rail density (kg/m^3).
    E, G : float
        Young's and shear modulus of the rail (N/m^2).
    A : float
        Cross-sectional area of the rail (m^2).
    I : float
        Second moment of area of the rail (m^4).
    kappa : float
        Shear coefficient of the rail cross-section (-).
    eta_rail : float
        Loss factor of the rail (-), applied to E and G.
    kv : float or FrequencyCurve or callable
        Vertical rail pad stiffness (N/m). A curve of stiffness
        (:class:`~semitrack.model.curves.FrequencyCurve`; a callable ``kv(f)`` of the frequencies
        in Hz is wrapped as one) is the complex stiffness with its damping: ``eta_pad`` does not
        apply to it.
    kphi : float or FrequencyCurve or callable
        Rotational rail pad stiffness (N m/rad); zero is allowed; a curve as for ``kv``.
    eta_pad : float
        Loss factor of the rail pad (-), for the pad stiffnesses given as numbers.
    spacing : float
        Support (fastener or sleeper) spacing d (m).
    sleeper_mass : float or None
        Mass supported under one rail seat (half a sleeper) (kg). ``None`` means the pad sits on
        a rigid foundation (the slab track of the paper).
    kb : float or None
        Ballast stiffness under one rail seat (N/m); required with ``sleeper_mass``.
    eta_ballast : float
        Loss factor of the ballast (-).
    name : str
        A label used in tables and plots.
    damping : {"hysteretic", "viscous"}
        ``"hysteretic"`` (the paper's): constant loss factors. ``"viscous"``: causal viscous
        dampers, each equal to its loss factor at the family's reference frequency
        (:meth:`reference_frequencies`); the loss factor then grows as ``eta f / f_ref``.
    slab : Slab or None
        A flexible slab under the pads (:class:`semitrack.Slab`), coupling the ``slab.fasteners``
        supports it carries; one slab is then one period of the track. ``None`` (default): each
        pad rests on its own rigid foundation or sleeper. With ``damping="viscous"`` the slab's
        bending and its layer are the families "slab" and "layer" (:meth:`loss_factor`).
    foundation : FrequencyCurve or callable or None
        The vertical receptance under each pad (m/N), a curve of kind ``"receptance"`` (a
        measured sleeper's or slab's; a callable ``G(f)`` is wrapped as one): the paper's G(omega)
        of Eq. 3, in place of the rigid ground. Not with ``sleeper_mass``/``kb`` or ``slab``.
    """

    rho: float
    E: float
    G: float
    A: float
    I: float  # noqa: E741 - the paper's symbol
    kappa: float
    eta_rail: float
    kv: float
    kphi: float
    eta_pad: float
    spacing: float
    sleeper_mass: float | None = None
    kb: float | None = None
    eta_ballast: float = 0.0
    name: str = "track"
    damping: str = "hysteretic"
    slab: Slab | None = None
    foundation: FrequencyCurve | None = None

    def __post_init__(self):
        for key in ("kv", "kphi"):
            object.__setattr__(self, key, as_curve(key, getattr(self, key), "stiffness"))
        if self.foundation is not None:
            object.__setattr__(self, "foundation", as_curve("foundation", self.foundation, "receptance"))
            if not isinstance(self.foundation, FrequencyCurve):
                raise InputTypeError("foundation must be a receptance curve (semitrack.FrequencyTable, a function "
                                     f"G(f)) or None, got {self.foundation!r}")
        if (self.sleeper_mass is None) != (self.kb is None):
            raise InputError(
                "sleeper_mass and kb go together: give both for a ballasted track or neither for a "
                f"rigid foundation, got sleeper_mass={self.sleeper_mass!r}, kb={self.kb!r}"
            )
        for key in FIELD_RULES:
            value = getattr(self, key)
            if value is None and key in OPTIONAL_FIELDS:  # a rigid foundation: both None (above)
                continue
            if not isinstance(value, FrequencyCurve):  # None is refused by the field's rule, naming it
                object.__setattr__(self, key, check_track_field(key, value))
        if self.slab is not None:
            self._check_slab()
        if self.is_frequency_dependent:
            self._check_curves()

    def _check_curves(self) -> None:
        """The rules a track with frequency-dependent supports adds."""
        if self.damping != "hysteretic":
            raise InputError("damping='viscous' builds causal dampers from constant stiffnesses; a frequency-dependent "
                             "pad or foundation holds its own damping: use damping='hysteretic'")
        if {"kv", "kphi"} <= set(self.curves) and self.eta_pad != 0:
            raise InputError(f"eta_pad={self.eta_pad!r} would damp nothing: kv and kphi are both curves, which hold "
                             "their own damping; set eta_pad=0")
        if self.foundation is not None and (self.is_ballasted or self.has_flexible_slab):
            raise InputError("foundation (a receptance under the pads) replaces the sleeper on ballast and the "
                             "flexible slab: give foundation, or sleeper_mass/kb, or slab, not two of them")

    def _check_slab(self) -> None:
        if not isinstance(self.slab, Slab):
            raise InputTypeError(f"slab must be a semitrack Slab or None, got {type(self.slab).__name__}")
        if self.is_ballasted:
            raise InputError("a track has either a flexible slab or sleepers on ballast under its pads, not both: "
                             "give slab or sleeper_mass/kb")
        self.slab.check_spacing(self.spacing)

    # ----------------------------------------------------------------------------------------
    @property
    def is_ballasted(self) -> bool:
        """True when the pad rests on a sleeper mass on ballast (paper Sec. 5)."""
        return self.sleeper_mass is not None

    @property
    def curves(self) -> dict[str, FrequencyCurve]:
        """The support fields given as curves of frequency, by name (``kv``, ``kphi``, ``foundation``)."""
        return {k: v for k in ("kv", "kphi", "foundation") if isinstance(v := getattr(self, k), FrequencyCurve)}

    @property
    def is_frequency_dependent(self) -> bool:
        """True when a pad stiffness or the foundation is a curve of frequency (no constant model)."""
        return bool(self.curves)

    @property
    def frequency_band(self) -> tuple[float, float]:
        """The frequencies (Hz) at which every support property is defined: all of them, unless a
        measured table refuses to go beyond its band (the intersection of the tables' bands)."""
        domains = [curve.domain for curve in self.curves.values()]
        return max((d[0] for d in domains), default=0.0), min((d[1] for d in domains), default=float("inf"))

    def require_constant(self, what: str, instead: str) -> None:
        """Refuse a frequency-dependent track where a model needs constant supports.

        Parameters
        ----------
        what : str
            What needs them (e.g. ``"the time-domain FE model"``).
        instead : str
            What to do instead, appended to the message.
        """
        if self.is_frequency_dependent:
            curves = list(self.curves)
            verb = "depends" if len(curves) == 1 else "depend"
            raise InputError(f"{what} needs constant supports, and this track's {' and '.join(curves)} {verb} on "
                             f"frequency: {instead}")

    @property
    def has_flexible_slab(self) -> bool:
        """True when the pads rest on a flexible :class:`Slab` that couples them."""
        return self.slab is not None

    def _refuse_slab(self, what: str) -> None:
        if self.has_flexible_slab:
            raise InputError(f"{what} is per support, and the supports of a flexible-slab track are coupled "
                             "through the slab: use track.cell().support_stiffness_matrix(f)")

    @property
    def EI(self) -> complex:
        """Bending stiffness with the hysteretic loss factor, E(1 + i eta_rail) I (N m^2).

        Frequency-domain code uses :meth:`rail_moduli`, which also covers ``damping="viscous"``.
        """
        return self.E * (1 + 1j * self.eta_rail) * self.I

    @property
    def kAG(self) -> complex:
        """Shear stiffness with the hysteretic loss factor, kappa A G(1 + i eta_rail) (N)."""
        return self.kappa * self.A * self.G * (1 + 1j * self.eta_rail)

    def reference_frequencies(self) -> dict[str, float]:
        """Frequencies (Hz) at which each family's viscous damper equals its loss factor.

        Returns
        -------
        dict
            ``{"rail": (pi / d)^2 sqrt(EI / rho A) / 2 pi, "pad": sqrt(kv / (rho A d)) / 2 pi,
            "ballast": sqrt(kb / (m_s + rho A d)) / 2 pi, "slab": f_2, "layer": sqrt(k_L / (m_L
            + rho A / 1 m)) / 2 pi}`` with real moduli: the Euler pinned-pinned frequency, the
            rail-on-pad resonance, the sleeper-on-ballast resonance, the free slab's first bending
            mode on its layer (:meth:`semitrack.Slab.natural_frequencies`) and the slab's bounce on
            its layer with the rail on it (k_L, m_L per unit length), near which each family's
            damping controls the response. "ballast" is NaN without sleepers, "slab" and "layer"
            without a flexible slab.
        """
        self.require_constant("the reference frequencies of viscous damping",
                              "a curve carries its own damping (only a hysteretic track takes curves)")
        d, ra, nan = self.spacing, self.mass_per_length, float("nan")
        slab = self.slab
        return {
            "rail": float((np.pi / d) ** 2 * np.sqrt(self.E * self.I / ra) / (2 * np.pi)),
            "pad": float(np.sqrt(self.kv / (ra * d)) / (2 * np.pi)),
            "ballast": (float(np.sqrt(self.kb / (self.sleeper_mass + ra * d)) / (2 * np.pi))
                        if self.is_ballasted else nan),
            "slab": nan if slab is None else float(slab.natural_frequencies(3)[2]),
            "layer": (nan if slab is None else
                      float(np.sqrt(slab.support_stiffness / (slab.mass_per_length + ra)) / (2 * np.pi))),
        }

    def loss_factors(self) -> dict[str, float]:
        """The loss factor (-) of each damped family, as given: ``{"rail", "pad", "ballast", "slab", "layer"}``.

        Returns
        -------
        dict
            ``eta_rail``, ``eta_pad``, ``eta_ballast``, and the slab's ``eta_slab`` and
            ``eta_support`` (0 without a flexible slab).
        """
        slab = self.slab
        return {"rail": self.eta_rail, "pad": self.eta_pad, "ballast": self.eta_ballast,
                "slab": 0.0 if slab is None else slab.eta_slab, "layer": 0.0 if slab is None else slab.eta_support}

    def loss_factor(self, family: str, f: ArrayLike, eta: float | None = None) -> np.ndarray:
        """Loss factor of a family ("rail", "pad", "ballast", "slab" or "layer") at frequencies ``f`` (Hz).

        Parameters
        ----------
        family : {"rail", "pad", "ballast", "slab", "layer"}
            The damped element family ("slab": the flexible slab's bending, "layer": its
            resilient layer).
        f : array_like
            Frequencies (Hz), any shape (zero allowed: a viscous damper has no loss there).
        eta : float, optional
            A loss factor in place of the family's own (a changed support's), under the same law
            and the track's own reference frequency.

        Returns
        -------
        ndarray
            ``eta`` (hysteretic) or ``eta f / f_ref`` (viscous), the shape of ``f``.
        """
        if eta is None:
            eta = self.loss_factors()[family]
        f = as_real_array(f, "f", finite=False)
        absent = (family == "ballast" and not self.is_ballasted) or (family in ("slab", "layer")
                                                                      and not self.has_flexible_slab)
        if absent:
            return np.zeros(f.shape)  # no such element: its loss factor damps nothing
        if self.damping == "hysteretic" or eta == 0:
            return np.full(f.shape, eta)
        return eta * f / self.reference_frequencies()[family]

    def slab_receptance(self, f: ArrayLike, from_span: int = 0) -> np.ndarray:
        """The flexible slab's receptance G_rs between its fasteners, with this track's damping (m/N).

        :meth:`semitrack.Slab.receptance` at the track's spacing, its loss factors those of the
        families "slab" and "layer" (:meth:`loss_factor`): constant, or viscous ``eta f / f_ref``.

        Parameters
        ----------
        f : array_like
            Frequencies (Hz), positive and finite; flattened.
        from_span : int
            As :meth:`semitrack.Slab.receptance`: 0 the whole slab, k the part right of its k-th mid-span.

        Returns
        -------
        ndarray of complex, shape ``(n_f, S - from_span, S - from_span)``
        """
        if not self.has_flexible_slab:
            raise InputError("slab_receptance needs a track with a flexible slab (track.slab), got slab=None")
        f = np.atleast_1d(as_frequencies(f)).ravel()
        return self.slab.receptance(f, self.spacing, from_span, eta_slab=self.loss_factor("slab", f),
                                    eta_support=self.loss_factor("layer", f))

    def rail_moduli(self, f: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        """Complex bending and shear stiffness of the rail at frequencies ``f`` (Hz).

        Parameters
        ----------
        f : array_like
            Frequencies (Hz), any shape.

        Returns
        -------
        EI : ndarray of complex
            ``E(1 + i eta) I`` (N m^2), the shape of ``f``.
        kAG : ndarray of complex
            ``kappa A G(1 + i eta)`` (N).
        """
        c = 1 + 1j * self.loss_factor("rail", f)
        return self.E * self.I * c, self.kappa * self.A * self.G * c

    @property
    def mass_per_length(self) -> float:
        """rho A (kg/m)."""
        return self.rho * self.A

    @property
    def rotary_inertia(self) -> float:
        """rho I (kg m)."""
        return self.rho * self.I

    @property
    def bouncing_frequency_estimate(self) -> float:
        """The paper's estimate sqrt(kv / (rho A d)) / (2 pi) of the bouncing frequency (Hz).

        Only meaningful for the slab track (rail on pads on a rigid foundation). Frequency-dependent
        supports (a pad curve, a measured foundation under it) are read, by a few fixed-point
        steps, at the frequency the estimate gives.
        """
        ra_d = self.mass_per_length * self.spacing
        if not self.is_frequency_dependent:
            return float(np.sqrt(self.kv / ra_d) / (2 * np.pi))
        lo, hi = self.frequency_band
        f = 100.0
        for _ in range(8):  # the support (pad on its measured foundation) at the frequency it gives
            k = self.support_stiffness(np.array([min(max(f, lo, 1e-3), hi)]))[0][0]
            f = float(np.sqrt(max(k.real, 1e-30) / ra_d) / (2 * np.pi))
        return f

    def replace(self, **changes) -> Track:
        """A copy with some fields changed (validated again).

        Parameters
        ----------
        **changes
            New values of Track fields by name, in SI units (e.g. ``kv=8e7`` in N/m).

        Returns
        -------
        Track
        """
        return dataclasses.replace(self, **changes)

    # ----------------------------------------------------------------------------------------
    def pad_stiffness(self, f: ArrayLike | None = None) -> tuple[np.ndarray, np.ndarray]:
        """Complex pad stiffness (vertical N/m, rotational N m/rad), damping included.

        Parameters
        ----------
        f : array_like, optional
            Frequencies (Hz). Required for ``damping="viscous"``; without it the hysteretic
            values are returned as scalars.

        Returns
        -------
        kv, kphi : complex or ndarray of complex
            The shape of ``f`` (scalars when ``f`` is omitted). A curve's values as they are
            (checked passive), a number times ``1 + i eta_pad``.
        """
        if f is None:
            if self.damping != "hysteretic" or self.is_frequency_dependent:
                raise InputError("pad_stiffness needs the frequencies f (Hz) for damping='viscous' or a "
                                 "frequency-dependent pad")
            c = 1 + 1j * self.eta_pad
            return self.kv * c, self.kphi * c
        f = as_real_array(f, "f", finite=False)
        c = 1 + 1j * self.loss_factor("pad", f)
        return stiffness_values("kv", self.kv, f, c), stiffness_values("kphi", self.kphi, f, c, allow_zero=True)

    def foundation_receptance(self, f: ArrayLike) -> np.ndarray:
        """Vertical receptance under the pad, G(omega) of the paper's Eq. (3) (m/N).

        Zero for a rigid foundation; ``1 / (kb(1 + i eta_ballast) - omega^2 m_s)`` for a sleeper
        mass on ballast; the ``foundation`` curve's values (checked passive) where one is given.

        Parameters
        ----------
        f : array_like
            Frequencies (Hz), positive and finite.

        Returns
        -------
        ndarray of complex
            Same shape as ``f`` (m/N).
        """
        f = as_frequencies(f)
        self._refuse_slab("foundation_receptance")
        if self.foundation is not None:
            return self.foundation(f, "foundation")
        if not self.is_ballasted:
            return np.zeros(f.shape, dtype=complex)
        omega = 2 * np.pi * f
        kb = self.kb * (1 + 1j * self.loss_factor("ballast", f))
        return 1.0 / (kb - omega**2 * self.sleeper_mass)

    def support_stiffness(self, f: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        """Dynamic stiffness of one support seen from the rail.

        Parameters
        ----------
        f : array_like
            Frequencies (Hz).

        Returns
        -------
        kv_dyn : ndarray of complex
            Vertical dynamic stiffness (N/m): the pad, in series with the sleeper mass on ballast
            for a ballasted track, ``1 / (1/kv* + G(omega))``.
        kphi_dyn : ndarray of complex
            Rotational dynamic stiffness (N m/rad): the pad alone (the sleeper does not rotate).
        """
        f = as_frequencies(f)
        self._refuse_slab("support_stiffness")
        k = self.cell().support_stiffness_matrix(f.ravel())  # one support: (n, 2, 2)
        return k[:, 0, 0].reshape(f.shape), k[:, 1, 1].reshape(f.shape)

    def cell(self, supports_per_period: int | None = None) -> PeriodicCell:
        """The periodic cell of this track with ``supports_per_period`` identical supports.

        Parameters
        ----------
        supports_per_period : int, optional
            Number S >= 1 of supports in one period; the period is S x spacing (m). Default 1,
            and for a flexible-slab track the slab's ``fasteners`` (the only choice there).

        Returns
        -------
        PeriodicCell
            For a flexible slab: supports at 0, d, ..., (S - 1) d, the slab's receptance as the
            coupled foundation, and the cut at the mid-span ``slab.cut`` names: x = (k - 1/2) d
            for k = ``slab.cut_span``, the slab joint (x = -d/2) for k = 0.
        """
        if not self.has_flexible_slab:
            return PeriodicCell.uniform(self, 1 if supports_per_period is None else supports_per_period)
        s = self.slab.fasteners
        if supports_per_period is not None and supports_per_period != s:
            raise InputError(f"a flexible-slab track has one slab, {s} supports, per period; got "
                             f"supports_per_period={supports_per_period!r}")
        d = self.spacing
        cut = (self.slab.cut_span - 0.5) * d  # the joint (k = 0) is the mid-span before the first fastener
        return PeriodicCell(self, s * d, tuple(d * np.arange(s)), foundation=self.slab_receptance, cut=cut % (s * d))


def slab_track(**overrides) -> Track:
    """The paper's high-speed slab track (Table 2): rail on pads on a rigid slab.

    The values are :data:`semitrack.base.paper_values.TABLE2_SLAB`. The paper states
    ``kphi = kv b^2 / 12`` with pad length b = 0.25 m; Table 2 prints the rounded value
    2.83e5 N m/rad, which is used here.

    Parameters
    ----------
    **overrides
        Track fields to change, by name, in SI units: ``rho`` (kg/m^3), ``E``, ``G`` (N/m^2),
        ``A`` (m^2), ``I`` (m^4), ``kappa``, ``eta_rail`` (-), ``kv`` (N/m), ``kphi``
        (N m/rad), ``eta_pad`` (-), ``spacing`` (m), ``name``, ``slab`` (a :class:`Slab` for a
        flexible slab that couples the fasteners; by default the paper's rigid slab) and
        ``foundation`` (a measured receptance under the pads, in place of the rigid slab);
        ``kv`` and ``kphi`` may be curves of frequency (:class:`Track`). The sleeper and ballast
        fields are refused.

    Returns
    -------
    Track

    Examples
    --------
    >>> import semitrack as st
    >>> track = st.slab_track(kv=8e7)
    >>> track.kv, track.spacing, track.is_ballasted
    (80000000.0, 0.65, False)

    A floating slab, 6.5 m long with 10 fasteners, on a slab mat (values per rail):

    >>> mat = st.Slab(length=6.5, fasteners=10, E=3.6e10, I=8.5e-4, mass_per_length=640.0,
    ...               support_stiffness=2.5e7, eta_support=0.2)
    >>> st.slab_track(slab=mat).cell().n_supports
    10
    """
    return _build(dict(TABLE2_SLAB, name="slab"), overrides, ("sleeper_mass", "kb", "eta_ballast"))


def ballasted_track(**overrides) -> Track:
    """The paper's ballasted track (Table 5): rail as in Table 2, pad, half sleeper, ballast.

    The values are :data:`semitrack.base.paper_values.TABLE5_BALLASTED`.

    Parameters
    ----------
    **overrides
        Track fields to change, by name, in SI units: the rail fields of :func:`slab_track`,
        ``kv`` (N/m), ``kphi`` (N m/rad), ``eta_pad`` (-), ``spacing`` (m), ``sleeper_mass``
        (kg), ``kb`` (N/m), ``eta_ballast`` (-) and ``name``.

    Returns
    -------
    Track
    """
    return _build(dict(TABLE5_BALLASTED, name="ballasted"), overrides, ("slab",))


def _build(params: dict, overrides: dict, forbidden: tuple[str, ...]) -> Track:
    known = {f.name for f in dataclasses.fields(Track)} - set(forbidden)
    unknown = sorted(set(overrides) - known)
    if unknown:
        raise InputTypeError(f"unknown track parameter(s) {unknown}; allowed: {sorted(known)}")
    params.update(overrides)
    return Track(**params)


def require_track(track: object, name: str = "track") -> Track:
    """Return ``track`` if it is a :class:`Track`, else raise the package's one TypeError for it.

    Parameters
    ----------
    track : object
        The value to check.
    name : str
        The parameter name to quote in the message.
    """
    if not isinstance(track, Track):
        raise _not_a(name, track, "Track")
    return track


def require_cell(track: object, name: str = "track") -> PeriodicCell:
    """The periodic cell of ``track``: a :class:`PeriodicCell` as it is, a :class:`Track` as ``track.cell()``.

    Parameters
    ----------
    track : Track or PeriodicCell
        The value to check.
    name : str
        The parameter name to quote in the message.

    Raises
    ------
    TypeError
        For anything else, in the words of :func:`require_track`.
    """
    if isinstance(track, PeriodicCell):
        return track
    if isinstance(track, Track):
        return track.cell()
    raise _not_a(name, track, "Track or PeriodicCell")


def _not_a(name: str, value: object, what: str) -> InputTypeError:
    """The package's one wording for a value that is not a track."""
    return InputTypeError(f"{name} must be a semitrack {what} (e.g. st.slab_track()), got {type(value).__name__}")


#: Most supports one periodic cell holds: a pattern repeating after 10 000 supports (6 km) is not
#: periodic in any sense the methods use (1e12 asked for 7 TiB).
MAX_SUPPORTS_PER_PERIOD = 10_000


@dataclass(frozen=True)
class PeriodicCell:
    """One period of an infinitely long periodic track (paper Sec. 2.1).

    Parameters
    ----------
    track : Track
        Rail properties and the support model.
    period : float
        Period L (m).
    positions : tuple of float
        Support positions x_s within the period, 0 <= x_s < L (m).
    foundation : callable, optional
        ``foundation(f) -> (n_f, S, S)`` complex array: the vertical receptance matrix G_rs of the
        foundation under the S pads (m/N), the paper's Eq. (3). By default each support has its
        own foundation, ``G_rs = delta_rs * track.foundation_receptance(f)``; a coupled slab can be
        given here: it couples the supports of one period [0, L) (the paper's bays), so the
        period boundary x = 0 is a joint that no coupling crosses.
    cut : float, optional
        The central cross-section (m) where alpha's cut and the central responses sit, in
        [0, period); the first mid-span (:attr:`mid_span`) by default.
    """

    track: Track
    period: float
    positions: tuple[float, ...]
    foundation: Callable[[np.ndarray], np.ndarray] | None = field(default=None, compare=False)
    cut: float | None = None

    def __post_init__(self):
        require_track(self.track)
        if self.foundation is not None and not callable(self.foundation):
            raise InputTypeError(f"foundation must be a function of f (Hz) or None, got "
                                 f"{type(self.foundation).__name__}")
        if self.foundation is not None and self.track.foundation is not None:
            raise InputError("a PeriodicCell's foundation would replace the track's measured foundation: give one "
                             "of them")
        check_positive("period", self.period)
        given = np.atleast_1d(as_real_array(self.positions, "positions"))
        if given.ndim != 1:
            raise InputError(f"positions must be a 1-D sequence of support positions (m), got shape {given.shape}")
        pos = tuple(float(x) for x in given)
        if len(pos) == 0:
            raise InputError("positions must hold at least one support position, got none")
        for x in pos:
            if not (0.0 <= x < self.period):
                raise InputError(f"support positions must satisfy 0 <= x_s < period={self.period}, got {x}")
        if list(pos) != sorted(pos) or len(set(pos)) != len(pos):
            raise InputError(f"support positions must be distinct and increasing, got {pos}")
        object.__setattr__(self, "positions", pos)
        if self.cut is not None:
            cut = check_nonnegative("cut", self.cut)
            if not cut < self.period:
                raise InputError(f"cut must satisfy 0 <= cut < period={self.period}, got {self.cut!r}")
            object.__setattr__(self, "cut", cut)

    @classmethod
    def uniform(cls, track: Track, supports_per_period: int = 1) -> PeriodicCell:
        """``S`` identical, equally spaced supports per period (period = S x spacing).

        Parameters
        ----------
        track : Track
            Rail and support; its ``spacing`` (m) separates the supports.
        supports_per_period : int
            S >= 1.

        Returns
        -------
        PeriodicCell
            Supports at 0, d, ..., (S - 1) d in a period of S d (m).
        """
        track = require_track(track)
        s = check_int_at_least("supports_per_period", supports_per_period, 1)
        if s > MAX_SUPPORTS_PER_PERIOD:
            raise InputError(f"supports_per_period must be at most {MAX_SUPPORTS_PER_PERIOD} (a period's transfer "
                             f"is a product over its supports), got {s}")
        return cls(track, s * track.spacing, tuple(track.spacing * np.arange(s)))

    @property
    def n_supports(self) -> int:
        """S, the number of supports in one period."""
        return len(self.positions)

    @property
    def mid_span(self) -> float:
        """Position of the first mid-span, between the first support and the next (m)."""
        nxt = self.positions[1] if self.n_supports > 1 else self.period
        return 0.5 * (self.positions[0] + nxt)

    @property
    def central_section(self) -> float:
        """Where alpha's cut and the central responses sit (m): ``cut``, else :attr:`mid_span`."""
        return self.mid_span if self.cut is None else self.cut

    @property
    def joint(self) -> float:
        """A cross-section that no foundation coupling crosses (m), between two periods' supports.

        Midway between the last support of the previous period and the first of this one:
        the slab joint of a flexible-slab track (-d/2). Negative values are allowed (positions
        are periodic).
        """
        return 0.5 * (self.positions[0] + self.positions[-1] - self.period)

    def is_symmetric_about(self, x: float, rtol: float = 1e-9) -> bool:
        """True when the periodic track is a mirror image of itself about the cross-section ``x``.

        The support positions must map onto each other under x -> 2x - position (modulo the
        period), and a custom foundation must be unchanged by the same permutation of supports
        (checked at a few frequencies). Eq. (14) of the paper relies on this symmetry.

        Parameters
        ----------
        x : float
            Position of the candidate mirror plane in the period (m).
        rtol : float
            Tolerance on positions, relative to the period, and on the foundation matrix (-).
        """
        pos = np.asarray(self.positions)
        mirrored = (2 * x - pos) % self.period
        tol = rtol * self.period
        mirrored = np.where(np.abs(mirrored - self.period) < tol, 0.0, mirrored)
        order = np.argsort(mirrored)
        if not np.allclose(np.sort(mirrored), pos, rtol=0, atol=tol):
            return False
        if self.foundation is None:
            return True
        g = self.foundation_matrix(np.array([10.0, 100.0, 1000.0]))
        return bool(np.allclose(g[:, order][:, :, order], g, rtol=rtol, atol=0))

    def foundation_matrix(self, f: ArrayLike) -> np.ndarray:
        """The foundation receptance matrix G_rs of the paper's Eq. (3).

        Parameters
        ----------
        f : array_like
            Frequencies (Hz), positive and finite; flattened.

        Returns
        -------
        ndarray of complex, shape ``(n_f, S, S)``
            Vertical receptance under the pads (m/N).
        """
        f = np.atleast_1d(as_frequencies(f))
        if self.foundation is not None:
            g = np.asarray(self.foundation(f), dtype=complex)
            expected = (f.size, self.n_supports, self.n_supports)
            if g.shape != expected:
                raise InputError(f"foundation(f) must return shape {expected}, got {g.shape}")
            return g
        g = self.track.foundation_receptance(f)
        return g[:, None, None] * np.eye(self.n_supports)

    def has_uncoupled_supports(self, f: ArrayLike) -> bool:
        """True when no foundation receptance couples two different supports.

        Parameters
        ----------
        f : array_like
            Frequencies (Hz) at which the foundation matrix is inspected.
        """
        g = self.foundation_matrix(f)
        off = g * (1 - np.eye(self.n_supports))
        return bool(np.all(off == 0))

    def support_stiffness_matrix(self, f: ArrayLike) -> np.ndarray:
        """Dynamic stiffness of all supports of the period.

        The DOFs are ordered (w_1, psi_1, w_2, psi_2, ...). This is the inverse of the paper's
        H_rs(omega) (Eq. 3), written as a stiffness so that ``kphi = 0`` stays finite.

        Parameters
        ----------
        f : array_like
            Frequencies (Hz), positive and finite; flattened.

        Returns
        -------
        ndarray of complex, shape ``(n_f, 2S, 2S)``
            Entries in N/m (w rows and columns), N m/rad (psi) and zero between w and psi.
        """
        f = np.atleast_1d(as_frequencies(f))
        s = self.n_supports
        kv, kphi = self.track.pad_stiffness(f)
        kv, kphi = kv[:, None, None], kphi[:, None, None]
        hv = self.foundation_matrix(f) + np.eye(s) / kv  # vertical receptance of the supports
        kvv = np.linalg.inv(hv)
        out = np.zeros((f.size, 2 * s, 2 * s), dtype=complex)
        out[:, 0::2, 0::2] = kvv
        out[:, 1::2, 1::2] = kphi * np.eye(s)
        return out


#: Symbol, description and unit of every Track field, in the order of the paper's Tables 2 and 5.
PARAMETER_INFO = (
    ("rho", "rho", "density of the rail", "kg/m^3"),
    ("E", "E", "Young's modulus of the rail", "N/m^2"),
    ("G", "G", "shear modulus of the rail", "N/m^2"),
    ("eta_rail", "eta_R", "loss factor of the rail", "-"),
    ("A", "A", "cross-sectional area of the rail", "m^2"),
    ("I", "I", "second moment of area of the rail", "m^4"),
    ("kappa", "kappa", "shear coefficient of the rail section", "-"),
    ("kv", "k_v", "vertical rail pad stiffness", "N/m"),
    ("kphi", "k_phi", "rotational rail pad stiffness", "N m/rad"),
    ("eta_pad", "eta_P", "rail pad loss factor", "-"),
    ("sleeper_mass", "m_S", "mass of half a sleeper", "kg"),
    ("spacing", "d", "support spacing", "m"),
    ("kb", "k_B", "ballast stiffness", "N/m"),
    ("eta_ballast", "eta_B", "ballast loss factor", "-"),
)

#: Symbol, description and unit of every numeric :class:`Slab` field (``cut`` is a choice, not a
#: parameter; ``shear_stiffness`` appears only for a Timoshenko slab).
SLAB_PARAMETER_INFO = (
    ("length", "L", "slab length", "m"),
    ("fasteners", "S", "fasteners per slab", "-"),
    ("E", "E_S", "Young's modulus of the slab", "N/m^2"),
    ("I", "I_S", "second moment of area of the slab (per rail)", "m^4"),
    ("mass_per_length", "m_S'", "slab mass per unit length (per rail)", "kg/m"),
    ("eta_slab", "eta_S", "loss factor of the slab", "-"),
    ("shear_stiffness", "kappa_S A_S G_S", "shear stiffness of the slab (per rail)", "N"),
    ("rotary_inertia", "rho_S I_S", "rotary inertia of the slab (per rail)", "kg m"),
    ("support_stiffness", "k_L", "resilient layer stiffness per unit length (per rail)", "N/m^2"),
    ("eta_support", "eta_L", "loss factor of the resilient layer", "-"),
)


def parameter_table(track: Track) -> pd.DataFrame:
    """The track's parameters as a table, in the order of the paper's Tables 2 and 5.

    Fields that do not apply (the sleeper and ballast of a slab track) are left out; a flexible
    slab's fields follow the pad's (:data:`SLAB_PARAMETER_INFO`).

    Parameters
    ----------
    track : Track
        The track.

    Returns
    -------
    pandas.DataFrame
        Columns ``symbol, description, value, unit`` (values in SI units), indexed 0, 1, ...
        A curve of frequency (a pad, a measured foundation) is its description in the value
        column, e.g. ``FrequencyTable('pad.csv', stiffness, 41 points, 0-4000 Hz)``.
    """
    import pandas as pd  # here, not at the top: the CLI's start-up need not pay for pandas

    track = require_track(track)
    rows = [(sym, desc, getattr(track, key), unit) for key, sym, desc, unit in PARAMETER_INFO
            if not (key in ("sleeper_mass", "kb", "eta_ballast") and not track.is_ballasted)]
    if track.has_flexible_slab:
        rows += [(sym, desc, getattr(track.slab, key), unit) for key, sym, desc, unit in SLAB_PARAMETER_INFO
                 if getattr(track.slab, key) is not None]
    if track.foundation is not None:
        rows.append(("G", "measured receptance under each pad", track.foundation, "m/N"))
    rows = [(sym, desc, repr(value) if isinstance(value, FrequencyCurve) else value, unit)
            for sym, desc, value, unit in rows]
    return pd.DataFrame(rows, columns=["symbol", "description", "value", "unit"])
