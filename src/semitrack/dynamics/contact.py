"""Hertzian contacts of k wheels: the nonlinear element of a wheel-rail step.

Within a time step the new displacement is linear in the contact forces ``F`` (N, compression,
one per wheel): with ``b_i`` the load vector of contact i (the shape weights of the rail under
it, and -1 at its wheel's DOF) and ``g_i = K_eff^-1 b_i``,

    u = u_free + sum_i g_i F_i,      delta = a - G F,      G_ij = b_i . g_j,

where ``delta`` are the contacts' approaches (m, positive in contact), ``a`` the approaches the
step would have without contact forces and ``G`` the (symmetric positive definite) compliance
the forces see through the structure within the step. The forces solve

    F_i = c_i max(delta_i, 0)^(3/2),     i.e.   delta + G h(delta) = a,   h_i = c_i max(delta_i, 0)^(3/2),

(:func:`solve_hertz`). ``h`` is continuously differentiable, so Newton's method on ``delta``
converges quadratically; it starts from ``delta = a``, the upper bound where the wheels' mutual
compliances are non-negative (the static case; within a step the rail's inertia makes the far
ones oscillate in sign, but they are small beside each wheel's own). A contact with
``a_i <= 0`` and no neighbour pressing it down carries no force (loss of contact: the force is
never negative). With one wheel the residual is convex and increasing and the iterates fall
monotonically to the root within ``[0, a]``; with several, a step that would not reduce the
residual is halved.

The same source runs as plain Python in the NumPy loop and compiled in the fast one.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..base.errors import InputError
from .points import PointSet

__all__ = ["MAX_NEWTON", "HertzContacts", "solve_hertz", "hertz_contact_force"]

#: Newton iterations allowed for one step's contact forces (a few on the paper's tracks, as measured
#: when the loop was written; the cap only stops a run that would not converge).
MAX_NEWTON = 100


def solve_hertz(c_h: np.ndarray, a: np.ndarray, G: np.ndarray, force: np.ndarray,
                work: np.ndarray, linear: np.ndarray | None = None) -> int:
    """Solve ``F = c_h max(a - G F, 0)^p`` for the contact forces of one step, in place.

    ``p = 3/2`` for a Hertzian contact; ``p = 1`` where ``linear`` is true: a unilateral linear
    spring (a sleeper on ballast that can lift off, :mod:`semitrack.fe.gaps`).

    One source for both loops: plain Python here, and compiled by :mod:`semitrack.dynamics.compiled`,
    which compiles the helpers it calls (:func:`_one_hertz`, :func:`_contact_laws`,
    :func:`_residual`, :func:`_newton_step`, :func:`_forces`) and binds them in their place. Everything runs on a
    workspace the caller owns.

    Parameters
    ----------
    c_h : ndarray, shape (k,)
        Hertz constants (N/m^1.5), positive.
    a : ndarray, shape (k,)
        The approaches without contact forces (m).
    G : ndarray, shape (k, k)
        The step's compliance (m/N), symmetric positive definite.
    force : ndarray, shape (k,)
        Receives the forces (N), >= 0.
    work : ndarray, shape (k, k + 5)
        Workspace.
    linear : ndarray of bool, shape (k,), optional
        Contacts that are unilateral linear springs (``c_h`` then in N/m); default none.

    Returns
    -------
    int
        Newton iterations taken (0 when no contact is closed); ``MAX_NEWTON + 1`` if it did not
        converge.

    Examples
    --------
    >>> F = np.zeros(1)
    >>> n = solve_hertz(np.array([9.3e10]), np.array([1e-4]), np.array([[1e-9]]), F, np.zeros((1, 6)))
    >>> bool(abs(F[0] - 9.3e10 * (1e-4 - 1e-9 * F[0]) ** 1.5) < 1e-6 * F[0])
    True
    """
    k = a.size
    scale = 0.0
    for i in range(k):
        force[i] = 0.0
        if a[i] > scale:
            scale = a[i]
    if scale <= 0.0:
        return 0
    lin = False  # any unilateral linear spring among the contacts
    if linear is not None:
        for i in range(k):
            if linear[i]:
                lin = True
    if k == 1 and not lin:
        return _one_hertz(c_h[0], G[0, 0], a[0], scale, force)
    delta, h, hp, r, step = work[:, k], work[:, k + 1], work[:, k + 2], work[:, k + 3], work[:, k + 4]
    for i in range(k):
        delta[i] = a[i]
    norm = math.inf
    for iteration in range(1, MAX_NEWTON + 1):
        _contact_laws(c_h, linear, lin, delta, h, hp)
        new_norm = _residual(a, G, delta, h, scale, r)
        if new_norm > norm and iteration < MAX_NEWTON:  # no better: halve the last step
            for i in range(k):
                step[i] *= 0.5
                delta[i] += step[i]
            continue
        norm = new_norm
        if _newton_step(G, hp, r, work, delta, scale):
            _forces(c_h, linear, lin, delta, force)
            return iteration
    return MAX_NEWTON + 1


def _one_hertz(c: float, g: float, a0: float, scale: float, force: np.ndarray) -> int:
    """One Hertzian contact, ``delta + g c delta^(3/2) = a0``, by Newton on floats (~5x faster than on arrays)."""
    d = a0
    for iteration in range(1, MAX_NEWTON + 1):
        root = math.sqrt(d) if d > 0.0 else 0.0
        step = (d + g * (c * d * root) - a0) / (1.0 + g * 1.5 * c * root)
        d -= step
        if abs(step) <= 4e-16 * max(abs(d), scale):
            force[0] = c * d * math.sqrt(d) if d > 0.0 else 0.0
            return iteration
    return MAX_NEWTON + 1


def _contact_laws(c_h: np.ndarray, linear, lin: bool, delta: np.ndarray, h: np.ndarray, hp: np.ndarray) -> None:
    """Each contact's force ``h(delta)`` and its derivative ``hp``: Hertzian, or a unilateral linear spring."""
    for j in range(delta.size):
        if linear is not None:  # a plain `if` on the argument: numba prunes it where none is given
            if lin and linear[j]:
                h[j] = c_h[j] * delta[j] if delta[j] > 0.0 else 0.0
                hp[j] = c_h[j] if delta[j] > 0.0 else 0.0
                continue
        root = math.sqrt(delta[j]) if delta[j] > 0.0 else 0.0
        h[j] = c_h[j] * delta[j] * root
        hp[j] = 1.5 * c_h[j] * root


