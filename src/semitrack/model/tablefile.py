"""Measured curves in CSV files: a frequency and a complex value per row, read with located messages.

The format (what a spreadsheet or a measurement system exports)::

    # any number of comment lines, e.g. where the data come from
    f_Hz, re, im
    0, 5.1e7, 0
    10, 5.3e7, 6.2e6
    ...

One header row of three names (the first names the frequency, Hz), then one row per frequency:
the frequency, the real and the imaginary part of the value, in the units of the table's quantity
(:data:`semitrack.model.curves.TABLE_QUANTITIES`). Blank lines and lines starting with ``#`` are
skipped. The file is read as bounded UTF-8 text (:func:`semitrack.base.files.read_text`): nothing
in it is executed or evaluated, numbers are parsed by ``float`` and must be finite.

Every error is a :class:`~semitrack.base.errors.InputError` on one line that names the file,
the line and the rule; the table's own rules (increasing frequencies, passivity) follow, from
:class:`~semitrack.model.curves.FrequencyTable`.
"""

from __future__ import annotations

import csv
import math
import os
from pathlib import Path

import numpy as np

from ..base.errors import InputError
from ..base.files import read_text
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
    path = Path(path)
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
    """Frequencies and complex values of the table's rows, each number checked."""
    rows = [(number, row) for number, row in enumerate(csv.reader(text.splitlines()), start=1)
            if row and not row[0].lstrip().startswith("#") and any(cell.strip() for cell in row)]
    if not rows:
        raise InputError(f"{source}: no header row (e.g. 'f_Hz, re, im') and no data")
    number, header = rows[0]
    names = [cell.strip() for cell in header]
    if len(names) != 3 or not names[0].lower().startswith("f") or _is_number(names[0]):
        raise InputError(f"{source}, line {number}: the header must name three columns, the frequency (Hz) first, "
                         f"e.g. 'f_Hz, re, im'; got {','.join(header)[:80]!r}")
    data = rows[1:]
    if len(data) > MAX_TABLE_POINTS:
        raise InputError(f"{source}: {len(data)} rows, more than the limit of {MAX_TABLE_POINTS}")
    out = np.empty((len(data), 3))
    for i, (number, row) in enumerate(data):
        if len(row) != 3:
            raise InputError(f"{source}, line {number}: {len(row)} columns, expected 3 ({', '.join(names)})")
        for j, cell in enumerate(row):
            try:
                value = float(cell)
            except ValueError:
                shown = cell.strip()[:40]
                raise InputError(f"{source}, line {number}: {names[j]} is not a number: {shown!r}") from None
            if not math.isfinite(value):
                raise InputError(f"{source}, line {number}: {names[j]} must be finite, got {cell.strip()!r}")
            out[i, j] = value
    return out[:, 0], out[:, 1] + 1j * out[:, 2]


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True
