"""Export and import of equivalent systems: JSON, CSV and MATLAB ``.mat``.

Every file holds the layout, the parameters with their units, and the matrices ``M``, ``C``,
``K`` with the names (and units) of the degrees of freedom, so that the system can be used
without this package. The parameters are the source of truth when a file is read back; the
stored matrices are compared with the ones rebuilt from them and a warning is issued if they
differ.

Formats
-------
JSON (:func:`save_system_json`, :func:`load_system_json`)::

    {"format": "semitrack.equivalent.systems", "version": 1, "layout": "slab" | "ballasted",
     "n_bars": N,
     "parameters": {name: {"unit": "kg", "values": [...]}, ...},
     "dof_names": ["w1 (m)", "phi_1 (rad)", ...],
     "matrices": {"M": {"values": [[...]], "entry_units": [[...]]}, "C": ..., "K": ...},
     "metadata": {"highest_natural_frequency": {"unit": "Hz", "value": ..., "note": ...},
                  "central_difference_time_step": {"unit": "s", "value": ..., "note": ...}},
     "conventions": {"side": "right", "load_convention": "applied_to_end", "port_dofs": ["w", "psi"],
                     "port_indices": [0, 1], "left_end_mirror": [[1, 0], [0, -1]], "units": {...},
                     "track": ..., "band_hz": [lo, hi] or null, "text": "..."}}

``metadata`` is written for the reader and ignored when a file is read (files without it, as
written before it existed, load as before): the highest undamped natural frequency of
:meth:`~.systems.EquivalentSystem.highest_natural_frequency` sets the time step of an explicit
integrator, and central differences (undamped) are stable for ``dt < 2 / omega_max``.

CSV (:func:`save_system_csv`, :func:`load_system_csv`): one file of sections, each started by
a line ``[name]``::

    [meta]        rows "key,value": format, version, layout, n_bars, and (informative, not
                  read back) highest_natural_frequency_Hz, central_difference_time_step_s
    [parameters]  header "parameter,unit,bar_1,...,bar_N"; one row per parameter; k_phi and
                  c_phi leave the bar_N cell empty (they have N - 1 values)
    [M] [C] [K]   header "dof,<dof names>"; one row per DOF, first cell the DOF name

Numbers are written with ``repr`` (17 significant digits), so a round trip is exact.

MAT (:func:`save_system_mat`, :func:`load_system_mat`), via :func:`scipy.io.savemat`:
variables ``layout`` (char), ``n_bars``, ``M``, ``C``, ``K`` (double matrices), ``dof_names``
(cell array of char), ``parameters`` (struct of row vectors), ``parameter_units`` (struct
of char), and (informative) ``highest_natural_frequency_Hz`` and
``central_difference_time_step_s``.

Every file also carries the conventions of an end file (:func:`.exchange.end_conventions`): the
side (the semi-infinite track to the right of the cut), the load convention (forces applied to the
end; the force on the user's node is their negative), psi, the mirror ``P = diag(1, -1)`` of a left
end, the port DOFs, units and the track and band fitted on: a ``conventions`` object in JSON, a
``[conventions]`` section in CSV (values as JSON), a ``conventions`` struct (and
``conventions_json``) in MAT. Readers check the fields a program acts on and refuse a file that
declares others (:func:`.exchange.check_conventions`). :func:`export_system` also writes any other
:class:`~.mechanical.MechanicalSystem` (a broadband end's M, C, K) and the Nastran ``.bdf`` and
Abaqus ``.inp`` files of :mod:`.exchange`.

All writes are atomic: the file is written to a temporary file in the target folder and moved
into place with :func:`os.replace`, so an error never leaves a half-written file.
"""

from __future__ import annotations

import csv
import io as _io
import json
import os
import warnings
from pathlib import Path
from typing import Any, Literal

import numpy as np

from ..base.checks import check_band, check_string
from ..base.deprecation import renamed_keywords
from ..base.errors import BadInput, InputError, InputTypeError
from ..base.files import atomic_write, check_input_path, file_suffix, read_json, read_mat, read_text
from .exchange import (
    MATRIX_SUFFIXES,
    check_conventions,
    check_track_damping,
    end_conventions,
    mat_conventions,
    refuse_labels,
    save_matrix_system,
)
from .mechanical import MechanicalSystem
from .systems import PARAMETER_UNITS, EquivalentSystem

