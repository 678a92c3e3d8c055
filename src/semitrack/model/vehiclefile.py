"""Vehicle description files in TOML: a wheel, wheels on their own suspensions, or a bogie, read
with located messages and written back.

The format mirrors :class:`semitrack.Wheel`, :class:`semitrack.WheelGroup` and
:class:`semitrack.Bogie` (examples ship in ``semitrack/examples``: ``bogie``, ``wheel``)::

    type = "bogie"           # or "wheel" (one wheel), "wheels" (several, each on its suspension)
    name = "my bogie"        # optional: a label for the reader (checked as text; the vehicle holds none)
    [wheel]   mass, preload, hertz_constant, primary_stiffness, primary_damping, radius
              (each optional: the Wheel's defaults; a bogie's wheel needs primary_stiffness > 0)
    [bogie]   wheelbase, frame_mass, frame_inertia, body_mass, secondary_stiffness,
              secondary_damping    (type = "bogie"; each optional: the Bogie's defaults)
    [wheels]  spacing = [0.0, -2.5]   (type = "wheels": each wheel's offset along +x from the
              first, m; every wheel is the [wheel])

Values in SI units (kg, N, N/m, N s/m, m, kg m^2; the Hertz constant in N/m^1.5). Every error is
a :class:`~semitrack.model.trackfile.TrackFileError` naming the file, the line, the key and the
rule (the classes' own rules, so that a file and a call refuse the same values); the file must be
UTF-8 text of at most :data:`~semitrack.model.trackfile.MAX_FILE_BYTES` (read as track files are,
:func:`~semitrack.model.trackfile.read_toml`).
"""

from __future__ import annotations

import dataclasses
import json
from importlib import resources
from pathlib import Path

from ..base.checks import check_string
from ..base.errors import BadInput
from .trackfile import Locator, read_toml
from .vehicle import Bogie, Vehicle, WheelGroup
from .wheel import Wheel

__all__ = ["VEHICLE_TYPES", "VEHICLE_EXAMPLES", "load_vehicle_toml", "vehicle_from_dict", "vehicle_to_toml",
           "vehicle_example_path"]

#: The kinds of vehicle a file describes.
VEHICLE_TYPES = ("wheel", "wheels", "bogie")
#: The keys of each table (all optional: the classes' defaults).
WHEEL_KEYS = ("mass", "preload", "hertz_constant", "primary_stiffness", "primary_damping", "radius")
BOGIE_KEYS = ("wheelbase", "frame_mass", "frame_inertia", "body_mass", "secondary_stiffness", "secondary_damping")
WHEELS_KEYS = ("spacing",)
#: The vehicle files that ship with the package (``semitrack example NAME``).
VEHICLE_EXAMPLES = ("bogie", "wheel")


def vehicle_example_path(name: str) -> Path:
    """The path of a shipped vehicle file (:data:`VEHICLE_EXAMPLES`)."""
    if name not in VEHICLE_EXAMPLES:
        raise BadInput(f"name must be one of {VEHICLE_EXAMPLES}, got {name!r}")
    return Path(str(resources.files("semitrack") / "examples" / f"{name}.toml"))


def load_vehicle_toml(path: str | Path) -> Vehicle:
    """Read a vehicle description file (module docstring).

    Parameters
    ----------
    path : str or Path
        The TOML file.

    Returns
    -------
    Vehicle
        A :class:`semitrack.WheelGroup` (one wheel or several) or a :class:`semitrack.Bogie`.

    Raises
    ------
    TrackFileError
        Missing, unreadable, too large or not TOML; unknown or missing keys; values the classes
        refuse. The message names the file, the line, the key and the rule.
    """
    data, text, path = read_toml(path, "vehicle file")
    return vehicle_from_dict(data, source=str(path), text=text)


def _table(data: dict, section: str, keys: tuple[str, ...], where: Locator) -> dict:
    table = data.get(section, {})
    if not isinstance(table, dict):
        where.fail(None, section, f"{section} must be a table [{section}], got {type(table).__name__}")
    unknown = sorted(set(table) - set(keys))
    if unknown:
        where.fail(section, unknown[0], f"[{section}]: unknown key {unknown[0]!r}; the keys are {', '.join(keys)}")
    return table


def _build(cls, table: dict, section: str, where: Locator, **extra):
    """``cls(**table, **extra)``, its refusal located at the key it names (else the section)."""
    try:
        return cls(**table, **extra)
    except BadInput as err:
        key = next((k for k in table if k in str(err).split()[0] or str(err).startswith(k)), "")
        where.fail(section, key, f"[{section}] {err}")


