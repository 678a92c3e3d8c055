"""Track description files in TOML: read, validate with located messages, write.

The format mirrors :class:`semitrack.Track` (examples ship in ``semitrack/examples``)::

    type = "slab"            # or "ballasted"
    name = "my track"        # optional
    damping = "hysteretic"   # optional; or "viscous" (causal, see semitrack.Track)
    [rail]    rho, E, G, A, I, kappa, eta_rail
    [pad]     kv, kphi, eta_pad, spacing
    [ballast] sleeper_mass, kb, eta_ballast      (ballasted only)
    [slab]    length, fasteners, E, I, mass_per_length, support_stiffness, eta_support, eta_slab,
              and optionally shear_stiffness, rotary_inertia, cut
              (type = "slab" only, and optional: a flexible slab, semitrack.Slab, that couples
              the fasteners it carries; without it the slab is rigid, as the paper's)
    [foundation]  table, quantity, and optionally outside
              (type = "slab" only, and optional: a measured receptance under the pads, a
              sleeper's or a slab's, in place of the rigid ground; not with [slab])

Local changes of the supports follow the track, one ``[[changes]]`` table each, read by
:func:`load_track_file` (a :class:`~semitrack.Track` holds none, so :func:`load_track_toml`
refuses a file that has them rather than drop them)::

    [[changes]]
    support = 0          # support k sits at x = (k + 1/2) d
    kb = 0.0             # a hanging sleeper (any of kv, kphi, eta_pad, sleeper_mass, kb, eta_ballast)
    gap = 1e-3           # ... over a gap of 1 mm (m): the FE routes' ballast_gaps
    [[changes]]
    support = 5
    failed = true        # a failed fastener: the rail passes the support unheld (changes={5: None})

A pad stiffness (``kv``, ``kphi``) that depends on frequency is an inline table instead of a
number: ``kv = {table = "pad_kv.csv"}`` (a measured curve, :mod:`semitrack.model.tablefile`;
optionally ``outside = "hold"``) or ``kv = {model = "standard-linear-solid", k_static = ...,
k_high = ..., tau = ...}``. ``[foundation]`` reads ``table`` with ``quantity = "receptance"``,
``"mobility"`` or ``"accelerance"``. A table's path is relative to the track file's folder. Such a
curve holds its own damping (``eta_pad`` damps the pad stiffnesses given as numbers only).

Every error is a :class:`TrackFileError` (a ValueError) whose message names the file, the line
where it can be found, the key, the value and the rule (the Track's own rules, including its
bounds such as the largest spacing, and the Slab's for ``[slab]``), and the file itself must be
UTF-8 text of at most :data:`MAX_FILE_BYTES`.
"""

from __future__ import annotations

import dataclasses
import json
import re
import tomllib
from importlib import resources
from pathlib import Path
from typing import NoReturn

from ..base.checks import check_choice
from ..base.errors import InputError
from ..base.files import check_input_path, read_text
from .curves import OUTSIDE, FrequencyCurve, FrequencyFunction, FrequencyTable, StandardLinearSolid
from .slab import Slab
from .tablefile import load_frequency_table
from .tracks import SUPPORT_FIELDS, Track, check_track_field, require_track

#: The tables of Track fields, with their keys (all required).
SECTIONS = {
    "rail": ("rho", "E", "G", "A", "I", "kappa", "eta_rail"),
    "pad": ("kv", "kphi", "eta_pad", "spacing"),
    "ballast": ("sleeper_mass", "kb", "eta_ballast"),
}
#: Keys of the optional ``[slab]`` table, the fields of :class:`semitrack.Slab`: required ...
SLAB_KEYS = ("length", "fasteners", "E", "I", "mass_per_length", "support_stiffness", "eta_support", "eta_slab")
#: ... and optional (written by :func:`track_to_toml` only where they differ from the Slab's defaults).
SLAB_OPTIONAL_KEYS = ("shear_stiffness", "rotary_inertia", "cut")
_SLAB_DEFAULTS = {f.name: f.default for f in dataclasses.fields(Slab)}
#: Keys of a pad stiffness given as a table or a model, and of the ``[foundation]`` table.
TABLE_KEYS = ("table", "quantity", "outside")
SLS_KEYS = ("model", "k_static", "k_high", "tau")
#: The models a pad stiffness may name, and what they are.
CURVE_MODELS = {"standard-linear-solid": StandardLinearSolid}
#: What a measured foundation table may hold (a receptance, or what a measurement gives).
FOUNDATION_QUANTITIES = ("receptance", "mobility", "accelerance")
TYPES = ("slab", "ballasted")
#: The shipped example files, by name: the paper's two tracks, and the paper's rail and pads on the
#: two flexible slabs of the book's flexible-slab chapter (a CA-mortar slab and a floating slab).
EXAMPLES = ("slab", "ballasted", "mortar-slab", "floating-slab")

