"""Files that carry their conventions: the end systems' M, C, K for this package and for other codes.

Every end file the package writes (a paper-style system, a broadband boundary, its M, C, K form)
holds a ``conventions`` record (:func:`end_conventions`), in fields a program reads and in words:

* ``side``: ``"right"``: the file models the semi-infinite track to the right of the cut;
* ``load_convention``: ``"applied_to_end"``: ``(Q, M)`` are the force and moment applied to the
  ports (the end of that semi-infinite track); the force on the user's end node is ``-(Q, M)``;
* ``port_dofs`` and ``port_indices``: the rail's ``w`` (m, downward) and ``psi`` (rad, the
  clockwise rotation of the cross-section from bending alone, seen with the track running to the
  right) are the matrices' first two DOFs;
* ``left_end_mirror``: ``[[1, 0], [0, -1]]``: a left end (track to the left of the cut) takes
  ``P K P`` on the ports with ``P = diag(1, -1)`` (the internal DOFs unchanged);
* ``units``, ``time_factor`` (``exp(i omega t)``), ``track`` and ``band_hz`` fitted on, and
  ``precision``: numbers in full double precision (``repr``, 17 significant digits).

This module also writes M, C, K for other codes, chosen by the suffix in
:func:`~semitrack.export_system`:

``.bdf``: Nastran bulk data, three symmetric ``DMIG`` matrices (IFO = 6, TIN = 2 real double,
    lower triangle by column, large-field fixed format) for the Case Control commands ``K2GG``
    (stiffness), ``B2GG`` (viscous damping) and ``M2GG`` (mass), which add them to the g-set
    matrices (MSC Nastran Quick Reference Guide, Bulk Data entry DMIG and the Case Control
    commands K2GG, B2GG, M2GG, whose remarks say that several matrices named on one command are
    added). A Nastran field holds 8 characters (16 in large field: free-field entries longer than
    8 are refused, Autodesk Nastran message T2005), so at most 11-12 significant digits, fewer
    than a double: each matrix is written as a leading part and its remainder (``KEND`` and
    ``KENDR``, ...), to be named together, ``K2GG = KEND, KENDR``; their sum is the double to the
    last bit or two. Internal DOFs are scalar points (``SPOINT``, component 0); the ports are
    components of the user's end grid.
``.inp``: Abaqus keywords (Abaqus Keywords Reference Guide 2017, *MATRIX INPUT and *MATRIX
    ASSEMBLE): ``*MATRIX INPUT, NAME=...`` with the data lines after the keyword (no INPUT
    parameter), "row node, row DOF, column node, column DOF, value", lower triangle (the default
    TYPE=SYMMETRIC), every digit (``repr``); then ``*MATRIX ASSEMBLE, STIFFNESS=END_K,
    MASS=END_M, VISCOUS DAMPING=END_C`` (model data, model level). The internal DOFs are DOF 1 of
    nodes the file declares (``*NODE``, in an assembly-level node set). The file is for Abaqus:
    CalculiX has no matrix keyword that takes rotations or damping, and CalculiX 2.20 skipped
    every line of such a file ("card image cannot be interpreted", exit code 0) and ran the model
    without the end; the file's header says so.

Both codes' models usually have ``y`` up and rotations counterclockwise about ``z``: the files map
``w = -u_y`` (DOF 2, T2) and ``psi = -theta_z`` (DOF 6, R3) for a track along ``+x``, i.e. the
ports' rows and columns of the internal coupling change sign (``P = diag(-1, -1)``, the port
block unchanged). The header comments say so, and which node to attach.
"""

from __future__ import annotations

import json
import os
import textwrap
from pathlib import Path

import numpy as np

from ..base.checks import check_int_at_least
from ..base.errors import InputError, InputTypeError
from ..base.files import atomic_write, check_input_path, file_suffix, read_json, read_mat, read_text
from ..base.notices import warn_user
from .mechanical import PORT_DOFS, MatrixSystem, MechanicalSystem

__all__ = ["end_conventions", "conventions_text", "check_conventions", "check_labels", "check_track_damping",
           "refuse_labels",
           "TRACK_DAMPING", "MAX_LABEL", "FIRST_INTERNAL_LABEL", "CHECKED_CONVENTIONS", "mat_conventions",
           "matrix_system_to_dict", "matrix_system_from_dict", "save_matrix_system", "load_matrix_system",
           "save_nastran_dmig", "save_abaqus_matrix", "MATRIX_FORMAT", "MATRIX_SUFFIXES", "CODE_AXES"]