__all__ = [
    "time_step_metadata",
    "system_to_dict",
    "system_from_dict",
    "save_system_json",
    "load_system_json",
    "save_system_csv",
    "load_system_csv",
    "save_system_mat",
    "load_system_mat",
    "export_system",
]

FORMAT_NAME = "semitrack.equivalent.systems"
FORMAT_VERSION = 1
#: Largest system file read (bytes): far above any real system, a guard against a wrong file.
MAX_SYSTEM_BYTES = 50_000_000

# Stored matrices count as consistent with the parameters when they agree to this relative
# (to the largest entry) tolerance: a JSON/CSV round trip is exact, a .mat one too (doubles).
_MATRIX_RTOL = 1e-12


def _dof_unit(name: str) -> str:
    return name[name.index("(") + 1 : name.index(")")]


def _entry_units(dof_names: list[str], per: str) -> list[list[str]]:
    """Unit of each matrix entry: generalised force of row i per ``per``-derivative of DOF j."""
    force = {"m": "N", "rad": "N m"}
    units = [_dof_unit(d) for d in dof_names]
    return [[f"{force[ui]}{per}/{uj}" for uj in units] for ui in units]


def _check_system(system) -> EquivalentSystem:
    if not isinstance(system, EquivalentSystem):
        raise InputTypeError(f"system must be a SlabEquivalent or BallastedEquivalent, got {type(system).__name__}")
    return system


def _check_path(path) -> Path:
    return check_input_path(path, "path")


def _check_matrices(system: EquivalentSystem, stored: dict, source: str) -> None:
    """Warn when stored matrices differ from those rebuilt from the parameters."""
    for name, rebuilt in zip("MCK", system.matrices()):
        if name not in stored:
            continue
        X = _numbers(stored[name], source, f"matrices[{name!r}]")
        if X.shape != rebuilt.shape:
            warnings.warn(f"{source}: stored {name} has shape {X.shape}, the parameters give "
                          f"{rebuilt.shape}; the parameters are used", UserWarning, stacklevel=3)
            continue
        scale = max(np.max(np.abs(rebuilt)), np.finfo(float).tiny)
        dev = np.max(np.abs(X - rebuilt)) / scale
        if dev > _MATRIX_RTOL:
            warnings.warn(f"{source}: stored {name} differs from the one rebuilt from the parameters "
                          f"(max relative deviation {dev:.3e}); the parameters are used",
                          UserWarning, stacklevel=3)


def time_step_metadata(system: EquivalentSystem) -> dict[str, dict[str, Any]]:
    """The ``metadata`` of a JSON file: highest natural frequency and central-difference step.

    Parameters
    ----------
    system : SlabEquivalent or BallastedEquivalent
        The system.

    Returns
    -------
    dict
        ``{"highest_natural_frequency": {"unit": "Hz", ...}, "central_difference_time_step":
        {"unit": "s", ...}}``, each with ``value`` and a ``note`` on its meaning; the step is
        None (JSON null) for a system without inertia.
    """
    dt = system.central_difference_time_step()
    return {
        "highest_natural_frequency": {
            "unit": "Hz", "value": system.highest_natural_frequency(),
            "note": "undamped, K v = omega^2 M v; massless directions condensed statically"},
        "central_difference_time_step": {  # JSON has no inf: null for a system without inertia
            "unit": "s", "value": dt if np.isfinite(dt) else None,
            "note": "stability limit 2 / omega_max of the undamped central-difference scheme"},
    }


# --- dict / JSON ----------------------------------------------------------------------------------
def system_to_dict(system: EquivalentSystem, *, track: str = "", band=None, track_damping: str = "") -> dict[str, Any]:
    """Plain-Python description of a system (the JSON layout above), with its conventions.

    Parameters
    ----------
    system : SlabEquivalent or BallastedEquivalent
        The system.
    track : str
        The track it was fitted on (recorded in the conventions; "" if not known).
    band : sequence of two floats, optional
        The band it was fitted on (Hz).
    track_damping : {"", "hysteretic", "viscous"}
        The damping model of the track it was fitted on (recorded in the conventions; "" if not known).
    """
    system = _check_system(system)
    names = system.dof_names()
    M, C, K = system.matrices()
    return {
        "format": FORMAT_NAME,
        "version": FORMAT_VERSION,
        "layout": system.layout,
        "n_bars": system.n_bars,
        "parameters": {
            name: {"unit": PARAMETER_UNITS[name], "values": values.tolist()}
            for name, values in system.parameters().items()
        },
        "dof_names": names,
        "matrices": {
            "M": {"values": M.tolist(), "entry_units": _entry_units(names, " s^2")},
            "C": {"values": C.tolist(), "entry_units": _entry_units(names, " s")},
            "K": {"values": K.tolist(), "entry_units": _entry_units(names, "")},
        },
        "metadata": time_step_metadata(system),
        "conventions": end_conventions(track, band, track_damping),
    }


