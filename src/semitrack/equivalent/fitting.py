"""Fitting an equivalent multi-rigid-body system to a track's receptance (paper Sec. 4.4, 5.2).

The paper determines the parameters of the slab layout (Fig. 7) and the ballasted layout
(Fig. 12) by nonlinear least squares (Matlab ``lsqnonlin``): at pre-selected frequencies the
residuals ``Re(alpha_E - alpha)/|alpha|`` and ``Im(alpha_E - alpha)/|alpha|`` of alpha11,
alpha12 and alpha22 are driven to zero, with some parameters tied to the track's characteristic
frequencies by Eq. (19)-(20) (slab) or Eq. (23), (28)-(30) (ballasted). :func:`fit_equivalent`
solves the same problem with :func:`scipy.optimize.least_squares`:

* **Parameterisation.** Each free parameter ``p`` is written ``p = p_ref exp(theta)`` with a
  reference value ``p_ref`` taken from the track (rail mass of one bay, pad stiffness, ...), and
  ``theta`` is bounded to ``[log(1e-8), log(1e4)]`` (lengths ``[log(1e-3), log(20)]``). The
  logarithm makes the solver scale-free: the parameters of the paper's tables span four to eight
  decades (Table 7: ``c_r`` from 4.76 to 37546 N s/m), and a step in ``theta`` is a relative
  change of the parameter, whatever its unit. The lower bound keeps every parameter strictly
  positive (``L > 0`` is required; M and K stay definite so that ``Z(omega)`` is invertible)
  while letting it reach ``1e-8`` of its reference, which is zero for all practical purposes:
  Table 4's massless bars with zero springs are inside the search space. A bounded linear
  parameter (lower bound 0) would reach exact zeros but has no natural scale across decades,
  and a softplus is linear for large values; both were judged worse for parameters spread over
  many decades.
* **Constraints.** With ``constrained=True`` the dependent parameters (``k, J`` for the slab,
  ``k, J, s, mu`` for the ballasted layout) follow the paper's relations from the free ones and
  the characteristic frequencies; the final system is built with
  :func:`~semitrack.equivalent.constraints.slab_from_free` / :func:`~semitrack.equivalent.constraints.ballasted_from_free`.
  With ``constrained=False`` these parameters are fitted freely too.
* **Characteristic frequencies** are detected, never hard-coded: they are extrema of
  ``|det(alpha^-1)|`` (Eq. 18), whose local minima are the resonances of the semi-infinite track.
  Slab: the dip of ``|det|`` closest to the bouncing-frequency estimate ``sqrt(kv/(rho A d))/(2 pi)``
  gives ``f_n`` (183.7 Hz for the paper's track). Ballasted: the two lowest dips give ``f_n1``
  and ``f_n2`` (114.9, 500.5 Hz) and the highest peak of ``|det|`` between them gives
  ``f_anti`` (244.8 Hz). The paper reads 117, 489 (or 465) and 243 Hz off its curves.
* **Speed.** Residuals and the Jacobian are vectorised over frequency (one batched
  ``numpy.linalg.solve`` of the dynamic stiffness ``Z = K + i omega C - omega^2 M``, with
  symmetric diagonal scaling). The Jacobian is analytic, ``d alpha = -X^T dZ X`` with
  ``X = Z^-1 E``, evaluated through the spring-elongation maps ``P`` (``Z`` is a sum of
  ``P^T diag(v) P`` terms) in O(n_f N n_theta) operations; the derivatives of the values ``v``
  through the constraints come from a complex-step differentiation (exact to rounding). BLAS
  runs single-threaded during a fit (the matrices are tiny; a ``threadpoolctl`` limit).
* **Multi-start.** Start 0 is the track-based guess suggested by the paper (pad stiffness, rail
  mass of one bay, lengths of half a bay, bar masses growing along the chain); the others are
  random log-normal perturbations of it (a factor ``e`` per standard deviation), drawn with
  ``numpy.random.default_rng(seed)``. Every start is screened by a short run (100 evaluations);
  the best three are continued to convergence (trust-region reflective, ``x_scale="jac"``) and
  then polished by a ``dogbox`` run, which holds the parameters that trf only creeps towards the
  lower bound (the "zero" dampers) at the bound and so certifies convergence in a few steps.
  The lowest cost wins.
* **Identifiability.** In the slab layout the right end of bar j and the left end of bar j+1
  move together (they are hinged) and their dampers both go to the ground, so the receptance
  determines only the sums ``c_r[j] + c_l[j+1]``: fitted dampers at a joint are not unique,
  which is one reason for the zeros in the paper's Table 4 and in our fits. (In the ballasted
  layout the two dampers end on different support masses.) Compare fits by their errors, not
  by their parameters.
"""

from __future__ import annotations

import math
import time
import warnings
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import least_squares
from threadpoolctl import threadpool_limits

from ..base.checks import as_frequencies, check_band, check_int_at_least
from ..base.paper_values import TABLE4_FIT_FREQUENCIES, TABLE7_FIT_FREQUENCIES
from ..methods.features import characteristic_frequencies, find_extrema
from ..methods.receptance import semi_infinite_receptance
from ..model.tracks import require_track
from .constraints import (
    ballasted_from_free,
    inertia_relation,
    lower_spring_relation,
    slab_from_free,
    slab_spring_relation,
    support_mass_relation,
    upper_spring_relation,
)
from .metrics import ErrorSummary, error_band_grid, error_summary
from .systems import BallastedEquivalent, EquivalentSystem, SlabEquivalent, _hinge_map

__all__ = [
    "FitResult",
    "fit_equivalent",
    "default_fit_frequencies",
    "fit_characteristic_frequencies",
    "LAYOUTS",
    "POOR_MEDIAN_ERROR",
    "CHARACTERISTIC_SEARCH_BAND",
]

#: The two layouts of the paper.
LAYOUTS = ("slab", "ballasted")

_TWO_PI = 2 * np.pi

