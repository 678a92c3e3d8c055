"""The broadband end in the paper's own form: symmetric positive semi-definite ``M, C, K``.

A passive, reciprocal rational end model (:mod:`.rational`),

    K(s) = K0 + s Z(s),    Z(s) = D + C (sI - A)^-1 B,

is turned, with no approximation, into a mechanical network on the two port DOFs ``(w, psi)``
plus internal DOFs by reciprocal passive synthesis (Anderson & Vongpanitlerd, *Network Analysis
and Synthesis*, Prentice-Hall 1973, ch. 9; Hughes, "A theory of passive linear systems with no
assumptions", arXiv:1804.01489; Beattie, Mehrmann & Xu, "Port-Hamiltonian realizations of linear
time invariant systems", arXiv:2201.05355):

1. Reciprocity: ``Z`` is symmetric, so a symmetric signature matrix ``T`` with ``T A = A^T T``
   and ``T B = C^T`` exists; it is found pole by pole, ``T [B, A B] = [C^T, A^T C^T]``.
2. Passivity: a storage ``P > 0`` of the KYP inequality ``[[-A^T P - P A, C^T - P B],
   [C - B^T P, D + D^T]] >= 0``: the extremal solution of the passivity Riccati equation.
3. The reciprocal storage, ``T P^-1 T = P``: ``T P`` is replaced by its matrix sign, reached by
   Newton's (determinant-scaled) sign iteration. Since ``T P^-1 T`` is a storage whenever ``P``
   is, and storages form a convex set, the limit is one too.
4. Coordinates with ``P = I`` and ``T = diag(I, -I)``; then ``A11``, ``A22`` are symmetric,
   ``A12 = -A21^T``, ``C = [B1^T, -B2^T]``, and the KYP inequality reads ``-A11 >= 0`` and
   ``[[-A22, -B2], [-B2^T, D]] >= 0``.
5. The network: the ``-1`` states are the velocities of unit masses, ``[[D, -B2^T], [-B2, -A22]]``
   the dampers between them and the ports; the ``+1`` states are the forces of unit springs of
   elongation ``B1 u + A12 q``; ``A11 = -V diag(lambda) V^T`` puts a dashpot ``1/lambda`` to the
   ground in series with spring ``i`` (a Maxwell element, one massless DOF), for every
   ``lambda > 0``. ``K0`` joins the port stiffness. The energy is ``x^T x / 2`` throughout.

Every first-order state gives at most one internal DOF (a mass or a Maxwell DOF; a pure spring
none); states that are not minimal (a residue of lower rank) are projected out first, exactly.
The synthesis runs on the model scaled by ``D^-1/2`` at the ports (as the passivity test does),
so that ``w`` and ``psi`` weigh alike.

**Limits**, stated where the system is made (:meth:`semitrack.BroadbandBoundary.matrix_system`):
implicit integrators only (the Maxwell DOFs are massless); the internal DOFs have no spring path
to the ground, so a static or preload step closes the cut with ``K0`` (the system's
:meth:`~semitrack.equivalent.mechanical.MechanicalSystem.static_stiffness`), and the dynamic step
starts its internal DOFs at :meth:`~semitrack.equivalent.mechanical.MechanicalSystem.static_internal`
of the static port displacement; the masses are mathematical (unit masses in energy coordinates),
so no gravity acts on them; and a file of the matrices needs at least 12 significant digits
(measured on the four study fits: 8 digits lose 1e-5 to 4.5 % of the receptance, 12 keep 1e-9 to
1e-5).
"""

from __future__ import annotations

import numpy as np
import scipy.linalg

from ..base.errors import InputError
from ..base.threads import serial_blas
from ..equivalent.mechanical import MatrixSystem
from .rational import RationalEndStiffness
from .vector_fitting import n_real_coefficients

__all__ = ["second_order_system", "reciprocity_matrix", "reciprocal_storage", "SynthesisError",
           "SYNTHESIS_TOL"]

#: Largest relative element error of the synthesised receptance against the state space, checked
#: from 1 mHz to 1 MHz before the system is returned (measured 1e-12 to 1e-9 on the paper's fits).
SYNTHESIS_TOL = 1e-6

# A symmetric A11 eigenvalue below this fraction of max |A| is rounding: the spring has no dashpot.
_MAXWELL_RTOL = 1e-13
# An eigenvalue of T below this fraction of the largest is a direction that is not minimal (the
# paper's fits have 1e-10 to 1 of the largest; an exact rank-1 residue leaves 1e-17).
_KERNEL_RTOL = 1e-14


class SynthesisError(InputError):
    """The model has no passive M, C, K network (it is not passive or not reciprocal):
    a refusal of the model given, as the command line reports it (exit code 2)."""


