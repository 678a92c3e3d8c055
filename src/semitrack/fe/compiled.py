"""The moving kernels' set-up compiled with numba where NumPy's passes are memory-bound (:mod:`.pointfield`).

Compiled on first use (about a second) and cached on disk beside this file (numba's
``cache=True``), so later processes read it. Importing this module imports numba.
"""

from __future__ import annotations

import numba

__all__ = ["point_field_into"]


@numba.njit(cache=True, nogil=True)
def point_field_into(Z, sidx, weights, phase, out):
    """``out[i, f, p] = phase[f, p] * sum_c weights[p, c] * Z[f, i, sidx[p, c]]`` (:mod:`.pointfield`).

    One pass over ``out`` in its order, each row ``Z[f, i]`` read while it is in cache; ``nogil``: the
    set-up's parts run on threads.
    """
    n_f, n = Z.shape[0], Z.shape[1]
    P, n_c = sidx.shape
    for f in range(n_f):
        for i in range(n):
            row = Z[f, i]
            for p in range(P):
                s = 0j
                for c in range(n_c):
                    s += weights[p, c] * row[sidx[p, c]]
                out[i, f, p] = phase[f, p] * s