#: The ``format`` of a MatrixSystem file.
MATRIX_FORMAT = "semitrack.mechanical.system"
MATRIX_VERSION = 1
#: The suffixes of the M, C, K files written here.
MATRIX_SUFFIXES = (".json", ".csv", ".mat", ".bdf", ".inp")
#: How the ports map to a finite-element code's axes (x along the track, y up): DOF and sign.
CODE_AXES = {"w": {"dof": 2, "sign": -1.0, "note": "w = -u_y (downward deflection, y up)"},
             "psi": {"dof": 6, "sign": -1.0, "note": "psi = -theta_z (clockwise, z out of the x-y plane)"}}
#: Largest M, C, K file read (bytes): an 800-DOF system in full precision is about 40 MB as JSON.
MAX_MATRIX_BYTES = 50_000_000
#: Node label of the first internal DOF in the .bdf and .inp files (one scalar point or node each).
FIRST_INTERNAL_LABEL = 9_000_001


def end_conventions(track: str = "", band=None, track_damping: str = "") -> dict:
    """The conventions record of an end file (module docstring), with the track and band fitted on.

    Parameters
    ----------
    track : str
        Name of the track the system models ("" if not known).
    band : sequence of two floats, optional
        Band of the fit (Hz), if any.
    track_damping : {"", "hysteretic", "viscous"}
        The damping model of the track it was fitted on ("" if not recorded): an end fitted to
        a hysteretic (loss-factor, not causal) track holds in the time domain only as well as
        its causal fit could follow it.

    Returns
    -------
    dict
        Plain data (JSON-ready), with a ``text`` entry saying it in words.
    """
    band = None if band is None else [float(b) for b in band]
    return {
        "side": "right", "load_convention": "applied_to_end", "port_dofs": list(PORT_DOFS), "port_indices": [0, 1],
        "w": "vertical deflection of the rail at the cut, downward positive (m)",
        "psi": "rotation of the rail's cross-section from bending alone, clockwise positive seen with the "
               "track running to the right (rad)",
        "left_end_mirror": [[1.0, 0.0], [0.0, -1.0]],
        "units": {"length": "m", "rotation": "rad", "force": "N", "moment": "N m", "time": "s", "mass": "kg",
                  "frequency": "Hz"},
        "time_factor": "exp(i omega t)", "track": str(track), "band_hz": band,
        "track_damping": check_track_damping(track_damping),
        "precision": "IEEE doubles written in full (repr: 17 significant digits); at least 12 are needed",
        "text": conventions_text(track, band, track_damping),
    }


#: The damping models an end file may record of its track ("": not recorded).
TRACK_DAMPING = ("", "hysteretic", "viscous")


def check_track_damping(value, source: str = "track_damping") -> str:
    """A recorded damping model of the track: one of :data:`TRACK_DAMPING`, or the package's refusal."""
    if not isinstance(value, str) or value not in TRACK_DAMPING:  # the type first: `array in tuple` raises
        raise InputError(f"{source} must be one of {', '.join(map(repr, TRACK_DAMPING))} (the track's damping "
                         f"model, '' if not recorded), got {str(value)[:40]!r}")
    return value


def conventions_text(track: str = "", band=None, track_damping: str = "") -> str:
    """The conventions in words, as every file states them.

    Parameters
    ----------
    track : str
        Name of the track the system models.
    band : sequence of two floats, optional
        Band of the fit (Hz).
    track_damping : {"", "hysteretic", "viscous"}
        The track's damping model, if recorded.
    """
    fitted = f" It was fitted on the track {track!r}" if track else " The track it models is not recorded"
    fitted += f" over {band[0]:g}-{band[1]:g} Hz." if band is not None else "."
    fitted += {"hysteretic": " That track's damping is hysteretic (loss factors, not causal): in the time domain "
                             "the end holds only as well as its causal fit follows it; fit a viscous track's end "
                             "for time-domain use.",
               "viscous": " That track's damping is viscous (causal).", "": ""}[track_damping]
    return ("This file models the semi-infinite track to the right of a cut. Its first two DOFs (the ports) are "
            "the rail's w (m, downward) and psi (rad, the clockwise rotation of the cross-section from bending "
            "alone) at the cut; (Q, M) are the force and moment applied to that end, so the force on your end "
            "node is -(Q, M). For a left end (track to the left of the cut) use P K P with P = diag(1, -1) on "
            "the ports. SI units, time factor exp(i omega t)." + fitted)


#: The conventions fields a program acts on (module docstring), checked when a file is read back:
#: the rest (``w``, ``psi``, ``text``, ``track``, ``band_hz``, ``precision``) only describe.
CHECKED_CONVENTIONS = ("side", "load_convention", "port_dofs", "port_indices", "left_end_mirror", "units",
                       "time_factor")


