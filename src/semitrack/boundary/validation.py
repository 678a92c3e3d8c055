"""The checks of a boundary read from a file or attached to a model: structure, values, physics, track.

A boundary file is data from anywhere: hand-edited, written by another program, damaged, or
hostile. Before a model is built from it, :func:`read_boundary_file` bounds what is read (the
file's size before parsing, a ``.mat`` file's inflated size, the JSON nesting) and
:func:`check_boundary_data` checks every field the loader uses, by type, shape and value,
bounding the number of poles (:data:`~.fitting.MAX_POLES`, the largest order a fit produces)
before any matrix of that size is formed. Once the model is built, :func:`check_boundary_physics`
refuses what would give a wrong answer without a word: a pole with ``Re >= 0`` (an unstable end,
whose pulse response grows to 1e281 m), a static stiffness ``K0`` that is not positive definite,
and a model that fails the exact (Hamiltonian) passivity test of :mod:`.passivity` (an end that
creates energy). Each refusal names the file and the check that failed.

:func:`check_boundary_track` compares a boundary with the track of the model it closes: a fit
pins ``K0`` and the dashpot ``D`` to its own track's (:func:`~.fitting.track_end_limits`), so
these two identify the track; a boundary fitted to another track (a ballasted boundary on the
slab track: 38 % error at 1 kHz) is refused with both tracks' numbers.
"""

from __future__ import annotations

import json
import math
import warnings
from pathlib import Path

import numpy as np

from ..base.errors import InputError
from ..base.files import check_input_path, read_json, read_mat
from ..equivalent.exchange import check_conventions, check_track_damping
from ..model.tracks import Track
from .fitting import MAX_POLES, track_end_limits
from .passivity import BoundaryPassivityReport
from .rational import RationalEndStiffness

__all__ = ["read_boundary_file", "check_boundary_data", "check_boundary_physics", "check_boundary_track",
           "MAX_BOUNDARY_BYTES", "TRACK_RTOL"]

#: Largest boundary file read (bytes): a file of :data:`~.fitting.MAX_POLES` poles, state space
#: included, is ~2 MB of JSON.
MAX_BOUNDARY_BYTES = 20_000_000
#: Most passivity-enforcement rounds a file may state (a fit stops far below).
MAX_ENFORCEMENT_ROUNDS = 10_000
#: Relative difference of ``K0`` or ``D`` (largest entry) beyond which a boundary belongs to another track.
TRACK_RTOL = 0.01
#: Relative difference below which the limits are the same track's (rounding, a file's 17 digits).
_SAME_RTOL = 1e-6
#: The variables of a boundary ``.mat`` file the loader reads.
_MAT_KEYS = ("format", "poles", "coefficients", "K0", "D", "band_hz")


def _mat_value(m: dict, key: str, source: str) -> np.ndarray:
    if key not in m:
        raise InputError(f"{source}: missing variable {key!r}")
    value = np.asarray(m[key])
    if value.size == 0 and key in _MAT_KEYS:
        raise InputError(f"{source}: the variable {key!r} is empty")
    return value


def _mat_text(m: dict, key: str, source: str, default: str = "") -> str:
    if key not in m and default is not None:
        return default
    value = _mat_value(m, key, source).ravel()
    if value.size == 0:
        return ""
    if value.dtype.kind != "U":
        raise InputError(f"{source}: the variable {key!r} must be text, got {value.dtype}")
    return str(value[0])


