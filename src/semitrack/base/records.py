"""Records stored as data: frozen dataclasses and named tuples of numbers, as JSON that cannot run code.

A pickle is a program: loading one runs whatever its writer chose, so a file planted where the
package looks (a shared cache folder) would run its code. The package's cached results are
numbers, arrays and strings inside a few record types, so they are stored as JSON instead:

* ``None``, ``bool``, ``str`` and ``int`` as themselves; a float as ``{"f": float.hex()}`` (bit
  exact, NaN and infinities included);
* an array as ``{"a": dtype, "shape": [...], "b64": ...}`` of its bytes, numeric dtypes only
  (bool, integer, float, complex; never ``object``), read back read-only;
* tuples, lists and dicts with string keys, tagged; a dict with integer keys (a fit's orders
  tried, by order) as the list of its ``[key, value]`` pairs, tagged apart;
* a record as ``{"r": name, "v": {field: value}}``, where ``name`` must be one of the types the
  caller allows (:func:`decode`'s ``types``); the record is rebuilt by calling that type with its
  fields, so its own validation runs again.

Decoding never imports or calls anything the caller did not name; an unknown tag, type or dtype
is an :class:`~.errors.InputError`.
"""

from __future__ import annotations

import base64
import dataclasses
import json
import math

import numpy as np

from .errors import InputError, InputTypeError

__all__ = ["encode", "decode", "dumps", "loads"]

#: dtype kinds an array may have in a record file: bool, signed/unsigned integer, float, complex.
_ARRAY_KINDS = "biufc"

#: Deepest nesting of containers that :func:`decode` follows (the records nest a few levels).
MAX_DEPTH = 32


def _fields(value) -> dict | None:
    """The fields of a record (dataclass instance or named tuple), or None for anything else."""
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return {f.name: getattr(value, f.name) for f in dataclasses.fields(value) if f.init}
    if isinstance(value, tuple) and hasattr(type(value), "_fields"):
        return dict(zip(type(value)._fields, value))
    return None


