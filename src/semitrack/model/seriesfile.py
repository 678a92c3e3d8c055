"""Two-column CSV files of what a wheel meets: a roughness spectrum or a rail profile.

The formats (what a measurement trolley's software or a spreadsheet exports)::

    # a roughness spectrum: one-third-octave band levels
    wavelength_m, level_dB          # or "wavelength (m), L (dB re 1 um)"
    0.4, 13.0
    0.315, 11.4
    ...

    # a rail profile: the surface's drop along the rail, downward positive
    x_m, r_m                        # or "x (m), roughness (m)"
    0.0, 0.0
    0.001, 2.1e-6
    ...

The header is read by meaning, word by word, as the frequency tables' (:mod:`.tablefile`): a
spectrum's first column has the word ``wavelength`` (in m) and its second ``level`` or ``l`` (in
dB re 1 um); a profile's first ``x`` (in m) and its second ``r``, ``roughness`` or ``profile`` (in
m). Any other word (mm, um, in, ft) is refused by name, never converted. Lines starting
with ``#`` and blank lines are skipped; numbers must be finite; at most :data:`MAX_ROWS` rows
and :data:`MAX_FILE_BYTES` bytes. Every error names the file, the line and the rule.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np

from ..base.errors import InputError
from ..base.files import check_input_path, read_text
from .irregularity import RailProfile

__all__ = ["SERIES_KINDS", "series_kind", "load_roughness_spectrum", "load_rail_profile"]

#: Largest file read (bytes) and most rows: a profile sampled every millimetre over 5 km.
MAX_FILE_BYTES = 200_000_000
MAX_ROWS = 5_000_000
#: The kinds of file, by the words of their header's columns: (first column's names, second
#: column's names, the other words each column may hold: its unit). Any other word is refused.
SERIES_KINDS = {"spectrum": (("wavelength", "lambda"), ("level", "l"), ({"m"}, {"db", "re", "1", "um", "µm", "μm"})),
                "profile": (("x",), ("r", "roughness", "profile", "z"), ({"m"}, {"m"}))}
#: Units refused by name (the package reads SI: m, and dB re 1 um for a level).
_FOREIGN_UNITS = {"mm": "mm", "um": "micrometres", "µm": "micrometres", "μm": "micrometres", "cm": "cm",
                  "km": "km", "nm": "nm"}


def _words(name: str) -> list[str]:
    return re.findall(r"[^\W\d_]+|\d+", name.lower())


def _rows(path: Path) -> tuple[list[str], list[tuple[int, list[str]]]]:
    """The header's cells and the data rows (line number, cells) of a two-column CSV."""
    text = read_text(path, MAX_FILE_BYTES, "series file")
    lines = [(n, line.strip()) for n, line in enumerate(text.lstrip("\ufeff").splitlines(), start=1)]
    lines = [(n, line) for n, line in lines if line and not line.startswith("#")]
    if not lines:
        raise InputError(f"{path}: no header row (e.g. 'wavelength_m, level_dB' or 'x_m, r_m') and no data")
    header = [c.strip() for c in lines[0][1].split(",")]
    if len(lines) - 1 > MAX_ROWS:
        raise InputError(f"{path}: {len(lines) - 1} rows, more than the {MAX_ROWS} read")
    return header, [(n, [c.strip() for c in line.split(",")]) for n, line in lines[1:]]


def series_kind(path: str | Path) -> str:
    """What a two-column CSV holds, from its header: ``"spectrum"`` or ``"profile"`` (module docstring).

    Parameters
    ----------
    path : str or Path
        The file.

    Returns
    -------
    str

    Raises
    ------
    InputError
        A header that names neither, or a unit the package does not read.
    """
    path = check_input_path(path, "path")
    header, _ = _rows(path)
    return _kind(path, header)


def _kind(path: Path, header: list[str]) -> str:
    hint = "a spectrum's header is 'wavelength_m, level_dB', a profile's 'x_m, r_m'"
    if len(header) != 2:
        raise InputError(f"{path}: the header must name two columns ({hint}), got {', '.join(header)[:80]!r}")
    first, second = (_words(c) for c in header)
    for column, words in ((header[0], first), (header[1], second)):
        foreign = [w for w in words if w in _FOREIGN_UNITS and "db" not in words]  # "dB re 1 um": a level's
        if foreign:
            raise InputError(f"{path}: the column {column!r} names {_FOREIGN_UNITS[foreign[0]]}, which is not read: "
                             "give metres (and a level in dB re 1 um)")
    for kind, (names, values, (unit_1, unit_2)) in SERIES_KINDS.items():
        if first and first[0] in names and set(second) & set(values):
            for column, words, allowed in ((header[0], first[1:], unit_1), (header[1], second, set(values) | unit_2)):
                other = [w for w in words if w not in allowed]
                if other:
                    raise InputError(f"{path}: the column {column!r} names {other[0]!r}, which is not read as a "
                                     f"unit: {hint}, in metres (a level in dB re 1 um)")
            return kind
    raise InputError(f"{path}: cannot tell a spectrum from a profile by its header {', '.join(header)[:80]!r}: "
                     f"{hint}")


def _numbers(path: Path, rows: list[tuple[int, list[str]]], names: tuple[str, str]) -> np.ndarray:
    out = np.empty((len(rows), 2))
    for i, (n, cells) in enumerate(rows):
        if len(cells) != 2:
            raise InputError(f"{path}, line {n}: {len(cells)} columns, expected 2")
        for j, cell in enumerate(cells):
            try:
                value = float(cell)
            except ValueError:
                raise InputError(f"{path}, line {n}: {names[j]} is not a number: {cell[:40]!r}") from None
            if not math.isfinite(value):
                raise InputError(f"{path}, line {n}: {names[j]} must be finite, got {cell[:40]!r}")
            out[i, j] = value
    return out


def load_roughness_spectrum(path: str | Path) -> tuple[np.ndarray, np.ndarray]:
    """A roughness spectrum file's band-centre wavelengths (m) and levels (dB re 1 um).

    Parameters
    ----------
    path : str or Path
        The CSV file (module docstring).

    Returns
    -------
    wavelengths, levels : ndarray
        As :func:`semitrack.roughness_from_spectrum` takes them (which checks the bands).
    """
    path = check_input_path(path, "path")
    header, rows = _rows(path)
    if _kind(path, header) != "spectrum":
        raise InputError(f"{path}: a rail profile ({', '.join(header)}), not a roughness spectrum")
    data = _numbers(path, rows, ("the wavelength", "the level"))
    if data.shape[0] < 1:
        raise InputError(f"{path}: no band levels after the header")
    return data[:, 0], data[:, 1]


def load_rail_profile(path: str | Path) -> RailProfile:
    """A rail profile file as a :class:`semitrack.RailProfile` (positions and drops, m).

    Parameters
    ----------
    path : str or Path
        The CSV file (module docstring): increasing positions, the drop zero at both ends.

    Returns
    -------
    RailProfile
    """
    path = check_input_path(path, "path")
    header, rows = _rows(path)
    if _kind(path, header) != "profile":
        raise InputError(f"{path}: a roughness spectrum ({', '.join(header)}), not a rail profile")
    data = _numbers(path, rows, ("x", "r"))
    try:
        return RailProfile(data[:, 0], data[:, 1])
    except InputError as err:
        raise InputError(f"{path}: {err}") from None