#: Largest track file read (bytes): a track file holds some 20 lines; this refuses e.g. /dev/zero.
MAX_FILE_BYTES = 1_000_000



class TrackFileError(InputError):
    """A track file that cannot be read or does not describe a valid track."""


def example_path(name: str) -> Path:
    """Path of a shipped example file, by its name in :data:`EXAMPLES` (``"floating-slab"`` is
    ``floating_slab.toml``)."""
    check_choice("name", name, EXAMPLES)
    return Path(str(resources.files("semitrack") / "examples" / f"{name.replace('-', '_')}.toml"))


def example_track(name: str) -> Track:
    """The track of a shipped example file (what ``semitrack example NAME`` prints).

    The files are where the example designs are defined, each value commented with its unit and
    where it comes from; this reads one of them.

    Parameters
    ----------
    name : {"slab", "ballasted", "mortar-slab", "floating-slab"}
        The example (:data:`EXAMPLES`): the paper's slab track (Table 2) and ballasted track
        (Table 5), and the paper's rail and pads (Table 2) on a flexible slab of 6.45 m with 10
        fasteners, either 0.20 m thick on cement-asphalt mortar (``"mortar-slab"``) or 0.30 m
        thick on an elastomer slab mat (``"floating-slab"``).

    Returns
    -------
    Track

    Raises
    ------
    ValueError
        If ``name`` is not one of :data:`EXAMPLES`.

    Examples
    --------
    >>> import semitrack as st
    >>> track = st.example_track("floating-slab")
    >>> track.slab.fasteners, track.slab.length, track.spacing
    (10, 6.45, 0.65)
    >>> track.slab.support_stiffness  # slab mat: 2e7 N/m^3 over 1.275 m of width (N/m^2)
    25500000.0
    >>> round(float(track.slab.natural_frequencies(1)[0]), 1)  # the free slab's bounce on the mat (Hz)
    26.0
    """
    return load_track_toml(example_path(name))


def _line_of(text: str, section: str | None, key: str) -> int | None:
    """1-based line of ``key = ...`` in ``[section]`` (top level if None), or of the
    ``[section]`` header itself when ``key`` is empty; None if not found."""
    current = None
    for number, line in enumerate(text.splitlines(), start=1):
        stripped = line.split("#", 1)[0].strip()
        header = re.fullmatch(r"\[\s*([A-Za-z0-9_]+)\s*\]", stripped)
        if header:
            current = header.group(1)
            if key == "" and current == section:
                return number
        elif key and current == section and re.match(rf"{re.escape(key)}\s*=", stripped):
            return number
    return None


def read_toml(path: str | Path, what: str = "track file") -> tuple[dict, str, Path]:
    """A description file's parsed document, its text and its path, or a located TrackFileError.

    Parameters
    ----------
    path : str or Path
        The TOML file, UTF-8 text of at most :data:`MAX_FILE_BYTES`.
    what : str
        What the file is, for the messages (``"track file"``, ``"vehicle file"``).

    Returns
    -------
    data : dict
    text : str
    path : Path
    """
    path = check_input_path(path, "path")
    try:
        text = read_text(path, MAX_FILE_BYTES, what)
    except OSError as err:
        raise TrackFileError(f"{path}: cannot read the {what} ({err.strerror})") from None
    except ValueError as err:  # too large, not UTF-8
        raise TrackFileError(str(err)) from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as err:
        raise TrackFileError(f"{path}: not a valid TOML file ({what}): {err}") from None
    except RecursionError:
        raise TrackFileError(f"{path}: not a {what}: its tables or arrays are nested too deeply") from None
    return data, text, path