def _entries(data: dict[str, Any], key: str, source: str) -> dict[str, Any]:
    """The named entries of ``data[key]`` (each a value, or an object with ``values``), checked."""
    table = data.get(key, {})
    if not isinstance(table, dict):
        raise InputError(f"{source}: {key!r} must be an object of named entries, got {json.dumps(table)[:40]}")
    out = {}
    for name, entry in table.items():
        if isinstance(entry, dict) and "values" not in entry:
            raise InputError(f"{source}: {key}[{name!r}] has no key 'values'")
        out[name] = entry["values"] if isinstance(entry, dict) else entry
    return out


def _numbers(values, source: str, key: str) -> np.ndarray:
    """``values`` as a float array, or a one-line refusal naming the source and the key."""
    try:
        return np.asarray(values, dtype=float)
    except (TypeError, ValueError, OverflowError):
        raise InputError(f"{source}: {key} must be a number or a list of numbers, got {str(values)[:40]}") from None


def system_from_dict(data: dict[str, Any], source: str = "data") -> EquivalentSystem:
    """Rebuild a system from :func:`system_to_dict` output (matrices checked if present).

    Parameters
    ----------
    data : dict
        The description; the parameters are the source of truth.
    source : str
        Where it came from, quoted in errors and warnings.

    Warns
    -----
    UserWarning
        When stored matrices differ from those rebuilt from the parameters.
    """
    if not isinstance(data, dict):
        raise InputTypeError(f"{source} must be a dict, got {type(data).__name__}")
    if data.get("format") != FORMAT_NAME:
        raise InputError(f"{source}: 'format' must be {FORMAT_NAME!r}, got {data.get('format')!r}")
    if data.get("version") != FORMAT_VERSION:
        raise InputError(f"{source}: 'version' must be {FORMAT_VERSION}, got {data.get('version')!r}")
    for key in ("layout", "parameters"):
        if key not in data:
            raise InputError(f"{source}: missing key {key!r}")
    check_conventions(data.get("conventions"), source)
    params = {name: _numbers(values, source, f"parameters[{name!r}]")
              for name, values in _entries(data, "parameters", source).items()}
    params["layout"] = data["layout"]
    try:
        system = EquivalentSystem.from_parameters(params)
    except BadInput as err:  # the rule that failed, with the file it failed in
        raise type(err)(f"{source}: {err}") from None
    stored = _entries(data, "matrices", source)
    _check_matrices(system, stored, source)
    return system


def save_system_json(system: EquivalentSystem, path: str | os.PathLike, *, track: str = "", band=None,
                     track_damping: str = "") -> Path:
    """Write ``system`` to a JSON file (atomically).

    Parameters
    ----------
    system : SlabEquivalent or BallastedEquivalent
        The system.
    path : str or os.PathLike
        The file.
    track : str
        The track it was fitted on (recorded in the conventions).
    band : sequence of two floats, optional
        The band it was fitted on (Hz).
    track_damping : {"", "hysteretic", "viscous"}
        The damping model of the track it was fitted on (recorded in the conventions; "" if not known).

    Returns
    -------
    Path
    """
    data = system_to_dict(system, track=track, band=band, track_damping=track_damping)
    return atomic_write(path, lambda fh: json.dump(data, fh, indent=1), binary=False)