def _plain(value):
    """A conventions value in one comparable form: arrays and tuples as lists, numbers as floats."""
    if isinstance(value, np.ndarray):
        value = value.tolist()
    if isinstance(value, dict):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, (int, float, np.number)) and not isinstance(value, bool):
        return float(value)
    return value


def check_conventions(conventions, source: str) -> None:
    """Refuse an end file whose declared conventions differ from the package's, naming the field.

    A file that declares millimetres, ``exp(-i omega t)``, the ports in another order, a left end
    or another load convention would otherwise load as if it followed the package's conventions,
    and its matrices would be used with the wrong signs or scale. A field the file does not
    declare (an older or hand-written file) is taken as the package's; no conversion is made, the
    message says what the package expects.

    Parameters
    ----------
    conventions : dict or None
        The file's ``conventions`` record, as read (None: the file declares none).
    source : str
        The file, quoted in the message.

    Raises
    ------
    InputError
        If the record is not a mapping, a field of :data:`CHECKED_CONVENTIONS` differs from
        :func:`end_conventions`, or the recorded ``track_damping`` is not one of :data:`TRACK_DAMPING`.
    """
    if conventions is None:
        return
    if not isinstance(conventions, dict):
        raise InputError(f"{source}: 'conventions' must be a record of fields, got {type(conventions).__name__}")
    ours = end_conventions()
    for field in CHECKED_CONVENTIONS:
        theirs = conventions.get(field)
        if field == "units" and isinstance(theirs, dict) and \
                all(_plain(value) == _plain(ours["units"].get(key, value)) for key, value in theirs.items()):
            continue  # each unit the file declares is ours (one it leaves out is taken as ours)
        if field in conventions and _plain(conventions[field]) != _plain(ours[field]):
            raise InputError(f"{source}: conventions[{field!r}] is {_plain(conventions[field])!r:.80}, not the "
                             f"package's {ours[field]!r}: convert the file to the package's conventions first")
    check_track_damping(conventions.get("track_damping", ""), f"{source}: conventions['track_damping']")


def _check_system(system) -> MechanicalSystem:
    if not isinstance(system, MechanicalSystem):
        raise InputTypeError(f"system must be a MechanicalSystem (an EquivalentSystem, or "
                             f"BroadbandBoundary.matrix_system()), got {type(system).__name__}")
    return system


def _info(system: MechanicalSystem, track: str | None, band, damping: str | None = None) -> tuple[str, object, str]:
    """The track, band and track's damping model of a system: given, or from a MatrixSystem's info."""
    info = system.info if isinstance(system, MatrixSystem) else {}
    if damping is None:
        damping = info.get("track_damping", "")
        damping = damping if damping in TRACK_DAMPING else ""
    return (track if track is not None else str(info.get("track", ""))), \
        (band if band is not None else info.get("band_hz")), check_track_damping(damping)


# --- JSON, CSV, MAT of a MatrixSystem --------------------------------------------------------------
def matrix_system_to_dict(system: MechanicalSystem, track: str | None = None, band=None,
                          track_damping: str | None = None) -> dict:
    """Plain data of any end system's matrices, with its conventions (format :data:`MATRIX_FORMAT`).

    Parameters
    ----------
    system : MechanicalSystem
        The system.
    track : str, optional
        The track it models (default: the system's ``info``).
    band : sequence of two floats, optional
        The band it was fitted on (Hz; default: the system's ``info``).
    track_damping : {"", "hysteretic", "viscous"}, optional
        The damping model of the track it was fitted on (default: the system's ``info``).
    """
    system = _check_system(system)
    track, band, damping = _info(system, track, band, track_damping)
    M, C, K = system.matrices()
    info = dict(system.info) if isinstance(system, MatrixSystem) else {"origin": f"{system.kind} equivalent system"}
    return {"format": MATRIX_FORMAT, "version": MATRIX_VERSION, "conventions": end_conventions(track, band, damping),
            "info": info, "dof_names": system.dof_names(),
            "static_stiffness": system.static_stiffness().tolist(),
            "limits": ("implicit integrators only when M is singular (massless DOFs); a static or preload step "
                       "closes the cut with static_stiffness (2x2) and starts the internal DOFs unloaded; the "
                       "internal masses are mathematical: no gravity on them"),
            "M": M.tolist(), "C": C.tolist(), "K": K.tolist()}


