"""Track description files in TOML: read, validate with located messages, write.

The format mirrors :class:`semitrack.Track` (examples ship in ``semitrack/examples``)::

    type = "slab"            # or "ballasted"
    name = "my track"        # optional
    [rail]    rho, E, G, A, I, kappa, eta_rail
    [pad]     kv, kphi, eta_pad, spacing
    [ballast] sleeper_mass, kb, eta_ballast      (ballasted only)

Every error is a :class:`TrackFileError` (a ValueError) whose message names the file, the line
where it can be found, the key, the value and the rule.
"""

from __future__ import annotations

import json
import math
import re
import tomllib
from importlib import resources
from pathlib import Path

from .tracks import Track

SECTIONS = {
    "rail": ("rho", "E", "G", "A", "I", "kappa", "eta_rail"),
    "pad": ("kv", "kphi", "eta_pad", "spacing"),
    "ballast": ("sleeper_mass", "kb", "eta_ballast"),
}
TYPES = ("slab", "ballasted")
EXAMPLES = ("slab", "ballasted")


class TrackFileError(ValueError):
    """A track file that cannot be read or does not describe a valid track."""


def example_path(name: str) -> Path:
    """Path of a shipped example file, ``"slab"`` or ``"ballasted"``."""
    if name not in EXAMPLES:
        raise ValueError(f"example must be one of {EXAMPLES}, got {name!r}")
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


def load_track_toml(path) -> Track:
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
        values out of range. The message names the file, line, key, value and rule.
    """
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as err:
        raise TrackFileError(f"{path}: cannot read the track file ({err.strerror})") from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as err:
        raise TrackFileError(f"{path}: not a valid TOML file: {err}") from None
    return track_from_dict(data, source=str(path), text=text)


def track_from_dict(data: dict, source: str = "track description", text: str = "") -> Track:
    """Build a Track from the parsed contents of a track file (see :func:`load_track_toml`)."""

    def where(section, key):
        line = _line_of(text, section, key) if text else None
        return f"{source}, line {line}" if line else source

    def fail(section, key, message):
        raise TrackFileError(f"{where(section, key)}: {message}")

    unknown_top = sorted(set(data) - {"type", "name", *SECTIONS})
    if unknown_top:
        key = unknown_top[0]
        fail(None, key, f"unknown key {key!r}; allowed at the top level: type, name, [rail], [pad], [ballast]")
    kind = data.get("type")
    if kind is None:
        fail(None, "type", f'missing key "type"; it must be one of {TYPES}')
    if kind not in TYPES:
        fail(None, "type", f"type must be one of {TYPES}, got {kind!r}")
    name = data.get("name", kind)
    if not isinstance(name, str):
        fail(None, "name", f"name must be a string, got {name!r}")
    needed = ("rail", "pad", "ballast") if kind == "ballasted" else ("rail", "pad")
    if kind == "slab" and "ballast" in data:
        fail("ballast", "", 'a [ballast] section needs type = "ballasted"; remove it for a slab track')
    params = {}
    for section in needed:
        table = data.get(section)
        if table is None:
            fail(None, section, f"missing section [{section}] with keys {', '.join(SECTIONS[section])}")
        if not isinstance(table, dict):
            fail(None, section, f"{section} must be a table [{section}], got {table!r}")
        unknown = sorted(set(table) - set(SECTIONS[section]))
        if unknown:
            fail(section, unknown[0], f"unknown key {unknown[0]!r} in [{section}]; allowed: {', '.join(SECTIONS[section])}")
        for key in SECTIONS[section]:
            if key not in table:
                fail(section, "", f"missing key {key!r} in [{section}]")
            value = table[key]
            if isinstance(value, bool) or not isinstance(value, (int, float)):
                fail(section, key, f"{key} must be a number, got {value!r}")
            value = float(value)
            nonneg = key in ("kphi",) or key.startswith("eta")
            ok = math.isfinite(value) and (value >= 0 if nonneg else value > 0)
            if not ok:
                rule = "non-negative and finite" if nonneg else "positive and finite"
                fail(section, key, f"{key} must be {rule}, got {table[key]!r}")
            params[key] = value
    try:
        return Track(name=name, **params)
    except (TypeError, ValueError) as err:  # cross-field rules of Track
        raise TrackFileError(f"{source}: {err}") from None


def track_to_toml(track: Track) -> str:
    """The TOML text of a track description (a round trip of :func:`load_track_toml`)."""
    kind = "ballasted" if track.is_ballasted else "slab"
    # A JSON string is a valid TOML basic string: quotes and backslashes come out escaped.
    lines = [f'type = "{kind}"', f"name = {json.dumps(track.name)}", ""]
    for section in ("rail", "pad") + (("ballast",) if track.is_ballasted else ()):
        lines.append(f"[{section}]")
        lines += [f"{key} = {getattr(track, key)!r}" for key in SECTIONS[section]]
        lines.append("")
    return "\n".join(lines)
