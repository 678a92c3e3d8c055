"""Fits and sweeps computed once: an in-process memo and, for the book build, a cache folder.

The N = 5 fits of the paper's two tracks take seconds each, and several chapters of the book
(and the tests) use them. :func:`cached_fit` returns the :class:`~.fitting.FitResult` of
:func:`~.fitting.fit_equivalent` for the same arguments, computing it at most once per process
and, when ``cache_dir`` is given, at most once per cache folder. :func:`cached_central_response`
does the same for a frequency sweep of :func:`~semitrack.methods.receptance.central_response`:
the paper's wavenumber method takes ~13 s for the paper's 500 frequencies, and the derivation
and slab chapters both show the slab track's.

**Key.** The SHA-256 of

* the package's own source: every ``*.py`` file below the installed ``semitrack`` directory
  (relative path and bytes, :func:`package_source_digest`), so any change of the code
  invalidates every entry;
* the track's parameters (every field of the :class:`~semitrack.model.tracks.Track` but its
  ``name``, a label);
* every argument of :func:`~.fitting.fit_equivalent`, defaults filled in and ``band=None``
  resolved to the paper's band of the layout (a sweep: its frequencies, method and settings).

Arrays (``fit_freqs``, a sampled ``target``) enter by dtype, shape and bytes, an ``initial``
system by its layout and parameters. A callable ``target`` cannot be keyed (its code and state
are not part of any stable identity) and is refused; call :func:`~.fitting.fit_equivalent`.

**Files.** With ``cache_dir``, the result is stored as data, never as a pickle: JSON of its
numbers, strings and arrays (:mod:`semitrack.base.records`) in ``<cache_dir>/fit-<key>.json``
(a sweep: ``response-<key>.json``), written atomically (a temporary file in the folder, then
:func:`os.replace`), and read back by later processes. Reading builds only the package's own
result types (the fit, its system and errors, a sweep), each through its constructor and its
checks, so a file planted in the folder can at worst hold wrong numbers, never run code. A file
that cannot be read (truncated, corrupt, too large, written by an incompatible version, or a
pickle left by an older version) is ignored: the result is recomputed and the file rewritten.

**For the book build only.** The notebooks call ``st.cached_fit(track, layout, band=...,
seed=0, cache_dir="../_build/.semitrack-cache")``; ``_build`` is git-ignored and removed by CI
before each build, so the cache lives for one build and is never committed. Nothing in the
folder is executed, but its numbers are trusted: point ``cache_dir`` at a folder your own build
writes.

A cached result is the very object the first call returned: its ``elapsed`` is the time of that
fit (or sweep), and warnings of the fit (poor or unconverged) are issued only when it is computed.
"""

from __future__ import annotations

import dataclasses
import functools
import hashlib
import inspect
import json
import os
import time
from pathlib import Path
from typing import NamedTuple

import numpy as np

from ..base import records
from ..base.checks import as_frequencies, check_band
from ..base.errors import InputError, InputTypeError
from ..base.files import atomic_write, check_cache_folder, exclusive, read_text
from ..base.paper_values import FIT_BANDS
from ..methods.receptance import CentralResponse, Method, central_response
from ..model.curves import FrequencyCurve
from ..model.slab import Slab
from ..model.tracks import Track, require_track
from .assembly import Layout, check_layout
from .fitting import FitResult, fit_equivalent
from .metrics import ErrorSummary
from .systems import BallastedEquivalent, EquivalentSystem, SlabEquivalent

__all__ = ["cached_fit", "fit_cache_key", "package_source_digest", "clear_fit_memo", "CachedResponse",
           "cached_central_response", "response_cache_key", "canonical"]

# The package directory: semitrack/, two levels above this file.
_PACKAGE_DIR = Path(__file__).resolve().parent.parent

_MEMO: dict[str, object] = {}

# Bound once, so that the arguments are those of the real fit_equivalent even where a test
# replaces the module's fit_equivalent to count calls.
_FIT_SIGNATURE = inspect.signature(fit_equivalent)