def matrix_system_from_dict(data: dict, source: str = "data") -> MatrixSystem:
    """Rebuild a :class:`~.mechanical.MatrixSystem` from :func:`matrix_system_to_dict` output.

    Parameters
    ----------
    data : dict
        The plain data.
    source : str
        Where it came from, quoted in errors.
    """
    if not isinstance(data, dict) or data.get("format") != MATRIX_FORMAT:
        raise InputError(f"{source}: not a {MATRIX_FORMAT} file (its 'format' must be {MATRIX_FORMAT!r})")
    check_conventions(data.get("conventions"), source)
    conv = data.get("conventions") or {}
    dofs = data.get("dof_names", ())
    if not isinstance(dofs, (list, tuple)) or not all(isinstance(name, str) for name in dofs):
        raise InputError(f"{source}: 'dof_names' must be a list of names, got {str(dofs)[:40]!r}")
    if len(dofs) >= 2 and (dofs[0].endswith("(rad)") or dofs[1].endswith("(m)")):  # named units that contradict
        raise InputError(f"{source}: 'dof_names' must start with the ports, a deflection (m) then a rotation "
                         f"(rad), got {dofs[:2]!r}: the matrices' DOFs are in another order")
    try:
        return MatrixSystem(np.asarray(data["M"], dtype=float), np.asarray(data["C"], dtype=float),
                            np.asarray(data["K"], dtype=float), dofs=tuple(dofs),
                            info=dict(data.get("info", {}), track=conv.get("track", ""), band_hz=conv.get("band_hz"),
                                      track_damping=check_track_damping(conv.get("track_damping", ""),
                                                                        f"{source}: conventions['track_damping']")))
    except KeyError as exc:
        raise InputError(f"{source}: missing key {exc.args[0]!r}") from None
    except (TypeError, ValueError) as exc:
        raise InputError(f"{source}: {exc}") from None


def _csv_text(data: dict) -> str:
    """Sections ``[meta]`` and ``[conventions]`` (key, value; anything but a string as JSON), ``[M] [C] [K]``."""
    import csv
    import io

    buf = io.StringIO()
    out = csv.writer(buf, lineterminator="\n")
    out.writerows([["[meta]"], ["key", "value"], ["format", data["format"]], ["version", data["version"]],
                   ["info", json.dumps(data["info"])], ["dof_names", json.dumps(data["dof_names"])],
                   ["static_stiffness", json.dumps(data["static_stiffness"])], ["[conventions]"], ["key", "value"]])
    out.writerows([key, json.dumps(value)] for key, value in data["conventions"].items())
    for name in "MCK":
        out.writerow([f"[{name}]"])
        out.writerows([repr(float(v)) for v in row] for row in data[name])
    return buf.getvalue()


def _csv_data(text: str, source: str) -> dict:
    """The dict of :func:`_csv_text`'s sections."""
    import csv

    sections, current = {}, None
    try:
        rows = list(csv.reader(text.splitlines()))
    except csv.Error as exc:
        raise InputError(f"{source}: not a CSV file ({exc})") from None
    for row in rows:
        if not row:
            continue
        if row[0].startswith("[") and row[0].endswith("]"):
            current = sections.setdefault(row[0][1:-1], [])
        elif current is None:
            raise InputError(f"{source}: data before the first [section] line")
        else:
            current.append(row)
    try:
        meta = {r[0]: r[1] for r in sections["meta"][1:]}
        data = {"format": meta["format"], "version": int(meta["version"]), "info": json.loads(meta["info"]),
                "dof_names": json.loads(meta["dof_names"]),
                "conventions": {r[0]: json.loads(r[1]) for r in sections["conventions"][1:]}}
        data.update({name: [[float(v) for v in r] for r in sections[name]] for name in "MCK"})
    except (KeyError, IndexError, ValueError, RecursionError) as exc:
        raise InputError(f"{source}: not a {MATRIX_FORMAT} CSV file ({type(exc).__name__}: {exc})") from None
    return data