def load_track_file(path: str | Path) -> tuple[Track, LocalChanges]:
    """Read a track file with its local changes (``[[changes]]``, module docstring).

    Parameters
    ----------
    path : str or Path
        The TOML file.

    Returns
    -------
    track : Track
    changes : LocalChanges
        ``changes.changes`` as :class:`semitrack.InfiniteTrack` and the FE models take them,
        ``changes.gaps`` as the FE routes' ``ballast_gaps``; both empty for a file without.

    Raises
    ------
    TrackFileError
        As :func:`load_track_toml`, and for a ``[[changes]]`` entry that names no support, an
        unknown key, a support twice, a failed fastener with fields, or a gap without
        ``kb = 0.0``. The values are checked by the models that take them.
    """
    data, text, path = read_toml(path)
    where = Locator(str(path), text, path.parent)
    changes = changes_from_dict(data, where)
    return track_from_dict({k: v for k, v in data.items() if k != "changes"}, source=str(path), text=text,
                           folder=path.parent), changes


def load_track_toml(path: str | Path) -> Track:
    """Read a track description file.

    Parameters
    ----------
    path : str or Path
        The TOML file.

    Returns
    -------
    Track

    Raises
    ------
    TrackFileError
        If the file is missing, not TOML, has unknown or missing keys, non-numeric values or
        values out of range (the Track's rules, :data:`semitrack.model.tracks.FIELD_RULES`), or if it is not
        UTF-8 text or larger than :data:`MAX_FILE_BYTES`. The message names the file, line,
        key, value and rule.
    """
    data, text, path = read_toml(path)
    if "changes" in data:
        rows = enumerate(text.splitlines(), start=1)
        line = next((n for n, row in rows if row.strip().startswith("[[changes")), None)
        place = f"{path}, line {line}" if line else str(path)
        raise TrackFileError(f"{place}: the file holds local changes ([[changes]]), which a Track does not: read it "
                             "with st.load_track_file(path) (the track and its changes; semitrack run and decay "
                             "take them), or remove them")
    return track_from_dict(data, source=str(path), text=text, folder=path.parent)


def track_from_dict(data: dict, source: str = "track description", text: str = "",
                    folder: str | Path | None = None) -> Track:
    """Build a Track from the parsed contents of a track file (see :func:`load_track_toml`).

    Two steps: ``_parse_track_dict`` checks the structure (sections and keys) and
    ``_check_track_values`` applies the Track's own rules (:data:`semitrack.model.tracks.FIELD_RULES`)
    to each value, so a file and a ``Track(...)`` call refuse exactly the same values.

    Parameters
    ----------
    data : dict
        The TOML document as a dict.
    source : str
        The file name (or another label) quoted in messages.
    text : str
        The file's text; when given, messages name the line of the offending key.
    folder : str or Path, optional
        The folder that relative table paths start from (the track file's); the current folder
        by default.

    Returns
    -------
    Track

    Raises
    ------
    TrackFileError
        Naming the source, line, key, value and rule.
    """
    where = Locator(source, text, Path(folder) if folder is not None else Path())
    return _check_track_values(_parse_track_dict(data, where), where)


class Locator:
    """Where a key sits in the file, for the messages of :class:`TrackFileError`."""

    def __init__(self, source: str, text: str, folder: Path = Path()):
        self.source, self.text, self.folder = source, text, folder

    def fail(self, section: str | None, key: str, message: str) -> NoReturn:
        """Raise a TrackFileError for ``key`` in ``[section]`` (top level if None)."""
        line = _line_of(self.text, section, key) if self.text else None
        place = f"{self.source}, line {line}" if line else self.source
        raise TrackFileError(f"{place}: {message}")