# Bounds of theta = log(p / p_ref): 1e-8 of the reference is "zero" for every parameter (a mass
# of 1e-8 rail bays is 4e-7 kg), 1e4 is far beyond anything physical for an equivalent of one
# track; lengths must stay positive and below ~20 half-bays.
_LOG_LO, _LOG_HI = math.log(1e-8), math.log(1e4)
_LOG_L_LO, _LOG_L_HI = math.log(1e-3), math.log(20.0)

# Complex-step size for dM/dtheta etc.: the derivative is exact to rounding for any tiny h.
_CSTEP = 1e-30

#: A fit whose median error exceeds this is reported as poor (RuntimeWarning): the paper's own
#: Tables 4 and 7 reach about 0.15-0.17 on the dense grid of their bands.
POOR_MEDIAN_ERROR = 0.25


# ------------------------------------------------------------------------------------------------
# Batched, complex-safe model: theta (B, n_theta) -> parameters -> M, C, K (B, n, n)
# ------------------------------------------------------------------------------------------------
def _quad(P: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Batched ``P^T diag(v) P`` for ``P`` (B, m, n) or (m, n) and ``v`` (B, m)."""
    if P.ndim == 2:
        return np.einsum("ji,bj,jk->bik", P, v, P)
    return np.matmul(np.swapaxes(P, 1, 2), v[:, :, None] * P)


class _Model:
    """Free parameters of one layout, their reference values and the map to M, C, K.

    The assembly repeats that of :mod:`semitrack.equivalent.systems` (Eq. A.16, A.18, A.24, B.15, B.20,
    B.26) batched over parameter sets and for complex parameters (complex-step derivatives);
    the tests check that both give the same matrices.
    """

    def __init__(self, layout: str, n_bars: int, constrained: bool, refs: dict, char: dict):
        self.layout, self.N, self.constrained, self.char = layout, n_bars, constrained, dict(char)
        N = n_bars
        names = ["m", "L", "c_l", "c_r", "k_phi", "c_phi"]
        if layout == "ballasted":
            names += ["d_l", "d_r"]
        if not constrained:
            names += ["k", "J"] + (["mu", "s"] if layout == "ballasted" else [])
        self.names = tuple(names)
        self.sizes = {n: (N - 1 if n in ("k_phi", "c_phi") else N) for n in names}
        self.slices, i = {}, 0
        for n in names:
            self.slices[n] = slice(i, i + self.sizes[n])
            i += self.sizes[n]
        self.n_theta = i
        self.refs = {n: float(refs[n]) for n in names}
        self.log_ref = np.concatenate([np.full(self.sizes[n], math.log(self.refs[n])) for n in names])
        lo = [np.full(self.sizes[n], _LOG_L_LO if n == "L" else _LOG_LO) for n in names]
        hi = [np.full(self.sizes[n], _LOG_L_HI if n == "L" else _LOG_HI) for n in names]
        self.lower, self.upper = np.concatenate(lo), np.concatenate(hi)
        self.n_dof = N + 1 if layout == "slab" else 3 * N + 1
        n = self.n_dof
        self._R = _hinge_map(N, n)
        self._tril = np.tril(np.ones((N, N)), -1)
        # Z = sum over terms of phi_kind(omega) P^T diag(v) P; phi = 1 (K), i omega (C), -omega^2 (M).
        if layout == "slab":  # Eq. (A.16), (A.18), (A.24)
            terms = [("A0", "m", "M"), ("E", "J", "M"), ("A1", "k", "K"), ("A2", "k", "K"),
                     ("A1", "c_l", "C"), ("A2", "c_r", "C")]
        else:  # Eq. (B.15), (B.20), (B.26)
            terms = [("A0", "m", "M"), ("E", "J", "M"), ("Bl", "mu", "M"), ("Br", "mu", "M"),
                     ("U1", "k", "K"), ("U2", "k", "K"), ("U1", "c_l", "C"), ("U2", "c_r", "C"),
                     ("Bl", "s", "K"), ("Br", "s", "K"), ("Bl", "d_l", "C"), ("Br", "d_r", "C")]
        if N > 1:
            terms += [("R", "k_phi", "K"), ("R", "c_phi", "C")]
        self.terms = tuple(terms)
        # d P[r, 1 + j] / d L_j of the maps that depend on the lengths (the others are constant).
        eye = np.eye(N)
        self.length_weights = {"A1": self._tril, "U1": self._tril, "A0": self._tril + 0.5 * eye,
                               "A2": self._tril + eye, "U2": self._tril + eye}
        if layout == "ballasted":
            self._Bl = np.zeros((N, n))
            self._Bl[:, N + 1 : 2 * N + 1] = np.eye(N)
            self._Br = np.zeros((N, n))
            self._Br[:, 2 * N + 1 :] = np.eye(N)

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

    def theta_of(self, system: EquivalentSystem) -> np.ndarray:
        """theta of the free parameters of ``system`` (clipped to the bounds)."""
        pars = system.parameters()
        with np.errstate(divide="ignore"):
            th = np.concatenate([np.log(pars[n]) for n in self.names]) - self.log_ref
        return np.clip(th, self.lower, self.upper)

    def system(self, theta: np.ndarray) -> EquivalentSystem:
        """The fitted system; with constraints it is built by the paper's relations."""
        p = {n: np.real(v[0]) for n, v in self.params(np.atleast_2d(theta)).items()}
        if self.constrained:
            free = {n: p[n] for n in ("m", "L", "c_l", "c_r", "k_phi", "c_phi")}
            if self.layout == "slab":
                return slab_from_free(**free, f_n=self.char["f_n"])
            return ballasted_from_free(**free, d_l=p["d_l"], d_r=p["d_r"], f_n1=self.char["f_n1"],
                                       f_n2=self.char["f_n2"], f_anti=self.char["f_anti"])
        cls = SlabEquivalent if self.layout == "slab" else BallastedEquivalent
        return cls.from_parameters({n: p[n] for n in cls.parameter_names()})

    # --- matrices ---------------------------------------------------------------------------
    def maps(self, L: np.ndarray) -> dict[str, np.ndarray]:
        """Maps from q to the spring elongations (Eq. A.1-A.12, B.1-B.12), each (B, rows, n).

        ``A1, A0, A2``: left end, centre, right end of each bar; ``E``: bar rotations;
        ``Bl, Br``: support masses; ``U1 = A1 - Bl``, ``U2 = A2 - Br``: upper springs;
        ``R``: relative rotations at the hinges. ``L`` is (B, N), possibly complex.
        """
        B, N, n = L.shape[0], self.N, self.n_dof
        A1 = np.zeros((B, N, n), dtype=L.dtype)
        A1[:, :, 0] = 1.0
        A1[:, :, 1 : N + 1] = self._tril[None] * L[:, None, :]
        idx = np.arange(N)
        A0, A2 = A1.copy(), A1.copy()
        A0[:, idx, 1 + idx] += 0.5 * L
        A2[:, idx, 1 + idx] += L
        E = np.zeros((N, n))
        E[idx, 1 + idx] = 1.0
        out = {"A0": A0, "A1": A1, "A2": A2, "E": E, "R": self._R}
        if self.layout == "ballasted":
            out.update(Bl=self._Bl, Br=self._Br, U1=A1 - self._Bl, U2=A2 - self._Br)
        return out

    def matrices(self, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """M, C, K of shape (B, n, n) for theta (B, n_theta): sums of ``P^T diag(v) P``."""
        p = self.params(theta)
        maps = self.maps(p["L"])
        B, n = theta.shape[0], self.n_dof
        out = {kind: np.zeros((B, n, n), dtype=p["L"].dtype) for kind in "MCK"}
        for map_name, value, kind in self.terms:
            out[kind] = out[kind] + _quad(maps[map_name], p[value])
        return out["M"], out["C"], out["K"]

    def param_derivatives(self, theta: np.ndarray) -> dict[str, np.ndarray]:
        """d p / d theta for every parameter family, each (n_theta, size), by complex step."""
        th = theta[None, :] + 1j * _CSTEP * np.eye(self.n_theta)
        return {name: v.imag / _CSTEP for name, v in self.params(th).items()}


# Pairs (row, column) of the compared receptance elements alpha11, alpha12, alpha22.
_PAIRS = ((0, 0), (0, 1), (1, 1))


class _Problem:
    """Residuals ``[Re, Im] (alpha_E - alpha) / |alpha|`` and their Jacobian at frequencies f."""

    def __init__(self, model: _Model, f: np.ndarray, alpha: np.ndarray):
        self.model = model
        self.f = np.asarray(f, float)
        self.omega = _TWO_PI * self.f
        self.target = np.stack([alpha[:, i, j] for i, j in _PAIRS], axis=1)  # (n_f, 3)
        self.scale = 1.0 / np.abs(self.target)  # (n_f, 3)
        self._key = None
        n = model.n_dof
        self._E = np.zeros((n, 2))
        self._E[0, 0] = self._E[1, 1] = 1.0

    def _solve(self, theta: np.ndarray):
        key = theta.tobytes()
        if key != self._key:
            M, C, K = (X[0] for X in self.model.matrices(theta[None, :]))
            w = self.omega[:, None, None]
            Z = K[None] + 1j * w * C[None] - w**2 * M[None]
            d = np.sqrt(np.abs(np.diagonal(Z, axis1=1, axis2=2)))
            s = 1.0 / np.where(d > 0, d, 1.0)
            Zs = s[:, :, None] * Z * s[:, None, :]
            try:
                X = s[:, :, None] * np.linalg.solve(Zs, s[:, :, None] * self._E[None])
            except np.linalg.LinAlgError:  # exactly singular: residuals become large (see fun)
                X = np.full((self.f.size, self.model.n_dof, 2), np.nan + 0j)
            self._key, self._X = key, X
        return self._X

    def alpha(self, theta: np.ndarray) -> np.ndarray:
        X = self._solve(theta)
        return np.stack([X[:, i, j] for i, j in _PAIRS], axis=1)

    def fun(self, theta: np.ndarray) -> np.ndarray:
        d = (self.alpha(theta) - self.target) * self.scale
        r = np.concatenate([d.real.ravel(), d.imag.ravel()])
        if not np.all(np.isfinite(r)):
            r = np.where(np.isfinite(r), r, 1e6)
        return r

    def projected_maps(self, X: np.ndarray, L: np.ndarray) -> dict[str, np.ndarray]:
        """``P X`` for every map, each (n_f, rows, 2), without forming the maps."""
        N = self.model.N
        X0, Xp = X[:, 0, :], X[:, 1 : N + 1, :]
        A1 = X0[:, None, :] + (self.model._tril * L[None, :])[None] @ Xp
        out = {"A1": A1, "A0": A1 + 0.5 * L[None, :, None] * Xp, "A2": A1 + L[None, :, None] * Xp,
               "E": Xp, "R": Xp[:, 1:, :] - Xp[:, :-1, :]}
        if self.model.layout == "ballasted":
            Bl, Br = X[:, N + 1 : 2 * N + 1, :], X[:, 2 * N + 1 :, :]
            out.update(Bl=Bl, Br=Br, U1=A1 - Bl, U2=out["A2"] - Br)
        return out

    def jac(self, theta: np.ndarray) -> np.ndarray:
        """Analytic Jacobian of :meth:`fun`.

        ``d alpha = -X^T dZ X`` with ``X = Z^-1 E``. With ``Z = sum phi P^T diag(v) P`` and
        ``Y = P X`` (rows ``Y_r``, shape (n_f, 2)), a change of the values gives
        ``sum_r dv_r Y_r^T Y_r`` and a change of a length L_j, which moves column ``1 + j`` of
        the maps by the weights ``W[r, j]``, gives ``Xj^T S_j + S_j^T Xj`` with
        ``S_j = sum_r v_r W[r, j] Y_r`` and ``Xj = X[:, 1 + j, :]``. The cost is
        O(n_f N n_theta), far below that of the solve.
        """
        model = self.model
        X = self._solve(theta)
        p = {k: np.real(v[0]) for k, v in model.params(theta[None, :]).items()}
        dp = model.param_derivatives(theta)
        Y = self.projected_maps(X, p["L"])
        w = self.omega
        phi = {"K": np.ones_like(w, dtype=complex), "C": 1j * w, "M": -(w**2) + 0j}
        a_idx = [a for a, _ in _PAIRS]
        b_idx = [b for _, b in _PAIRS]
        Xp = X[:, 1 : model.N + 1, :]
        G = np.zeros((self.f.size, 3, model.n_theta), dtype=complex)
        GL = np.zeros((self.f.size, 3, model.N), dtype=complex)
        acc: dict[str, np.ndarray] = {}  # phi-weighted Y_r^T Y_r per value family
        for map_name, value, kind in model.terms:
            Yt = Y[map_name]
            Q = phi[kind][:, None, None] * (Yt[:, :, a_idx] * Yt[:, :, b_idx])  # (n_f, rows, 3)
            acc[value] = Q if value not in acc else acc[value] + Q
            W = model.length_weights.get(map_name)
            if W is not None:
                S = (p[value][:, None] * W).T[None] @ Yt  # (n_f, N, 2)
                H = Xp[:, :, a_idx] * S[:, :, b_idx] + S[:, :, a_idx] * Xp[:, :, b_idx]
                GL += phi[kind][:, None, None] * np.swapaxes(H, 1, 2)
        for value, Q in acc.items():
            d = dp[value]  # (n_theta, rows), non-zero in a few columns only
            cols = np.flatnonzero(np.any(d != 0, axis=1))
            G[:, :, cols] += np.swapaxes(Q, 1, 2) @ d[cols].T
        G[:, :, model.slices["L"]] += GL * p["L"][None, None, :]  # dL/dtheta_L = L
        dalpha = -G * self.scale[:, :, None]
        J = np.concatenate([dalpha.real.reshape(-1, model.n_theta), dalpha.imag.reshape(-1, model.n_theta)])
        return np.where(np.isfinite(J), J, 0.0)


# ------------------------------------------------------------------------------------------------
# Characteristic frequencies, fit frequencies, targets
# ------------------------------------------------------------------------------------------------
_CHAR_KEYS = {"slab": ("f_n",), "ballasted": ("f_n1", "f_n2", "f_anti")}

#: Where characteristic frequencies are looked for by default (Hz): the paper's range.
CHARACTERISTIC_SEARCH_BAND = (3.0, 3000.0)


def _check_layout(layout) -> str:
    if not isinstance(layout, str):
        raise TypeError(f"layout must be a str, one of {LAYOUTS}, got {layout!r}")
    if layout not in LAYOUTS:
        raise ValueError(f"layout must be one of {LAYOUTS}, got {layout!r}")
    return layout


def _check_characteristic(layout: str, characteristic) -> dict[str, float]:
    if not isinstance(characteristic, dict):
        raise TypeError(f"characteristic must be a dict of frequencies (Hz), got {type(characteristic).__name__}")
    keys = _CHAR_KEYS[layout]
    if set(characteristic) != set(keys):
        raise ValueError(f"characteristic for the {layout} layout must have exactly the keys {keys}, "
                         f"got {sorted(characteristic)}")
    out = {}
    for k in keys:
        v = characteristic[k]
        if isinstance(v, bool) or not isinstance(v, (int, float, np.integer, np.floating)):
            raise TypeError(f"characteristic[{k!r}] must be a real number (Hz), got {v!r}")
        if not (math.isfinite(v) and v > 0):
            raise ValueError(f"characteristic[{k!r}] must be positive and finite (Hz), got {v!r}")
        out[k] = float(v)
    if layout == "ballasted" and not (out["f_n1"] < out["f_anti"] < out["f_n2"]):
        raise ValueError("characteristic must satisfy f_n1 < f_anti < f_n2 (Eq. 30 gives s > 0 only then), "
                         f"got {out}")
    return out


def _det_extrema(track, target, search_band, df):
    """Peaks and dips of |det(alpha^-1)| as a DataFrame (see features.find_extrema)."""
    if target is None:
        table = characteristic_frequencies(track, band=search_band, df=df)
        return table[table["quantity"] == "det"]
    if callable(target):
        f = np.arange(search_band[0], search_band[1] + 1e-9, df)

        def det_inv(ff):
            a = _evaluate_target(target, np.atleast_1d(ff))
            return 1.0 / np.linalg.det(a)

        return find_extrema(f, {"det": det_inv(f)}, lambda x: {"det": det_inv(x)[0]})
    f, alpha = target
    return find_extrema(f, {"det": 1.0 / np.linalg.det(alpha)})


def fit_characteristic_frequencies(track, layout: str, *, target=None,
                                   search_band=CHARACTERISTIC_SEARCH_BAND, df: float = 6.0) -> dict[str, float]:
    """The characteristic frequencies (Hz) that the paper's constraints need, detected on the track.

    They are extrema of ``|det(alpha^-1)|`` (Eq. 18), whose local minima are the resonances of
    the semi-infinite track (where the end dynamic stiffness is nearly singular):

    * slab: ``f_n`` = the dip closest to the bouncing-frequency estimate
      ``sqrt(kv / (rho A d)) / (2 pi)`` (Eq. 19-20 make both frequencies of every bar equal to it);
    * ballasted: ``f_n1``, ``f_n2`` = the two lowest dips and ``f_anti`` = the highest peak of
      ``|det(alpha^-1)|`` between them (the anti-resonance, Eq. 23, 28-30).

    Parameters
    ----------
    track : Track
        The track (its bouncing-frequency estimate selects the slab dip).
    layout : {"slab", "ballasted"}
        Which set to return.
    target : None, callable or (f, alpha), optional
        As in :func:`fit_equivalent`: None for the exact receptance of ``track`` (searched with
        :func:`~semitrack.methods.features.characteristic_frequencies`), a callable ``alpha(f)``
        (extrema refined by Brent's method), or sampled ``(f, alpha)`` (parabolic refinement).
    search_band : (float, float)
        Frequency range searched (Hz); default the paper's 3-3000 Hz.
    df : float
        Grid step of the search (Hz).

    Returns
    -------
    dict
        ``{"f_n": ...}`` or ``{"f_n1": ..., "f_n2": ..., "f_anti": ...}`` in Hz.

    Raises
    ------
    ValueError
        When the needed extrema are not found in ``search_band``.
    """
    layout = _check_layout(layout)
    track = require_track(track)
    search_band = check_band(search_band)
    if target is not None:
        target = _normalise_target(target)
    table = _det_extrema(track, target, search_band, df)
    dips = np.sort(table.loc[table["kind"] == "dip", "f"].to_numpy(float))
    if layout == "slab":
        if dips.size == 0:
            raise ValueError(f"no dip of |det(alpha^-1)| found in {search_band} Hz: cannot set f_n; "
                             "pass characteristic={'f_n': ...}")
        f_b = track.bouncing_frequency_estimate
        return {"f_n": float(dips[np.argmin(np.abs(dips - f_b))])}
    if dips.size < 2:
        raise ValueError(f"fewer than two dips of |det(alpha^-1)| in {search_band} Hz (found {dips.size}): "
                         "cannot set f_n1, f_n2; pass characteristic={'f_n1': ..., 'f_n2': ..., 'f_anti': ...}")
    f1, f2 = float(dips[0]), float(dips[1])
    peaks = table[(table["kind"] == "peak") & (table["f"] > f1) & (table["f"] < f2)]
    if peaks.empty:
        raise ValueError(f"no peak of |det(alpha^-1)| between its dips at {f1:.4g} and {f2:.4g} Hz: "
                         "cannot set f_anti; pass characteristic={...}")
    fa = float(peaks["f"].to_numpy(float)[np.argmax(peaks["magnitude"].to_numpy(float))])
    return {"f_n1": f1, "f_n2": f2, "f_anti": fa}


def default_fit_frequencies(band, characteristic: dict | None = None, n: int = 80) -> np.ndarray:
    """The default fit frequencies (Hz).

    ``n // 2`` log-spaced and ``n - n // 2`` uniformly spaced frequencies over ``band`` (the
    log-spaced ones resolve the low-frequency end, the uniform ones weight the band as the
    dense error grid does), plus each characteristic frequency inside the band and its
    neighbours at +-1, 3 and 6 % (the receptance varies fastest around the resonances).

    Parameters
    ----------
    band : (float, float)
        Frequency range (Hz).
    characteristic : dict, optional
        Characteristic frequencies (Hz), e.g. from :func:`fit_characteristic_frequencies`.
    n : int
        Number of frequencies spread over the band, >= 4.

    Returns
    -------
    ndarray
        Sorted, unique frequencies (Hz).
    """
    lo, hi = check_band(band)
    n = check_int_at_least("n", n, 4)
    f = [np.geomspace(lo, hi, n // 2), np.linspace(lo, hi, n - n // 2)]
    for v in (characteristic or {}).values():
        extra = np.array([0.94, 0.97, 0.99, 1.0, 1.01, 1.03, 1.06]) * float(v)
        f.append(extra[(extra >= lo) & (extra <= hi)])
    return np.unique(np.concatenate(f))


def _normalise_target(target):
    """None, a callable, or (f, alpha) with validated arrays."""
    if target is None or callable(target):
        return target
    if isinstance(target, (tuple, list)) and len(target) == 2:
        f = as_frequencies(target[0], "target[0] (frequencies)")
        if f.ndim != 1 or f.size < 3 or np.any(np.diff(f) <= 0):
            raise ValueError(f"target[0] must be a 1-D increasing array of at least 3 frequencies (Hz), "
                             f"got shape {f.shape}")
        alpha = _check_alpha(np.asarray(target[1]), f.size, "target[1]")
        return f, alpha
    raise TypeError("target must be None (exact receptance of track), a callable alpha(f) -> (n_f, 2, 2), "
                    f"or a pair (f, alpha) of sampled receptances, got {type(target).__name__}")


def _check_alpha(alpha: np.ndarray, n_f: int, name: str) -> np.ndarray:
    if alpha.shape != (n_f, 2, 2):
        raise ValueError(f"{name} must have shape ({n_f}, 2, 2), got {alpha.shape}")
    if alpha.dtype.kind not in "fc" or not np.all(np.isfinite(alpha)):
        raise ValueError(f"{name} must hold finite (complex) receptances")
    if np.any(alpha[:, [0, 0, 1], [0, 1, 1]] == 0):
        raise ValueError(f"{name} must have non-zero alpha11, alpha12, alpha22 (relative residuals)")
    return alpha.astype(complex)


def _evaluate_target(target, f: np.ndarray) -> np.ndarray:
    return _check_alpha(np.asarray(target(f)), f.size, "target(f)")


def _sampled(target, f_req: np.ndarray, what: str) -> np.ndarray:
    """Receptances of a sampled target at frequencies that must be among its samples."""
    f_s, alpha = target
    idx = np.searchsorted(f_s, f_req)
    idx = np.clip(idx, 0, f_s.size - 1)
    lower = np.clip(idx - 1, 0, f_s.size - 1)
    pick = np.where(np.abs(f_s[lower] - f_req) < np.abs(f_s[idx] - f_req), lower, idx)
    bad = ~np.isclose(f_s[pick], f_req, rtol=1e-9, atol=0)
    if np.any(bad):
        raise ValueError(f"{what} must be among the sampled frequencies of target, e.g. "
                         f"{float(f_req[bad][0])!r} Hz is not")
    return alpha[pick]


# ------------------------------------------------------------------------------------------------
# Result and driver
# ------------------------------------------------------------------------------------------------
@dataclass(frozen=True, eq=False)
class FitResult:
    """Outcome of :func:`fit_equivalent`.

    Attributes
    ----------
    system : EquivalentSystem
        The fitted :class:`~semitrack.equivalent.systems.SlabEquivalent` or
        :class:`~semitrack.equivalent.systems.BallastedEquivalent` (SI units).
    layout : str
        ``"slab"`` or ``"ballasted"``.
    n_bars : int
        Number of bars N.
    constrained : bool
        Whether the paper's constraints tie ``k, J`` (and ``s, mu``) to the characteristic
        frequencies.
    band : (float, float)
        Frequency band of the error measures (Hz).
    median_error, max_error : float
        Median and maximum of the complex relative error ``|alpha_E - alpha| / |alpha|`` of
        alpha11, alpha12 and alpha22 over :attr:`error_frequencies` (-).
    errors : ErrorSummary
        The per-element errors behind them.
    error_frequencies : ndarray
        The dense grid of the error measures (Hz), spacing <= 3 Hz by default.
    characteristic_frequencies : dict
        The characteristic frequencies used by the constraints (Hz): ``f_n`` (slab) or
        ``f_n1, f_n2, f_anti`` (ballasted).
    fit_freqs : ndarray
        The frequencies of the least-squares residuals (Hz).
    success : bool
        True when the best run of ``least_squares`` converged (``status > 0``).
    status : int
        ``least_squares`` status of the best run (0: ``max_nfev`` reached; 1-4: converged).
    message : str
        ``least_squares`` message of the best run.
    cost : float
        Least-squares cost ``0.5 sum r^2`` at the solution, residuals ``r`` being the real and
        imaginary parts of ``(alpha_E - alpha)/|alpha|`` at :attr:`fit_freqs` (-).
    optimality : float
        First-order optimality (inf-norm of the projected gradient) at the solution (-).
    nfev, njev : int
        Function and Jacobian evaluations of the best run (screening, continuation, polish).
    n_starts : int
        Number of starts tried.
    start_costs : ndarray
        Cost of every start after the short screening run (-), in start order.
    best_start : int
        Index of the start that gave the result (0 is the deterministic track-based guess).
    free_parameters : tuple of str
        Names of the fitted parameter families, in the order of :attr:`theta`.
    theta : ndarray
        Solution in the solver's variables, ``log(p / p_ref)`` (-).
    at_bound : ndarray of int
        Per entry of :attr:`theta`: -1 at the lower bound (parameter ~1e-8 of its reference,
        practically zero), +1 at the upper bound, 0 inside (``active_mask`` of least_squares).
    elapsed : float
        Wall-clock time of the fit (s).
    seed : int
        The seed of the multi-start.
    """

    system: EquivalentSystem = field(repr=False)
    layout: str
    n_bars: int
    constrained: bool
    band: tuple
    median_error: float
    max_error: float
    errors: ErrorSummary = field(repr=False)
    error_frequencies: np.ndarray = field(repr=False)
    characteristic_frequencies: dict
    fit_freqs: np.ndarray = field(repr=False)
    success: bool
    status: int
    message: str
    cost: float
    optimality: float
    nfev: int
    njev: int
    n_starts: int
    start_costs: np.ndarray = field(repr=False)
    best_start: int
    free_parameters: tuple = field(repr=False)
    theta: np.ndarray = field(repr=False)
    at_bound: np.ndarray = field(repr=False)
    elapsed: float
    seed: int

    def diagnostics(self) -> dict:
        """The least-squares diagnostics as a plain dict (for tables and logs)."""
        return {
            "success": self.success, "status": self.status, "message": self.message,
            "cost": self.cost, "optimality": self.optimality, "nfev": self.nfev, "njev": self.njev,
            "n_starts": self.n_starts, "best_start": self.best_start,
            "n_at_lower_bound": int(np.sum(self.at_bound < 0)),
            "n_at_upper_bound": int(np.sum(self.at_bound > 0)), "elapsed_s": self.elapsed,
        }


# Multi-start schedule: every start gets a short screening run; the best few are continued.
_SCREEN_NFEV = 100
_N_REFINE = 3
_POLISH_NFEV = 300
# Spread of the random starts around the track-based guess, in log units (a factor e^1 = 2.7).
_START_SPREAD = 1.0


def _references(track, layout: str, char: dict) -> dict[str, float]:
    """Reference value of every parameter family, from the track (SI units)."""
    m_bay = track.mass_per_length * track.spacing  # rail mass of one bay (paper's suggestion)
    L = 0.5 * track.spacing
    w_ref = _TWO_PI * (char["f_n"] if layout == "slab" else char["f_n1"])
    eta = max(track.eta_pad, 0.01)
    k_bend = track.E * track.I / track.spacing
    refs = {
        "m": m_bay, "L": L, "k": track.kv, "J": 0.25 * m_bay * L**2,
        "c_l": eta * track.kv / w_ref, "c_r": eta * track.kv / w_ref,
        "k_phi": k_bend, "c_phi": max(eta, track.eta_rail) * k_bend / w_ref,
    }
    if layout == "ballasted":
        if track.is_ballasted:
            mu, s, eta_b = 0.5 * track.sleeper_mass, 0.5 * track.kb, max(track.eta_ballast, eta)
        else:
            mu, s, eta_b = m_bay, track.kv, eta
        refs.update(mu=mu, s=s, d_l=eta_b * s / w_ref, d_r=eta_b * s / w_ref)
    return refs


def _initial_theta(model: _Model) -> np.ndarray:
    """Start 0: reference values, bar masses growing along the chain from 0.2 to 6 rail bays
    (the far bars stand for more and more of the semi-infinite rail, as in Tables 4 and 7)."""
    th = np.zeros(model.n_theta)
    if model.N > 1:
        th[model.slices["m"]] = np.log(np.geomspace(0.2, 6.0, model.N))
    return th


def fit_equivalent(track, layout: str | None = None, n_bars: int = 5, band=None, fit_freqs=None,
                   seed: int = 0, constrained: bool = True, n_starts: int = 20, target=None, *,
                   characteristic: dict | None = None, initial: EquivalentSystem | None = None,
                   max_nfev: int = 1000, error_df: float = 3.0) -> FitResult:
    """Fit an equivalent multi-rigid-body system to the receptance of a semi-infinite track.

    Solves the paper's least-squares problem (Sec. 4.4, 5.2): residuals
    ``Re(alpha_E - alpha)/|alpha|`` and ``Im(alpha_E - alpha)/|alpha|`` of alpha11, alpha12
    and alpha22 at ``fit_freqs``, minimised with :func:`scipy.optimize.least_squares` (trf,
    analytic Jacobian) from ``n_starts`` deterministic starts. See the module docstring for
    the parameterisation, the constraints and the multi-start.

    Parameters
    ----------
    track : Track
        The track (paper Table 2 or 5, or any other). It gives the reference values of the
        parameters (pad stiffness, rail mass of one bay, spacing, ...) and, with
        ``target=None``, the receptance to fit.
    layout : {"slab", "ballasted"}, optional
        Layout of the equivalent system (paper Fig. 7 or 12); default ``"ballasted"`` for a
        track with sleepers and ``"slab"`` otherwise.
    n_bars : int
        Number of bars N >= 1 (the paper uses 5).
    band : (float, float), optional
        Frequency band (Hz) of the error measures and of the default fit frequencies; default
        the paper's: 3-900 Hz (slab layout), 3-750 Hz (ballasted).
    fit_freqs : None, "paper" or array_like
        Frequencies of the residuals (Hz). None: :func:`default_fit_frequencies` (40
        log-spaced and 40 uniformly spaced over ``band``, plus the characteristic frequencies
        in the band and their +-1, 3, 6 % neighbours: 85 for the slab, 99 for the ballasted
        track on the paper's bands);
        ``"paper"``: the paper's sets (Table 4: 9 frequencies 3-897 Hz; Table 7: 18
        frequencies 3-800 Hz); or any array of positive frequencies.
    seed : int
        Seed of ``numpy.random.default_rng`` for the random starts; the fit is deterministic.
    constrained : bool
        True: ``k, J`` (slab) or ``k, J, s, mu`` (ballasted) follow Eq. (19)-(20) or (23),
        (28)-(30) from the free parameters and the characteristic frequencies (6N - 2 or 8N - 2
        unknowns, as in the paper). False: they are fitted too (8N - 2 or 12N - 2 unknowns).
    n_starts : int
        Number of starts >= 1: start 0 is the track-based guess (or ``initial``), the others
        random perturbations of it. Each is run for 100 evaluations; the best 3 are continued
        to convergence (at most ``max_nfev`` evaluations) and polished.
    target : None, callable or (f, alpha), optional
        The receptance to fit. None: the exact receptance of ``track``
        (:func:`~semitrack.methods.receptance.semi_infinite_receptance`). A callable ``alpha(f)``
        returning shape (n_f, 2, 2) for frequencies in Hz. A pair ``(f, alpha)`` of sampled
        receptances: the fit frequencies must then be among the samples (default: the samples
        in ``band``), and the errors are measured on the samples in ``band``.
    characteristic : dict, optional
        Characteristic frequencies (Hz) to use instead of detecting them with
        :func:`fit_characteristic_frequencies` (on ``target`` when given, else on ``track``):
        ``{"f_n": ...}`` or ``{"f_n1": ..., "f_n2": ..., "f_anti": ...}``.
    initial : EquivalentSystem, optional
        A system of the same layout and ``n_bars`` to use as start 0 instead of the track-based
        guess (its free parameters, clipped to the bounds; with ``constrained=True`` its ``k, J``
        (``s, mu``) are replaced by the constraints). Starting an unconstrained fit from a
        constrained one shows what the constraints cost: the cost can only go down.
    max_nfev : int
        Largest number of function evaluations of each continued run.
    error_df : float
        Largest spacing (Hz) of the dense grid of the error measures.

    Returns
    -------
    FitResult
        The fitted system, its errors over ``band`` and the least-squares diagnostics.

    Raises
    ------
    TypeError, ValueError
        For bad arguments; the message names the argument.

    Warns
    -----
    RuntimeWarning
        When the best run did not converge (``status <= 0``) or the median error exceeds
        :data:`POOR_MEDIAN_ERROR`; the message gives status, message, cost and n_starts.

    Notes
    -----
    BLAS runs single-threaded during the fit (a ``threadpoolctl`` limit).

    Examples
    --------
    >>> import semitrack as st
    >>> fit = st.fit_equivalent(st.slab_track(), layout="slab", n_bars=5, band=(3, 900), seed=0)
    >>> fit.median_error < 0.05
    True
    """
    t_start = time.perf_counter()
    track = require_track(track)
    if layout is None:
        layout = "ballasted" if track.is_ballasted else "slab"
    layout = _check_layout(layout)
    n_bars = check_int_at_least("n_bars", n_bars, 1)
    if band is None:
        band = (3.0, 900.0) if layout == "slab" else (3.0, 750.0)
    band = check_band(band)
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)):
        raise TypeError(f"seed must be a non-negative integer, got {seed!r} ({type(seed).__name__})")
    if seed < 0:
        raise ValueError(f"seed must be a non-negative integer, got {seed!r}")
    if not isinstance(constrained, (bool, np.bool_)):
        raise TypeError(f"constrained must be True or False, got {constrained!r}")
    n_starts = check_int_at_least("n_starts", n_starts, 1)
    max_nfev = check_int_at_least("max_nfev", max_nfev, 1)
    if isinstance(error_df, bool) or not isinstance(error_df, (int, float)) or not (
            math.isfinite(error_df) and error_df > 0):
        raise ValueError(f"error_df must be positive and finite (Hz), got {error_df!r}")
    if initial is not None:
        if not isinstance(initial, EquivalentSystem):
            raise TypeError(f"initial must be an EquivalentSystem, got {type(initial).__name__}")
        if initial.layout != layout or initial.n_bars != n_bars:
            raise ValueError(f"initial must be a {layout} system with n_bars = {n_bars}, got a "
                             f"{initial.layout} system with {initial.n_bars} bars")
    target = _normalise_target(target)

    # characteristic frequencies: detected on the target, never hard-coded
    if characteristic is None:
        search = (min(CHARACTERISTIC_SEARCH_BAND[0], band[0]), max(CHARACTERISTIC_SEARCH_BAND[1], band[1]))
        if isinstance(target, tuple):
            search = (float(target[0][0]), float(target[0][-1]))
        char = fit_characteristic_frequencies(track, layout, target=target, search_band=search)
    else:
        char = _check_characteristic(layout, characteristic)

    # fit frequencies, error grid and target values
    if isinstance(target, tuple):
        f_s = target[0]
        f_err = f_s[(f_s >= band[0]) & (f_s <= band[1])]
        if f_err.size < 2:
            raise ValueError(f"target must have at least 2 samples inside band {band} Hz, got {f_err.size}")
    else:
        f_err = error_band_grid(band, error_df)
    if fit_freqs is None:
        f_fit = f_err if isinstance(target, tuple) else default_fit_frequencies(band, char)
    elif isinstance(fit_freqs, str):
        if fit_freqs != "paper":
            raise ValueError(f"fit_freqs must be None, 'paper' or an array of frequencies (Hz), got {fit_freqs!r}")

        f_fit = np.array(TABLE4_FIT_FREQUENCIES if layout == "slab" else TABLE7_FIT_FREQUENCIES)
    else:
        f_fit = as_frequencies(fit_freqs, "fit_freqs")
        if f_fit.ndim != 1:
            raise ValueError(f"fit_freqs must be one-dimensional, got shape {f_fit.shape}")
        f_fit = np.unique(f_fit)
    if target is None:
        alpha_fit = _exact(track, f_fit)
        alpha_err = _exact(track, f_err)
    elif callable(target):
        alpha_fit = _evaluate_target(target, f_fit)
        alpha_err = _evaluate_target(target, f_err)
    else:
        alpha_fit = _sampled(target, f_fit, "fit_freqs")
        alpha_err = _sampled(target, f_err, "the error frequencies")

    model = _Model(layout, n_bars, bool(constrained), _references(track, layout, char), char)
    problem = _Problem(model, f_fit, alpha_fit)
    kw = dict(jac=problem.jac, bounds=(model.lower, model.upper), method="trf", x_scale="jac")

    rng = np.random.default_rng(int(seed))
    th0 = _initial_theta(model) if initial is None else model.theta_of(initial)
    starts = [th0] + [th0 + _START_SPREAD * rng.standard_normal(model.n_theta) for _ in range(n_starts - 1)]
    margin = 1e-6  # strictly inside the bounds, as trf requires
    starts = [np.clip(s, model.lower + margin, model.upper - margin) for s in starts]

    # The matrices of a fit are tiny, so threaded BLAS only costs; on a loaded 2-core machine a
    # threaded LAPACK call waits for preempted workers (the SVD inside least_squares was measured
    # 100-300 times slower). One thread for the duration of the fit.
    with threadpool_limits(limits=1, user_api="blas"):
        screened = [least_squares(problem.fun, s, max_nfev=min(_SCREEN_NFEV, max_nfev), **kw) for s in starts]
        start_costs = np.array([r.cost for r in screened])
        order = np.argsort(start_costs, kind="stable")[:_N_REFINE]
        best, best_i = None, -1
        for i in order:
            r0 = screened[i]
            nfev, njev = r0.nfev, r0.njev or 0
            r = r0
            if r0.status == 0:  # continue the screening run to convergence
                r = least_squares(problem.fun, _inside(r0.x, model), max_nfev=max_nfev, **kw)
                nfev, njev = nfev + r.nfev, njev + (r.njev or 0)
            # Final dogbox run: it holds the parameters that trf drives slowly towards the
            # lower bound (the "zero" springs and dampers) at the bound, so it certifies
            # convergence within a few evaluations where trf would creep to max_nfev.
            rd = least_squares(problem.fun, _inside(r.x, model), max_nfev=min(_POLISH_NFEV, max_nfev),
                               **dict(kw, method="dogbox"))
            if rd.status <= 0 < r.status:  # keep trf's certificate if dogbox ran out
                rd.status, rd.message = r.status, r.message
            r = rd
            nfev, njev = nfev + rd.nfev, njev + (rd.njev or 0)
            r.nfev, r.njev = nfev, njev
            if best is None or r.cost < best.cost:
                best, best_i = r, int(i)
    system = model.system(best.x)
    try:
        alpha_sys = system.receptance(f_err)
    except ValueError as exc:  # the system's own conditioning check refused a frequency
        warnings.warn(f"fit_equivalent: {exc}; the errors are computed without that check",
                      RuntimeWarning, stacklevel=2)
        alpha_sys = np.zeros((f_err.size, 2, 2), complex)
        a = _Problem(model, f_err, alpha_err).alpha(best.x)
        alpha_sys[:, 0, 0], alpha_sys[:, 0, 1], alpha_sys[:, 1, 1] = a[:, 0], a[:, 1], a[:, 2]
        alpha_sys[:, 1, 0] = a[:, 1]
    summary = error_summary(alpha_sys, alpha_err)
    result = FitResult(
        system=system, layout=layout, n_bars=n_bars, constrained=bool(constrained), band=band,
        median_error=summary.median, max_error=summary.max, errors=summary,
        error_frequencies=_readonly(f_err), characteristic_frequencies=dict(char),
        fit_freqs=_readonly(f_fit), success=bool(best.status > 0), status=int(best.status),
        message=str(best.message), cost=float(best.cost), optimality=float(best.optimality),
        nfev=int(best.nfev), njev=int(best.njev or 0), n_starts=n_starts,
        start_costs=_readonly(start_costs), best_start=best_i, free_parameters=model.names,
        theta=_readonly(best.x), at_bound=_readonly(np.asarray(best.active_mask, int)),
        elapsed=time.perf_counter() - t_start, seed=int(seed),
    )
    if not result.success or not (result.median_error <= POOR_MEDIAN_ERROR):
        reason = "did not converge" if not result.success else (
            f"is poor (median error {result.median_error:.3g} > {POOR_MEDIAN_ERROR})")
        warnings.warn(
            f"fit_equivalent: the best fit ({layout}, N = {n_bars}) {reason}: status {result.status} "
            f"({result.message}), cost {result.cost:.4g}, median/max error {result.median_error:.3g}/"
            f"{result.max_error:.3g}, n_starts {n_starts}; try more starts (n_starts), a larger "
            "max_nfev, other fit_freqs or another n_bars",
            RuntimeWarning, stacklevel=2,
        )
    return result


def _inside(x: np.ndarray, model: _Model) -> np.ndarray:
    """``x`` moved strictly inside the bounds (least_squares needs a feasible interior start)."""
    return np.clip(x, model.lower + 1e-10, model.upper - 1e-10)


def _exact(track, f: np.ndarray) -> np.ndarray:
    return _check_alpha(np.asarray(semi_infinite_receptance(track, f)), f.size, "the track receptance")


def _readonly(a) -> np.ndarray:
    a = np.array(a)
    a.setflags(write=False)
    return a