def save_matrix_system(system: MechanicalSystem, path: str | os.PathLike, track: str | None = None,
                       band=None, format: str | None = None, *, node: int | None = None,
                       first_label: int | None = None, track_damping: str | None = None) -> Path:
    """Write any end system's M, C, K with its conventions: ``.json``, ``.csv``, ``.mat``, ``.bdf``, ``.inp``.

    Parameters
    ----------
    system : MechanicalSystem
        The system (an :class:`~.systems.EquivalentSystem`, or a broadband end's second-order form).
    path : str or os.PathLike
        The file; its suffix selects the format. Written atomically.
    track : str, optional
        The track it models (default: the system's ``info``).
    band : sequence of two floats, optional
        The band it was fitted on (Hz; default: the system's ``info``).
    format : {"json", "csv", "mat", "bdf", "inp"}, optional
        The format; default: from the suffix of ``path``.
    node : int, optional
        ``.bdf`` and ``.inp`` only: the grid or node of the user's end that carries the ports
        (default 1).
    first_label : int, optional
        ``.bdf`` and ``.inp`` only: the label of the first internal DOF's scalar point or node
        (default :data:`FIRST_INTERNAL_LABEL`); the internal DOFs take the labels after it.
    track_damping : {"", "hysteretic", "viscous"}, optional
        The damping model of the track it was fitted on (default: the system's ``info``).

    Returns
    -------
    Path

    Warns
    -----
    UserWarning
        A ``.bdf`` or ``.inp`` file (for a time-domain code) of an end fitted to a hysteretic track.
    """
    suffix = file_suffix(path, format)
    if suffix in (".bdf", ".inp"):
        write = save_nastran_dmig if suffix == ".bdf" else save_abaqus_matrix
        return write(system, path, track, band, node=node, first_label=first_label, track_damping=track_damping)
    refuse_labels(suffix, node, first_label)
    data = matrix_system_to_dict(system, track, band, track_damping)
    if suffix == ".json":
        return atomic_write(path, lambda fh: json.dump(data, fh, indent=1), binary=False)
    if suffix == ".csv":
        text = _csv_text(data)
        return atomic_write(path, lambda fh: fh.write(text), binary=False)
    if suffix == ".mat":
        import scipy.io  # deferred: ~0.15 s of every command line's start-up

        content = {"format": MATRIX_FORMAT, "version": MATRIX_VERSION, "M": np.array(data["M"]),
                   "C": np.array(data["C"]), "K": np.array(data["K"]),
                   "dof_names": np.array(data["dof_names"], dtype=object),
                   "static_stiffness": np.array(data["static_stiffness"]),
                   "conventions": mat_conventions(data["conventions"]),
                   "conventions_json": json.dumps(data["conventions"]), "info_json": json.dumps(data["info"])}
        return atomic_write(path, lambda fh: scipy.io.savemat(fh, content, oned_as="row"), binary=True)
    raise InputError(f"path must end in one of {', '.join(MATRIX_SUFFIXES)}, got {str(path)!r}")


def mat_conventions(conv: dict) -> dict:
    """The conventions record as a MATLAB struct (:func:`scipy.io.savemat`): numbers as arrays,
    lists of names as cell arrays, None as an empty array.

    Parameters
    ----------
    conv : dict
        A record of :func:`end_conventions`.
    """
    out = {}
    for key, value in conv.items():
        if isinstance(value, dict):
            out[key] = {k: str(v) for k, v in value.items()}
        elif value is None:
            out[key] = np.zeros((0, 0))
        elif isinstance(value, list) and value and isinstance(value[0], str):
            out[key] = np.array(value, dtype=object)
        else:
            out[key] = np.array(value) if isinstance(value, list) else value
    return out


def load_matrix_system(path: str | os.PathLike) -> MatrixSystem:
    """Read a file of :func:`save_matrix_system` (``.json``, ``.csv`` or ``.mat``).

    Parameters
    ----------
    path : str or os.PathLike
        The file, at most :data:`MAX_MATRIX_BYTES` (a ``.mat`` file's variables too, once
        inflated).

    Returns
    -------
    MatrixSystem

    Raises
    ------
    InputError
        For another suffix, a file too large (``/dev/zero`` behind the name), not UTF-8, not JSON or
        nested too deeply, a damaged ``.mat`` file, a missing key or variable, conventions that
        differ from the package's (:func:`check_conventions`), or matrices that are not a
        system's; one line naming the file.
    OSError
        If the file cannot be opened or read.
    """
    source = str(check_input_path(path, "path"))
    suffix = Path(path).suffix.lower()
    if suffix == ".json":
        return matrix_system_from_dict(read_json(path, MAX_MATRIX_BYTES, "system file"), source)
    if suffix == ".csv":
        return matrix_system_from_dict(_csv_data(read_text(path, MAX_MATRIX_BYTES, "system file"), source), source)
    if suffix == ".mat":
        raw = read_mat(path, MAX_MATRIX_BYTES, "system file", simplify=True)
        try:
            data = {"format": raw["format"], "M": np.atleast_2d(raw["M"]), "C": np.atleast_2d(raw["C"]),
                    "K": np.atleast_2d(raw["K"]), "dof_names": list(np.atleast_1d(raw["dof_names"])),
                    "conventions": _json_variable(raw, "conventions_json", source),
                    "info": _json_variable(raw, "info_json", source)}
        except KeyError as exc:
            raise InputError(f"{source}: missing variable {exc.args[0]!r}") from None
        return matrix_system_from_dict(data, source)
    raise InputError(f"path must end in .json, .csv or .mat to be read, got {source!r}")