def _parse_track_dict(data: dict, where: Locator) -> dict[str, tuple[str | None, object]]:
    """The structure of a track file: known sections and keys, none missing.

    Returns ``{key: (section, raw value)}`` for every Track field the file gives (``name``
    at the top level), values not yet checked; a ``[slab]`` table is the one entry
    ``"slab": ("slab", table)``, its keys checked, its values not yet.
    """
    unknown_top = sorted(set(data) - {"type", "name", "damping", *SECTIONS, "slab", "foundation"})
    if unknown_top:
        key = unknown_top[0]
        where.fail(None, key, f"unknown key {key!r}; allowed at the top level: type, name, damping, [rail], [pad], "
                   "[ballast], [slab], [foundation]")
    kind = data.get("type")
    if kind is None:
        where.fail(None, "type", f'missing key "type"; it must be one of {TYPES}')
    try:
        check_choice("type", kind, TYPES)
    except ValueError as err:
        where.fail(None, "type", str(err))
    if kind == "slab" and "ballast" in data:
        where.fail("ballast", "", 'a [ballast] section needs type = "ballasted"; remove it for a slab track')
    if kind == "ballasted" and "slab" in data:
        where.fail("slab", "", 'a [slab] section (a flexible slab under the pads) needs type = "slab"; a ballasted '
                   "track has sleepers on ballast instead: remove it")
    if "foundation" in data and (kind == "ballasted" or "slab" in data):
        where.fail("foundation", "", "a [foundation] section (a measured receptance under the pads) replaces the "
                   'rigid ground of type = "slab"; it goes with neither [ballast] nor [slab]')
    values: dict[str, tuple[str | None, object]] = {"name": (None, data.get("name", kind)),
                                                    "damping": (None, data.get("damping", "hysteretic"))}
    for section in ("rail", "pad", "ballast") if kind == "ballasted" else ("rail", "pad"):
        values.update({key: (section, value) for key, value in _section(data, section, where).items()})
    if "slab" in data:  # the Slab's fields, under one key: E and I are the rail's names too
        values["slab"] = ("slab", _section(data, "slab", where, SLAB_KEYS, SLAB_OPTIONAL_KEYS))
    if "foundation" in data:
        values["foundation"] = ("foundation", _section(data, "foundation", where, ("table", "quantity"), ("outside",)))
    return values


def _section(data: dict, section: str, where: Locator, required: tuple[str, ...] | None = None,
             optional: tuple[str, ...] = ()) -> dict:
    """The table ``[section]`` of the file: all ``required`` keys (by default those of
    :data:`SECTIONS`), any of ``optional``, no other."""
    required = SECTIONS[section] if required is None else required
    table = data.get(section)
    if table is None:
        where.fail(None, section, f"missing section [{section}] with keys {', '.join(required)}")
    if not isinstance(table, dict):
        where.fail(None, section, f"{section} must be a table [{section}], got {table!r}")
    unknown = sorted(set(table) - set(required) - set(optional))
    if unknown:
        allowed = ", ".join(required) + (f", and optionally {', '.join(optional)}" if optional else "")
        where.fail(section, unknown[0], f"unknown key {unknown[0]!r} in [{section}]; allowed: {allowed}")
    missing = [key for key in required if key not in table]
    if missing:
        where.fail(section, "", f"missing key {missing[0]!r} in [{section}]")
    return table


def _check_track_values(values: dict[str, tuple[str | None, object]], where: Locator) -> Track:
    """Apply the Track's rules to each parsed value (located), then build the Track.

    A ``[slab]`` table becomes a :class:`Slab` by the Slab's own rules (:func:`_check_slab_values`);
    the rules between slab and track (the slab must carry its fasteners at the track's spacing,
    no sleepers beside it) are the Track's, located at the ``[slab]`` header.
    """
    values = dict(values)
    _, slab_table = values.pop("slab", (None, None))
    _, foundation = values.pop("foundation", (None, None))
    params = {}
    if foundation is not None:
        params["foundation"] = _curve("foundation", "", foundation, where, "receptance")
    for key, (section, value) in values.items():
        if key in ("kv", "kphi") and isinstance(value, dict):
            params[key] = _curve(section, key, value, where, "stiffness")
            continue
        try:
            params[key] = check_track_field(key, value)
        except (TypeError, ValueError) as err:
            where.fail(section, key, str(err))
    try:
        track = Track(**params)
    except (TypeError, ValueError) as err:  # rules between fields
        raise TrackFileError(f"{where.source}: {err}") from None
    if slab_table is None:
        return track
    slab = _check_slab_values(slab_table, where)
    try:
        return track.replace(slab=slab)
    except (TypeError, ValueError) as err:  # rules between the slab and the rest of the track
        where.fail("slab", "", f"[slab] {err}")