def load_system_json(path: str | os.PathLike) -> EquivalentSystem:
    """Read a system written by :func:`save_system_json`.

    Parameters
    ----------
    path : str or os.PathLike
        The JSON file.

    Returns
    -------
    SlabEquivalent or BallastedEquivalent
        Built from the stored parameters (the stored matrices are only compared with it).

    Raises
    ------
    ValueError
        For a file that is not UTF-8 JSON of at most :data:`MAX_SYSTEM_BYTES`, of another format
        or version, without layout or parameters, or with entries that are not ``{"values": ...}``
        objects; the message names the file and the key.
    OSError
        If the file cannot be read.
    """
    path = _check_path(path)
    data = read_json(path, MAX_SYSTEM_BYTES, "system file")
    if not isinstance(data, dict):
        raise InputError(f"{path}: not a system file: it must hold a JSON object, got {type(data).__name__}")
    return system_from_dict(data, source=str(path))


# --- CSV --------------------------------------------------------------------------------------------
def _fmt(x: float) -> str:
    return repr(float(x))


def save_system_csv(system: EquivalentSystem, path: str | os.PathLike, *, track: str = "", band=None,
                    track_damping: str = "") -> Path:
    """Write ``system`` to one sectioned CSV file (format in the module docstring), atomically.

    Parameters
    ----------
    system : SlabEquivalent or BallastedEquivalent
        The system.
    path : str or os.PathLike
        The file.
    track : str
        The track it was fitted on (recorded in the conventions).
    band : sequence of two floats, optional
        The band it was fitted on (Hz).
    track_damping : {"", "hysteretic", "viscous"}
        The damping model of the track it was fitted on (recorded in the conventions; "" if not known).

    Returns
    -------
    Path
    """
    system = _check_system(system)
    N = system.n_bars
    names = system.dof_names()
    buf = _io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(["[meta]"])
    w.writerow(["key", "value"])
    for key, value in (("format", FORMAT_NAME), ("version", FORMAT_VERSION),
                       ("layout", system.layout), ("n_bars", N),
                       ("highest_natural_frequency_Hz", _fmt(system.highest_natural_frequency())),
                       ("central_difference_time_step_s", _fmt(system.central_difference_time_step()))):
        w.writerow([key, value])
    w.writerow(["[parameters]"])
    w.writerow(["parameter", "unit"] + [f"bar_{j}" for j in range(1, N + 1)])
    for name, values in system.parameters().items():
        cells = [_fmt(v) for v in values]
        w.writerow([name, PARAMETER_UNITS[name]] + cells + [""] * (N - len(cells)))
    w.writerow(["[conventions]"])
    w.writerow(["key", "value"])
    w.writerows([key, json.dumps(value)] for key, value in end_conventions(track, band, track_damping).items())
    for label, X in zip("MCK", system.matrices()):
        w.writerow([f"[{label}]"])
        w.writerow(["dof"] + names)
        for dof, row in zip(names, X):
            w.writerow([dof] + [_fmt(v) for v in row])
    text = buf.getvalue()
    return atomic_write(path, lambda fh: fh.write(text), binary=False)


def load_system_csv(path: str | os.PathLike) -> EquivalentSystem:
    """Read a system written by :func:`save_system_csv`.

    Parameters
    ----------
    path : str or os.PathLike
        The CSV file.

    Returns
    -------
    SlabEquivalent or BallastedEquivalent
        Built from the stored parameters (the stored matrices are only compared with it).

    Raises
    ------
    ValueError
        For a file without its [meta] or [parameters] section, of another format or version.
    """
    path = _check_path(path)
    sections = _csv_sections(path)
    for key in ("meta", "parameters"):
        if key not in sections:
            raise InputError(f"{path}: missing section [{key}]")
    meta = {row[0]: row[1] if len(row) > 1 else "" for row in sections["meta"][1:]}
    data = {
        "format": meta.get("format"),
        "version": _csv_number(meta["version"], path, "[meta] version") if "version" in meta else None,
        "layout": meta.get("layout"),
        "parameters": {
            row[0]: [_csv_number(c, path, f"[parameters] {row[0]}") for c in row[2:] if c.strip() != ""]
            for row in sections["parameters"][1:]
        },
        "matrices": {
            label: [[_csv_number(c, path, f"[{label}] {row[0]}") for c in row[1:]] for row in sections[label][1:]]
            for label in "MCK" if label in sections
        },
    }
    if "conventions" in sections:
        data["conventions"] = {row[0]: _json_cell(row, path) for row in sections["conventions"][1:]}
    return system_from_dict(data, source=str(path))