def _json_variable(raw: dict, name: str, source: str):
    """A ``.mat`` variable holding JSON text, parsed (missing: KeyError)."""
    text = raw[name]
    if not isinstance(text, str):
        raise InputError(f"{source}: the variable {name!r} must be JSON text, got {type(text).__name__}")
    try:
        return json.loads(text)
    except RecursionError:
        raise InputError(f"{source}: the variable {name!r} is nested too deeply") from None
    except ValueError as err:
        raise InputError(f"{source}: the variable {name!r} is not JSON ({err})") from None


# --- Nastran and Abaqus ---------------------------------------------------------------------------
def _code_matrices(system: MechanicalSystem) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """M, C, K in a code's axes (:data:`CODE_AXES`): the ports' signs applied on both sides."""
    sign = np.ones(system.n_dof)
    sign[:2] = [CODE_AXES["w"]["sign"], CODE_AXES["psi"]["sign"]]
    return tuple(sign[:, None] * X * sign[None, :] for X in system.matrices())


#: Largest grid, node or scalar-point label a .bdf or .inp file names (Nastran's IDs stay below 10^8).
MAX_LABEL = 99_999_999


def check_labels(system: MechanicalSystem, node, first_label) -> tuple[int, int]:
    """The port node and the first internal label, checked: integers in 1..:data:`MAX_LABEL`, the
    internal labels' range clear of the port node and within the limit."""
    node = 1 if node is None else check_int_at_least("node", node, 1)
    first = FIRST_INTERNAL_LABEL if first_label is None else check_int_at_least("first_label", first_label, 1)
    last = first + max(system.n_internal, 1) - 1
    if node > MAX_LABEL or last > MAX_LABEL:
        raise InputError(f"node={node} and the internal labels {first}..{last} must stay at most {MAX_LABEL} "
                         "(Nastran's largest ID): give a smaller node or first_label")
    if system.n_internal and first <= node <= last:
        raise InputError(f"node={node} lies among the internal DOFs' labels {first}..{last}: give a first_label "
                         f"above {node} or below {node - system.n_internal + 1}")
    return node, first


def refuse_labels(suffix: str, node, first_label) -> None:
    """Refuse ``node`` or ``first_label`` for a format that names DOFs, not labels (never ignored)."""
    given = [name for name, value in (("node", node), ("first_label", first_label)) if value is not None]
    if given:
        raise InputError(f"{' and '.join(given)} label the DOFs of a .bdf or .inp file; a {suffix} file holds the "
                         "matrices by DOF name: leave them out, or write .bdf/.inp")


def _labels(system: MechanicalSystem, node: int, first: int) -> list[tuple[int, int]]:
    """(node or grid, component) of each DOF: the ports on ``node``, internal DOFs as scalar points."""
    ports = [(node, CODE_AXES["w"]["dof"]), (node, CODE_AXES["psi"]["dof"])]
    return ports + [(first + j, 0) for j in range(system.n_internal)]


def _header(system: MechanicalSystem, comment: str, fitted_on: tuple, node: int, first: int,
            static: str) -> list[str]:
    """Comment lines of at most 72 characters (Nastran reads 80 columns, Abaqus 256): the conventions
    in words, the node mapping and limits, then the conventions as JSON split over lines ``<comment>|``
    (a reader joins them)."""
    conv = end_conventions(*fitted_on)
    last = first + system.n_internal - 1
    words = (f"semitrack end system: {system.n_dof} DOFs ({system.n_internal} internal), SI units. "
             + conv["text"] + f" Ports on node {node}: {CODE_AXES['w']['note']} (DOF 2), "
             f"{CODE_AXES['psi']['note']} (DOF 6), for x along the track and y up; the port rows and columns "
             f"are written in those axes. Internal DOFs: labels {first}..{last}. Massless "
             "DOFs: implicit integration only. A static or preload step closes the cut with the 2x2 static "
             f"stiffness (the matrix {static} below) instead of the whole end; the internal DOFs' static state "
             "(listed below) is where a dynamic step that follows starts them; the internal masses are "
             "mathematical (no gravity on them).")
    lines = [f"{comment} {line}" for line in textwrap.wrap(words, 72 - len(comment) - 1)]
    data = json.dumps({k: v for k, v in conv.items() if k != "text"})
    width = 72 - len(comment) - 1
    lines.append(f"{comment} conventions as JSON (join the lines that start with {comment}|):")
    return lines + [f"{comment}|{data[k:k + width]}" for k in range(0, len(data), width)]