def _mat_to_data(m: dict, source: str) -> dict:
    """The fields of a boundary ``.mat`` file in the layout of its JSON twin (checked afterwards)."""
    poles = _mat_value(m, "poles", source).ravel()
    if poles.dtype.kind not in "iufc":
        raise InputError(f"{source}: the variable 'poles' must be numbers, got {poles.dtype}")
    if poles.size > MAX_POLES:
        raise InputError(f"{source}: 'poles' holds {poles.size} poles, more than the {MAX_POLES} a fit gives")
    data = {"format": _mat_text(m, "format", source, default=None), "poles": np.c_[poles.real, poles.imag],
            **{key: _mat_value(m, key, source) for key in ("coefficients", "K0", "D")},
            "band_hz": _mat_value(m, "band_hz", source).ravel(), "track": _mat_text(m, "track", source)}
    for key in ("median_error", "max_error", "enforcement_rounds"):
        if key in m:
            value = _mat_value(m, key, source).ravel()
            if value.size != 1:
                raise InputError(f"{source}: the variable {key!r} must be one number, got {value.size} values")
            data[key] = value[0].item() if value.dtype.kind in "biuf" else str(value[0])
    if any(k in m for k in "ABC"):
        data["state_space"] = {k: _mat_value(m, k, source) for k in ("A", "B", "C", "D", "K0")}
    if "conventions_json" in m:
        text = _mat_text(m, "conventions_json", source)
        try:
            data["conventions"] = json.loads(text)
        except (ValueError, RecursionError):
            raise InputError(f"{source}: the variable 'conventions_json' is not JSON text") from None
    return data


def read_boundary_file(path: str | Path) -> dict:
    """The fields of a boundary file (``.json`` or ``.mat``), read within bounds.

    Parameters
    ----------
    path : str or Path
        The file; its suffix selects the format.

    Returns
    -------
    dict
        The plain data, as :func:`~.io.boundary_to_dict` lays it out (``.mat`` variables mapped to
        it); not yet checked (:func:`check_boundary_data`).

    Raises
    ------
    InputError
        For another suffix, a file larger than :data:`MAX_BOUNDARY_BYTES` (``/dev/zero`` behind a
        ``.json`` name), JSON that is not an object or nests too deeply, a ``.mat`` file that is
        JSON, empty, truncated, HDF5 (v7.3), random bytes, inflates to more than that
        size, lacks a variable or holds an empty one; one line naming the file (and the key).
    OSError
        If the file cannot be read.
    """
    source = str(check_input_path(path, "path"))
    suffix = Path(path).suffix.lower()
    if suffix == ".json":
        data = read_json(path, MAX_BOUNDARY_BYTES, "boundary file")
        if not isinstance(data, dict):
            raise InputError(f"{source}: not a boundary file: it must hold a JSON object, got {type(data).__name__}")
        return data
    if suffix == ".mat":
        return _mat_to_data(read_mat(path, MAX_BOUNDARY_BYTES, "boundary file"), source)
    raise InputError(f"path must end in .json or .mat, got {source!r}")


def _real(data: dict, key: str, source: str, default=None) -> float:
    """A finite real number of the file (a default when absent, if one is given)."""
    if key not in data and default is not None:
        return default
    value = data.get(key)
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise InputError(f"{source}: {key!r} must be a number, got {str(value)[:40]!r}")
    try:
        out = float(value)
    except OverflowError:
        out = math.inf
    if not math.isfinite(out) or out < 0:
        raise InputError(f"{source}: {key!r} must be a non-negative finite number, got {value!r:.40}")
    return out


def _rounds(data: dict, source: str) -> int:
    value = data.get("enforcement_rounds", 0)
    if isinstance(value, (float, np.floating)) and math.isfinite(value) and value == int(value):
        value = int(value)  # a .mat file stores integers as doubles
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or not 0 <= value <= MAX_ENFORCEMENT_ROUNDS:
        raise InputError(f"{source}: 'enforcement_rounds' must be an integer from 0 to {MAX_ENFORCEMENT_ROUNDS}, "
                         f"got {value!r:.40}")
    return int(value)


