"""A flexible track slab: a free-free beam on a resilient layer, coupling the fasteners it carries.

The paper (Sec. 2, Eq. 3, Fig. 1) lets the S fasteners of one slab interact through the slab's
vertical receptance G_rs(omega), then treats its slab as rigid because the CA mortar under it is
far stiffer than the rail pads. Here the slab is what it is: a beam of length L with free ends
(the joints between slabs are weak, as the paper assumes), on a continuous Winkler layer (CA
mortar, or a slab mat for a floating-slab track) resting on a rigid base. The S fasteners sit at
the rail's support spacing d, centred on the slab, so one slab is one period of the track, S d.

G_rs is exact: the slab is cut at its fasteners into uniform segments, each with the exact
dynamic stiffness of a beam on an elastic foundation (the rail's wave kernel,
:func:`semitrack.model.beam.wave_dynamic_stiffness`, with the foundation shifting the
inertia term), assembled with free ends and inverted. The beam is Euler-Bernoulli unless a shear
stiffness is given (then Timoshenko, with the given rotary inertia).

Damping is by loss factors: E(1 + i eta_slab) and k(1 + i eta_support). The pads' rotational
stiffness still acts against the ground: the slab's rotation under a fastener is not coupled to
the rail (the paper's Eq. 3 couples the vertical direction only).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ..base.checks import (
    as_frequencies,
    check_choice,
    check_int_at_least,
    check_nonnegative,
    check_positive,
    check_work,
)
from ..base.errors import InputError, InputTypeError
from .beam import beam_scaling, beam_state_matrix, wave_dynamic_stiffness

#: Where the cut of alpha and the central responses sits on a flexible-slab track, by name: at the
#: joint between two slabs (the paper's choice, Sec. 3) or at the slab's centre (a mid-span when
#: the slab carries an even number of fasteners). An integer k picks the k-th mid-span inside.
SLAB_CUTS = ("joint", "centre")

#: Most fasteners on one slab: each adds a node to the batched solves of every frequency.
MAX_FASTENERS = 200
#: Most free-free modes asked of one call.
MAX_MODES = 100_000


@dataclass(frozen=True)
class Slab:
    """A track slab of finite length on a resilient layer (per rail: half the slab of a track).

    All quantities in SI units, for the share of the slab under one rail.

    Parameters
    ----------
    length : float
        Slab length L (m). The fasteners sit at the rail's spacing d, centred on the slab, so the
        track needs (S - 1) d < L <= S d: slabs do not overlap, and the end fasteners have slab
        beyond them.
    fasteners : int
        Number S >= 1 of fasteners (rail supports) on one slab.
    E : float
        Young's modulus of the slab (N/m^2).
    I : float
        Second moment of area of the slab section under one rail (m^4).
    mass_per_length : float
        Mass of that section per unit length (kg/m).
    support_stiffness : float
        Stiffness of the resilient layer (CA mortar, slab mat) per unit length of slab (N/m^2):
        bedding modulus (N/m^3) times the supported width.
    eta_support : float
        Loss factor of the resilient layer (-), > 0: every real layer dissipates, and an
        undamped layer would make the exact slab receptance singular at the slab's bounce.
    eta_slab : float
        Loss factor of the slab (-).
    shear_stiffness : float or None
        kappa A G of the slab section (N) for a Timoshenko slab; ``None`` (default) for an
        Euler-Bernoulli slab (rigid in shear).
    rotary_inertia : float
        rho I of the slab section (kg m), used with ``shear_stiffness`` (default 0).
    cut : {"joint", "centre"} or int
        Where alpha's cut (and the central responses) sits: at the joint between two slabs
        (default, the paper's choice); at the slab's centre (needs an even ``fasteners``, so that
        the centre is a mid-span); or at the k-th mid-span inside the slab, 1 <= k <= S - 1 (k
        fasteners of the slab lie left of it). Inside a slab the slab is cut too: alpha is that
        of the semi-infinite track whose first slab starts, free, at the cut. With a flexible
        slab alpha depends on the cut.
    """

    length: float
    fasteners: int
    E: float
    I: float  # noqa: E741 - the usual symbol
    mass_per_length: float
    support_stiffness: float
    eta_support: float
    eta_slab: float = 0.0
    shear_stiffness: float | None = None
    rotary_inertia: float = 0.0
    cut: str = "joint"

    def __post_init__(self):
        for key in ("length", "E", "I", "mass_per_length", "support_stiffness", "eta_support"):
            object.__setattr__(self, key, check_positive(key, getattr(self, key)))
        for key in ("eta_slab", "rotary_inertia"):
            object.__setattr__(self, key, check_nonnegative(key, getattr(self, key)))
        if self.shear_stiffness is not None:
            object.__setattr__(self, "shear_stiffness", check_positive("shear_stiffness", self.shear_stiffness))
        with np.errstate(over="ignore", invalid="ignore"):
            modes = self._frequencies(4)
        if not np.all(np.isfinite(modes)):
            raise InputError("length, E, I, mass_per_length and support_stiffness give no finite natural frequency "
                             f"(got {modes.tolist()} Hz): a value is far outside any slab's")
        s = check_int_at_least("fasteners", self.fasteners, 1)
        if s > MAX_FASTENERS:
            raise InputError(f"fasteners must be at most {MAX_FASTENERS} (a slab is a few metres long), got {s}")
        object.__setattr__(self, "fasteners", s)
        if isinstance(self.cut, str):
            check_choice("cut", self.cut, SLAB_CUTS)
            if self.cut == "centre" and s % 2:
                raise InputError(f"cut='centre' needs an even number of fasteners (the centre of a slab with "
                                 f"{s} is a fastener, not a mid-span); use cut='joint' or a mid-span number")
        else:
            try:
                k = check_int_at_least("cut", self.cut, 1)
            except TypeError:
                raise InputTypeError(f"cut must be one of {SLAB_CUTS} or a mid-span number, got {self.cut!r}") from None
            if k > s - 1:
                raise InputError(f"cut must be a mid-span inside the slab, 1 <= cut <= fasteners - 1 = {s - 1}, "
                                 f"got {self.cut!r}")
            object.__setattr__(self, "cut", k)

    @property
    def cut_span(self) -> int:
        """The cut as a mid-span number k: 0 at the joint, S/2 at the centre, else ``cut``."""
        if isinstance(self.cut, str):
            return 0 if self.cut == "joint" else self.fasteners // 2
        return self.cut

    def check_spacing(self, spacing: float) -> None:
        """Raise ValueError unless S fasteners fit on the slab as the ``length`` rule states.

        Parameters
        ----------
        spacing : float
            The rail's support spacing d (m).
        """
        s, length = self.fasteners, self.length
        if not (s - 1) * spacing < length <= s * spacing * (1 + 1e-12):
            raise InputError(
                f"a slab of length {length!r} m cannot carry {s} fasteners at spacing {spacing!r} m centred "
                f"on it: it needs ({s} - 1) x spacing < length <= {s} x spacing, i.e. "
                f"{(s - 1) * spacing:.6g} < length <= {s * spacing:.6g}")

    def natural_frequencies(self, n: int = 6) -> np.ndarray:
        """Undamped natural frequencies (Hz) of the free slab on its layer, no rail (Euler-Bernoulli).

        omega_k^2 = (k + EI beta_k^4) / m with the free-free beam's beta_k L = 0, 0 (bounce and
        pitch on the layer), 4.730, 7.853, 10.996, ... (roots of cos x cosh x = 1). The rail and
        its pads stiffen and load these modes; the track's receptance shows them shifted.

        Parameters
        ----------
        n : int
            How many (>= 1).

        Returns
        -------
        ndarray, shape (n,)
            Increasing, Hz.
        """
        n = check_int_at_least("n", n, 1)
        check_work(n, MAX_MODES, f"n={n} modes", "a slab's response needs a few dozen")
        return self._frequencies(n)

    def _frequencies(self, n: int) -> np.ndarray:
        beta_l = np.zeros(n)
        for k in range(2, n):
            beta_l[k] = _free_free_root(k - 1)
        beta = beta_l / self.length
        omega2 = (self.support_stiffness + self.E * self.I * beta**4) / self.mass_per_length
        return np.sqrt(omega2) / (2 * np.pi)

    def receptance(self, f: ArrayLike, spacing: float, from_span: int = 0, *, eta_slab: ArrayLike | None = None,
                   eta_support: ArrayLike | None = None) -> np.ndarray:
        """Vertical receptance G_rs of the slab between its fasteners (paper Eq. 3), exact.

        Parameters
        ----------
        f : array_like
            Frequencies (Hz), positive and finite; flattened.
        spacing : float
            Fastener spacing d (m), as the track's.
        from_span : int
            0 (default): the whole slab. k >= 1: the part of the slab right of its k-th mid-span,
            cut there with a free end, carrying the last S - k fasteners.
        eta_slab, eta_support : array_like, optional
            Loss factors (-) of the slab and of its layer at each frequency, in place of the
            slab's own constant ones: the track's viscous law ``eta f / f_ref``
            (:meth:`semitrack.Track.slab_receptance` gives them).

        Returns
        -------
        ndarray of complex, shape ``(n_f, S - from_span, S - from_span)``
            Slab deflection under fastener r per unit downward force at fastener s (m/N),
            symmetric; fasteners ordered along x.
        """
        f = np.atleast_1d(as_frequencies(f)).ravel()
        spacing = check_positive("spacing", spacing)
        self.check_spacing(spacing)
        k = check_int_at_least("from_span", from_span, 0)  # 5.5, True and '1' are no span index
        if not k < self.fasteners:
            raise InputError(f"from_span must be in 0..{self.fasteners - 1}, got {from_span!r}")
        omega = 2 * np.pi * f
        s = self.fasteners - k
        c_slab = 1 + 1j * np.broadcast_to(self.eta_slab if eta_slab is None else np.ravel(eta_slab), f.shape)
        c_layer = 1 + 1j * np.broadcast_to(self.eta_support if eta_support is None else np.ravel(eta_support), f.shape)
        ei = self.E * self.I * c_slab
        compliance = 0.0 if self.shear_stiffness is None else 1.0 / (self.shear_stiffness * c_slab)
        a = beam_state_matrix(omega, ei, compliance, self.mass_per_length, self.rotary_inertia,
                              self.support_stiffness * c_layer)
        overhang = 0.5 * (self.length - (self.fasteners - 1) * spacing)
        lengths = np.r_[0.5 * spacing if k else overhang, np.full(s - 1, spacing), overhang]  # left end to right
        unique, which = np.unique(lengths, return_inverse=True)
        seg = wave_dynamic_stiffness(a, beam_scaling(spacing, self.E * self.I), unique)  # (<= 3, n, 4, 4)
        n_nodes = s + 2  # left end, the fasteners, right end
        stiff = np.zeros((f.size, 2 * n_nodes, 2 * n_nodes), dtype=complex)
        for j in range(n_nodes - 1):
            stiff[:, 2 * j: 2 * j + 4, 2 * j: 2 * j + 4] += seg[which[j]]
        fastener_w = 2 * np.arange(1, s + 1)
        unit = np.zeros((2 * n_nodes, s))
        unit[fastener_w, np.arange(s)] = 1.0
        g = np.linalg.solve(stiff, np.broadcast_to(unit, (f.size,) + unit.shape))[:, fastener_w, :]
        return 0.5 * (g + np.swapaxes(g, 1, 2))  # symmetric by reciprocity; remove rounding asymmetry


def _free_free_root(k: int) -> float:
    """k-th positive root (k >= 1) of cos x cosh x = 1: beta L of the free-free beam's k-th bending mode."""
    x = (k + 0.5) * np.pi  # the asymptote; Newton converges in a few steps from it
    for _ in range(50):
        g = np.cos(x) - 1.0 / np.cosh(x)  # cos x cosh x - 1, divided by cosh x to stay bounded
        dg = -np.sin(x) + np.tanh(x) / np.cosh(x)
        step = g / dg
        x -= step
        if abs(step) < 1e-14 * x:
            break
    return float(x)
