"""First-order state blocks driven by DOF velocities, and their trapezoidal discretisation.

A state block is a small linear system attached to a few DOFs (the rational model of a broadband
boundary, or any user state-space element): with ``y = P u[dofs]`` its input motion (``P`` a
fixed map of the DOFs, e.g. the mirror ``diag(1, -1)`` at a left end),

    dx/dt = A x + B dy/dt,       force on the DOFs  f = -P^T C x.

Its static stiffness and direct dashpot, if any, belong in the system's ``K`` and ``C``.

The trapezoidal rule with average acceleration's ``dt/2 (v_n + v_n+1) = u_n+1 - u_n`` gives

    x_n+1 = E x_n + Phi (y_n+1 - y_n),   E = (I - dt/2 A)^-1 (I + dt/2 A),  Phi = (I - dt/2 A)^-1 B,

so the force at the new step splits into a constant stiffness ``P^T C Phi P`` at the DOFs (added
to the effective stiffness once) and a history load known from ``x_n`` and ``u_n``. It is the
same discretisation as average acceleration (the bilinear map), so the time-domain model with
its states is the frequency-domain one at the warped frequencies ``2/dt tan(omega dt/2)``.

:class:`TrapezoidalStates` merges every block of a system into one block-diagonal state vector
with the products ``P^T C E`` and ``P^T C Phi P`` formed once, as sparse matrices: a rational
model's ``A`` is block diagonal in its poles, and so are ``E`` and ``Phi``.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from scipy.linalg import block_diag

from ..base.errors import InputError

__all__ = ["StateBlock", "TrapezoidalStates"]


@dataclass(frozen=True)
class StateBlock:
    """A first-order element on a few DOFs: ``dx/dt = A x + B d(P u[dofs])/dt``, force ``-P^T C x``.

    Attributes
    ----------
    dofs : ndarray of int, shape (p,)
        The DOFs it acts on.
    A : ndarray, shape (m, m)
        State matrix (1/s), stable.
    B : ndarray, shape (m, p)
        Input matrix: states per input velocity.
    C : ndarray, shape (p, m)
        Output matrix: forces per state.
    port : ndarray, shape (p, p)
        ``P``: the input motion per DOF motion (the identity, or a mirror).
    label : str
        A description.
    """

    dofs: np.ndarray
    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    port: np.ndarray
    label: str = ""

    def __post_init__(self):
        dofs = np.asarray(self.dofs, dtype=np.int64).ravel()
        A, B, C, P = (np.asarray(getattr(self, k), dtype=float) for k in ("A", "B", "C", "port"))
        m, p = A.shape[0], dofs.size
        if A.shape != (m, m) or B.shape != (m, p) or C.shape != (p, m) or P.shape != (p, p):
            raise InputError(f"a state block on {p} DOFs with {m} states needs A ({m}, {m}), B ({m}, {p}), "
                             f"C ({p}, {m}) and port ({p}, {p}); got {A.shape}, {B.shape}, {C.shape}, {P.shape}")
        for key, value in (("dofs", dofs), ("A", A), ("B", B), ("C", C), ("port", P)):
            object.__setattr__(self, key, value)

    @property
    def n_states(self) -> int:
        """Number of states."""
        return self.A.shape[0]

    def renumbered(self, where: np.ndarray) -> StateBlock:
        """The same block on DOFs renamed ``where[i]``."""
        return StateBlock(where[self.dofs], self.A, self.B, self.C, self.port, self.label)


class TrapezoidalStates:
    """Every state block of a system, discretised by the trapezoidal rule at step ``dt`` and merged.

    Attributes
    ----------
    dofs : ndarray of int
        The DOFs of all blocks, concatenated (distinct).
    E, Phi_P : scipy.sparse.csr_matrix
        ``x_n+1 = E x_n + Phi_P (u_n+1 - u_n)[dofs]``.
    history_x : scipy.sparse.csr_matrix
        ``P^T C E``: the part of the new force known from ``x_n``.
    block : ndarray
        ``P^T C Phi P`` on ``dofs`` (dense, small): the constant stiffness of the states.
    stiffness : scipy.sparse.csc_matrix, shape (n, n)
        ``block`` placed at ``dofs``, without the zero couplings between blocks (which would
        widen the band of the effective stiffness).
    """

    def __init__(self, blocks: Sequence[StateBlock], dt: float, n: int):
        E, Phi_P, P_C = [], [], []
        for blk in blocks:
            m = blk.n_states
            lhs = np.eye(m) - 0.5 * dt * blk.A
            E.append(np.linalg.solve(lhs, np.eye(m) + 0.5 * dt * blk.A))
            Phi_P.append(np.linalg.solve(lhs, blk.B) @ blk.port)
            P_C.append(blk.port.T @ blk.C)
        self.dofs = np.concatenate([blk.dofs for blk in blocks]) if blocks else np.zeros(0, np.int64)
        if np.unique(self.dofs).size != self.dofs.size:
            raise InputError(f"state blocks must act on distinct DOFs, got {self.dofs.tolist()}")
        E, Phi_P, P_C = (block_diag(*X) if blocks else np.zeros((0, 0)) for X in (E, Phi_P, P_C))
        self.block = P_C @ Phi_P
        self.E, self.Phi_P = sp.csr_matrix(E), sp.csr_matrix(Phi_P)
        self.history_x = sp.csr_matrix(P_C @ E)
        for X in (self.E, self.Phi_P, self.history_x):
            X.eliminate_zeros()
        rows, cols = np.meshgrid(self.dofs, self.dofs, indexing="ij")
        self.stiffness = sp.csc_matrix((self.block.ravel(), (rows.ravel(), cols.ravel())), shape=(n, n))
        self.stiffness.eliminate_zeros()

    @property
    def n_states(self) -> int:
        """Number of states of all blocks."""
        return self.E.shape[0]