def _matrix(data: dict, key: str, source: str, shape: tuple | None = None) -> np.ndarray:
    """A finite real array of the file, of ``shape`` (None: any) (``-1`` in it: any length)."""
    if key not in data:
        raise InputError(f"{source}: missing key {key!r}")
    try:
        out = np.asarray(data[key], dtype=float)
    except (TypeError, ValueError, OverflowError):
        raise InputError(f"{source}: {key!r} must be an array of numbers") from None
    if shape is not None and (out.ndim != len(shape) or any(n not in (-1, m) for n, m in zip(shape, out.shape))):
        want = "x".join("n" if n == -1 else str(n) for n in shape)
        raise InputError(f"{source}: {key!r} must have shape {want}, got {out.shape}")
    if not np.all(np.isfinite(out)):
        raise InputError(f"{source}: {key!r} must be finite")
    return out


def _band(data: dict, source: str) -> tuple[float, float]:
    band = _matrix(data, "band_hz", source, (-1,))
    if band.size != 2 or not (0 < band[0] < band[1]):
        raise InputError(f"{source}: 'band_hz' must be two frequencies 0 < f_lo < f_hi (Hz), got {band.tolist()}")
    return float(band[0]), float(band[1])


def _checked_version(data: dict, source: str, fmt: str, version: int) -> None:
    if data.get("format") != fmt:
        raise InputError(f"{source}: not a {fmt} file (its 'format' must be {fmt!r})")
    value = data.get("version", 1)  # the files written before the field existed are version 1
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or not 1 <= value <= version:
        raise InputError(f"{source}: 'version' must be an integer from 1 to {version} (this package reads those), "
                         f"got {value!r:.40}")


def check_boundary_data(data: dict, source: str, fmt: str, version: int) -> dict:
    """Every field of a boundary's plain data checked: structure, types, shapes, sizes and values.

    Parameters
    ----------
    data : dict
        The plain data (:func:`read_boundary_file` or :func:`~.io.boundary_to_dict`).
    source : str
        Where it came from, quoted in messages.
    fmt : str
        The ``format`` the data must name.
    version : int
        The newest format version this package reads (versions 1 to it are read).

    Returns
    -------
    dict
        ``poles`` (complex array), ``coefficients``, ``K0``, ``D``, ``band`` (tuple),
        ``median_error``, ``max_error`` (floats, NaN when absent), ``enforcement_rounds`` (int),
        ``track`` (str) and ``state_space`` (dict of arrays, or None).

    Raises
    ------
    InputError
        Naming the source and the key: another format, an unknown version, a missing key, more
        than :data:`~.fitting.MAX_POLES` poles, shapes that do not match, non-finite numbers,
        text where a number belongs, a band that is not two increasing frequencies, negative
        errors, enforcement rounds that are not a bounded integer, a track name that is not text,
        conventions that differ from the package's (e.g. ``side: "left"``).
    """
    if not isinstance(data, dict):
        raise InputError(f"{source}: not a boundary: it must be a dict, got {type(data).__name__}")
    _checked_version(data, source, fmt, version)
    check_conventions(data.get("conventions"), source)
    raw = data.get("poles")
    if not isinstance(raw, (list, tuple, np.ndarray)):
        raise InputError(f"{source}: 'poles' must be a list of [re, im] pairs, got {str(raw)[:40]!r}")
    if len(raw) > MAX_POLES:
        raise InputError(f"{source}: 'poles' holds {len(raw)} poles, more than the {MAX_POLES} a fit gives")
    poles = _matrix(data, "poles", source, (-1, 2))
    track = data.get("track", "")
    if not isinstance(track, str):
        raise InputError(f"{source}: 'track' must be text (the fitted track's name), got {str(track)[:40]!r}")
    stored = data.get("state_space")
    if stored is not None and not isinstance(stored, dict):
        raise InputError(f"{source}: 'state_space' must be an object of matrices, got {type(stored).__name__}")
    return {"poles": poles[:, 0] + 1j * poles[:, 1], "coefficients": _matrix(data, "coefficients", source, (-1, 3)),
            "K0": _matrix(data, "K0", source, (2, 2)), "D": _matrix(data, "D", source, (2, 2)),
            "band": _band(data, source), "median_error": _real(data, "median_error", source, math.nan),
            "max_error": _real(data, "max_error", source, math.nan), "enforcement_rounds": _rounds(data, source),
            "track": track, "track_damping": _track_damping(data, source),
            "state_space": None if stored is None else {k: _matrix(stored, k, f"{source}: state_space")
                                                        for k in ("A", "B", "C", "D", "K0")}}


