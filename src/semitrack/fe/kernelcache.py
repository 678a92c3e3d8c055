"""The moving Green's functions kept on disk: NumPy's ``.npz`` of arrays and a JSON key, never a pickle.

A study of many roughnesses, preloads or vehicles at one track, speed and time step pays the
kernels' set-up once: :func:`cached_kernels` keeps them in memory for the process and, given a
folder, in one file per key, ``kernels-<sha256>.npz``. The key holds everything the kernels depend
on: the track's parameters (every field, its name aside), the mesh, the damping's reference
frequencies, the time step, the grid (steps per spacing, the wheels' offsets), the memory, and the
digest of the package's source (code that changed recomputes). The file holds only numeric arrays
and the key as text, never a pickle; its size, and every member's header against what the member
stores, are checked before any array is read (:func:`~semitrack.base.files.read_npz`). A file that
cannot be read, is a link, holds another key or arrays of the wrong shapes is computed again and
written over (atomically, replacing a link rather than writing through it).
"""

from __future__ import annotations

import hashlib
import json
import os
from pathlib import Path

import numpy as np

from ..base.files import atomic_write, check_cache_folder, exclusive, read_npz
from ..model.tracks import Track
from .kernels import KernelGrid, MovingKernels, kernel_key, moving_kernels, release_starts

__all__ = ["MAX_KERNEL_BYTES", "cached_kernels", "clear_kernel_memo"]

#: Largest kernel file read back (bytes): a bogie's kernels on the ballasted track at 20 us hold ~180 MB.
MAX_KERNEL_BYTES = 2_000_000_000

#: The members of a kernel file.
_MEMBERS = ("key", "lags", "loop", "starts", "release", "flexibility", "scalars")

_MEMO: dict[str, MovingKernels] = {}


def _digest(key: dict) -> str:
    return hashlib.sha256(json.dumps(key, sort_keys=True).encode()).hexdigest()


def _write(path: Path, kernels: MovingKernels) -> None:
    starts = sorted(kernels.release)
    arrays = {"key": np.array(json.dumps(kernels.key, sort_keys=True)),
              "lags": np.array(kernels.grid.lags, dtype=np.int64),
              "loop": kernels.loop,  # in the loop's order: read back, run as they are
              "starts": np.array(starts, dtype=np.int64).reshape(-1, 2),
              "release": np.stack([kernels.release[start] for start in starts]),
              "flexibility": kernels.flexibility,
              "scalars": np.array([kernels.tail, kernels.elapsed, kernels.elements_per_bay])}
    atomic_write(path, lambda fh: np.savez(fh, **arrays), binary=True, follow_links=False)


def _read(path: Path, key: dict, grid: KernelGrid, starts: list) -> MovingKernels | None:
    """The kernels stored at ``path`` for ``key``, or None: absent, too large (stored or inflated), unreadable,
    another key, or arrays that are not finite float64 of the grid's shapes and starts."""
    L, P = key["memory"], grid.positions
    try:  # sizes, links and every member's header checked before any array is read (read_npz)
        arrays = read_npz(path, MAX_KERNEL_BYTES, _MEMBERS, "kernel file")
        if json.loads(str(arrays.pop("key")[()])) != json.loads(json.dumps(key, sort_keys=True)):
            return None
        lags, stored = arrays["lags"].tolist(), [tuple(s) for s in arrays["starts"].tolist()]
        floats = [arrays[name] for name in ("loop", "release", "flexibility", "scalars")]
        if (lags != list(grid.lags) or stored != starts or arrays["loop"].shape != (len(lags), P, L)
                or arrays["release"].shape != (len(starts), L) or arrays["flexibility"].shape != (P,)
                or arrays["scalars"].shape != (3,) or not all(a.dtype == np.float64 and np.isfinite(a).all()
                                                               for a in floats)):
            return None
    except (OSError, ValueError, KeyError, TypeError, RecursionError):  # absent, a link, damaged, forged, ...
        return None
    tail, elapsed, ne = arrays["scalars"].tolist()
    if ne != int(ne) or ne < 2 or (key["mesh"][0] == "elements" and ne != key["mesh"][1]):
        return None
    return MovingKernels(grid, arrays["loop"],
                         {(int(a), int(b)): arrays["release"][i] for i, (a, b) in enumerate(starts)},
                         arrays["flexibility"], float(tail), key, float(elapsed), int(ne), key["start"])


def cached_kernels(track: Track, elements_per_bay: int | None, f_max: float | None, grid: KernelGrid, memory: int,
                   f_ref=None, cache: str | os.PathLike | None = None, start: int = 0) -> MovingKernels:
    """The kernels of ``grid``: from this process's memory, else the cache folder, else computed (and stored).

    Parameters
    ----------
    track : Track
        A periodic track.
    elements_per_bay : int or None
        The mesh (None: :class:`semitrack.TruncatedTrack`'s default for ``f_max``).
    f_max : float or None
        The highest frequency of interest of the default mesh (Hz).
    grid : KernelGrid
        From :func:`semitrack.fe.kernels.grid_of`.
    memory : int
        L, steps.
    f_ref : None, float or dict
        Reference frequencies of the viscous damping.
    cache : str or os.PathLike, optional
        The folder of kernel files, checked before any work (:func:`~semitrack.base.files.check_cache_folder`);
        a symbolic link planted in it under a kernel file's name is replaced, never followed.
    start : int
        The first wheel's phase at the start.

    Returns
    -------
    MovingKernels
    """
    folder = None if cache is None else check_cache_folder(cache, "cache")  # before the work, not after
    key = kernel_key(track, elements_per_bay, grid, memory, f_ref, start, f_max)
    digest = _digest(key)
    held = _MEMO.get(digest)  # one read: another thread may clear the memo between a test and a read
    if held is not None:
        return held
    if folder is None:
        kernels = moving_kernels(track, elements_per_bay, grid, memory, f_ref, f_max, start)
    else:
        path = folder / f"kernels-{digest}.npz"
        with exclusive(path):  # a process computing the same kernels meanwhile: wait for its file
            kernels = _read(path, key, grid, release_starts(grid, start))
            if kernels is None:
                kernels = moving_kernels(track, elements_per_bay, grid, memory, f_ref, f_max, start)
                _write(path, kernels)
    _MEMO[digest] = kernels
    return kernels


def clear_kernel_memo(kernels: MovingKernels | None = None) -> None:
    """Forget the kernels kept in this process's memory: all of them, or ``kernels`` alone.

    Parameters
    ----------
    kernels : MovingKernels, optional
        The kernels to forget (by their key); None forgets all (a test, or memory to spare).
    """
    if kernels is None:
        _MEMO.clear()
    else:
        _MEMO.pop(_digest(kernels.key), None)
