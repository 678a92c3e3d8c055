"""Timoshenko beam finite elements for the rail on discrete supports: long and truncated tracks.

The third route to the paper's quantities (after the wavenumber method and the exact transfer
method) and the test bed for the equivalent systems in truncated track models.

Element
    The two-node shear-locking-free Timoshenko element with *interdependent interpolation*
    (IIE; Reddy 1997, Friedman & Kosmatka 1993): cubic ``w`` and quadratic ``psi`` that solve
    the homogeneous static beam equations exactly, so one element gives the exact static
    stiffness for any slenderness. DOFs per node ``(w, psi)`` in the paper's signs (w downward,
    psi clockwise, ``Q = -kAG (w' - psi)``, ``M = -EI psi'``); with ``phi = 12 EI / (kAG l^2)``

        K = EI / (l^3 (1 + phi)) [[ 12,  6l,          -12,  6l         ],
                                  [ 6l,  (4 + phi) l^2, -6l, (2 - phi) l^2],
                                  [-12, -6l,           12, -6l         ],
                                  [ 6l,  (2 - phi) l^2, -6l, (4 + phi) l^2]]

    and the consistent mass ``rho A int Nw^T Nw + rho I int Npsi^T Npsi`` of the same shape
    functions, integrated exactly by 5-point Gauss quadrature (the IIE consistent mass, which
    Friedman & Kosmatka give in closed form; it tends to the classical Euler consistent mass
    plus rotary inertia as ``phi -> 0``, which the tests check). At high frequency the FE error
    is second order in the element length (the shear strain is constant per element). The rail's loss factor multiplies E and G alike, so ``phi`` stays real and the
    complex stiffness is simply ``(1 + i eta_rail) K``.

Supports (``Track.support_stiffness`` in assembled form)
    Slab track: a vertical pad spring ``kv`` and a rotational pad spring ``kphi`` from the rail
    node to the ground. Ballasted track: the vertical pad between the rail node and a sleeper
    DOF (vertical only, mass ``sleeper_mass``), the ballast spring ``kb`` from the sleeper to the
    ground, and ``kphi`` from the rail rotation to the ground (the sleeper does not rotate).
    Frequency domain: every spring family carries its loss factor as a complex stiffness.

Geometry
    x is measured from the central cross-section (or the cut of a semi-infinite track), which
    is a mid-span; the supports sit at ``x = (k + 1/2) d`` and the ends of the model are
    mid-spans, so the paper's equivalent system attaches exactly at an end. Each half bay is
    divided into ``elements_per_bay / 2`` equal elements (so mid-spans and supports are nodes).

Ends
    ``"pinned"`` (w = 0, psi free), ``"free"``, ``"equivalent"`` (an :class:`EquivalentSystem`'s
    ``M, C, K`` attached: as is at the right end; mirrored at the left end, where its rotation
    ``phi_1`` is ``-psi`` of the rail because the mirrored system's clockwise rotation is the
    rail's anticlockwise one; its internal DOFs become extra DOFs of the model) and
    ``"exact"`` (the frequency-dependent 2x2 dynamic stiffness of the missing semi-infinite track
    from :func:`semitrack.methods.transfer.end_stiffness`; frequency domain only).

Time domain (:meth:`FETrack.matrices`, :mod:`semitrack.fe.timedomain`)
    Loss factors have no exact viscous counterpart. Each spring family gets the viscous damping
    that equals its loss factor at its own reference frequency,
    ``C = eta_rail K_rail / omega_rail + eta_pad K_pad / omega_pad + eta_ballast K_ballast /
    omega_ballast`` (stiffness-proportional for the rail, a dashpot ``eta kv / omega_pad`` per
    pad, ``eta_ballast kb / omega_ballast`` per ballast spring). A viscous damper can match the
    hysteretic one at one frequency only; it is chosen where that family's damping controls the
    response (:func:`viscous_reference_frequencies`): the pads at the rail-on-pad resonance
    ``sqrt(kv / (rho A d)) / 2 pi`` (slab 187 Hz, ballasted 495 Hz), the ballast at the
    sleeper-on-ballast resonance ``sqrt(kb / (m_s + rho A d)) / 2 pi`` (117 Hz, the paper's
    f_n1), the rail at the Euler estimate of the pinned-pinned frequency ``(pi / d)^2
    sqrt(EI / rho A) / 2 pi`` (1.2-1.4 kHz), where only the rail damps. On the paper's tracks
    (long FE tracks, 3-1500 Hz) the viscous w1 then deviates from the hysteretic one by a median
    3 % (slab) and 7 % (ballasted) and 7 % / 35 % at most below 750 Hz; a single 250 Hz for all
    families gives 3 % / 17 % median and 24 % / 66 % max. Below the reference frequency a
    viscous damper damps less, above it more. The equivalent systems' dampers are viscous by
    construction and enter as they are, although the paper fitted them to the hysteretic track.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import splu

from ..base.checks import as_frequencies, check_int_at_least, check_positive, check_real
from ..equivalent.systems import EquivalentSystem
from ..methods.transfer import end_stiffness
from ..model.tracks import Track, require_track

__all__ = [
    "ENDS",
    "viscous_reference_frequencies",
    "timoshenko_element",
    "timoshenko_shape_functions",
    "FETrack",
    "TruncatedTrack",
    "fe_semi_infinite_receptance",
    "fe_central_receptance",
]

#: End conditions of a finite track model.
ENDS = ("pinned", "free", "equivalent", "exact")


# 5-point Gauss-Legendre rule on [0, 1]: exact for polynomials up to degree 9 (mass needs 6).
_GAUSS_X, _GAUSS_W = np.polynomial.legendre.leggauss(5)
_GAUSS_X = 0.5 * (_GAUSS_X + 1.0)
_GAUSS_W = 0.5 * _GAUSS_W


# ------------------------------------------------------------------------------------------------
# The element
# ------------------------------------------------------------------------------------------------
def timoshenko_shape_functions(xi, length: float, phi):
    """Exact static (IIE) shape functions of the two-node Timoshenko element.

    Parameters
    ----------
    xi : array_like
        Local coordinate x / length in [0, 1] (-).
    length : float
        Element length l (m).
    phi : float or complex
        Shear parameter ``12 EI / (kAG l^2)`` (-).

    Returns
    -------
    n_w, n_psi : ndarray, shape ``xi.shape + (4,)``
        ``w(xi) = n_w @ (w_a, psi_a, w_b, psi_b)`` (rows m/m, 1, m/m, 1 times m for the psi
        columns) and ``psi(xi) = n_psi @ (...)``.
    """
    xi = np.asarray(xi, dtype=float)
    l, mu = length, 1.0 / (1.0 + phi)
    x2, x3 = xi * xi, xi**3
    n_w = np.stack([
        mu * (2 * x3 - 3 * x2 - phi * xi + 1 + phi),
        mu * l * (x3 - (2 + phi / 2) * x2 + (1 + phi / 2) * xi),
        -mu * (2 * x3 - 3 * x2 - phi * xi),
        mu * l * (x3 - (1 - phi / 2) * x2 - (phi / 2) * xi),
    ], axis=-1)
    n_psi = np.stack([
        6 * mu / l * (x2 - xi),
        mu * (3 * x2 - (4 + phi) * xi + 1 + phi),
        -6 * mu / l * (x2 - xi),
        mu * (3 * x2 - (2 - phi) * xi),
    ], axis=-1)
    return n_w, n_psi


def timoshenko_element(EI, kAG, rho_A: float, rho_I: float, length: float):
    """Stiffness and consistent mass matrices of the IIE Timoshenko element.

    Parameters
    ----------
    EI : float or complex
        Bending stiffness (N m^2); complex for a loss factor.
    kAG : float or complex
        Shear stiffness kappa A G (N).
    rho_A : float
        Mass per length (kg/m).
    rho_I : float
        Rotary inertia per length (kg m).
    length : float
        Element length (m), positive.

    Returns
    -------
    K, M : ndarray, shape (4, 4)
        DOFs ``(w_a, psi_a, w_b, psi_b)``; K in N/m, N/rad, N m/rad..., M in kg, kg m, kg m^2.
        Complex when EI or kAG is complex.
    """
    l = check_positive("length", length)
    phi = 12.0 * EI / (kAG * l * l)
    c = EI / (l**3 * (1.0 + phi))
    K = c * np.array([
        [12.0, 6 * l, -12.0, 6 * l],
        [6 * l, (4 + phi) * l * l, -6 * l, (2 - phi) * l * l],
        [-12.0, -6 * l, 12.0, -6 * l],
        [6 * l, (2 - phi) * l * l, -6 * l, (4 + phi) * l * l],
    ])
    n_w, n_psi = timoshenko_shape_functions(_GAUSS_X, l, phi)
    wq = _GAUSS_W * l
    M = rho_A * np.einsum("q,qi,qj->ij", wq, n_w, n_w) + rho_I * np.einsum("q,qi,qj->ij", wq, n_psi, n_psi)
    return K, M


# ------------------------------------------------------------------------------------------------
# Sparse helpers
# ------------------------------------------------------------------------------------------------
class _Triplets:
    """COO triplets of a family of matrices on a common DOF numbering."""

    def __init__(self):
        self.rows, self.cols, self.vals = [], [], []

    def add(self, idx, block, sign=None):
        idx = np.asarray(idx)
        block = np.asarray(block, dtype=float)
        if sign is not None:
            s = np.asarray(sign, dtype=float)
            block = s[:, None] * block * s[None, :]
        r, c = np.meshgrid(idx, idx, indexing="ij")
        self.rows.append(r.ravel())
        self.cols.append(c.ravel())
        self.vals.append(block.ravel())

    def add_many(self, idx, blocks):
        """``idx`` (n, k) DOFs of n blocks, ``blocks`` (k, k) or (n, k, k)."""
        idx = np.asarray(idx)
        n, k = idx.shape
        blocks = np.broadcast_to(np.asarray(blocks, dtype=float), (n, k, k))
        self.rows.append(np.repeat(idx, k, axis=1).ravel())
        self.cols.append(np.tile(idx, (1, k)).ravel())
        self.vals.append(blocks.ravel())

    def coo(self):
        if not self.rows:
            return np.zeros(0, int), np.zeros(0, int), np.zeros(0)
        return np.concatenate(self.rows), np.concatenate(self.cols), np.concatenate(self.vals)


def _on_pattern(keys_union, n, rows, cols, vals, keep):
    """Sum COO entries onto the sorted union pattern (CSC order), after DOF elimination."""
    out = np.zeros(keys_union.size, dtype=float)
    if rows.size == 0:
        return out
    r, c = keep[rows], keep[cols]
    ok = (r >= 0) & (c >= 0)
    keys = c[ok].astype(np.int64) * n + r[ok]
    np.add.at(out, np.searchsorted(keys_union, keys), vals[ok])
    return out


# ------------------------------------------------------------------------------------------------
# The model
# ------------------------------------------------------------------------------------------------
def viscous_reference_frequencies(track: Track) -> dict:
    """Reference frequencies (Hz) of the viscous damping model of the time domain.

    Returns ``{"rail": (pi / d)^2 sqrt(EI / rho A) / 2 pi, "pad": sqrt(kv / (rho A d)) / 2 pi,
    "ballast": sqrt(kb / (m_s + rho A d)) / 2 pi}`` (real moduli): the Euler pinned-pinned
    frequency, the rail-on-pad resonance and the sleeper-on-ballast resonance, near which the
    damping of each family controls the response. "ballast" is NaN for a slab track.
    """
    require_track(track)
    d, ra = track.spacing, track.mass_per_length
    out = {
        "rail": (np.pi / d) ** 2 * np.sqrt(track.E * track.I / ra) / (2 * np.pi),
        "pad": np.sqrt(track.kv / (ra * d)) / (2 * np.pi),
        "ballast": (np.sqrt(track.kb / (track.sleeper_mass + ra * d)) / (2 * np.pi)
                    if track.is_ballasted else float("nan")),
    }
    return {k: float(v) for k, v in out.items()}


def _reference_frequencies(track, f_ref):
    fr = viscous_reference_frequencies(track)
    if not track.is_ballasted:
        fr["ballast"] = 1.0  # unused: no ballast springs
    if f_ref is None:
        return fr
    if isinstance(f_ref, dict):
        unknown = sorted(set(f_ref) - set(fr))
        if unknown:
            raise ValueError(f"f_ref keys must be among {sorted(fr)}, got {unknown}")
        fr.update({k: check_positive(f"f_ref[{k!r}]", v) for k, v in f_ref.items()})
        return fr
    v = check_positive("f_ref", f_ref)
    return dict.fromkeys(fr, v)


def _check_end(name, value):
    if not isinstance(value, str) or value not in ENDS:
        raise ValueError(f"{name} must be one of {ENDS}, got {value!r}")
    return value


class FETrack:
    """A finite FE model of the rail on discrete supports between two mid-span cuts.

    The rail runs from ``x = -n_left d`` to ``x = n_right d`` (d the support spacing); x = 0 is a
    mid-span (the central cross-section, or the cut of a semi-infinite track when
    ``n_left = 0``), supports at ``x = (k + 1/2) d``.

    Parameters
    ----------
    track : Track
        Rail, pad and (ballasted) sleeper/ballast parameters.
    n_left, n_right : int
        Number of bays left and right of x = 0 (>= 0, at least one bay in all).
    left, right : {"pinned", "free", "equivalent", "exact"}
        End conditions, see the module docstring.
    system : EquivalentSystem, optional
        The equivalent system attached at an ``"equivalent"`` end (required then).
    elements_per_bay : int
        Number of elements per support spacing; even (>= 2), so that mid-spans are nodes. The
        FE error is second order in the element length; with 12 (the default) the discretisation
        error of w1 and alpha over 3-3000 Hz has a median of 0.25-0.4 % (8: 0.6-0.9 %).

    Attributes
    ----------
    x : ndarray
        Positions of the rail nodes (m).
    n_dof : int
        Number of DOFs after pinned DOFs are removed: rail (w, psi) per node, then sleeper
        DOFs (ballasted track), then the internal DOFs of attached equivalent systems.
    """

    def __init__(self, track: Track, n_left: int, n_right: int, left: str = "pinned", right: str = "pinned",
                 system: EquivalentSystem | None = None, elements_per_bay: int = 12):
        require_track(track)
        self.track = track
        self.n_left = check_int_at_least("n_left", n_left, 0)
        self.n_right = check_int_at_least("n_right", n_right, 0)
        self.left = _check_end("left", left)
        self.right = _check_end("right", right)
        ne = check_int_at_least("elements_per_bay", elements_per_bay, 2)
        if ne % 2:
            raise ValueError(f"elements_per_bay must be even (mid-spans are nodes), got {ne}")
        self.elements_per_bay = ne
        uses_system = "equivalent" in (self.left, self.right)
        if uses_system and not isinstance(system, EquivalentSystem):
            raise TypeError(f"system must be an EquivalentSystem for an 'equivalent' end, got {type(system).__name__}")
        if system is not None and not uses_system:
            raise ValueError(f"system is only used with an 'equivalent' end, got ends ({left!r}, {right!r})")
        self.system = system
        n_bays = self.n_left + self.n_right
        if n_bays == 0 and not ({self.left, self.right} <= {"equivalent", "exact"}):
            raise ValueError(
                f"a model with zero bays needs 'equivalent' or 'exact' ends, got ends ({left!r}, {right!r})"
            )
        self._build()

    # --------------------------------------------------------------------------------------------
    def _build(self):
        tr, d, ne = self.track, self.track.spacing, self.elements_per_bay
        n_el = ne * (self.n_left + self.n_right)
        n_nodes = n_el + 1
        h = d / ne
        self.x = -self.n_left * d + h * np.arange(n_nodes)
        self.x[np.abs(self.x) < 1e-12 * d] = 0.0
        self.element_length = h
        # Support nodes: x = (k + 1/2) d, i.e. node index offset ne/2 within each bay.
        sup = np.arange(ne // 2, n_el, ne)
        self.support_nodes = sup
        n_rail = 2 * n_nodes
        n_sl = sup.size if tr.is_ballasted else 0
        n_full = n_rail + n_sl
        # Attached systems' internal DOFs.
        sys_dofs = {}
        if self.system is not None:
            n_int = self.system.n_dof - 2
            for side in ("left", "right"):
                if getattr(self, side) == "equivalent":
                    sys_dofs[side] = np.arange(n_full, n_full + n_int)
                    n_full += n_int

        parts = {key: _Triplets() for key in ("K_rail", "K_pad", "K_ballast", "K_end", "C_end", "M")}
        # Rail elements.
        k_el, m_el = timoshenko_element(tr.E * tr.I, tr.kappa * tr.A * tr.G, tr.mass_per_length,
                                        tr.rotary_inertia, h)
        el_dofs = 2 * np.arange(n_el)[:, None] + np.arange(4)[None, :]
        parts["K_rail"].add_many(el_dofs, k_el)
        parts["M"].add_many(el_dofs, m_el)
        # Supports.
        w_sup, psi_sup = 2 * sup, 2 * sup + 1
        if tr.kphi > 0:
            parts["K_pad"].add_many(psi_sup[:, None], np.array([[tr.kphi]]))
        if tr.is_ballasted:
            s_dofs = n_rail + np.arange(n_sl)
            self.sleeper_dofs_full = s_dofs
            pad = tr.kv * np.array([[1.0, -1.0], [-1.0, 1.0]])
            parts["K_pad"].add_many(np.stack([w_sup, s_dofs], 1), pad)
            parts["K_ballast"].add_many(s_dofs[:, None], np.array([[tr.kb]]))
            parts["M"].add_many(s_dofs[:, None], np.array([[tr.sleeper_mass]]))
        else:
            self.sleeper_dofs_full = np.zeros(0, int)
            parts["K_pad"].add_many(w_sup[:, None], np.array([[tr.kv]]))
        # Equivalent systems.
        end_nodes = {"left": 0, "right": n_nodes - 1}
        for side, internal in sys_dofs.items():
            node = end_nodes[side]
            idx = np.concatenate(([2 * node, 2 * node + 1], internal))
            sign = np.ones(idx.size)
            if side == "left":
                sign[1] = -1.0  # mirrored system: its clockwise phi_1 is the rail's -psi
            Ms, Cs, Ks = self.system.matrices()
            parts["M"].add(idx, Ms, sign)
            parts["C_end"].add(idx, Cs, sign)
            parts["K_end"].add(idx, Ks, sign)
        self.system_dofs_full = sys_dofs

        # Pinned DOFs removed.
        keep = np.ones(n_full, dtype=bool)
        for side in ("left", "right"):
            if getattr(self, side) == "pinned":
                keep[2 * end_nodes[side]] = False
        new_index = np.full(n_full, -1, dtype=np.int64)
        new_index[keep] = np.arange(int(keep.sum()))
        self._new_index = new_index
        n = int(keep.sum())
        self.n_dof = n
        self.n_nodes = n_nodes

        # Frequency-dependent exact-end blocks: their positions must be in the pattern.
        self._exact = {}
        exact_r, exact_c = [], []
        for side in ("left", "right"):
            if getattr(self, side) == "exact":
                node = end_nodes[side]
                idx = new_index[[2 * node, 2 * node + 1]]
                r, c = np.meshgrid(idx, idx, indexing="ij")
                self._exact[side] = (r.ravel(), c.ravel())
                exact_r.append(r.ravel())
                exact_c.append(c.ravel())

        # Union pattern in CSC order: key = col * n + row, sorted.
        coo = {key: t.coo() for key, t in parts.items()}
        all_r = [new_index[c[0]] for c in coo.values()] + exact_r
        all_c = [new_index[c[1]] for c in coo.values()] + exact_c
        rr, cc = np.concatenate(all_r), np.concatenate(all_c)
        ok = (rr >= 0) & (cc >= 0)
        keys = np.unique(cc[ok].astype(np.int64) * n + rr[ok])
        self._keys = keys
        self._indices = (keys % n).astype(np.int32)
        self._indptr = np.searchsorted(keys // n, np.arange(n + 1)).astype(np.int32)
        self._data = {key: _on_pattern(keys, n, *c, new_index) for key, c in coo.items()}
        self._exact_pos = {side: np.searchsorted(keys, c.astype(np.int64) * n + r)
                           for side, (r, c) in self._exact.items()}

    # --------------------------------------------------------------------------------------------
    def _csc(self, data) -> sp.csc_matrix:
        return sp.csc_matrix((data, self._indices, self._indptr), shape=(self.n_dof, self.n_dof))

    def dof(self, x: float, kind: str = "w") -> int:
        """Index of the rail DOF ``kind`` ("w" or "psi") at the node at position ``x`` (m).

        Raises ValueError when x is not a node (within 1e-9 d) or the DOF was removed (pinned).
        """
        x = check_real("x", x)
        if kind not in ("w", "psi"):
            raise ValueError(f"kind must be 'w' or 'psi', got {kind!r}")
        j = int(np.argmin(np.abs(self.x - x)))
        if abs(self.x[j] - x) > 1e-9 * self.track.spacing:
            raise ValueError(
                f"x must be a node position of the mesh (spacing {self.element_length:.6g} m from "
                f"{self.x[0]:.6g} to {self.x[-1]:.6g} m), got {x!r}"
            )
        i = int(self._new_index[2 * j + (kind == "psi")])
        if i < 0:
            raise ValueError(f"the {kind} DOF at x={x!r} is removed by a pinned end")
        return i

    @property
    def sleeper_dofs(self) -> np.ndarray:
        """Indices of the sleeper DOFs (ballasted track; empty otherwise)."""
        return self._new_index[self.sleeper_dofs_full]

    def output_matrix(self, positions: Sequence[float], kind: str = "w") -> sp.csr_matrix:
        """Sparse matrix mapping the DOF vector to ``w`` (or ``psi``) at arbitrary positions (m).

        Uses the element shape functions, so between nodes it is the FE interpolation; rows
        follow ``positions``. Positions must lie on the rail, ``x[0] <= x <= x[-1]``.
        """
        if kind not in ("w", "psi"):
            raise ValueError(f"kind must be 'w' or 'psi', got {kind!r}")
        rows, cols, vals = [], [], []
        for r, xp in enumerate(np.atleast_1d(np.asarray(positions, dtype=float))):
            idx, n = self._element_weights(xp, "positions", kind)
            for i, v in zip(idx, n):
                if i >= 0:
                    rows.append(r)
                    cols.append(i)
                    vals.append(v)
        n_out = np.atleast_1d(positions).size
        return sp.csr_matrix((vals, (rows, cols)), shape=(n_out, self.n_dof))

    def _element_weights(self, xp, name, kind="w"):
        """DOF indices (-1 if removed) and shape-function values at position xp."""
        if not (np.isfinite(xp) and self.x[0] - 1e-12 <= xp <= self.x[-1] + 1e-12):
            raise ValueError(f"{name} must lie on the rail, {self.x[0]:.6g} <= x <= {self.x[-1]:.6g} m, got {xp!r}")
        h = self.element_length
        e = min(int(np.floor((xp - self.x[0]) / h)), self.n_nodes - 2)
        e = max(e, 0)
        xi = min(max((xp - self.x[e]) / h, 0.0), 1.0)
        phi = 12 * self.track.E * self.track.I / (self.track.kappa * self.track.A * self.track.G * h * h)
        n_w, n_psi = timoshenko_shape_functions(xi, h, phi)
        full = 2 * e + np.arange(4)
        return self._new_index[full], (n_w if kind == "w" else n_psi)

    # --------------------------------------------------------------------------------------------
    def complex_stiffness(self) -> sp.csc_matrix:
        """Frequency-independent complex stiffness (N/m...): loss factors as complex moduli.

        ``(1 + i eta_rail) K_rail + (1 + i eta_pad) K_pad + (1 + i eta_ballast) K_ballast + K_end``
        where ``K_end`` holds the springs of attached equivalent systems (their dampers are
        viscous and enter as ``i omega C`` in :meth:`dynamic_stiffness`).
        """
        return self._csc(self._complex_k_data())

    def _complex_k_data(self):
        tr, d = self.track, self._data
        return ((1 + 1j * tr.eta_rail) * d["K_rail"] + (1 + 1j * tr.eta_pad) * d["K_pad"]
                + (1 + 1j * tr.eta_ballast) * d["K_ballast"] + d["K_end"])

    def mass(self) -> sp.csc_matrix:
        """Mass matrix (kg, kg m, kg m^2): rail (consistent), sleepers, attached systems."""
        return self._csc(self._data["M"].copy())

    def _exact_blocks(self, omega):
        if not self._exact:
            return {}
        k_right, k_left = end_stiffness(self.track.cell(), omega, self.track.cell().mid_span)
        return {side: (k_right if side == "right" else k_left) for side in self._exact}

    def dynamic_stiffness(self, f: float) -> sp.csc_matrix:
        """``Z = K* + i omega C_end - omega^2 M (+ exact end blocks)`` at one frequency ``f`` (Hz)."""
        f = float(as_frequencies(f))
        omega = 2 * np.pi * f
        data = self._complex_k_data() + 1j * omega * self._data["C_end"] - omega**2 * self._data["M"]
        for side, k in self._exact_blocks(np.array([omega])).items():
            np.add.at(data, self._exact_pos[side], k[0].ravel())
        return self._csc(data)

    def solve(self, f, rhs) -> np.ndarray:
        """Solve ``Z(f) u = rhs`` frequency by frequency with a sparse LU factorisation.

        Parameters
        ----------
        f : array_like
            Frequencies (Hz), 1-D.
        rhs : array_like, shape (n_dof, n_rhs)
            Load vectors (N, N m), the same at every frequency.

        Returns
        -------
        ndarray of complex, shape (n_f, n_dof, n_rhs)
        """
        f = np.atleast_1d(as_frequencies(f))
        if f.ndim != 1:
            raise ValueError(f"f must be a scalar or a 1-D array of frequencies (Hz), got shape {f.shape}")
        rhs = np.asarray(rhs)
        if rhs.ndim != 2 or rhs.shape[0] != self.n_dof:
            raise ValueError(f"rhs must have shape ({self.n_dof}, n_rhs), got {rhs.shape}")
        omega = 2 * np.pi * f
        k0 = self._complex_k_data()
        c_end, m = self._data["C_end"], self._data["M"]
        exact = self._exact_blocks(omega)
        out = np.empty((f.size, self.n_dof, rhs.shape[1]), dtype=complex)
        rhs_c = np.ascontiguousarray(rhs, dtype=complex)
        for i, w in enumerate(omega):
            data = k0 + (1j * w) * c_end - (w * w) * m
            for side, k in exact.items():
                data[self._exact_pos[side]] += k[i].ravel()
            z = sp.csc_matrix((data, self._indices, self._indptr), shape=(self.n_dof, self.n_dof))
            out[i] = splu(z, permc_spec="MMD_AT_PLUS_A").solve(rhs_c)
        return out

    def receptance(self, f, x: float = 0.0) -> np.ndarray:
        """2x2 point receptance at the rail node at ``x`` (m): (w, psi) per (F, M) there.

        Parameters
        ----------
        f : float or array_like
            Frequencies (Hz); scalar or 1-D.
        x : float
            A node position (m); default the central cross-section / the cut.

        Returns
        -------
        ndarray of complex, shape (n_f, 2, 2), or (2, 2) for a scalar ``f``
            ``[[w/F (m/N), w/M (1/N)], [psi/F (rad/N), psi/M (rad/(N m))]]``; F downward, M
            clockwise.
        """
        idx = [self.dof(x, "w"), self.dof(x, "psi")]
        rhs = np.zeros((self.n_dof, 2))
        rhs[idx, [0, 1]] = 1.0
        u = self.solve(f, rhs)[:, idx, :]
        return u[0] if np.ndim(f) == 0 else u

    def central_receptance(self, f) -> np.ndarray:
        """:meth:`receptance` at x = 0: the central cross-section (w1 = ``[..., 0, 0]``, psi2 =
        ``[..., 1, 1]`` for a complete track), or the end of a semi-infinite one (alpha)."""
        return self.receptance(f, 0.0)

    # --------------------------------------------------------------------------------------------
    def matrices(self, f_ref=None):
        """Real ``(M, C, K)`` sparse matrices for time integration (SI; DOFs as :attr:`n_dof`).

        Parameters
        ----------
        f_ref : None, float or dict
            Reference frequencies (Hz) at which the viscous damping of the rail, the pads and
            the ballast equals their loss factors: ``C = eta_rail K_rail / (2 pi f_rail) +
            eta_pad K_pad / (2 pi f_pad) + eta_ballast K_ballast / (2 pi f_ballast) + C_end``.
            ``None``: :func:`viscous_reference_frequencies` (see the module docstring); a float:
            the same for all three; a dict: overrides for some of the keys "rail", "pad",
            "ballast".

        Returns
        -------
        M, C, K : scipy.sparse.csc_matrix
        """
        if "exact" in (self.left, self.right):
            raise ValueError("ends='exact' is frequency dependent and has no time-domain matrices; "
                             "use 'equivalent', 'pinned' or 'free'")
        fr = _reference_frequencies(self.track, f_ref)
        tr, d = self.track, self._data
        K = d["K_rail"] + d["K_pad"] + d["K_ballast"] + d["K_end"]
        C = (tr.eta_rail * d["K_rail"] / (2 * np.pi * fr["rail"]) + tr.eta_pad * d["K_pad"] / (2 * np.pi * fr["pad"])
             + tr.eta_ballast * d["K_ballast"] / (2 * np.pi * fr["ballast"]) + d["C_end"])
        return self._csc(d["M"].copy()), self._csc(C), self._csc(K)

    def __repr__(self):
        return (f"{type(self).__name__}({self.track.name!r}, bays {self.n_left}+{self.n_right}, ends "
                f"({self.left!r}, {self.right!r}), elements_per_bay={self.elements_per_bay}, n_dof={self.n_dof})")


class TruncatedTrack(FETrack):
    """A truncated track: ``n_bays`` bays on each side of the central cross-section (a mid-span).

    The model is cut at mid-spans, so an equivalent system attaches exactly at its ends.

    Parameters
    ----------
    track : Track
        The track.
    n_bays : int
        Bays on each side of the centre (>= 1; 0 is allowed with "equivalent"/"exact" ends and
        then reduces to the paper's Sec. 5.3 pair of mirrored systems).
    ends : {"pinned", "free", "equivalent", "exact"}
        End condition at both ends (see the module docstring).
    system : EquivalentSystem, optional
        Required with ``ends="equivalent"`` (e.g. ``paper_table4()`` for the slab track,
        ``paper_table7()`` for the ballasted one, or a fitted system).
    elements_per_bay : int
        Elements per support spacing, even.

    Examples
    --------
    >>> tt = TruncatedTrack(slab_track(), 10, ends="equivalent", system=paper_table4())
    >>> H = tt.central_receptance(f)        # (n_f, 2, 2); H[:, 0, 0] is w1
    >>> M, C, K = tt.matrices()             # time domain
    """

    def __init__(self, track: Track, n_bays: int, ends: str = "pinned", system: EquivalentSystem | None = None,
                 elements_per_bay: int = 12):
        n = check_int_at_least("n_bays", n_bays, 0)
        _check_end("ends", ends)
        if n == 0 and ends not in ("equivalent", "exact"):
            raise ValueError(f"n_bays must be >= 1 with ends={ends!r}, got 0")
        self.n_bays = n
        self.ends = ends
        super().__init__(track, n, n, ends, ends, system, elements_per_bay)


# ------------------------------------------------------------------------------------------------
# Long tracks: the third route to alpha and w1
# ------------------------------------------------------------------------------------------------
def fe_semi_infinite_receptance(track: Track, f, n_bays: int = 200, elements_per_bay: int = 12,
                                far_end: str = "pinned") -> np.ndarray:
    """End receptance alpha of a long semi-infinite FE track cut at a mid-span.

    The rail starts at the cut (node 0, loaded by F and M), the first support at d/2; the
    model holds ``n_bays`` bays and ends at a mid-span with ``far_end``. Damping removes the far
    end's reflection when the track is long enough. With the defaults (12 elements per bay, 200
    bays: 130 m slab, 120 m ballasted) the median error against the exact transfer method over
    3-2997 Hz is 0.5 % (slab) and 0.3 % (ballasted); 100 bays leave 3.8 % on the slab track
    (weakly damped propagating waves above the 183 Hz cut-on), 8 elements per bay 0.8 %. The
    largest errors (tens of %) sit at the sharp second pinned-pinned peak (2.6 / 2.9 kHz),
    whose frequency the mesh shifts (24 elements per bay: 14 % / 28 %).

    Parameters
    ----------
    track : Track
    f : float or array_like
        Frequencies (Hz).
    n_bays : int
        Number of bays (>= 1).
    elements_per_bay : int
        Even number of elements per support spacing.
    far_end : {"pinned", "free", "exact"}
        The far end; ``"exact"`` terminates it with the exact semi-infinite end stiffness
        (removes the reflection, so a few bays suffice).

    Returns
    -------
    ndarray of complex, shape (n_f, 2, 2) or (2, 2)
        Units as :func:`semitrack.semi_infinite_receptance`.
    """
    if far_end not in ("pinned", "free", "exact"):
        raise ValueError(f"far_end must be one of ('pinned', 'free', 'exact'), got {far_end!r}")
    n = check_int_at_least("n_bays", n_bays, 1)
    return FETrack(track, 0, n, "free", far_end, elements_per_bay=elements_per_bay).receptance(f, 0.0)


def fe_central_receptance(track: Track, f, n_bays: int = 200, elements_per_bay: int = 12,
                          far_end: str = "pinned") -> np.ndarray:
    """2x2 receptance at the central cross-section (a mid-span) of a long complete FE track.

    ``n_bays`` bays on each side; ``[..., 0, 0]`` is w1 and ``[..., 1, 1]`` is psi2 of the
    paper's Eq. (14). Parameters as :func:`fe_semi_infinite_receptance`.
    """
    if far_end not in ("pinned", "free", "exact"):
        raise ValueError(f"far_end must be one of ('pinned', 'free', 'exact'), got {far_end!r}")
    n = check_int_at_least("n_bays", n_bays, 1)
    return TruncatedTrack(track, n, far_end, elements_per_bay=elements_per_bay).central_receptance(f)