def _track_damping(data: dict, source: str) -> str:
    """The fitted track's damping model from the conventions ("" in a file that does not record it)."""
    conventions = data.get("conventions") or {}
    return check_track_damping(conventions.get("track_damping", ""), f"{source}: conventions['track_damping']")


def check_boundary_physics(model: RationalEndStiffness, passivity: BoundaryPassivityReport, source: str) -> None:
    """Refuse a rational end model that is unstable, has a static stiffness that is not positive
    definite, or fails the exact passivity test.

    Parameters
    ----------
    model : RationalEndStiffness
        The model.
    passivity : BoundaryPassivityReport
        Its exact passivity test (:func:`~.passivity.passivity_report`).
    source : str
        Where it came from (a file, "boundary"), quoted in messages.

    Raises
    ------
    InputError
        Naming the check that failed and its numbers.
    """
    bad = model.poles[model.poles.real >= 0]
    if bad.size:
        raise InputError(f"{source}: the model is unstable: {bad.size} pole(s) with Re >= 0 rad/s, e.g. "
                         f"{complex(bad[0]):.6g} (a stable end has every pole in the left half-plane)")
    eig = np.linalg.eigvalsh(0.5 * (model.K0 + model.K0.T))
    if not eig[0] > 0:
        raise InputError(f"{source}: K0 (the static stiffness) is not positive definite: eigenvalues "
                         f"{eig[0]:.6g}, {eig[1]:.6g} (a track end is stiff at rest)")
    if not passivity.passive:
        bands = ", ".join(f"{lo:.6g}-{hi:.6g} Hz" for lo, hi in passivity.violations_hz[:3]) or "somewhere"
        raise InputError(f"{source}: the model is not passive (exact Hamiltonian test): Re Z(i omega) is not "
                         f"positive semi-definite on {bands} (an end that creates energy)")


def _deviation(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.max(np.abs(a - b)) / max(np.max(np.abs(b)), np.finfo(float).tiny))


def check_boundary_track(model: RationalEndStiffness, track: Track, label: str = "boundary") -> None:
    """Refuse a boundary whose pinned limits are another track's; warn when they differ slightly.

    Parameters
    ----------
    model : RationalEndStiffness
        The boundary's model (its ``K0`` and ``D``).
    track : Track
        The track of the model it closes.
    label : str
        How messages call the boundary.

    Raises
    ------
    InputError
        When ``K0`` or ``D`` differs from the track's (:func:`~.fitting.track_end_limits`) by
        more than :data:`TRACK_RTOL` (largest entry), with both values.

    Warns
    -----
    UserWarning
        When one differs by more than 1e-6 but less than :data:`TRACK_RTOL`: a near variant of the
        fitted track (e.g. another loss factor).
    """
    K0, D = track_end_limits(track)
    for name, mine, theirs in (("K0", model.K0, K0), ("D", model.D, D)):
        dev = _deviation(mine, theirs)
        text = (f"{label} was fitted to another track: its {name} {np.round(mine, 0).tolist()} differs from the "
                f"track {track.name!r}'s {np.round(theirs, 0).tolist()} by {100 * dev:.3g} %")
        if dev > TRACK_RTOL:
            raise InputError(f"{text} (fit the boundary to this track: fit_boundary(track))")
        if dev > _SAME_RTOL:
            warnings.warn(f"{text}; used as it is", UserWarning, stacklevel=4)