def _curve(section: str, key: str, spec: dict, where: Locator, kind: str) -> FrequencyCurve:
    """A frequency-dependent field of the file: a CSV table beside it, or a named model.

    ``key`` is the field (``kv``, ``kphi``) in ``[section]``, or ``""`` for the ``[foundation]``
    table itself; ``kind`` is what the curve must relate (stiffness, receptance).
    """
    label = f"[{section}] {key}".rstrip() if key else f"[{section}]"
    if kind == "stiffness" and "model" in spec and (not isinstance(spec["model"], str)
                                                    or spec["model"] not in CURVE_MODELS):
        where.fail(section, key, f"{label}: model must be one of {tuple(CURVE_MODELS)}, got {spec['model']!r}")
    if kind == "stiffness" and "model" in spec:
        allowed, required = SLS_KEYS, SLS_KEYS
    else:
        allowed, required = TABLE_KEYS, ("table", "quantity") if kind == "receptance" else ("table",)
    unknown = sorted(set(spec) - set(allowed))
    missing = [k for k in required if k not in spec]
    if unknown or missing:
        if kind == "stiffness":
            forms = ('{table = "file.csv"} (optionally outside = "hold") or {model = "standard-linear-solid", '
                     "k_static = ..., k_high = ..., tau = ...}")
        else:
            forms = 'table = "file.csv", quantity = "receptance", "mobility" or "accelerance", optionally outside'
        what = f"unknown key {unknown[0]!r}" if unknown else f"missing key {missing[0]!r}"
        where.fail(section, key, f"{label}: {what}; a curve is {forms}")
    try:
        if "model" in spec:
            return CURVE_MODELS[spec["model"]](**{k: v for k, v in spec.items() if k != "model"})
        quantity = spec.get("quantity", "stiffness")
        choices = FOUNDATION_QUANTITIES if kind == "receptance" else ("stiffness",)
        if quantity not in choices:
            raise InputError(f"quantity must be one of {choices}, got {quantity!r}")
        outside = spec.get("outside", "refuse")
        if outside not in OUTSIDE:
            raise InputError(f"outside must be one of {OUTSIDE}, got {outside!r}")
        if not isinstance(spec["table"], str) or not spec["table"]:
            raise InputError(f"table must name a CSV file (a string), got {spec['table']!r}")
        return load_frequency_table(where.folder / spec["table"], quantity, outside)
    except (TypeError, ValueError) as err:
        where.fail(section, key, f"{label}: {err}")


def _field_to_toml(key: str, value: object) -> str:
    """A Track field's TOML value: a float's shortest repr, a curve's inline table."""
    return _curve_to_toml(key, value) if isinstance(value, FrequencyCurve) else repr(value)


def _curve_to_toml(key: str, curve: FrequencyCurve) -> str:
    """An inline TOML table for a curve the file can hold: a model's parameters, a table's file."""
    if isinstance(curve, StandardLinearSolid):
        return (f'{{model = "standard-linear-solid", k_static = {curve.k_static!r}, k_high = {curve.k_high!r}, '
                f"tau = {curve.tau!r}}}")
    if isinstance(curve, FrequencyTable) and curve.file is not None:
        return "{" + ", ".join(_table_items(curve)) + "}"
    what = "Python code" if isinstance(curve, FrequencyFunction) else "built in Python, not read from a file"
    raise InputError(f"{key} is a {type(curve).__name__} ({what}), which a track file cannot hold: write its values "
                     "to a CSV table (f_Hz, re, im) and read it with st.load_frequency_table")


def _table_items(curve: FrequencyTable) -> list[str]:
    """``key = value`` of a table read from a file: its file, quantity (a stiffness's is implied) and ``outside``."""
    items = [("table", curve.file), ("quantity", curve.quantity), ("outside", curve.outside)]
    return [f"{key} = {json.dumps(value)}" for key, value in items if not (key == "quantity" and value == "stiffness")]


def _foundation_to_toml(curve: FrequencyCurve) -> list[str]:
    """The lines of a ``[foundation]`` table: the measured table's file, quantity and ``outside``."""
    if not (isinstance(curve, FrequencyTable) and curve.file is not None):
        _curve_to_toml("foundation", curve)  # raises: the file cannot hold it
    return _table_items(curve)


def _check_slab_values(table: dict, where: Locator) -> Slab:
    """The :class:`Slab` of a ``[slab]`` table (keys already checked), by the Slab's own rules.

    Each of the Slab's messages starts with the field it refuses (its checks name the parameter
    first), so the message is located at that key's line; "[slab]" in front tells the slab's E
    and I from the rail's.
    """
    try:
        return Slab(**table)
    except (TypeError, ValueError) as err:
        key = re.match(r"\w*", str(err)).group()
        where.fail("slab", key if key in table else "", f"[slab] {err}")


