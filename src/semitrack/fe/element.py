"""The two-node Timoshenko beam element of the rail: shape functions, stiffness and mass.

The element is the shear-locking-free Timoshenko element with *interdependent interpolation*
(IIE; Reddy 1997, Friedman & Kosmatka 1993): cubic ``w`` and quadratic ``psi`` that solve the
homogeneous static beam equations exactly, so one element gives the exact static stiffness for
any slenderness. DOFs per node ``(w, psi)`` in the paper's signs (w downward, psi clockwise,
``Q = -kAG (w' - psi)``, ``M = -EI psi'``); with ``phi = 12 EI / (kAG l^2)``

    K = EI / (l^3 (1 + phi)) [[ 12,  6l,          -12,  6l         ],
                              [ 6l,  (4 + phi) l^2, -6l, (2 - phi) l^2],
                              [-12, -6l,           12, -6l         ],
                              [ 6l,  (2 - phi) l^2, -6l, (4 + phi) l^2]]

and the consistent mass ``rho A int Nw^T Nw + rho I int Npsi^T Npsi`` of the same shape
functions, integrated exactly by 5-point Gauss quadrature (the IIE consistent mass, which
Friedman & Kosmatka give in closed form; it tends to the classical Euler consistent mass plus
rotary inertia as ``phi -> 0``, which the tests check). At high frequency the FE error is second
order in the element length (the shear strain is constant per element). The rail's loss factor
multiplies E and G alike, so ``phi`` stays real and the complex stiffness of a track model is
simply ``(1 + i eta_rail) K``.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from ..base.checks import check_positive
from ..model.tracks import Track, require_track

__all__ = ["shear_parameter", "timoshenko_shape_functions", "timoshenko_curvature_weights", "timoshenko_element",
           "point_flexibility", "rail_element"]

# 5-point Gauss-Legendre rule on [0, 1]: exact for polynomials up to degree 9 (mass needs 6).
_GAUSS_X, _GAUSS_W = np.polynomial.legendre.leggauss(5)
_GAUSS_X = 0.5 * (_GAUSS_X + 1.0)
_GAUSS_W = 0.5 * _GAUSS_W


def shear_parameter(EI: complex, kAG: complex, length: float) -> complex:
    """The element's shear parameter ``phi = 12 EI / (kAG l^2)`` (-).

    Parameters
    ----------
    EI : float or complex
        Bending stiffness (N m^2).
    kAG : float or complex
        Shear stiffness kappa A G (N).
    length : float
        Element length l (m).

    Returns
    -------
    float or complex
        0 for a slender element (Euler-Bernoulli limit), large for a stocky one.

    Examples
    --------
    >>> round(shear_parameter(6.4e6, 6.4e8, 0.1), 6)
    12.0
    """
    return 12.0 * EI / (kAG * length * length)


def timoshenko_shape_functions(xi: ArrayLike, length: float, phi: complex) -> tuple[np.ndarray, np.ndarray]:
    """Exact static (IIE) shape functions of the two-node Timoshenko element.

    Parameters
    ----------
    xi : array_like
        Local coordinate x / length in [0, 1] (-).
    length : float
        Element length l (m).
    phi : float or complex
        Shear parameter ``12 EI / (kAG l^2)`` (-), see :func:`shear_parameter`.

    Returns
    -------
    n_w, n_psi : ndarray, shape ``xi.shape + (4,)``
        ``w(xi) = n_w @ (w_a, psi_a, w_b, psi_b)`` (m per m for the w columns, m per rad for
        the psi columns) and ``psi(xi) = n_psi @ (...)`` (rad per m, rad per rad).

    Examples
    --------
    The functions interpolate the nodal values:

    >>> n_w, n_psi = timoshenko_shape_functions([0.0, 1.0], 0.1, 0.5)
    >>> n_w.round(12).tolist()
    [[1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0]]
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