def _forces(c_h: np.ndarray, linear, lin: bool, delta: np.ndarray, force: np.ndarray) -> None:
    """The contact forces at the converged approaches: 0 where a contact is open (never negative)."""
    for i in range(delta.size):
        if delta[i] <= 0.0:
            force[i] = 0.0
            continue
        force[i] = c_h[i] * delta[i] * math.sqrt(delta[i])
        if linear is not None:  # pruned by numba where none is given, as in _contact_laws
            if lin and linear[i]:
                force[i] = c_h[i] * delta[i]


def _residual(a: np.ndarray, G: np.ndarray, delta: np.ndarray, h: np.ndarray, scale: float, r: np.ndarray) -> float:
    """``r = delta + G h - a`` in place, and its largest entry, each on its own contact's scale.

    An open gap's approach (metres below) would leave round-off far above a closed contact's
    residual and stall the step halving: each residual is measured against its own ``|a_i|``.
    """
    k = a.size
    norm = 0.0
    for i in range(k):
        s = delta[i] - a[i]
        for j in range(k):
            s += G[i, j] * h[j]
        r[i] = s
        s = abs(s) / (abs(a[i]) if abs(a[i]) > scale else scale)
        if s > norm:
            norm = s
    return norm


def _newton_step(G: np.ndarray, hp: np.ndarray, r: np.ndarray, work: np.ndarray, delta: np.ndarray,
                 scale: float) -> bool:
    """Solve ``(I + G diag(hp)) step = r`` by Gaussian elimination with partial pivoting, take ``delta -= step``.

    The matrix and the step live in ``work`` (its first k columns and its last). Returns whether
    every step is within round-off of its contact's approach (converged).
    """
    k = delta.size
    J, step = work[:, :k], work[:, k + 4]
    for i in range(k):
        for j in range(k):
            J[i, j] = G[i, j] * hp[j]
        J[i, i] += 1.0
        step[i] = r[i]
    for p in range(k):
        q = p
        for i in range(p + 1, k):
            if abs(J[i, p]) > abs(J[q, p]):
                q = i
        if q != p:
            for j in range(k):
                tmp = J[p, j]
                J[p, j] = J[q, j]
                J[q, j] = tmp
            tmp = step[p]
            step[p] = step[q]
            step[q] = tmp
        for i in range(p + 1, k):
            m = J[i, p] / J[p, p]
            for j in range(p, k):
                J[i, j] -= m * J[p, j]
            step[i] -= m * step[p]
    for p in range(k - 1, -1, -1):
        s = step[p]
        for j in range(p + 1, k):
            s -= J[p, j] * step[j]
        step[p] = s / J[p, p]
    done = True
    for i in range(k):
        delta[i] -= step[i]
        bound = abs(delta[i]) if abs(delta[i]) > scale else scale
        if abs(step[i]) > 4e-16 * bound:
            done = False
    return done


