"""Track description files in TOML: read, validate with located messages, write.

The format mirrors :class:`semitrack.Track` (examples ship in ``semitrack/examples``)::

    type = "slab"            # or "ballasted"
    name = "my track"        # optional
    damping = "hysteretic"   # optional; or "viscous" (causal, see semitrack.Track)
    [rail]    rho, E, G, A, I, kappa, eta_rail
    [pad]     kv, kphi, eta_pad, spacing
    [ballast] sleeper_mass, kb, eta_ballast      (ballasted only)

Every error is a :class:`TrackFileError` (a ValueError) whose message names the file, the line
where it can be found, the key, the value and the rule (the Track's own rules, including its
bounds such as the largest spacing), and the file itself must be UTF-8 text of at most
:data:`MAX_FILE_BYTES`.
"""

from __future__ import annotations

import json
import re
import tomllib
from importlib import resources
from pathlib import Path
from typing import NoReturn

from ..base.checks import check_choice
from ..base.files import read_text
from .tracks import Track, check_track_field, require_track

SECTIONS = {
    "rail": ("rho", "E", "G", "A", "I", "kappa", "eta_rail"),
    "pad": ("kv", "kphi", "eta_pad", "spacing"),
    "ballast": ("sleeper_mass", "kb", "eta_ballast"),
}
TYPES = ("slab", "ballasted")
EXAMPLES = ("slab", "ballasted")

#: Largest track file read (bytes): a track file holds some 20 lines; this refuses e.g. /dev/zero.
MAX_FILE_BYTES = 1_000_000



class TrackFileError(ValueError):
    """A track file that cannot be read or does not describe a valid track."""


def example_path(name: str) -> Path:
    """Path of a shipped example file, ``"slab"`` or ``"ballasted"``."""
    check_choice("example", name, EXAMPLES)
    return Path(str(resources.files("semitrack") / "examples" / f"{name}.toml"))


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
    path = Path(path)
    try:
        text = read_text(path, MAX_FILE_BYTES, "track file")
    except OSError as err:
        raise TrackFileError(f"{path}: cannot read the track file ({err.strerror})") from None
    except ValueError as err:  # too large, not UTF-8
        raise TrackFileError(str(err)) from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as err:
        raise TrackFileError(f"{path}: not a valid TOML file: {err}") from None
    except RecursionError:
        raise TrackFileError(f"{path}: not a track file: its tables or arrays are nested too deeply") from None
    return track_from_dict(data, source=str(path), text=text)


def track_from_dict(data: dict, source: str = "track description", text: str = "") -> Track:
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

    Returns
    -------
    Track

    Raises
    ------
    TrackFileError
        Naming the source, line, key, value and rule.
    """
    where = _Locator(source, text)
    return _check_track_values(_parse_track_dict(data, where), where)


class _Locator:
    """Where a key sits in the file, for the messages of :class:`TrackFileError`."""

    def __init__(self, source: str, text: str):
        self.source, self.text = source, text

    def fail(self, section: str | None, key: str, message: str) -> NoReturn:
        """Raise a TrackFileError for ``key`` in ``[section]`` (top level if None)."""
        line = _line_of(self.text, section, key) if self.text else None
        place = f"{self.source}, line {line}" if line else self.source
        raise TrackFileError(f"{place}: {message}")


def _parse_track_dict(data: dict, where: _Locator) -> dict[str, tuple[str | None, object]]:
    """The structure of a track file: known sections and keys, none missing.

    Returns ``{key: (section, raw value)}`` for every Track field the file gives (``name``
    at the top level), values not yet checked.
    """
    unknown_top = sorted(set(data) - {"type", "name", "damping", *SECTIONS})
    if unknown_top:
        key = unknown_top[0]
        where.fail(None, key, f"unknown key {key!r}; allowed at the top level: type, name, damping, [rail], [pad], "
                   "[ballast]")
    kind = data.get("type")
    if kind is None:
        where.fail(None, "type", f'missing key "type"; it must be one of {TYPES}')
    try:
        check_choice("type", kind, TYPES)
    except ValueError as err:
        where.fail(None, "type", str(err))
    if kind == "slab" and "ballast" in data:
        where.fail("ballast", "", 'a [ballast] section needs type = "ballasted"; remove it for a slab track')
    values: dict[str, tuple[str | None, object]] = {"name": (None, data.get("name", kind)),
                                                    "damping": (None, data.get("damping", "hysteretic"))}
    for section in ("rail", "pad", "ballast") if kind == "ballasted" else ("rail", "pad"):
        values.update({key: (section, value) for key, value in _section(data, section, where).items()})
    return values


def _section(data: dict, section: str, where: _Locator) -> dict:
    """The table ``[section]`` of the file, with exactly the keys of :data:`SECTIONS`."""
    allowed = SECTIONS[section]
    table = data.get(section)
    if table is None:
        where.fail(None, section, f"missing section [{section}] with keys {', '.join(allowed)}")
    if not isinstance(table, dict):
        where.fail(None, section, f"{section} must be a table [{section}], got {table!r}")
    unknown = sorted(set(table) - set(allowed))
    if unknown:
        where.fail(section, unknown[0], f"unknown key {unknown[0]!r} in [{section}]; allowed: {', '.join(allowed)}")
    missing = [key for key in allowed if key not in table]
    if missing:
        where.fail(section, "", f"missing key {missing[0]!r} in [{section}]")
    return table


def _check_track_values(values: dict[str, tuple[str | None, object]], where: _Locator) -> Track:
    """Apply the Track's rules to each parsed value (located), then build the Track."""
    params = {}
    for key, (section, value) in values.items():
        try:
            params[key] = check_track_field(key, value)
        except (TypeError, ValueError) as err:
            where.fail(section, key, str(err))
    try:
        return Track(**params)
    except (TypeError, ValueError) as err:  # rules between fields
        raise TrackFileError(f"{where.source}: {err}") from None


def track_to_toml(track: Track) -> str:
    """The TOML text of a track description (a round trip of :func:`load_track_toml`).

    Parameters
    ----------
    track : Track
        The track to describe.
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
        lines += [f"{key} = {getattr(track, key)!r}" for key in SECTIONS[section]]
        lines.append("")
    return "\n".join(lines)