def track_to_toml(track: Track) -> str:
    """The TOML text of a track description (a round trip of :func:`load_track_toml`).

    Every float is written as its shortest repr, so the file reads back to the same Track, bit
    for bit. A flexible slab becomes a ``[slab]`` table with its required keys and those of its
    optional keys that differ from the :class:`Slab`'s defaults.

    Parameters
    ----------
    track : Track
        The track to describe.

    Returns
    -------
    str
        The file's text.
    """
    track = require_track(track)
    kind = "ballasted" if track.is_ballasted else "slab"
    # A JSON string is a valid TOML basic string: quotes and backslashes come out escaped.
    lines = [f'type = "{kind}"', f"name = {json.dumps(track.name)}"]
    if track.damping != "hysteretic":
        lines.append(f"damping = {json.dumps(track.damping)}")
    lines.append("")
    for section in ("rail", "pad") + (("ballast",) if track.is_ballasted else ()):
        lines.append(f"[{section}]")
        lines += [f"{key} = {_field_to_toml(key, getattr(track, key))}" for key in SECTIONS[section]]
        lines.append("")
    if track.has_flexible_slab:
        slab = track.slab
        keys = SLAB_KEYS + tuple(k for k in SLAB_OPTIONAL_KEYS if getattr(slab, k) != _SLAB_DEFAULTS[k])
        lines.append("[slab]")
        # repr of a float or an int is TOML; cut may be a name (a TOML string) or a mid-span number.
        lines += [f"{key} = {json.dumps(value) if isinstance(value := getattr(slab, key), str) else repr(value)}"
                  for key in keys]
        lines.append("")
    if track.foundation is not None:
        lines += ["[foundation]", *_foundation_to_toml(track.foundation), ""]
    return "\n".join(lines)


# --- local changes ([[changes]]) -----------------------------------------------------------------
#: The keys of a ``[[changes]]`` entry beside the support fields: the support, a failed fastener,
#: the gap a hanging sleeper hangs over.
CHANGE_KEYS = ("support", "failed", "gap")
#: Most ``[[changes]]`` entries a file may hold.
MAX_CHANGES = 100_000


@dataclasses.dataclass(frozen=True)
class LocalChanges:
    """The local changes of a track file: ``changes`` as :class:`semitrack.InfiniteTrack` takes
    them, and the hanging sleepers' gaps as the FE routes take them (``ballast_gaps``)."""

    changes: dict
    gaps: dict


def changes_from_dict(data: dict, where: Locator) -> LocalChanges:
    """The ``[[changes]]`` of a parsed track file, checked in structure (their values by the models)."""
    entries = data.get("changes", [])
    if not isinstance(entries, list) or not all(isinstance(e, dict) for e in entries):
        where.fail(None, "changes", "changes must be an array of tables, [[changes]] with support = k and the "
                   "support's fields (or failed = true)")
    if len(entries) > MAX_CHANGES:
        where.fail(None, "changes", f"a file holds at most {MAX_CHANGES} [[changes]], got {len(entries)}")
    changes, gaps = {}, {}
    for n, entry in enumerate(entries, start=1):
        label = f"[[changes]] number {n}"
        unknown = sorted(set(entry) - set(CHANGE_KEYS) - set(SUPPORT_FIELDS))
        if unknown:
            where.fail(None, "", f"{label}: unknown key {unknown[0]!r}; the keys are support, failed, gap and the "
                       f"support's fields {', '.join(SUPPORT_FIELDS)}")
        k = entry.get("support")
        if isinstance(k, bool) or not isinstance(k, int):
            where.fail(None, "", f"{label}: support must be the support's index k (an integer; support k sits at "
                       f"x = (k + 1/2) d), got {k!r}")
        if k in changes:
            where.fail(None, "", f"{label}: support {k} is changed twice; give each support one [[changes]]")
        fields = {key: entry[key] for key in SUPPORT_FIELDS if key in entry}
        failed = entry.get("failed", False)
        if not isinstance(failed, bool):
            where.fail(None, "", f"{label}: failed must be true or false, got {failed!r}")
        if failed and (fields or "gap" in entry):
            where.fail(None, "", f"{label}: failed = true takes the support away (a failed fastener: the rail "
                       "passes it unheld); it takes no fields or gap")
        if "gap" in entry:
            if fields.get("kb") != 0:
                where.fail(None, "", f"{label}: a gap hangs support {k}'s sleeper over it: give kb = 0.0 too")
            gaps[k] = entry["gap"]
        if not failed and not fields:
            where.fail(None, "", f"{label}: support {k} changes nothing; give its fields (e.g. kb = 0.0, a "
                       "hanging sleeper) or failed = true")
        changes[k] = None if failed else fields
    return LocalChanges(changes, gaps)
