"""A study's cases and results as data: checked inputs, one key per case, and its record on disk.

A study is a function run over a list of cases. Each case is a dict of inputs (numbers, strings,
None, tuples of them, a Track: whatever :func:`semitrack.base.records.encode` stores), each result
a dict of numbers. A case's record, one JSON file per case under the study's ``cache_dir``, holds
the function's name, the case and the result or the error, and a digest of all of it, written
atomically (an interrupted study leaves whole records only) and read back through the package's
non-executing reader: a record that is malformed, truncated, damaged anywhere (its digest), or
written for another case or function is recomputed, never trusted.
"""

from __future__ import annotations

import functools
import hashlib
import importlib.metadata
import json
import math
import os
import pickle
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path

import numpy as np

from ..base import records
from ..base.checks import brief
from ..base.errors import InputError, InputTypeError
from ..base.files import atomic_write, read_json

__all__ = ["ERROR", "MAX_CASES", "check_cases", "study_name", "case_key", "result_error", "error_text",
           "read_record", "write_record"]

#: The table's column of each case's error ("" when it ran).
ERROR = "error"
#: Most cases of one study (a million runs of a second each is eleven days of one core).
MAX_CASES = 1_000_000
#: Largest record file written and read back (bytes): a result is a few numbers, a case a few inputs;
#: a case holding arrays beyond it is run, and not stored (a warning says so).
MAX_RECORD_BYTES = 8_000_000
#: What a record file says it is, and its version.
FORMAT, VERSION = "semitrack study record", 1
#: Longest error message kept in the table (characters).
MAX_ERROR_CHARS = 500


def check_cases(cases: object) -> list[dict]:
    """``cases`` checked: a list of dicts of inputs with string keys, each storable in a record.

    Raises
    ------
    InputTypeError, InputError
        Naming ``cases[i]`` and the key.
    """
    if isinstance(cases, (str, bytes, Mapping)) or not isinstance(cases, Sequence):
        raise InputTypeError(f"cases must be a list of dicts of inputs, got {brief(cases)}")
    if len(cases) > MAX_CASES:
        raise InputError(f"cases holds {len(cases)} cases, more than {MAX_CASES}: split the study")
    out = []
    for i, case in enumerate(cases):
        if not isinstance(case, Mapping):
            raise InputTypeError(f"cases[{i}] must be a dict of inputs (func's keyword arguments), got {brief(case)}")
        for key in case:
            if not isinstance(key, str) or not key.isidentifier():
                raise InputError(f"cases[{i}] has the key {brief(key)}: keys are func's keyword names")
            if key == ERROR:
                raise InputError(f"cases[{i}] has the key {ERROR!r}, which the table keeps for each case's error")
        try:
            json.dumps(records.encode(dict(case)))
        except InputTypeError as err:
            raise InputTypeError(f"cases[{i}] holds an input a record cannot store ({err}): give numbers, strings, "
                                 "None, tuples of them or the package's records, and fix other objects in func "
                                 "(functools.partial)") from None
        except (RecursionError, ValueError):  # a case that holds itself, or an integer of thousands of digits
            raise InputError(f"cases[{i}] holds an input nested too deeply or too large to store") from None
        out.append(dict(case))
    return out


@functools.cache
def _package_version() -> str:
    """The installed package's version (its metadata; the root module is a layer above this one)."""
    try:
        return importlib.metadata.version("semitrack")
    except importlib.metadata.PackageNotFoundError:  # run from a source tree that is not installed
        return "source"


def _code_text(code) -> str:
    """What a function's code is, for its study's name: its bytecode, names and constants (nested code too)."""
    consts = [_code_text(c) if hasattr(c, "co_code") else repr(c) for c in code.co_consts]
    return f"{code.co_code.hex()}|{code.co_names}|{consts}"


def _fixed_arguments(func: functools.partial) -> bytes | None:
    """A partial's fixed arguments as bytes to digest (their record, else their pickle), or None."""
    try:
        return records.dumps({"args": list(func.args), "keywords": dict(func.keywords)}).encode()
    except (InputTypeError, RecursionError, ValueError):
        try:  # objects a record does not store: their pickle, only digested (never loaded)
            return pickle.dumps((func.args, func.keywords), protocol=4)
        except Exception:  # noqa: BLE001 - an object that will not pickle has no name to keep records under
            return None


def study_name(func: Callable) -> str | None:
    """The name a study's records are kept under, or None when ``func`` has none that identifies it.

    A function defined at a module's top level is named by its module, qualified name and a digest
    of its code (so that records of an edited function are not read back as its results) and of the
    package's version; a :func:`functools.partial` of one adds a digest of its fixed arguments (a
    partial of another track is another study). A lambda, a nested function, a method or a callable
    object has no such name: ``None``.
    """
    if isinstance(func, functools.partial):
        inner, fixed = study_name(func.func), _fixed_arguments(func)
        if inner is None or fixed is None:
            return None
        return f"{inner}[{hashlib.sha256(fixed).hexdigest()[:16]}]"
    code = getattr(func, "__code__", None)
    name = getattr(func, "__qualname__", "<")
    if code is None or not isinstance(name, str) or "<" in name or hasattr(func, "__self__"):
        return None
    digest = hashlib.sha256(f"{_package_version()}\n{_code_text(code)}".encode()).hexdigest()[:16]
    return f"{func.__module__}.{name}[{digest}]"


