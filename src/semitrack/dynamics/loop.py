"""The step loop in NumPy and SciPy: the reference that the compiled loop is tested against.

Both loops take the same :class:`StepArrays` and fill the same outputs; this one applies the
factorisation with LAPACK (``dpbtrs`` or ``?gbtrs``, or SuperLU) and the sparse products with
SciPy, in the system's own numbering, so that it also serves any factorisation and any
Newmark parameters. It is the fallback where numba is not installed.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from .contact import MAX_NEWTON, HertzContacts, solve_hertz
from .newmark import Newmark
from .states import TrapezoidalStates

__all__ = ["FLUSH", "StepArrays", "Outputs", "run_numpy"]

#: Motion below this (m, m/s, m/s^2) is set to zero after each step, in both loops: far from the
#: load an implicit step's amplitudes decay to subnormal numbers, whose arithmetic is a hundred
#: times slower, and stay there (the scheme does not dissipate); 1e-200 is zero for any track.
FLUSH = 1e-200


@dataclass
class StepArrays:
    """Everything a step loop reads: the system's products, its factor, loads, states, contacts, probes.

    Attributes
    ----------
    stepper : Newmark
        The scheme.
    n_steps : int
        Steps to take.
    MC : scipy.sparse.csr_matrix, shape (n, 2 n)
        ``[M C]``: the step's load from the state is ``MC @ stepper.predict(...)``.
    factor : object
        The effective stiffness's factorisation (``solve(b)``).
    loads : list of (PointSet, ndarray)
        Each load's points and its amplitude per step, shape (n_steps + 1, n_points) (N).
    states : TrapezoidalStates or None
        The discretised state blocks.
    contacts : HertzContacts or None
        The nonlinear contacts.
    probes : dict of str to PointSet
        Responses recorded at points.
    record : ndarray of int
        DOFs recorded.
    u, v, a : ndarray
        The initial state (overwritten by the final one).
    offset : ndarray
        A constant load added at every step (N; empty for none).
    u_ref : ndarray
        The displacement the loop's ``u`` is measured from (m).
    x : ndarray
        The states' initial values (overwritten by the final ones; zeros for a start at rest).
    """

    stepper: Newmark
    n_steps: int
    MC: sp.csr_matrix
    factor: object
    loads: list
    states: TrapezoidalStates | None
    contacts: HertzContacts | None
    probes: dict
    record: np.ndarray
    u: np.ndarray
    v: np.ndarray
    a: np.ndarray
    offset: np.ndarray
    u_ref: np.ndarray
    x: np.ndarray


@dataclass
class Outputs:
    """What a loop fills, one row per step from t = 0 (row 0 is the initial state's)."""

    dofs: np.ndarray
    probes: dict
    force: np.ndarray
    wheel: np.ndarray
    rail: np.ndarray

    @classmethod
    def empty(cls, arrays: StepArrays) -> Outputs:
        rows = arrays.n_steps + 1
        k = arrays.contacts.n_contacts if arrays.contacts is not None else 0
        return cls(np.empty((rows, arrays.record.size)),
                   {name: np.empty((rows, p.n_points)) for name, p in arrays.probes.items()},
                   np.empty((rows, k)), np.empty((rows, k)), np.empty((rows, k)))

    def write(self, k: int, u: np.ndarray, probes: dict, record: np.ndarray) -> None:
        """Row ``k`` of the DOFs and probes from the state ``u``."""
        self.dofs[k] = u[record]
        for name, points in probes.items():
            self.probes[name][k] = points.values(u, k)


def add_loads(rhs: np.ndarray, loads: list, k: int) -> None:
    """Add the loads of step ``k`` (fixed or moving points, their amplitudes) into ``rhs`` in place."""
    for points, amplitude in loads:
        if isinstance(points, np.ndarray):  # fixed points as a dense (n, n_points) matrix
            rhs += points @ amplitude[k]
        else:
            dofs, weights = points.at(k)
            np.add.at(rhs, dofs.ravel(), (amplitude[k][:, None] * weights).ravel())


class _ContactStep:
    """The contact forces of each step: the load vectors' responses ``g`` (once for fixed contacts)."""

    def __init__(self, contacts: HertzContacts, factor, n: int):
        self.contacts, self.factor, self.n = contacts, factor, n
        self.g = self.G = None
        self.force = np.zeros(contacts.n_contacts)
        self.work = np.zeros((contacts.n_contacts, contacts.n_contacts + 5))

    def __call__(self, k: int, u_free: np.ndarray) -> np.ndarray:
        c = self.contacts
        if self.g is None or c.points.moving:
            B = c.load_vectors(self.n, k)
            self.g = self.factor.solve(B.toarray())
            self.G = np.asarray(B.T @ self.g) + np.diag(c.local_compliance(k))
            if not np.all(np.diagonal(self.G) > 0):
                raise RuntimeError(f"the contacts' step compliance must be positive, got {np.diagonal(self.G)} m/N")
        a = c.approach(u_free, k)
        if solve_hertz(c.hertz_constants, a, self.G, self.force, self.work, c.linear) > MAX_NEWTON:
            raise RuntimeError(f"the contact forces did not converge in {MAX_NEWTON} Newton steps at step {k}")
        return u_free + self.g @ self.force if np.any(self.force > 0) else u_free


def _write_contacts(out: Outputs, contacts: HertzContacts, k: int, u: np.ndarray, force: np.ndarray) -> None:
    out.force[k] = force
    out.wheel[k] = u[contacts.wheel_dofs]
    out.rail[k] = contacts.points.values(u, k) + contacts.local_compliance(k) * force


def run_numpy(arrays: StepArrays) -> Outputs:
    """Take ``n_steps`` steps from the initial state; return the recorded rows.

    Parameters
    ----------
    arrays : StepArrays
        The loop's inputs; its ``u, v, a`` end as the final state.

    Returns
    -------
    Outputs
    """
    s, n = arrays.stepper, arrays.u.size
    u, v, a = arrays.u.copy(), arrays.v.copy(), arrays.a.copy()
    states, contacts = arrays.states, arrays.contacts
    x = arrays.x.copy()
    if states is not None:  # a few hundred states: dense products skip SciPy's per-call overhead
        E, Phi_P, H = (X.toarray() for X in (states.E, states.Phi_P, states.history_x))
    loads = [(p.matrix(n).T.toarray() if not p.moving and p.n_points <= 16 else p, amp)  # a few fixed points: dense
             for p, amp in arrays.loads]
    contact = _ContactStep(contacts, arrays.factor, n) if contacts is not None else None
    out = Outputs.empty(arrays)
    out.write(0, u, arrays.probes, arrays.record)
    if contacts is not None:
        _write_contacts(out, contacts, 0, u, contacts.forces(u, 0))
    y = np.empty(2 * n)
    for k in range(1, arrays.n_steps + 1):
        rhs = arrays.MC @ s.predict(u, v, a, y)
        add_loads(rhs, loads, k)
        if arrays.offset.size:
            rhs += arrays.offset
        if states is not None:
            rhs[states.dofs] -= H @ x - states.block @ u[states.dofs]
        u_new = arrays.factor.solve(rhs)
        if contact is not None:
            u_new = contact(k, u_new)
        if states is not None:
            x = E @ x + Phi_P @ (u_new[states.dofs] - u[states.dofs])
        v, a = s.correct(u, v, a, u_new)
        u = u_new
        still = (np.abs(u) < FLUSH) & (np.abs(v) < FLUSH) & (np.abs(a) < FLUSH)
        u[still] = v[still] = a[still] = 0.0  # as the compiled loop: no subnormal numbers far from the load
        out.write(k, u, arrays.probes, arrays.record)
        if contacts is not None:
            _write_contacts(out, contacts, k, u, contact.force)
    arrays.u[:], arrays.v[:], arrays.a[:], arrays.x[:] = u, v, a, x
    return out

