"""The checks of a broadband end's M, C, K form against its state space, shared by the tests.

Independent of the package's own condensation: the port receptance of the matrices is a dense
Schur complement solved here, the state space's ``K0 + s (D + C (sI - A)^-1 B)`` is solved here too.
The tolerances are issue 23's targets (measured values in ``benchmarks/bench_synthesis.py``):
1e-5 relative from 1 mHz to 1 MHz (measured 1e-12 to 1e-9), K(0) and the dashpot 1e-10,
eigenvalues of M, C, K >= -1e-10 of the largest, one internal DOF per state at most, <= 1 s.
"""

from __future__ import annotations

import time

import numpy as np

F_WIDE = np.geomspace(1e-3, 1e6, 400)


def _state_space_stiffness(ss, f):
    """``K0 + s (D + C (sI - A)^-1 B)`` from the state space, solved here."""
    s = 2j * np.pi * np.asarray(f)
    n = ss.A.shape[0]
    X = np.linalg.solve(s[:, None, None] * np.eye(n) - ss.A, np.broadcast_to(ss.B, (s.size,) + ss.B.shape))
    return ss.K0 + s[:, None, None] * (ss.D + ss.C @ X)


def _condensed(M, C, K, f):
    """The 2x2 port dynamic stiffness of M, C, K (dense Schur complement, solved here)."""
    w = 2 * np.pi * np.asarray(f)[:, None, None]
    Z = K + 1j * w * C - w ** 2 * M
    return Z[:, :2, :2] - Z[:, :2, 2:] @ np.linalg.solve(Z[:, 2:, 2:], Z[:, 2:, :2])


def check_second_order(bnd, name):
    """Every target of the M, C, K form of ``bnd`` (named ``name`` in the messages)."""
    # CPU time of this process: the conversion runs on one BLAS thread, so on an idle machine it is
    # the wall time, and other jobs on a busy one do not count
    start = time.process_time()
    system = bnd.matrix_system()
    elapsed = time.process_time() - start
    M, C, K = system.matrices()
    ss = bnd.state_space()
    alpha_ref = np.linalg.inv(_state_space_stiffness(ss, F_WIDE))
    alpha = np.linalg.inv(_condensed(M, C, K, F_WIDE))
    assert np.max(np.abs(alpha - alpha_ref) / np.abs(alpha_ref)) < 1e-5, name
    for X in (M, C, K):
        assert np.allclose(X, X.T, rtol=0, atol=0), name
        lam = np.linalg.eigvalsh(X)
        assert lam[0] >= -1e-10 * np.max(np.abs(lam)), name
    assert np.allclose(C[:2, :2], ss.D, rtol=1e-10, atol=0), name  # the high-frequency dashpot
    high = _condensed(M, C, K, [1e9])[0] / (2j * np.pi * 1e9)
    assert np.allclose(high, _state_space_stiffness(ss, [1e9])[0] / (2j * np.pi * 1e9), rtol=1e-9), name
    # the condensation at 1e-9 Hz solves with a K that is singular on the Maxwell DOFs (cond ~1e30):
    # round-off, not the model, sets what is left (2e-10 of K0 measured on one machine's OpenBLAS)
    low = _condensed(M, C, K, [1e-9])[0]
    assert np.max(np.abs(low - ss.K0)) < 1e-9 * np.max(np.abs(ss.K0)), name
    assert np.max(np.abs(system.static_stiffness() - ss.K0)) < 1e-8 * np.max(np.abs(ss.K0)), name
    assert system.n_internal <= ss.n_states, name
    assert elapsed < 1.0, (name, elapsed)