def _static_lines(system: MechanicalSystem, comment: str, labels: list[tuple[int, int]]) -> list[str]:
    """The internal DOFs' static state per unit port displacement, in the file's axes, as comments:
    ``u_j = T_w u_port_w + T_psi u_port_psi`` (label, T_w, T_psi; 0 for a DOF no spring holds)."""
    if not system.n_internal:
        return []
    # a unit displacement of DOF 2 (6) in the file's axes is the package's w (psi) times its sign
    T = np.column_stack([system.static_internal([CODE_AXES["w"]["sign"], 0.0]),
                         system.static_internal([0.0, CODE_AXES["psi"]["sign"]])])
    lines = [f"{comment} static state of the internal DOFs, per unit port displacement in this",
             f"{comment} file's axes (u_j = T_w * DOF 2 + T_psi * DOF 6 of node {labels[0][0]}):",
             f"{comment} label, T_w (u_j per m), T_psi (u_j per rad)"]
    return lines + [f"{comment} {labels[2 + j][0]}, {float(T[j, 0])!r}, {float(T[j, 1])!r}" for j in range(T.shape[0])]


def _hysteretic_warning(fitted_on: tuple, suffix: str) -> None:
    """Warn when a time-domain file is written for an end fitted to a hysteretic track."""
    name, _, damping = fitted_on
    if damping == "hysteretic":
        warn_user(f"export {suffix}: the end was fitted to the hysteretic track {name!r} (loss factors, not "
                  "causal); a time-domain code gets its causal fit, which follows that track less closely than "
                  "a viscous track's end follows its own: fit on damping='viscous' for time-domain use (the "
                  "file records track_damping)")


def _nastran_real(value: float) -> str:
    """A real in a 16-character large field, as many significant digits as fit (D exponent: double)."""
    for digits in range(12, 0, -1):
        mantissa, exponent = f"{value:.{digits}E}".split("E")
        text = f"{mantissa}D{int(exponent):+d}"
        if len(text) <= 16:
            return text
    raise AssertionError(value)  # a double always fits with one digit


def _dmig_lines(name: str, X: np.ndarray, labels: list[tuple[int, int]]) -> list[str]:
    """One symmetric DMIG matrix (IFO 6, TIN 2) in large-field fixed format, lower triangle by column."""
    def card(first: str, fields: list[str]) -> list[str]:
        rows = [f"{first:<8}" + "".join(f"{f:>16}" for f in fields[:4])]
        rows += ["*       " + "".join(f"{f:>16}" for f in fields[k:k + 4]) for k in range(4, len(fields), 4)]
        return rows
    lines = card("DMIG*", [name, "0", "6", "2", "0", "", "", ""])
    for j, (gj, cj) in enumerate(labels):
        terms = [k for k in range(j, X.shape[0]) if X[k, j] != 0.0]
        if not terms:
            continue
        fields = [name, str(gj), str(cj), ""]
        for k in terms:
            fields += [str(labels[k][0]), str(labels[k][1]), _nastran_real(X[k, j]), ""]
        lines += card("DMIG*", fields)
    return lines


def save_nastran_dmig(system: MechanicalSystem, path: str | os.PathLike, track: str | None = None,
                      band=None, *, node: int | None = None, first_label: int | None = None,
                      track_damping: str | None = None) -> Path:
    """Write M, C, K as Nastran ``DMIG`` bulk data for ``K2GG``, ``B2GG``, ``M2GG`` (module docstring).

    Parameters
    ----------
    system : MechanicalSystem
        The system.
    path : str or os.PathLike
        The ``.bdf`` file, written atomically.
    track : str, optional
        The track it models (default: the system's ``info``).
    band : sequence of two floats, optional
        The band it was fitted on (Hz).
    node : int, optional
        The grid of the user's end node that carries the ports (default 1).
    first_label : int, optional
        The first internal DOF's scalar point (default :data:`FIRST_INTERNAL_LABEL`).
    track_damping : {"", "hysteretic", "viscous"}, optional
        The damping model of the track it was fitted on (default: the system's ``info``).

    Returns
    -------
    Path
    """
    system = _check_system(system)
    node, first = check_labels(system, node, first_label)
    fitted_on = _info(system, track, band, track_damping)
    _hysteretic_warning(fitted_on, ".bdf")
    labels = _labels(system, node, first)
    lines = _header(system, "$", fitted_on, node, first, "KSTAT")
    lines += ["$ Case Control: K2GG = KEND, KENDR   B2GG = BEND, BENDR   M2GG = MEND, MENDR",
              "$ (each matrix is a leading part and its remainder: their sum is the double)",
              "$ A static or preload run: K2GG = KSTAT, KSTATR (the 2x2 static stiffness on",
              f"$ node {node}) in place of KEND, KENDR, and no B2GG, M2GG; the scalar points",
              "$ then carry nothing (constrain them, or let AUTOSPC)."]
    lines += _static_lines(system, "$", labels)
    if system.n_internal:
        lines.append(f"SPOINT  {first:<8}THRU    {first + system.n_internal - 1:<8}")
    for code, X in zip("MBK", _code_matrices(system)):
        lines += _split_dmig(f"{code}END", X, labels)
    lines += _split_dmig("KSTAT", _code_static(system), labels[:2])
    text = "\n".join(lines) + "\n"
    return atomic_write(path, lambda fh: fh.write(text), binary=False)