def reciprocity_matrix(model: RationalEndStiffness) -> np.ndarray:
    """The symmetric ``T`` with ``T A = A^T T`` and ``T B = C^T`` for ``model.state_space()``.

    The state matrix is block diagonal by pole (a real pole: two states, ``B = I``; a pair: four,
    ``B = [2 I; 0]``), so ``T`` is too, each block from ``T [B, A B] = [C^T, A^T C^T]``.

    Parameters
    ----------
    model : RationalEndStiffness
        The rational end model (symmetric coefficients: reciprocal).

    Returns
    -------
    ndarray, shape (n, n)
    """
    A, B, C, _ = model.state_space()
    T = np.zeros_like(A)
    i = 0
    for pole in model.poles:
        k = 2 * n_real_coefficients(np.array([pole]))
        blk = slice(i, i + k)
        a, b, c = A[blk, blk], B[blk], C[:, blk]
        krylov = b if k == 2 else np.hstack([b, a @ b])
        image = c.T if k == 2 else np.hstack([c.T, a.T @ c.T])
        T[blk, blk] = np.linalg.solve(krylov.T, image.T).T
        i += k
    return 0.5 * (T + T.T)


def _passivity_storage(A: np.ndarray, B: np.ndarray, C: np.ndarray, R: np.ndarray) -> np.ndarray:
    """The extremal storage ``P`` of the passivity Riccati equation
    ``A^T P + P A + (P B - C^T) R^-1 (B^T P - C) = 0`` (with ``X = -P`` the stabilising solution of
    SciPy's ``A^T X + X A - (X B + C^T) R^-1 (B^T X + C) = 0``)."""
    try:
        P = -scipy.linalg.solve_continuous_are(A, B, np.zeros_like(A), R, s=C.T)
    except (np.linalg.LinAlgError, ValueError):  # imaginary-axis eigenvalues: Re Z changes sign
        raise SynthesisError("the passivity Riccati equation has no solution: the model is not passive") from None
    P = 0.5 * (P + P.T)
    if np.linalg.eigvalsh(P)[0] <= 0:
        raise SynthesisError("the passivity Riccati equation has no positive definite solution: the model is "
                             "not passive (or not minimal)")
    return P


def reciprocal_storage(P: np.ndarray, signature: np.ndarray, max_iter: int = 100) -> np.ndarray:
    """The storage ``P = T P^-1 T`` reached from a storage ``P`` by Newton's sign iteration on ``T P``.

    ``P <- (mu P + T P^-1 T / mu) / 2`` with the determinant scaling ``mu = det(P)^(-1/n)`` while
    the steps are large (it only speeds the iteration: the limit, the matrix sign, is the same),
    then ``mu = 1``.

    Parameters
    ----------
    P : ndarray, shape (n, n)
        A symmetric positive definite storage.
    signature : ndarray, shape (n,)
        The diagonal of ``T`` (+-1).
    max_iter : int
        Iterations allowed.

    Returns
    -------
    ndarray, shape (n, n)
    """
    t = np.asarray(signature, dtype=float)
    n = P.shape[0]
    step = np.inf
    for _ in range(max_iter):
        mu = np.exp(-np.linalg.slogdet(P)[1] / n) if step > 1e-2 else 1.0
        new = 0.5 * (mu * P + t[:, None] * np.linalg.inv(P) * t[None, :] / mu)
        new = 0.5 * (new + new.T)
        step = np.max(np.abs(new - P)) / np.max(np.abs(new))
        P = new
        if step < 1e-13 and mu == 1.0:
            return P
    if step > 1e-9:
        raise SynthesisError(f"Newton's sign iteration did not converge (last relative step {step:.2e})")
    return P


def _to_signature(A, B, C, T):
    """Coordinates in which ``T = diag(+-1)``: ``x = W z`` with ``W = U |t|^-1/2``, the kernel of ``T``
    dropped.

    A state space that is not minimal (a residue of lower rank than its pole's states, e.g. a real
    pole's 2x2 coefficient of rank 1) has a singular ``T``. Its kernel is unobservable
    (``C v = B^T T v = 0``) and invariant under ``A`` (``T A v = A^T T v = 0``), so projecting it
    out, ``z = W^+ x``, ``A_r = W^+ A W``, is exact, and the model gets fewer states.
    """
    t, U = np.linalg.eigh(T)
    keep = np.abs(t) > _KERNEL_RTOL * np.max(np.abs(t))
    U, t = U[:, keep], t[keep]
    W = U / np.sqrt(np.abs(t))
    if np.all(keep):  # W is square: a solve keeps a few more digits than its transpose-based inverse
        return np.linalg.solve(W, A @ W), np.linalg.solve(W, B), C @ W, np.sign(t)
    W_plus = np.sqrt(np.abs(t))[:, None] * U.T
    return W_plus @ A @ W, W_plus @ B, C @ W, np.sign(t)


