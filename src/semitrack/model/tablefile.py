"""Measured curves in CSV files: a frequency and a complex value per row, read with located messages.

The format (what a spreadsheet or a measurement system exports)::

    # any number of comment lines, e.g. where the data come from
    f_Hz, re, im
    0, 5.1e7, 0
    10, 5.3e7, 6.2e6
    ...

One header row that names the three columns by meaning, read word by word (case and
punctuation aside): first the frequency (its first word ``f``, ``freq`` or ``frequency``; in Hz:
``f``, ``f_Hz``, ``f (Hz)``, ``frequency [Hz]``), then the real part (a word ``re`` or ``real``:
``re``, ``Re k (N/m)``, ``real_N_per_m``) and the imaginary part (``im``, ``imag`` or
``imaginary``); then one row per frequency, in the SI unit of the table's quantity
(:data:`semitrack.model.curves.TABLE_QUANTITIES`) and the package's time factor
``exp(i omega t)``. Columns are separated by commas; blank lines and lines starting with ``#``
are skipped, each line on its own; a byte-order mark is dropped. A header that names another
table or unit (a magnitude, a phase, dB, kHz, an angular frequency, kN or mm) is refused by that
word, not misread or converted. The file is read as bounded UTF-8 text
(:func:`semitrack.base.files.read_text`): nothing in it is executed or evaluated, numbers are
parsed by ``float`` and must be finite.

Every error is a :class:`~semitrack.base.errors.InputError` on one line that names the file,
the line and the rule; the table's own rules (increasing frequencies, passivity) follow, from
:class:`~semitrack.model.curves.FrequencyTable`.
"""

from __future__ import annotations

import math
import os
import re

import numpy as np

from ..base.errors import InputError
from ..base.files import check_input_path, read_text
from .curves import MAX_TABLE_POINTS, FrequencyTable

__all__ = ["load_frequency_table", "MAX_TABLE_BYTES"]

#: Largest CSV file read (bytes): some 100 000 rows of three numbers.
MAX_TABLE_BYTES = 10_000_000


def load_frequency_table(path: str | os.PathLike, quantity: str = "stiffness", outside: str = "refuse"
                         ) -> FrequencyTable:
    """Read a measured curve from a CSV file.

    Parameters
    ----------
    path : str or os.PathLike
        The CSV file (format in the module's docstring).
    quantity : {"stiffness", "receptance", "mobility", "accelerance"}
        What its values are: N/m or N m/rad, m/N, m/(s N), m/(s^2 N). A mobility or accelerance
        becomes a receptance.
    outside : {"refuse", "hold"}
        What the table does below its first and above its last frequency
        (:class:`~semitrack.model.curves.FrequencyTable`).

    Returns
    -------
    FrequencyTable
        With ``source`` the path as given and ``file`` the resolved path.

    Raises
    ------
    InputError
        If the file is missing or unreadable, too large, not UTF-8, has no header or a malformed
        row, or its table breaks a rule of :class:`~semitrack.model.curves.FrequencyTable`
        (frequencies not increasing, a value that is not passive): one line, naming the file
        and, for a row, its line.
    """
    path = check_input_path(path, "path")
    try:
        text = read_text(path, MAX_TABLE_BYTES, "CSV table")
    except OSError as err:
        raise InputError(f"{path}: cannot read the table ({err.strerror or err})") from None
    f, values = _parse(text, str(path))
    try:
        return FrequencyTable(f, values, quantity=quantity, outside=outside, source=str(path),
                              file=str(path.resolve()))
    except ValueError as err:
        message = str(err)
        raise InputError(message if message.startswith(str(path)) else f"{path}: {message}") from None


def _parse(text: str, source: str) -> tuple[np.ndarray, np.ndarray]:
    """Frequencies and complex values of the table's rows, each number checked.

    Lines are taken one at a time (a comment can never swallow the rows after it), split at
    commas; a byte-order mark (a spreadsheet's "CSV UTF-8") is dropped.
    """
    lines = [(number, line.strip()) for number, line in enumerate(text.removeprefix("\ufeff").splitlines(), start=1)]
    rows = [(number, [cell.strip().strip('"') for cell in line.split(",")]) for number, line in lines
            if line and not line.startswith("#")]
    if not rows:
        raise InputError(f"{source}: no header row (e.g. 'f_Hz, re, im') and no data")
    number, names = rows[0]
    _check_header(source, number, names)
    data = rows[1:]
    if len(data) > MAX_TABLE_POINTS:
        raise InputError(f"{source}: {len(data)} rows, more than the limit of {MAX_TABLE_POINTS}")
    out = np.empty((len(data), 3))
    for i, (number, row) in enumerate(data):
        if len(row) != 3:
            raise InputError(f"{source}, line {number}: {len(row)} columns, expected 3 ({', '.join(names)})"
                             f"{_separator_hint(row)}")
        for j, cell in enumerate(row):
            try:
                value = float(cell)
            except ValueError:
                raise InputError(f"{source}, line {number}: {names[j]} is not a number: {cell[:40]!r}") from None
            if not math.isfinite(value):
                raise InputError(f"{source}, line {number}: {names[j]} must be finite, got {cell!r}")
            out[i, j] = value
    return out[:, 0], out[:, 1] + 1j * out[:, 2]