def _json_cell(row: list[str], path: Path):
    """The value of a ``[conventions]`` row: JSON text in its second cell."""
    try:
        return json.loads(row[1])
    except (IndexError, ValueError, RecursionError):
        raise InputError(f"{path}: [conventions] {row[0]!r:.40} must hold one JSON value") from None


def _csv_sections(path: Path) -> dict[str, list[list[str]]]:
    """The rows of each ``[section]`` of a system CSV file, read as bounded text."""
    sections: dict[str, list[list[str]]] = {}
    current = None
    try:
        rows = list(csv.reader(_io.StringIO(read_text(path, MAX_SYSTEM_BYTES, "system file"), newline="")))
    except csv.Error as err:
        raise InputError(f"{path}: not a CSV file ({err})") from None
    for row in rows:
        if not row or not any(cell.strip() for cell in row):
            continue
        head = row[0].strip()
        if head.startswith("[") and head.endswith("]"):
            current = head[1:-1]
            sections[current] = []
        elif current is None:
            raise InputError(f"{path}: not a system file: data before the first [section] line: {row!r:.60}")
        else:
            sections[current].append(row)
    return sections


def _csv_number(cell: str, path: Path, where: str) -> float | int:
    """A number of a system CSV file (an int when it is written as one), or a one-line refusal."""
    text = cell.strip()
    try:
        return int(text) if text.lstrip("+-").isdigit() else float(text)
    except ValueError:
        raise InputError(f"{path}: {where}: {text[:40]!r} is not a number") from None


# --- MAT --------------------------------------------------------------------------------------------
def save_system_mat(system: EquivalentSystem, path: str | os.PathLike, *, track: str = "", band=None,
                    track_damping: str = "") -> Path:
    """Write ``system`` to a MATLAB .mat file (format 5) with :func:`scipy.io.savemat`, atomically.

    Parameters
    ----------
    system : SlabEquivalent or BallastedEquivalent
        The system.
    path : str or os.PathLike
        The file.
    track : str
        The track it was fitted on (recorded in the conventions).
    band : sequence of two floats, optional
        The band it was fitted on (Hz).
    track_damping : {"", "hysteretic", "viscous"}
        The damping model of the track it was fitted on (recorded in the conventions; "" if not known).

    Returns
    -------
    Path
    """
    system = _check_system(system)
    M, C, K = system.matrices()
    conventions = end_conventions(track, band, track_damping)
    content = {
        "format": FORMAT_NAME,
        "version": FORMAT_VERSION,
        "layout": system.layout,
        "n_bars": system.n_bars,
        "M": M,
        "C": C,
        "K": K,
        "dof_names": np.array(system.dof_names(), dtype=object),
        "parameters": {name: values.reshape(1, -1) for name, values in system.parameters().items()},
        "parameter_units": {name: PARAMETER_UNITS[name] for name in system.parameter_names()},
        "highest_natural_frequency_Hz": system.highest_natural_frequency(),
        "central_difference_time_step_s": system.central_difference_time_step(),
        "conventions": mat_conventions(conventions),
        "conventions_json": json.dumps(conventions),
    }
    import scipy.io  # here, not at the top: it costs ~0.15 s of every command line's start-up

    return atomic_write(path, lambda fh: scipy.io.savemat(fh, content, oned_as="row"), binary=True)


def load_system_mat(path: str | os.PathLike) -> EquivalentSystem:
    """Read a system written by :func:`save_system_mat`.

    Parameters
    ----------
    path : str or os.PathLike
        The .mat file.

    Returns
    -------
    SlabEquivalent or BallastedEquivalent
        Built from the stored parameters (the stored matrices are only compared with it).

    Raises
    ------
    ValueError
        For a file without the variables ``layout`` and ``parameters``.
    """
    path = _check_path(path)
    raw = read_mat(path, MAX_SYSTEM_BYTES, "system file", simplify=True)
    for key in ("layout", "parameters"):
        if key not in raw:
            raise InputError(f"{path}: missing variable {key!r}")
    if not isinstance(raw["parameters"], dict):
        raise InputError(f"{path}: the variable 'parameters' must be a struct, got {type(raw['parameters']).__name__}")
    try:
        data = {
            "format": raw.get("format"),
            "version": int(raw["version"]) if "version" in raw else None,
            "layout": raw["layout"],
            "parameters": {n: np.atleast_1d(np.asarray(v, dtype=float)).ravel() for n, v in raw["parameters"].items()},
            "matrices": {n: np.atleast_2d(np.asarray(raw[n], dtype=float)) for n in "MCK" if n in raw},
        }
        if "conventions_json" in raw:
            data["conventions"] = json.loads(str(raw["conventions_json"]))
    except (TypeError, ValueError, OverflowError, RecursionError) as err:
        raise InputError(f"{path}: a variable is not a number, an array of numbers or JSON text "
                         f"({type(err).__name__}: {err})") from None
    return system_from_dict(data, source=str(path))