def _case_text(case: dict) -> str:
    return json.dumps(records.encode(case), sort_keys=True, separators=(",", ":"))


def case_key(name: str, case: dict) -> str:
    """The file stem of a case's record: a digest of the study's name and the case."""
    return hashlib.sha256(f"{name}\n{_case_text(case)}".encode()).hexdigest()[:40]


def result_error(result: object, inputs) -> tuple[dict | None, str]:
    """``(result, "")`` for a dict of numbers whose keys are none of the study's ``inputs``, else
    ``(None, what is wrong)``."""
    if not isinstance(result, Mapping):
        return None, f"func returned {brief(result)} ({type(result).__name__}), not a dict of numbers"
    out = {}
    for key, value in result.items():
        if not isinstance(key, str) or not key:
            return None, f"func returned the key {brief(key)}: the keys name the table's columns (strings)"
        if key in inputs or key == ERROR:
            return None, f"func returned the key {key!r}, which is also an input or the error column"
        if isinstance(value, (bool, np.bool_)):
            out[key] = bool(value)
        elif isinstance(value, (int, np.integer)) and -2**63 <= int(value) < 2**63:
            out[key] = int(value)
        elif isinstance(value, (float, np.floating)):
            out[key] = float(value)
        else:
            return None, f"func returned {key}={brief(value)} ({type(value).__name__}), not a number"
    return out, ""


def error_text(err: BaseException) -> str:
    """One line for the table: the exception's type and the first line of its message."""
    message = str(err).strip().splitlines()[0] if str(err).strip() else ""
    text = f"{type(err).__name__}: {message}" if message else type(err).__name__
    return text[:MAX_ERROR_CHARS]


def _digest(body: dict) -> str:
    """The digest a record carries of the rest of its content: a flipped bit anywhere is caught."""
    return hashlib.sha256(json.dumps(body, sort_keys=True, separators=(",", ":")).encode()).hexdigest()


def _record_path(folder: Path, key: str) -> Path:
    return folder / f"{key}.json"


def write_record(folder: Path, key: str, name: str, case: dict, result: dict | None, error: str,
                 seconds: float) -> str:
    """Store one case's outcome (atomically; a link in the folder is replaced, never written through).

    Returns
    -------
    str
        "" once stored, else why it was not (too large, or the file could not be written): the
        case's outcome stands, and a rerun computes it again.
    """
    body = {"format": FORMAT, "version": VERSION, "study": name, "case": records.encode(case),
            "result": records.encode(result), "error": error, "seconds": seconds if math.isfinite(seconds) else 0.0}
    text = json.dumps({**body, "digest": _digest(body)}, allow_nan=False, separators=(",", ":"))
    if len(text) > MAX_RECORD_BYTES:
        return f"its record would be {len(text)} bytes, more than {MAX_RECORD_BYTES}"
    try:
        atomic_write(_record_path(folder, key), lambda fh: fh.write(text), follow_links=False)
    except (OSError, ValueError) as err:  # a full disk, a FIFO or a folder planted under its name
        return str(err).splitlines()[0]
    return ""


def read_record(folder: Path, key: str, name: str, case: dict, inputs) -> tuple[dict | None, str, float] | None:
    """``(result, error, seconds)`` of a stored case, or None when there is none to trust.

    None for a missing record and for one that cannot be trusted: unreadable, malformed, of another
    format or version, of another study or case, or a result that is not a dict of numbers.
    """
    path = _record_path(folder, key)
    if not os.path.lexists(path) or path.is_symlink():
        return None
    try:
        data = read_json(path, MAX_RECORD_BYTES, "study record")
        if not isinstance(data, dict) or data.get("format") != FORMAT or data.get("version") != VERSION:
            return None
        if data.pop("digest", None) != _digest(data):  # damaged, or edited by hand
            return None
        if data.get("study") != name or json.dumps(data.get("case"), sort_keys=True,
                                                   separators=(",", ":")) != _case_text(case):
            return None
        error, seconds = data.get("error"), data.get("seconds")
        if not isinstance(error, str) or isinstance(seconds, bool) or not isinstance(seconds, (int, float)):
            return None
        result = records.decode(data.get("result"), {})
    except (OSError, ValueError, TypeError, RecursionError):
        return None
    if error:
        return (None, error, float(seconds)) if result is None else None
    result, problem = result_error(result, inputs)
    return None if problem else (result, "", float(seconds))