#: The helpers :func:`solve_hertz` calls, which the compiled loop compiles and binds in their place.
HELPERS = (_one_hertz, _contact_laws, _forces, _residual, _newton_step)


def hertz_contact_force(c_h: float, a: float, beta: float) -> float:
    """The force F >= 0 (N) with ``F = c_h max(a - beta F, 0)^(3/2)``: one wheel's contact equation in a step.

    The one-wheel case of :func:`semitrack.dynamics.contact.solve_hertz`.

    Parameters
    ----------
    c_h : float
        Hertz constant (N/m^1.5), positive.
    a : float
        The approach the step would have without contact force (m).
    beta : float
        The compliance that the contact force sees within the step (m/N), positive: the approach
        is ``a - beta F``.

    Returns
    -------
    float
        The contact force (N): 0 when ``a <= 0`` (loss of contact).

    Examples
    --------
    >>> f = hertz_contact_force(9.3e10, 1e-4, 1e-9)
    >>> bool(abs(f - 9.3e10 * (1e-4 - 1e-9 * f) ** 1.5) < 1e-6 * f)
    True
    """
    force = np.zeros(1)
    if solve_hertz(np.array([float(c_h)]), np.array([float(a)]), np.array([[float(beta)]]), force,
                   np.zeros((1, 6))) > MAX_NEWTON:
        raise RuntimeError(f"the contact force did not converge in {MAX_NEWTON} Newton steps")
    return float(force[0])


