"""The fit's unknowns: log-parameters ``theta``, their bounds and the map to the physical parameters.

* **Parameterisation.** Each free parameter ``p`` is written ``p = p_ref exp(theta)`` with a
  reference value ``p_ref`` taken from the track (rail mass of one bay, pad stiffness, ...,
  :func:`references`), and ``theta`` is bounded to ``[log(1e-8), log(1e4)]`` (lengths
  ``[log(1e-3), log(20)]``). The logarithm makes the solver scale-free: the parameters of the
  paper's tables span four to eight decades (Table 7: ``c_r`` from 4.76 to 37546 N s/m), and a
  step in ``theta`` is a relative change of the parameter, whatever its unit. The lower bound
  keeps every parameter strictly positive (``L > 0`` is required; M and K stay definite so that
  ``Z(omega)`` is invertible) while letting it reach ``1e-8`` of its reference, which is zero
  for all practical purposes: Table 4's massless bars with zero springs are inside the search
  space. A bounded linear parameter (lower bound 0) would reach exact zeros but has no natural
  scale across decades, and a softplus is linear for large values; both were judged worse for
  parameters spread over many decades.
* **Constraints.** With ``constrained=True`` the dependent parameters (``k, J`` for the slab,
  ``k, J, s, mu`` for the ballasted layout) follow the paper's relations from the free ones and
  the characteristic frequencies (:mod:`.constraints`, the same functions, evaluated batched
  and complex-safe); the final system is built with
  :func:`~semitrack.equivalent.constraints.slab_from_free` /
  :func:`~semitrack.equivalent.constraints.ballasted_from_free`. With ``constrained=False``
  these parameters are fitted freely too.
* **Derivatives** of the parameters with respect to ``theta`` (through the constraints) come
  from a complex-step differentiation, exact to rounding.
"""

from __future__ import annotations

import math

import numpy as np

from ..model.curves import FrequencyCurve
from ..model.tracks import Track
from .assembly import Layout, assembly
from .constraints import (
    ballasted_from_free,
    inertia_relation,
    lower_spring_relation,
    slab_from_free,
    slab_spring_relation,
    support_mass_relation,
    upper_spring_relation,
)
from .systems import BallastedEquivalent, EquivalentSystem, SlabEquivalent

__all__ = ["FitParametrisation", "references", "free_parameter_names"]

_TWO_PI = 2 * np.pi

# Bounds of theta = log(p / p_ref): 1e-8 of the reference is "zero" for every parameter (a mass
# of 1e-8 rail bays is 4e-7 kg), 1e4 is far beyond anything physical for an equivalent of one
# track; lengths must stay positive and below ~20 half-bays.
_LOG_LO, _LOG_HI = math.log(1e-8), math.log(1e4)
_LOG_L_LO, _LOG_L_HI = math.log(1e-3), math.log(20.0)

# Complex-step size for dp/dtheta: the derivative is exact to rounding for any tiny h.
_CSTEP = 1e-30

# Distance kept from the bounds by a start point: least_squares needs a strictly feasible one.
_INSIDE_MARGIN = 1e-10

# The parameters of the paper's fits (6N - 2 slab, 8N - 2 ballasted) and the ones its
# constraints derive.
_FREE = {"slab": ("m", "L", "c_l", "c_r", "k_phi", "c_phi"),
         "ballasted": ("m", "L", "c_l", "c_r", "k_phi", "c_phi", "d_l", "d_r")}
_DERIVED = {"slab": ("k", "J"), "ballasted": ("k", "J", "mu", "s")}


def free_parameter_names(layout: Layout, constrained: bool) -> tuple[str, ...]:
    """The parameter families the fit solves for, in the order of ``theta``.

    Parameters
    ----------
    layout : {"slab", "ballasted"}
        The layout.
    constrained : bool
        Whether the paper's constraints derive ``k, J`` (and ``mu, s``).
    """
    return _FREE[layout] + (() if constrained else _DERIVED[layout])


def references(track: Track, layout: Layout, char: dict[str, float]) -> dict[str, float]:
    """Reference value of every parameter family, from the track (SI units).

    Parameters
    ----------
    track : Track
        The track: rail mass of one bay, pad (and ballast) stiffness, bending stiffness, loss
        factors and the support spacing set the scales.
    layout : {"slab", "ballasted"}
        The layout.
    char : dict
        Characteristic frequencies (Hz): ``f_n`` or ``f_n1`` set the damping scales.

    Returns
    -------
    dict
        ``{family: p_ref}`` in the units of :data:`~.systems.PARAMETER_UNITS`.
    """
    m_bay = track.mass_per_length * track.spacing  # rail mass of one bay (paper's suggestion)
    L = 0.5 * track.spacing
    w_ref = _TWO_PI * (char["f_n"] if layout == "slab" else char["f_n1"])
    kv, eta_pad = _pad_scale(track, w_ref / _TWO_PI)
    eta = max(eta_pad, 0.01)
    k_bend = track.E * track.I / track.spacing
    refs = {
        "m": m_bay, "L": L, "k": kv, "J": 0.25 * m_bay * L**2,
        "c_l": eta * kv / w_ref, "c_r": eta * kv / w_ref,
        "k_phi": k_bend, "c_phi": max(eta, track.eta_rail) * k_bend / w_ref,
    }
    if layout == "ballasted":
        if track.is_ballasted:
            mu, s, eta_b = 0.5 * track.sleeper_mass, 0.5 * track.kb, max(track.eta_ballast, eta)
        else:
            mu, s, eta_b = m_bay, kv, eta
        refs.update(mu=mu, s=s, d_l=eta_b * s / w_ref, d_r=eta_b * s / w_ref)
    return refs


