"""Measured curves in CSV files: a frequency and a complex value per row, read with located messages.

The format (what a spreadsheet or a measurement system exports)::

    # any number of comment lines, e.g. where the data come from
    f_Hz, re, im
    0, 5.1e7, 0
    10, 5.3e7, 6.2e6
    ...

One header row that names the three columns, the frequency in Hz (``f``, ``f_Hz``, ``f (Hz)``,
``frequency``), the real part (``re``, ``real``) and the imaginary part (``im``, ``imag``); then
one row per frequency, in the units of the table's quantity
(:data:`semitrack.model.curves.TABLE_QUANTITIES`) and the package's time factor
``exp(i omega t)``. Columns are separated by commas; blank lines and lines starting with ``#``
are skipped, each line on its own; a byte-order mark is dropped. A magnitude-and-phase table or
a frequency in kHz is refused by its header, not misread. The file is read as bounded UTF-8 text
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


#: What the header's columns may be called (case aside): the frequency in Hz, the real part, the
#: imaginary part. A magnitude and phase, or a frequency in kHz, is another table: refused by name.
_HEADER = (("f", "f_hz", "freq", "freq_hz", "frequency", "frequency_hz"), ("re", "real"), ("im", "imag", "imaginary"))


def _check_header(source: str, number: int, names: list[str]) -> None:
    """The header must say the columns are f (Hz), real part, imaginary part."""
    hint = "the header must name the frequency in Hz, the real part and the imaginary part, e.g. 'f_Hz, re, im'"
    if len(names) != 3:
        raise InputError(f"{source}, line {number}: {hint}; got {len(names)} column(s) "
                         f"{', '.join(names)[:80]!r}{_separator_hint(names)}")
    for name, allowed in zip(names, _HEADER):
        key = re.sub(r"[\s()\[\]_]+", "_", name.lower()).strip("_")  # "f (Hz)", "f [Hz]" -> "f_hz"
        if key not in allowed:
            raise InputError(f"{source}, line {number}: {hint} (a magnitude and phase, or kHz, is not read); "
                             f"got {', '.join(names)[:80]!r}")


def _separator_hint(cells: list[str]) -> str:
    """A hint when a row is one cell that holds semicolons or tabs."""
    if len(cells) == 1:
        for sep, name in ((";", "semicolons"), ("\t", "tabs")):
            if sep in cells[0]:
                return f"; the columns look separated by {name}: separate them by commas"
    return ""