@dataclass(frozen=True)
class HertzContacts:
    """k wheels in Hertzian contact with a structure, each at a point that may move.

    Parameters
    ----------
    wheel_dofs : array_like of int, shape (k,)
        The vertical DOF of each wheel (m, downward).
    points : PointSet
        The contact point of each wheel on the structure (k points, fixed or per step).
    hertz_constants : array_like, shape (k,)
        C_H of each contact (N/m^1.5), positive.
    irregularity : ndarray, shape (n_steps + 1, k)
        The rail surface's downward displacement under each wheel at every step (m): the
        roughness, a dip or a joint; the approach is ``w_wheel - w_rail - irregularity``.
    labels : tuple of str
        A label per wheel.
    linear : array_like of bool, shape (k,), optional
        Contacts that are unilateral linear springs, ``F = c max(delta, 0)`` with ``c`` in N/m
        (``hertz_constants``' place): a sleeper on ballast that can lift off, the "wheel" DOF the
        sleeper's, its point a weight-0 point (the ground). Default none.
    compliance : ndarray, optional
        A local compliance in series with each contact (m/N), ``(1, k)`` for fixed points or
        ``(n_steps + 1, k)`` per step for moving ones: what the structure's interpolation misses
        under a point force (a beam element's own deflection under a load between its nodes,
        :func:`semitrack.fe.element.point_flexibility`). The rail's surface under the wheel is
        ``points.values(u) + compliance F``; default none.
    """

    wheel_dofs: np.ndarray
    points: PointSet
    hertz_constants: np.ndarray
    irregularity: np.ndarray
    labels: tuple = ()
    compliance: np.ndarray | None = None
    linear: np.ndarray | None = None

    def __post_init__(self):
        wheels = np.asarray(self.wheel_dofs, dtype=np.int64).ravel()
        c_h = np.asarray(self.hertz_constants, dtype=float).ravel()
        r = np.asarray(self.irregularity, dtype=float)
        k = wheels.size
        if self.points.n_points != k or c_h.shape != (k,) or r.ndim != 2 or r.shape[1] != k:
            raise InputError(f"{k} contacts need {k} points, {k} Hertz constants and an irregularity of shape "
                             f"(n_steps + 1, {k}); got {self.points.n_points}, {c_h.shape} and {r.shape}")
        if not np.all(np.isfinite(c_h) & (c_h > 0)):
            raise InputError(f"hertz_constants must be positive and finite (N/m^1.5), got {c_h.tolist()}")
        rows = self.points.dofs.shape[0]
        g = np.zeros((rows, k)) if self.compliance is None else np.asarray(self.compliance, dtype=float)
        if g.shape != (rows, k) or not np.all(np.isfinite(g) & (g >= 0)):
            raise InputError(f"compliance must be ({rows}, {k}) values >= 0 (m/N), one row per row of the points")
        object.__setattr__(self, "wheel_dofs", wheels)
        object.__setattr__(self, "hertz_constants", c_h)
        object.__setattr__(self, "irregularity", np.ascontiguousarray(r))
        object.__setattr__(self, "labels", tuple(self.labels) or tuple(f"wheel {i}" for i in range(k)))
        object.__setattr__(self, "compliance", np.ascontiguousarray(g))
        lin = np.zeros(k, dtype=bool) if self.linear is None else np.asarray(self.linear, dtype=bool).ravel()
        if lin.shape != (k,):
            raise InputError(f"linear must give one flag per contact ({k}), got shape {lin.shape}")
        object.__setattr__(self, "linear", lin)

    @property
    def n_contacts(self) -> int:
        """Number of wheels."""
        return self.wheel_dofs.size

    def local_compliance(self, k: int) -> np.ndarray:
        """The contacts' local compliance at step ``k`` (m/N), shape (k,)."""
        return self.compliance[k if self.compliance.shape[0] > 1 else 0]

    def approach(self, u: np.ndarray, k: int) -> np.ndarray:
        """The approaches ``w_wheel - points.values(u) - irregularity`` (m) in state ``u`` at step ``k``,
        before the local compliance's share ``compliance F``."""
        return u[self.wheel_dofs] - self.points.values(u, k) - self.irregularity[k]

    def forces(self, u: np.ndarray, k: int) -> np.ndarray:
        """The contact forces (N) of the state ``u`` at step ``k``: ``F = C_H max(a - g F, 0)^(3/2)`` (or
        ``^1`` for the :attr:`linear` contacts) with the local compliance g alone (no step compliance)."""
        force = np.zeros(self.n_contacts)
        if solve_hertz(self.hertz_constants, self.approach(u, k), np.diag(self.local_compliance(k)), force,
                       np.zeros((self.n_contacts, self.n_contacts + 5)), self.linear) > MAX_NEWTON:
            raise RuntimeError(f"the contact forces did not converge in {MAX_NEWTON} Newton steps")
        return force

    def load_vectors(self, n: int, k: int):
        """The sparse ``(n, k)`` matrix of the contacts' load vectors ``b_i`` at step ``k``."""
        B = self.points.matrix(n, k).T.tolil()
        B[self.wheel_dofs, np.arange(self.n_contacts)] = -1.0
        return B.tocsc()

    def renumbered(self, where: np.ndarray) -> HertzContacts:
        """The same contacts on DOFs renamed ``where[i]``."""
        return HertzContacts(where[self.wheel_dofs], self.points.renumbered(where), self.hertz_constants,
                             self.irregularity, self.labels, self.compliance, self.linear)