def _split_dmig(name: str, X: np.ndarray, labels: list[tuple[int, int]]) -> list[str]:
    """A matrix as two DMIG entries, ``name`` (what a field holds) and ``name + "R"`` (the rest)."""
    lead = np.vectorize(lambda v: float(_nastran_real(v).replace("D", "E")))(X)
    return _dmig_lines(name, lead, labels) + _dmig_lines(f"{name}R", X - lead, labels)


def _code_static(system: MechanicalSystem) -> np.ndarray:
    """The 2x2 static stiffness in a code's axes (both ports flip: the signs cancel, kept for clarity)."""
    sign = np.array([CODE_AXES["w"]["sign"], CODE_AXES["psi"]["sign"]])
    return sign[:, None] * system.static_stiffness() * sign[None, :]


def save_abaqus_matrix(system: MechanicalSystem, path: str | os.PathLike, track: str | None = None,
                       band=None, *, node: int | None = None, first_label: int | None = None,
                       track_damping: str | None = None) -> Path:
    """Write M, C, K as Abaqus ``*MATRIX INPUT`` keywords for ``*MATRIX ASSEMBLE`` (module docstring).

    Parameters
    ----------
    system : MechanicalSystem
        The system.
    path : str or os.PathLike
        The ``.inp`` file, written atomically (to ``*INCLUDE`` in the model).
    track : str, optional
        The track it models (default: the system's ``info``).
    band : sequence of two floats, optional
        The band it was fitted on (Hz).
    node : int, optional
        The label of the user's end node that carries the ports (default 1).
    first_label : int, optional
        The node of the first internal DOF (default :data:`FIRST_INTERNAL_LABEL`).
    track_damping : {"", "hysteretic", "viscous"}, optional
        The damping model of the track it was fitted on (default: the system's ``info``).

    Returns
    -------
    Path
    """
    system = _check_system(system)
    node, first = check_labels(system, node, first_label)
    fitted_on = _info(system, track, band, track_damping)
    _hysteretic_warning(fitted_on, ".inp")
    labels = [(label, max(dof, 1)) for label, dof in _labels(system, node, first)]  # internal: DOF 1 of a node
    lines = _header(system, "**", fitted_on, node, first, "END_K_STATIC")
    lines[0:0] = ["** For Abaqus (*MATRIX INPUT, *MATRIX ASSEMBLE). Not for CalculiX: it has no matrix",
                  "** keyword for rotations or damping and skips these cards, running without the end."]
    lines += ["** END_K_STATIC: the 2x2 static stiffness, for a static or preload analysis:",
              "** assemble STIFFNESS=END_K_STATIC alone there (the internal nodes then carry",
              "** nothing: constrain them)."]
    lines += _static_lines(system, "**", labels)
    if system.n_internal:
        lines.append("*NODE, NSET=SEMITRACK_END_INTERNAL")
        lines += [f"{label}, 0., 0., 0." for label, _ in labels[2:]]
    for name, X, rows in zip(("END_M", "END_C", "END_K", "END_K_STATIC"),
                             (*_code_matrices(system), _code_static(system)), (labels,) * 3 + (labels[:2],)):
        lines.append(f"*MATRIX INPUT, NAME={name}")
        lines += [f"{rows[i][0]}, {rows[i][1]}, {rows[j][0]}, {rows[j][1]}, {float(X[i, j])!r}"
                  for j in range(X.shape[0]) for i in range(j, X.shape[0]) if X[i, j] != 0.0]
    lines.append("*MATRIX ASSEMBLE, STIFFNESS=END_K, MASS=END_M, VISCOUS DAMPING=END_C")
    text = "\n".join(lines) + "\n"
    return atomic_write(path, lambda fh: fh.write(text), binary=False)