def package_source_digest(root: str | os.PathLike | None = None) -> str:
    """SHA-256 (hex) of every ``*.py`` file below ``root``: relative path and content, sorted.

    Parameters
    ----------
    root : str or os.PathLike, optional
        The folder; default the installed ``semitrack`` package, whose digest is computed once
        per process (the code a process runs does not change under it).

    Returns
    -------
    str
        64 hexadecimal digits.
    """
    if root is None:
        return _own_source_digest()
    return _digest_of(Path(root))


@functools.cache
def _own_source_digest() -> str:
    return _digest_of(_PACKAGE_DIR)


def _digest_of(root: Path) -> str:
    h = hashlib.sha256()
    for rel in sorted(p.relative_to(root).as_posix() for p in root.rglob("*.py") if p.is_file()):
        data = (root / rel).read_bytes()
        for part in (rel.encode(), len(data).to_bytes(8, "little"), data):
            h.update(part)
    return h.hexdigest()


def canonical(value):
    """A JSON-able, type-tagged description of an argument (TypeError for what cannot be keyed)."""
    if value is None or isinstance(value, (bool, np.bool_, str)):
        return value if not isinstance(value, np.bool_) else bool(value)
    if isinstance(value, (int, np.integer)):
        return ["int", int(value)]
    if isinstance(value, (float, np.floating)):
        return ["float", float(value).hex()]
    if isinstance(value, np.ndarray):
        a = np.ascontiguousarray(value)
        return ["ndarray", a.dtype.str, list(a.shape), hashlib.sha256(a.tobytes()).hexdigest()]
    if isinstance(value, (tuple, list)):
        return [type(value).__name__] + [canonical(v) for v in value]
    if isinstance(value, dict):
        out = ["dict"]
        for k in sorted(value, key=str):
            try:
                out.append([str(k), canonical(value[k])])
            except InputTypeError as err:  # say which argument: the caller's name for it
                raise InputTypeError(f"{k}: {err}") from None
        return out
    if isinstance(value, EquivalentSystem):
        return ["system", value.layout, canonical(value.parameters())]
    if isinstance(value, Track):
        return ["track"] + [[f.name, canonical(getattr(value, f.name))]
                            for f in dataclasses.fields(value) if f.name != "name"]
    if isinstance(value, Slab):
        return ["slab"] + [[f.name, canonical(getattr(value, f.name))] for f in dataclasses.fields(value)]
    if isinstance(value, FrequencyCurve):  # a frequency-dependent pad or foundation: its data or parameters
        return ["curve", type(value).__name__] + value.key()
    if callable(value):
        raise InputTypeError("cached_fit cannot key a callable target (its code and state have no stable identity); "
                        "pass sampled (f, alpha) or call fit_equivalent")
    raise InputTypeError(f"a cache cannot key an argument of type {type(value).__name__}: {value!r}")


def named_canonical(arguments: dict) -> list:
    """``[[name, canonical(value)], ...]`` of a call's arguments, a refusal naming the argument it could not key."""
    return canonical(dict(arguments))[1:]


def _bound_arguments(track, layout, n_bars, band, seed, options) -> dict:
    """Every argument of fit_equivalent, defaults filled in and the band resolved."""
    layout = check_layout(layout)
    band = check_band(FIT_BANDS[layout] if band is None else band)
    bound = _FIT_SIGNATURE.bind(track, layout, n_bars=n_bars, band=band, seed=seed, **options)
    bound.apply_defaults()
    return dict(bound.arguments)