def _pad_scale(track: Track, f: float) -> tuple[float, float]:
    """The pad's stiffness scale (N/m) and loss factor (-): a constant pad's, or a curve's at ``f`` (Hz)."""
    if not isinstance(track.kv, FrequencyCurve):
        return track.kv, track.eta_pad
    k = track.kv.sample(f)
    return abs(k), max(k.imag, 0.0) / abs(k)


class FitParametrisation:
    """Free parameters of one layout, their reference values, bounds and the map to M, C, K.

    Parameters
    ----------
    layout : {"slab", "ballasted"}
        The layout.
    n_bars : int
        Number of bars N.
    constrained : bool
        Whether the paper's constraints derive ``k, J`` (and ``mu, s``).
    refs : dict
        Reference value of every family (:func:`references`).
    char : dict
        Characteristic frequencies (Hz) of the constraints.

    Attributes
    ----------
    names : tuple of str
        The free families, in the order of ``theta``.
    slices : dict
        The slice of ``theta`` of each family.
    n_theta : int
        Number of unknowns.
    lower, upper : ndarray
        Bounds of ``theta``.
    assembly : Assembly
        The layout's maps and term table (:mod:`.assembly`).
    """

    def __init__(self, layout: Layout, n_bars: int, constrained: bool, refs: dict, char: dict):
        self.layout, self.N, self.constrained, self.char = layout, n_bars, constrained, dict(char)
        self.assembly = assembly(layout, n_bars)
        self.n_dof = self.assembly.n_dof
        self.names = free_parameter_names(layout, constrained)
        sizes = {n: (n_bars - 1 if n in ("k_phi", "c_phi") else n_bars) for n in self.names}
        self.slices, i = {}, 0
        for n in self.names:
            self.slices[n] = slice(i, i + sizes[n])
            i += sizes[n]
        self.n_theta = i
        self.refs = {n: float(refs[n]) for n in self.names}
        self.log_ref = np.concatenate([np.full(sizes[n], math.log(self.refs[n])) for n in self.names])
        self.lower = np.concatenate([np.full(sizes[n], _LOG_L_LO if n == "L" else _LOG_LO) for n in self.names])
        self.upper = np.concatenate([np.full(sizes[n], _LOG_L_HI if n == "L" else _LOG_HI) for n in self.names])

    # --- parameters -----------------------------------------------------------------------
    def params(self, theta: np.ndarray) -> dict[str, np.ndarray]:
        """All physical parameters (B, size) from theta (B, n_theta); complex-safe."""
        p = {n: np.exp(theta[:, self.slices[n]] + self.log_ref[self.slices[n]]) for n in self.names}
        if self.constrained:
            m, L, c = p["m"], p["L"], self.char
            p["J"] = inertia_relation(m, L)
            if self.layout == "slab":
                p["k"] = slab_spring_relation(m, c["f_n"])
            else:
                p["k"] = upper_spring_relation(m, c["f_n1"], c["f_n2"], c["f_anti"])
                p["s"] = lower_spring_relation(p["k"], c["f_n1"], c["f_n2"], c["f_anti"])
                p["mu"] = support_mass_relation(p["k"], p["s"], c["f_anti"])
        return p

    def param_derivatives(self, theta: np.ndarray) -> dict[str, np.ndarray]:
        """d p / d theta for every parameter family, each (n_theta, size), by complex step."""
        th = theta[None, :] + 1j * _CSTEP * np.eye(self.n_theta)
        return {name: v.imag / _CSTEP for name, v in self.params(th).items()}

    def matrices(self, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """M, C, K of shape (B, n, n) for theta (B, n_theta) (:meth:`.assembly.Assembly.matrices`)."""
        return self.assembly.matrices(self.params(theta))

    def theta_of(self, system: EquivalentSystem) -> np.ndarray:
        """theta of the free parameters of ``system`` (clipped to the bounds)."""
        pars = system.parameters()
        with np.errstate(divide="ignore"):
            th = np.concatenate([np.log(pars[n]) for n in self.names]) - self.log_ref
        return np.clip(th, self.lower, self.upper)

    def inside(self, theta: np.ndarray, margin: float = _INSIDE_MARGIN) -> np.ndarray:
        """``theta`` moved strictly inside the bounds (least_squares needs a feasible interior start)."""
        return np.clip(theta, self.lower + margin, self.upper - margin)

    def system(self, theta: np.ndarray) -> EquivalentSystem:
        """The system of ``theta``; with constraints it is built by the paper's relations."""
        p = {n: np.real(v[0]) for n, v in self.params(np.atleast_2d(theta)).items()}
        if self.constrained:
            free = {n: p[n] for n in _FREE["slab"]}
            if self.layout == "slab":
                return slab_from_free(**free, f_n=self.char["f_n"])
            return ballasted_from_free(**free, d_l=p["d_l"], d_r=p["d_r"], f_n1=self.char["f_n1"],
                                       f_n2=self.char["f_n2"], f_anti=self.char["f_anti"])
        cls = SlabEquivalent if self.layout == "slab" else BallastedEquivalent
        return cls.from_parameters({n: p[n] for n in cls.parameter_names()})