def _passive_coordinates(A, B, C, R, t):
    """Coordinates with the reciprocal storage ``P = I`` and ``T = diag(+-1)``, the +1 states first."""
    P = reciprocal_storage(_passivity_storage(A, B, C, R), t)
    L = np.linalg.cholesky(P)
    Tl = np.linalg.solve(L, np.linalg.solve(L, np.diag(t)).T)  # L^-1 T L^-T, orthogonally diagonalisable
    e, Q = np.linalg.eigh(0.5 * (Tl + Tl.T))
    order = np.argsort(-e, kind="stable")
    W = np.linalg.solve(L.T, Q[:, order])
    return np.linalg.solve(W, A @ W), np.linalg.solve(W, B), int(np.sum(e > 0))


def _network(A: np.ndarray, B: np.ndarray, n1: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """``(M, C, K, maxwell)`` of the unit network of step 5 (ports scaled; ``K0`` not yet added)."""
    A11, A12, A22 = A[:n1, :n1], A[:n1, n1:], A[n1:, n1:]
    B1, B2 = B[:n1], B[n1:]
    lam, V = np.linalg.eigh(-0.5 * (A11 + A11.T))
    maxwell = lam > _MAXWELL_RTOL * np.max(np.abs(A))
    n2, nm = A22.shape[0], int(np.sum(maxwell))
    elongation = np.hstack([V.T @ B1, V.T @ A12, -np.eye(n1)[:, maxwell]])  # springs' e per DOF
    n = 2 + n2 + nm
    damper = np.zeros((n, n))
    damper[:2, :2] = np.eye(2)  # D scaled by D^-1/2
    damper[:2, 2:2 + n2] = -B2.T
    damper[2:2 + n2, :2] = -B2
    damper[2:2 + n2, 2:2 + n2] = -0.5 * (A22 + A22.T)
    damper[2 + n2:, 2 + n2:] = np.diag(1.0 / lam[maxwell])
    mass = np.zeros((n, n))
    mass[2:2 + n2, 2:2 + n2] = np.eye(n2)
    return mass, damper, elongation.T @ elongation, maxwell


def _matrices(model: RationalEndStiffness) -> tuple[np.ndarray, np.ndarray, np.ndarray, int]:
    """``(M, C, K, n_maxwell)`` of the network in physical port units, ``K0`` and ``D`` exact."""
    A, B, C, D = model.state_space()
    scale = 1.0 / np.sqrt(np.diag(D))  # D is diagonal: the Timoshenko dashpot
    try:
        A, B, C, t = _to_signature(A, B * scale, scale[:, None] * C, reciprocity_matrix(model))
        A, B, n1 = _passive_coordinates(A, B, C, 2 * np.eye(2), t)
    except np.linalg.LinAlgError as exc:  # a singular Krylov block or a storage that is not definite
        raise SynthesisError(f"the model has no passive reciprocal realisation here ({exc})") from None
    M, Cd, K, maxwell = _network(A, B, n1)
    ports = np.ones(M.shape[0])
    ports[:2] = 1.0 / scale
    M, Cd, K = (ports[:, None] * X * ports[None, :] for X in (M, Cd, K))
    K[:2, :2] += model.K0
    Cd[:2, :2] = model.D  # exactly: the dashpot is pinned, not re-derived
    return M, Cd, K, int(np.sum(maxwell))


def second_order_system(model: RationalEndStiffness, info: dict | None = None) -> MatrixSystem:
    """The passive rational end model as symmetric positive semi-definite ``M, C, K`` (module docstring).

    Parameters
    ----------
    model : RationalEndStiffness
        A passive, reciprocal rational end model (as :func:`~.fitting.fit_boundary` returns).
    info : dict, optional
        What to record with the system (track, band, ...).

    Returns
    -------
    MatrixSystem
        DOFs ``(w, psi)`` (m, rad), then the unit masses ``q_j`` (kg^1/2 m) and the massless
        Maxwell DOFs ``r_j`` (N^1/2 m^1/2).

    Raises
    ------
    SynthesisError
        When the model is not passive, or the result misses :data:`SYNTHESIS_TOL`.
    """
    # Small dense matrices: threaded BLAS only contends; with other jobs on the machine its
    # spinning threads cost 20 s of CPU where one thread takes 0.1-0.4 s (measured).
    with serial_blas():
        M, C, K, n_maxwell = _matrices(model)
        n2 = M.shape[0] - 2 - n_maxwell
        dofs = ("w (m)", "psi (rad)") + tuple(f"q{j} (kg^1/2 m, unit mass)" for j in range(1, n2 + 1)) \
            + tuple(f"r{j} (N^1/2 m^1/2, massless)" for j in range(1, n_maxwell + 1))
        system = MatrixSystem(M, C, K, dofs=dofs, info=dict(info or {}))
        f = np.geomspace(1e-3, 1e6, 181)
        ref = model.receptance(f)
        error = float(np.max(np.abs(system.receptance(f) - ref) / np.abs(ref)))
    if error > SYNTHESIS_TOL:
        raise SynthesisError(f"the synthesised M, C, K differ from the rational model by {error:.2e} "
                             f"(relative, > {SYNTHESIS_TOL:g}) between 1 mHz and 1 MHz")
    return system