# --- dispatch ---------------------------------------------------------------------------------------
_WRITERS = {".json": save_system_json, ".csv": save_system_csv, ".mat": save_system_mat}


@renamed_keywords({"band_hz": "band"})
def export_system(system: MechanicalSystem, path: str | os.PathLike,
                  format: Literal["json", "csv", "mat", "bdf", "inp"] | None = None, *, track: str | None = None,
                  band=None, node: int | None = None, first_label: int | None = None,
                  track_damping: str | None = None) -> Path:
    """Write an end system as JSON, CSV, MAT, Nastran ``.bdf`` or Abaqus ``.inp``, atomically.

    A paper-style system (:class:`~.systems.EquivalentSystem`) is written with its parameters
    (formats in the module docstring) as JSON, CSV or MAT; any other
    :class:`~.mechanical.MechanicalSystem` (a broadband end's
    :meth:`~semitrack.BroadbandBoundary.matrix_system`), and every system as ``.bdf`` or ``.inp``,
    by its matrices (:mod:`.exchange`). Every file states its conventions.

    Parameters
    ----------
    system : MechanicalSystem
        The system.
    path : str or os.PathLike
        The file.
    format : {"json", "csv", "mat", "bdf", "inp"}, optional
        The format; default: from the suffix of ``path``.
    track : str, optional
        The track it was fitted on (default: the system's own record, if any).
    band : sequence of two floats, optional
        The band it was fitted on (Hz); until 0.3 also ``band_hz=``.
    node : int, optional
        ``.bdf`` and ``.inp``: the grid or node of your model's end that carries the ports
        (default 1); refused for the other formats, which name DOFs, not labels.
    first_label : int, optional
        ``.bdf`` and ``.inp``: the scalar point or node of the first internal DOF (default
        9000001); the others follow it, clear of ``node``, at most 99999999.
    track_damping : {"", "hysteretic", "viscous"}, optional
        The damping model of the track it was fitted on, recorded in the file (default: the
        system's own record, if any; a paper-style system has none, so give ``track.damping``).

    Returns
    -------
    Path

    Warns
    -----
    UserWarning
        A ``.bdf`` or ``.inp`` file of an end fitted to a hysteretic track (``track_damping`` or
        its record says so).

    Raises
    ------
    ValueError
        When neither ``format`` nor the suffix names a format.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> import semitrack as st
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> path = st.export_system(st.paper_table4(), folder / "table4.json")
    >>> st.load_system_json(path) == st.paper_table4()
    True
    >>> import shutil; shutil.rmtree(folder)
    """
    path = _check_path(path)
    key = file_suffix(path, format)
    if key not in MATRIX_SUFFIXES:
        raise InputError(f"format must be one of {', '.join(x[1:] for x in MATRIX_SUFFIXES)} (or a path with that "
                         f"suffix), got {format if format is not None else path.suffix!r}")
    if track is not None:
        check_string("track", track)
    band = None if band is None else check_band(band)
    if track_damping is not None:
        check_track_damping(track_damping)
    if not isinstance(system, MechanicalSystem):
        raise InputTypeError(f"system must be a MechanicalSystem (an EquivalentSystem or "
                             f"BroadbandBoundary.matrix_system()), got {type(system).__name__}")
    if isinstance(system, EquivalentSystem) and key in _WRITERS:
        refuse_labels(key, node, first_label)
        return _WRITERS[key](system, path, track=track or "", band=band, track_damping=track_damping or "")
    return save_matrix_system(system, path, track, band, format=key, node=node, first_label=first_label,
                              track_damping=track_damping)
