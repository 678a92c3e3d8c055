"""Broadband ends fitted once: :func:`cached_boundary`, as :func:`~semitrack.cached_fit` is for the
equivalent systems.

Several chapters of the book put the same broadband ends on their truncated models (the default
fit of the viscous slab and ballasted tracks: 0.6 and 1.5 s of one core each, measured), and each
chapter runs in a process of its own. :func:`cached_boundary` returns what
:func:`~.fitting.fit_boundary` returns for the same arguments, computed at most once per process
and, with ``cache_dir``, at most once per folder: the same key (the package's own source, the
track's parameters, every argument with its default filled in), the same record file of numbers
that cannot run code (:mod:`semitrack.base.records`), written atomically without following links
and read back bounded, through the constructors and their checks, as
:mod:`semitrack.equivalent.cache` describes. A file that cannot be read is ignored and the fit
computed again. The book's notebooks keep the folder under ``_build``, which CI removes before
each build: the cache lives for one build.

A cached boundary is the very object the first call returned within a process, and equal field by
field (bit for bit) when read back from its file; its ``elapsed`` is the time of that fit, and the
fit's warnings (a hysteretic track, an unconverged order) are issued only when it is computed.
"""

from __future__ import annotations

import hashlib
import inspect
import json
import os

from ..base.checks import check_band
from ..base.files import check_cache_folder
from ..equivalent.cache import computed_once, named_canonical, package_source_digest
from ..equivalent.metrics import ErrorSummary
from ..model.tracks import Track, require_track
from .fitting import DEFAULT_BOUNDARY_BAND, BroadbandBoundary, OrderTrial, fit_boundary
from .passivity import BoundaryPassivityReport
from .rational import RationalEndStiffness

__all__ = ["boundary_cache_key", "cached_boundary"]

# Bound once, so that the arguments are those of the real fit_boundary even where a test replaces the
# module's fit_boundary to count calls.
_FIT_SIGNATURE = inspect.signature(fit_boundary)
#: The only types a boundary's cache file may build.
_RECORD_TYPES = {kind.__name__: kind for kind in (BroadbandBoundary, RationalEndStiffness, ErrorSummary,
                                                   BoundaryPassivityReport, OrderTrial)}


def _bound_arguments(track: Track, band, options: dict) -> dict:
    """Every argument of fit_boundary, defaults filled in (an unknown option: the TypeError of the call)."""
    bound = _FIT_SIGNATURE.bind(require_track(track), check_band(band), **options)  # (3, 3000) keyed as (3.0, 3000.0)
    bound.apply_defaults()
    return dict(bound.arguments)


def boundary_cache_key(track: Track, band: tuple[float, float] = DEFAULT_BOUNDARY_BAND, **options) -> str:
    """The key of :func:`cached_boundary`: SHA-256 (hex) of the package source, the track and the arguments.

    Parameters
    ----------
    track : Track
        The track.
    band : (float, float)
        The fit band (Hz).
    **options
        Any other argument of :func:`~.fitting.fit_boundary`; omitted ones enter with their defaults.

    Returns
    -------
    str
        64 hexadecimal digits.
    """
    return _key_of(_bound_arguments(track, band, options))


def _key_of(arguments: dict) -> str:
    """SHA-256 (hex) of the package source and fit_boundary's bound ``arguments``."""
    description = {"source": package_source_digest(), "kind": "fit_boundary",
                   "arguments": named_canonical(arguments)}
    return hashlib.sha256(json.dumps(description, sort_keys=True).encode()).hexdigest()


def cached_boundary(track: Track, band: tuple[float, float] = DEFAULT_BOUNDARY_BAND,
                    cache_dir: str | os.PathLike | None = None, **options) -> BroadbandBoundary:
    """:func:`~.fitting.fit_boundary`, computed once per process and, with ``cache_dir``, once per folder.

    See the module docstring. Meant for the book build and the tests, which put the same ends on
    many models; the folder is never committed.

    Parameters
    ----------
    track : Track
        The track.
    band : (float, float)
        The fit band (Hz), as :func:`~.fitting.fit_boundary` takes it.
    cache_dir : str or os.PathLike, optional
        Folder of the stored fits (created if missing), checked before the fit; None: the
        in-process memo only.
    **options
        Any other argument of :func:`~.fitting.fit_boundary` (``n_poles``, ``seed``, ``tol``,
        ``df``, ``n_starts``, ``n_iter``).

    Returns
    -------
    BroadbandBoundary
        Equal to what :func:`~.fitting.fit_boundary` returns for these arguments.

    Examples
    --------
    >>> import semitrack as st
    >>> track = st.slab_track(damping="viscous")
    >>> end = st.cached_boundary(track, band=(3.0, 300.0), n_poles=4, df=30.0, n_iter=3)
    >>> st.cached_boundary(track, (3.0, 300.0), n_poles=4, df=30.0, n_iter=3) is end
    True
    """
    arguments = _bound_arguments(track, band, options)
    key = _key_of(arguments)  # an unkeyable argument refused before any work
    folder = None if cache_dir is None else check_cache_folder(cache_dir, "cache_dir")
    path = None if folder is None else folder / f"boundary-{key}.json"
    return computed_once(key, path, BroadbandBoundary, lambda: fit_boundary(**arguments), _RECORD_TYPES)