def vehicle_from_dict(data: dict, source: str = "vehicle description", text: str = "") -> Vehicle:
    """Build a vehicle from the parsed contents of a vehicle file (see :func:`load_vehicle_toml`).

    Parameters
    ----------
    data : dict
        The TOML document as a dict.
    source : str
        The file name quoted in messages.
    text : str
        The file's text; when given, messages name the line of the offending key.

    Returns
    -------
    Vehicle
    """
    where = Locator(source, text)
    if not isinstance(data, dict):
        where.fail(None, "", f"a vehicle file is a table of keys, got {type(data).__name__}")
    kind = data.get("type")
    if kind not in VEHICLE_TYPES:
        where.fail(None, "type", f"type must be one of {', '.join(map(repr, VEHICLE_TYPES))}, got {kind!r}")
    sections = {"wheel": ("wheel",), "wheels": ("wheel", "wheels"), "bogie": ("wheel", "bogie")}[kind]
    unknown = sorted(set(data) - {"type", "name", *sections})
    if unknown:
        where.fail(None, unknown[0], f"unknown key {unknown[0]!r} for type = {kind!r}; allowed: type, name, "
                   + ", ".join(f"[{s}]" for s in sections))
    if "name" in data and not isinstance(data["name"], str):
        where.fail(None, "name", f"name must be text, got {data['name']!r}")
    wheel_table = _table(data, "wheel", WHEEL_KEYS, where)
    if kind == "bogie":
        defaults = {f.name: f.default_factory() for f in dataclasses.fields(Bogie) if f.name == "wheel"}["wheel"]
        wheel = _build(Wheel, {**{k: getattr(defaults, k) for k in WHEEL_KEYS}, **wheel_table}, "wheel", where)
        return _build(Bogie, _table(data, "bogie", BOGIE_KEYS, where), "bogie", where, wheel=wheel)
    wheel = _build(Wheel, wheel_table, "wheel", where)
    if kind == "wheel":
        return WheelGroup((wheel,))
    spacing = _table(data, "wheels", WHEELS_KEYS, where).get("spacing")
    if not isinstance(spacing, list) or not spacing:
        where.fail("wheels", "spacing", f"[wheels] spacing must be a list of offsets (m) from the first wheel, "
                   f"e.g. [0.0, -2.5], got {spacing!r}")
    group = _build(WheelGroup, {"members": (wheel,) * len(spacing), "spacing": tuple(spacing)}, "wheels", where)
    return group


def vehicle_to_toml(vehicle: Vehicle, name: str = "") -> str:
    """A vehicle file's text for ``vehicle`` (read back by :func:`load_vehicle_toml` to the same vehicle).

    Parameters
    ----------
    vehicle : WheelGroup or Bogie
        The vehicle; a WheelGroup's wheels must be alike (a file holds one [wheel]).
    name : str
        The ``name`` written (optional).

    Returns
    -------
    str
    """
    def table(obj, keys):
        return [f"{k} = {float(getattr(obj, k))!r}" for k in keys]

    name = check_string("name", name)
    quoted = json.dumps(name)  # a TOML basic string: JSON's escapes are TOML's

    lines = []
    if isinstance(vehicle, Bogie):
        lines += ['type = "bogie"'] + ([f"name = {quoted}"] if name else [])
        lines += ["", "[wheel]"] + table(vehicle.wheel, WHEEL_KEYS) + ["", "[bogie]"] + table(vehicle, BOGIE_KEYS)
    elif isinstance(vehicle, WheelGroup):
        wheels = vehicle.members
        if any(w != wheels[0] for w in wheels):
            raise BadInput("vehicle_to_toml writes wheels that are alike (a file holds one [wheel]); these differ")
        if any(w.defects for w in wheels):
            raise BadInput("vehicle_to_toml does not write a wheel's defects (flats, polygons) yet: a file would "
                           "drop them")
        kind = "wheel" if len(wheels) == 1 else "wheels"
        lines += [f'type = "{kind}"'] + ([f"name = {quoted}"] if name else [])
        lines += ["", "[wheel]"] + table(wheels[0], WHEEL_KEYS)
        if kind == "wheels":
            lines += ["", "[wheels]", f"spacing = {[float(s) for s in vehicle.spacing]!r}"]
    else:
        raise BadInput(f"vehicle must be a WheelGroup or a Bogie, got {type(vehicle).__name__}")
    return "\n".join(lines) + "\n"