def encode(value):
    """A JSON-able description of ``value`` (see the module docstring).

    Parameters
    ----------
    value : object
        Numbers, strings, None, arrays of numbers, tuples, lists, dicts with string keys or with
        integer keys, and records (frozen dataclasses, named tuples) made of them.

    Returns
    -------
    object
        Made of dicts, lists, str, int, bool and None only.

    Raises
    ------
    InputTypeError
        For anything else (an object array, a function, ...).
    """
    if value is None or isinstance(value, (bool, str)):
        return value
    if isinstance(value, (np.bool_,)):
        return bool(value)
    if isinstance(value, (int, np.integer)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        return {"f": float(value).hex()}
    if isinstance(value, (complex, np.complexfloating)):
        return {"c": [float(value.real).hex(), float(value.imag).hex()]}
    if isinstance(value, np.ndarray):
        if value.dtype.kind not in _ARRAY_KINDS:
            raise InputTypeError(f"a record cannot store an array of dtype {value.dtype}")
        a = np.ascontiguousarray(value)
        return {"a": a.dtype.str, "shape": list(a.shape), "b64": base64.b64encode(a.tobytes()).decode("ascii")}
    fields = _fields(value)
    if fields is not None:
        return {"r": type(value).__name__, "v": {k: encode(v) for k, v in fields.items()}}
    if isinstance(value, (tuple, list)):
        return {"tuple" if isinstance(value, tuple) else "list": [encode(v) for v in value]}
    if isinstance(value, dict) and all(isinstance(k, str) for k in value):
        return {"d": {k: encode(v) for k, v in value.items()}}
    if isinstance(value, dict) and all(isinstance(k, (int, np.integer)) and not isinstance(k, bool) for k in value):
        return {"di": [[int(k), encode(v)] for k, v in value.items()]}
    raise InputTypeError(f"a record cannot store a value of type {type(value).__name__}")


def _array(data: dict) -> np.ndarray:
    dtype = np.dtype(str(data["a"]))
    if dtype.kind not in _ARRAY_KINDS or dtype.hasobject:
        raise InputError(f"a record file holds an array of dtype {dtype}: only numbers are read")
    shape = tuple(int(n) for n in data["shape"])
    raw = base64.b64decode(str(data["b64"]), validate=True)
    if len(raw) != math.prod(shape) * dtype.itemsize:
        raise InputError(f"a record file holds an array of shape {shape} with {len(raw)} bytes")
    arr = np.frombuffer(raw, dtype=dtype).reshape(shape).copy()
    arr.setflags(write=False)
    return arr


def _tagged(data: dict, tag: str, kind: type):
    """``data[tag]``, which must be a ``kind`` (a list or a dict)."""
    value = data[tag]
    if not isinstance(value, kind):
        raise InputError(f"a record file's {tag!r} holds a {type(value).__name__}, not a {kind.__name__}")
    return value


def _int_keyed(pair, types: dict[str, type], depth: int) -> tuple[int, object]:
    """One ``[key, value]`` pair of a dict with integer keys."""
    if not (isinstance(pair, list) and len(pair) == 2 and type(pair[0]) is int):
        raise InputError(f"a record file's integer-keyed dict holds {type(pair).__name__} {str(pair)[:40]!r}, "
                         "not an [int, value] pair")
    return pair[0], _decode(pair[1], types, depth)


def _decode(data, types: dict[str, type], depth: int):
    if depth > MAX_DEPTH:
        raise InputError(f"a record file nests deeper than {MAX_DEPTH} levels")
    if data is None or isinstance(data, (bool, str, int)):
        return data
    if not isinstance(data, dict) or len(data) not in (1, 2, 3):
        raise InputError(f"a record file holds an unknown value of type {type(data).__name__}")
    if "f" in data:
        return float.fromhex(str(data["f"]))
    if "c" in data:
        return complex(float.fromhex(str(data["c"][0])), float.fromhex(str(data["c"][1])))
    if "a" in data:
        return _array(data)
    if "r" in data:
        cls = types.get(data["r"]) if isinstance(data["r"], str) else None
        if cls is None:
            raise InputError(f"a record file names the type {data['r']!r}, which is not one of {sorted(types)}")
        return cls(**{str(k): _decode(v, types, depth + 1) for k, v in _tagged(data, "v", dict).items()})
    for tag, build in (("tuple", tuple), ("list", list)):
        if tag in data:
            return build(_decode(v, types, depth + 1) for v in _tagged(data, tag, list))
    if "d" in data:
        return {str(k): _decode(v, types, depth + 1) for k, v in _tagged(data, "d", dict).items()}
    if "di" in data:
        pairs = [_int_keyed(pair, types, depth + 1) for pair in _tagged(data, "di", list)]
        if len({k for k, _ in pairs}) != len(pairs):
            raise InputError("a record file's integer-keyed dict repeats a key")
        return dict(pairs)
    raise InputError(f"a record file holds an unknown tag {sorted(data)}")


def decode(data, types: dict[str, type]):
    """The value that :func:`encode` described, building only records of ``types``.

    Parameters
    ----------
    data : object
        What :func:`encode` returned (after a JSON round trip).
    types : dict
        Record type name -> type, the only types that may be built.

    Returns
    -------
    object

    Raises
    ------
    InputError
        For an unknown tag, a type not in ``types``, a non-numeric dtype, inconsistent array sizes,
        nesting deeper than :data:`MAX_DEPTH`, or a record its type refuses.
    """
    try:
        return _decode(data, types, 0)
    except InputError:
        raise
    except (KeyError, TypeError, ValueError, IndexError, AttributeError, OverflowError) as err:
        raise InputError(f"a record file is malformed ({type(err).__name__}: {err})") from None


def dumps(value) -> str:
    """:func:`encode` as JSON text.

    Parameters
    ----------
    value : object
        As for :func:`encode`.

    Returns
    -------
    str
    """
    return json.dumps(encode(value), allow_nan=False, separators=(",", ":"))


def loads(text: str, types: dict[str, type]):
    """The value of JSON text written by :func:`dumps`, building only records of ``types``.

    Parameters
    ----------
    text : str
        The JSON text.
    types : dict
        Record type name -> type, the only types that may be built.

    Returns
    -------
    object

    Raises
    ------
    InputError
        For text that is not JSON (or nests too deep for the parser) and as :func:`decode`.
    """
    try:
        data = json.loads(text)
    except (ValueError, RecursionError) as err:
        raise InputError(f"a record file is not JSON ({type(err).__name__})") from None
    return decode(data, types)