#: How a header names its columns, read by meaning (case aside), word by word: the frequency, the
#: real part, the imaginary part. Each name is split into words (letters, or digits) so that
#: ``frequency_Hz``, ``f (Hz)``, ``Re k (N/m)`` and ``real_N_per_m`` all read.
FREQUENCY_WORDS = ("f", "freq", "frequency")
REAL_WORDS = ("re", "real")
IMAG_WORDS = ("im", "imag", "imaginary")
#: Words that name another table (a magnitude and phase, a level) or another unit than the
#: package's (kHz, an angular frequency, a prefixed force or length): refused by name, never
#: converted or misread.
FOREIGN_WORDS = {"khz": "a frequency in kHz", "mhz": "a frequency in MHz", "omega": "an angular frequency",
                 "rad": "an angular frequency", "rpm": "a speed", "mag": "a magnitude", "magnitude": "a magnitude",
                 "abs": "a magnitude", "amplitude": "a magnitude", "phase": "a phase", "arg": "a phase",
                 "angle": "a phase", "deg": "degrees", "db": "decibels", "kn": "kN", "mn": "MN", "mm": "mm",
                 "um": "micrometres", "cm": "cm", "km": "km"}


#: Every other word a value column may hold: the symbol of a quantity and the SI units of the
#: quantities (N/m, N m/rad, m/N, m/(s N), m/(s^2 N)). A word outside these is refused, so that a
#: unit nobody listed (N/um, GN/m, N/in) is never read as the package's.
SYMBOL_WORDS = {"k", "kv", "kphi", "r", "y", "a", "g", "h", "z", "alpha", "value", "stiffness", "receptance",
                "mobility", "accelerance", "part", "of"}
SI_UNIT_WORDS = {"n", "m", "rad", "s", "per", "2"}


def _words(name: str) -> list[str]:
    """The words of a column's name: runs of letters (any alphabet: ``µ`` and ``μ`` too) or of digits,
    lower case (``f (Hz)``: f, hz)."""
    return re.findall(r"[^\W\d_]+|\d+", name.lower())


def _check_header(source: str, number: int, names: list[str]) -> None:
    """The header must say the columns are f (Hz), real part, imaginary part (module docstring)."""
    hint = ("the header must name the frequency in Hz, the real part and the imaginary part, e.g. 'f_Hz, re, im' "
            "or 'frequency (Hz), Re k (N/m), Im k (N/m)'")
    if len(names) != 3:
        raise InputError(f"{source}, line {number}: {hint}; got {len(names)} column(s) "
                         f"{', '.join(names)[:80]!r}{_separator_hint(names)}")
    for position, (name, part) in enumerate(zip(names, (FREQUENCY_WORDS, REAL_WORDS, IMAG_WORDS))):
        words = _words(name)
        # rad in a value's unit is a rotational stiffness's (N m/rad), the package's; in the frequency's, rad/s
        foreign = [w for w in words if w in FOREIGN_WORDS and not (position > 0 and w == "rad")]
        if foreign:
            raise InputError(f"{source}, line {number}: column {position + 1}, {name.strip()[:40]!r}, names "
                             f"{FOREIGN_WORDS[foreign[0]]}: a magnitude and phase, or kHz, is not read (convert "
                             f"the table); {hint}")
        if not words or (words[0] not in part if position == 0 else not set(words) & set(part)):
            what = ("the frequency (Hz) first", "the real part second", "the imaginary part third")[position]
            raise InputError(f"{source}, line {number}: {hint}; column {position + 1}, {name.strip()[:40]!r}, does "
                             f"not name {what}")
        if position == 0 and len(words) > 1 and "hz" not in words:
            raise InputError(f"{source}, line {number}: column 1, {name.strip()[:40]!r}, names no unit the package "
                             f"reads: the frequency in Hz ('f_Hz' or 'f (Hz)'; 'f' alone is Hz)")
        allowed = {"hz"} if position == 0 else set(part) | SYMBOL_WORDS | SI_UNIT_WORDS
        other = [w for w in words[1:] if w not in allowed] if position == 0 else [w for w in words if w not in allowed]
        if other:
            raise InputError(f"{source}, line {number}: column {position + 1}, {name.strip()[:40]!r}, names "
                             f"{other[0]!r}, which the package does not read as a unit: the frequency in Hz, the "
                             "values in the quantity's SI unit (N/m, N m/rad, m/N, m/(s N), m/(s^2 N))")


def _separator_hint(cells: list[str]) -> str:
    """A hint when a row is one cell that holds semicolons or tabs."""
    if len(cells) == 1:
        for sep, name in ((";", "semicolons"), ("\t", "tabs")):
            if sep in cells[0]:
                return f"; the columns look separated by {name}: separate them by commas"
    return ""
