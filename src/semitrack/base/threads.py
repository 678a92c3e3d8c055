"""One BLAS thread inside the package's hot loops, whatever the environment says.

The package's work is many small solves: batched 2x2/4x4 algebra, sparse LU factorisations per
frequency, least-squares steps on a few dozen unknowns, the wavenumber method's products of a
few MB per frequency, the time steps. Threaded BLAS does not speed these up
and, on a machine that is busy (a 2-core laptop building the book while a browser runs, CI), its
spinning threads contend with the work: measured up to 3-15x slower. So the loops that call BLAS
many times run under :func:`serial_blas` (the fits, the FE sweeps, the time steps, the
wavenumber method), and the user's setting is restored afterwards; no
``OPENBLAS_NUM_THREADS`` is needed.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from functools import cache

from threadpoolctl import ThreadpoolController


@cache
def _controller() -> ThreadpoolController:
    # Inspecting the loaded libraries costs ~1 ms; done once, a limit then costs ~20 us.
    return ThreadpoolController()


@contextmanager
def serial_blas() -> Iterator[None]:
    """Context in which BLAS libraries (OpenBLAS, MKL, BLIS) run on one thread.

    Examples
    --------
    >>> import numpy as np
    >>> with serial_blas():
    ...     x = np.linalg.solve(np.eye(3), np.ones(3))
    >>> x.tolist()
    [1.0, 1.0, 1.0]
    """
    with _controller().limit(limits=1, user_api="blas"):
        yield