def fit_cache_key(track: Track, layout: Layout, n_bars: int = 5, band: tuple[float, float] | None = None,
                  seed: int = 0, **options) -> str:
    """The key of :func:`cached_fit`: SHA-256 (hex) of the package source, the track and the arguments.

    Parameters
    ----------
    track : Track
        The track.
    layout : {"slab", "ballasted"}
        The layout.
    n_bars : int
        Number of bars.
    band : (float, float), optional
        Band (Hz); None is the paper's band of the layout and gives the same key as that band.
    seed : int
        Seed of the multi-start.
    **options
        Any other argument of :func:`~.fitting.fit_equivalent`; omitted ones enter with their
        defaults.

    Returns
    -------
    str
        64 hexadecimal digits.

    Raises
    ------
    TypeError
        For an unknown option or an argument that cannot be keyed (a callable target).
    """
    track = require_track(track)
    arguments = _bound_arguments(track, layout, n_bars, band, seed, options)
    description = {"source": package_source_digest(),
                   "arguments": named_canonical(arguments)}
    return hashlib.sha256(json.dumps(description, sort_keys=True).encode()).hexdigest()


#: Largest cache file read back (bytes): a fit or a sweep of the paper's grid is well under 1 MB.
MAX_CACHE_BYTES = 50_000_000


def _record_types() -> dict[str, type]:
    """The only types a cache file may build: the results and what they hold."""
    kinds = (FitResult, ErrorSummary, SlabEquivalent, BallastedEquivalent, CachedResponse, CentralResponse)
    return {kind.__name__: kind for kind in kinds}


def _load(path: Path, kind: type = FitResult, types: dict[str, type] | None = None):
    """The result (of type ``kind``, built from ``types`` only) stored at ``path``, or None when it is absent
    or cannot be read."""
    try:
        result = records.loads(read_text(path, MAX_CACHE_BYTES, "cache file"), types or _record_types())
    except (OSError, InputError):  # absent, too large, not JSON, a foreign type: recompute and rewrite
        return None
    return result if isinstance(result, kind) else None


def computed_once(key: str, path: Path | None, kind: type, compute, types: dict[str, type] | None = None):
    """The memoised result of ``key``, else the one stored at ``path``, else ``compute()`` (stored).

    Parameters
    ----------
    key : str
        The result's key (a digest that includes the package's source).
    path : Path or None
        Its file in a cache folder already checked (None: the in-process memo only).
    kind : type
        The result's type: a file that holds another is recomputed.
    compute : callable
        Computes the result when neither the memo nor the file has it.
    types : dict of str to type, optional
        The only record types the file may build (default: the fits' and sweeps').

    Returns
    -------
    object
    """
    held = _MEMO.get(key)  # one read: another thread may clear the memo between a test and a read
    if held is not None:
        return held
    if path is None:
        result = compute()
    else:
        with exclusive(path):  # a process computing the same key meanwhile: wait for its file
            result = None if path.is_symlink() else _load(path, kind, types)  # a planted link is not read
            if result is None:
                result = compute()
                text = records.dumps(result)
                atomic_write(path, lambda fh: fh.write(text), follow_links=False)
    _MEMO[key] = result
    return result


def cached_fit(track: Track, layout: Layout, n_bars: int = 5, band: tuple[float, float] | None = None,
               seed: int = 0, cache_dir: str | os.PathLike | None = None, **options) -> FitResult:
    """:func:`~.fitting.fit_equivalent`, computed once per process and, with ``cache_dir``, once per folder.

    See the module docstring for the key and the files. Meant for the book build and the
    tests, which use the paper's fits many times; the cache folder is never committed.

    Parameters
    ----------
    track : Track
        The track.
    layout : {"slab", "ballasted"}
        Layout of the equivalent system.
    n_bars : int
        Number of bars N (the paper's 5 by default).
    band : (float, float), optional
        Frequency band (Hz); default the paper's band of the layout
        (:data:`~semitrack.base.paper_values.FIT_BANDS`).
    seed : int
        Seed of the multi-start.
    cache_dir : str or os.PathLike, optional
        Folder of the stored results (created if missing), e.g.
        ``"../_build/.semitrack-cache"`` from the book's notebooks. None: the in-process memo
        only.
    **options
        Any other argument of :func:`~.fitting.fit_equivalent` (``n_starts``, ``constrained``,
        ``fit_freqs``, ...), except a callable ``target``.

    Returns
    -------
    FitResult
        Equal to what :func:`~.fitting.fit_equivalent` returns for these arguments.

    Raises
    ------
    TypeError, ValueError
        As :func:`~.fitting.fit_equivalent` does, and TypeError for a callable ``target``.

    Examples
    --------
    >>> import semitrack as st
    >>> a = st.cached_fit(st.slab_track(), "slab", n_bars=2, band=(3, 300), n_starts=1)
    >>> st.cached_fit(st.slab_track(), "slab", n_bars=2, band=(3.0, 300.0), n_starts=1) is a
    True
    """
    key = fit_cache_key(track, layout, n_bars, band, seed, **options)
    path = None if cache_dir is None else check_cache_folder(cache_dir, "cache_dir") / f"fit-{key}.json"
    return computed_once(key, path, FitResult,
                         lambda: fit_equivalent(**_bound_arguments(track, layout, n_bars, band, seed, options)))