def timoshenko_element(EI: complex, kAG: complex, rho_A: float, rho_I: float,
                       length: float) -> tuple[np.ndarray, np.ndarray]:
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

    Examples
    --------
    One clamped element: the tip flexibility is the Timoshenko cantilever's ``l^3 / 3 EI + l / kAG``.

    >>> K, M = timoshenko_element(6.4e6, 6.4e8, 60.0, 0.24, 0.5)
    >>> bool(np.isclose(np.linalg.inv(K[2:, 2:])[0, 0], 0.5**3 / (3 * 6.4e6) + 0.5 / 6.4e8))
    True
    """
    l = check_positive("length", length)
    phi = shear_parameter(EI, kAG, l)
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


def timoshenko_curvature_weights(xi: ArrayLike, length: ArrayLike, phi: ArrayLike) -> np.ndarray:
    """The weights that give ``dpsi/dx`` (1/m) from an element's ``(w_a, psi_a, w_b, psi_b)``: the bending curvature.

    The derivative of :func:`timoshenko_shape_functions`' ``n_psi``; the bending moment is
    ``EI dpsi/dx`` (linear along an element, as the IIE element's static solution).

    Parameters
    ----------
    xi : array_like
        Local coordinate x / length in [0, 1] (-).
    length : array_like
        Element length l (m).
    phi : array_like
        Shear parameter (-), :func:`shear_parameter`.

    Returns
    -------
    ndarray, shape ``broadcast + (4,)``
        1/m^2 for the w columns, 1/m for the psi columns.

    Examples
    --------
    A rigid rotation bends nothing:

    >>> weights = timoshenko_curvature_weights(0.3, 0.1, 0.5)
    >>> abs(float(weights @ np.array([0.0, 1.0, 0.1, 1.0]))) < 1e-12
    True
    """
    xi, l, phi = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (xi, length, phi)))
    mu = 1.0 / (1.0 + phi)
    return np.stack([6 * mu / l**2 * (2 * xi - 1), mu / l * (6 * xi - 4 - phi),
                     -6 * mu / l**2 * (2 * xi - 1), mu / l * (6 * xi - 2 + phi)], axis=-1)


#: Relative positions in an element this close to a node are the node (:func:`point_flexibility`).
_AT_NODE = 1e-9


def point_flexibility(EI: ArrayLike, kAG: ArrayLike, length: ArrayLike, xi: ArrayLike) -> np.ndarray:
    """The element's own deflection under a unit force at ``xi``, its nodes held (m/N): what the mesh misses.

    The element's shape functions are the exact static response to *nodal* loads; a force
    between the nodes also bends and shears the element within itself. That deflection, the
    clamped-clamped Timoshenko beam's at its load point (two exact static sub-elements of
    lengths ``xi l`` and ``(1 - xi) l`` joined at the load), is added in series with a contact
    there: for the rail of the paper's tracks it is up to 1.4e-11 m/N at mid-element with 48
    elements per bay (the shear part ``xi (1 - xi) l / kAG`` dominates), 2 % of the Hertzian
    contact's compliance, and its neglect left the receptance between nodes 8 % off at 3 kHz
    with a first-order error in l (measured). Quasi-static: the element is short beside the
    wavelengths it carries.

    Parameters
    ----------
    EI, kAG : array_like
        Bending stiffness (N m^2) and shear stiffness kappa A G (N), real.
    length : array_like
        Element length l (m).
    xi : array_like
        Position of the force in the element, x / l in [0, 1] (-).

    Returns
    -------
    ndarray
        m/N, the broadcast shape; 0 at the nodes.

    Examples
    --------
    Without shear it is the clamped-clamped Euler beam's ``a^3 b^3 / (3 EI l^3)``:

    >>> g = point_flexibility(6.4e6, 1e20, 0.05, 0.3)
    >>> a, b = 0.015, 0.035
    >>> bool(np.isclose(g, a**3 * b**3 / (3 * 6.4e6 * 0.05**3)))
    True
    """
    EI, kAG, l, xi = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (EI, kAG, length, xi)))
    # Within 1e-9 of a node the flexibility is below 1e-19 m/N (shear: a / kAG), and its terms
    # ~1/a^3 overflow into NaN as a -> 0: there it is the node's 0.
    inside = (xi > _AT_NODE) & (xi < 1 - _AT_NODE)
    a = np.where(inside, xi * l, 1.0)
    b = np.where(inside, (1 - xi) * l, 1.0)
    ca, cb = (EI / (s**3 * (1 + 12 * EI / (kAG * s**2))) for s in (a, b))
    pa, pb = 12 * EI / (kAG * a**2), 12 * EI / (kAG * b**2)
    # the load node's stiffness (w, psi) from both sub-elements, the outer nodes clamped
    k11, k12, k22 = 12 * (ca + cb), 6 * (b * cb - a * ca), (4 + pa) * a * a * ca + (4 + pb) * b * b * cb
    return np.where(inside, k22 / (k11 * k22 - k12 * k12), 0.0)


def rail_element(track: Track, length: float) -> tuple[np.ndarray, np.ndarray]:
    """Real stiffness and mass of one rail element of ``track`` (loss factor not applied).

    Parameters
    ----------
    track : Track
        The rail's E, I, kappa, A, G, mass per length and rotary inertia.
    length : float
        Element length (m).

    Returns
    -------
    K, M : ndarray, shape (4, 4)
        As :func:`timoshenko_element`.

    Examples
    --------
    The mass of a rigid vertical translation is the element's rail mass:

    >>> from semitrack.model.tracks import slab_track
    >>> track = slab_track()
    >>> K, M = rail_element(track, 0.05)
    >>> u = np.array([1.0, 0.0, 1.0, 0.0])
    >>> bool(np.isclose(u @ M @ u, track.mass_per_length * 0.05))
    True
    """
    require_track(track)
    return timoshenko_element(track.E * track.I, track.kappa * track.A * track.G, track.mass_per_length,
                              track.rotary_inertia, length)