class CachedResponse(NamedTuple):
    """A sweep of :func:`~semitrack.methods.receptance.central_response` and the time it took.

    Attributes
    ----------
    response : CentralResponse
        The central responses (and through them alpha) at the frequencies of the sweep.
    elapsed : float
        Wall-clock time of the computation (s), when it was computed (a cached sweep keeps the
        time of its first computation).
    """

    response: CentralResponse
    elapsed: float


def response_cache_key(track: Track, f, method: Method = "wavenumber", **settings) -> str:
    """The key of :func:`cached_central_response`: SHA-256 (hex) of the package source, the
    track, the frequencies, the method and its settings.

    Parameters
    ----------
    track : Track
        The track.
    f : array_like
        Frequencies (Hz).
    method : {"transfer", "wavenumber"}
        The method.
    **settings
        Settings of the wavenumber method (``beta_max``, ``dx``, ...), as for
        :func:`~semitrack.methods.receptance.central_response`.

    Returns
    -------
    str
        64 hexadecimal digits.
    """
    track = require_track(track)
    arguments = {"track": track, "f": np.atleast_1d(as_frequencies(f)), "method": method, "settings": settings}
    description = {"source": package_source_digest(), "kind": "central_response",
                   "arguments": named_canonical(arguments)}
    return hashlib.sha256(json.dumps(description, sort_keys=True).encode()).hexdigest()


def cached_central_response(track: Track, f, method: Method = "wavenumber",
                            cache_dir: str | os.PathLike | None = None, **settings) -> CachedResponse:
    """:func:`~semitrack.methods.receptance.central_response`, computed once per process and, with
    ``cache_dir``, once per folder (see the module docstring).

    Meant for the book build, where the paper's wavenumber method over the paper's grid (~13 s)
    appears in more than one chapter.

    Parameters
    ----------
    track : Track
        The track.
    f : array_like
        Frequencies (Hz).
    method : {"transfer", "wavenumber"}
        The method; the paper's wavenumber method by default.
    cache_dir : str or os.PathLike, optional
        Folder of the stored results (created if missing); None: the in-process memo only.
    **settings
        Settings of the wavenumber method, as for
        :func:`~semitrack.methods.receptance.central_response`.

    Returns
    -------
    CachedResponse
        The response and the time its computation took (s).

    Examples
    --------
    >>> import semitrack as st
    >>> from semitrack.equivalent.cache import cached_central_response
    >>> sweep = cached_central_response(st.slab_track(), [100.0, 200.0], "transfer")
    >>> sweep.response.alpha.shape, cached_central_response(st.slab_track(), [100.0, 200.0], "transfer") is sweep
    ((2, 2, 2), True)
    """
    key = response_cache_key(track, f, method, **settings)
    path = None if cache_dir is None else check_cache_folder(cache_dir, "cache_dir") / f"response-{key}.json"

    def compute() -> CachedResponse:
        start = time.perf_counter()
        response = central_response(track, f, method, **settings)
        return CachedResponse(response, time.perf_counter() - start)

    return computed_once(key, path, CachedResponse, compute)


def clear_fit_memo() -> None:
    """Forget the results (fits, sweeps and :func:`~semitrack.cached_boundary`'s ends) memoised in this
    process (the files of a cache folder stay)."""
    _MEMO.clear()
