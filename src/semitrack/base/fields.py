"""Result records checked as they are built: each field is what its annotation says.

The package's result records (:class:`~semitrack.CentralResponse`, :class:`~semitrack.ErrorSummary`,
:class:`~semitrack.FitResult`, ...) are frozen dataclasses that the package builds and readers
may build by hand (from stored numbers, in a test). A record built with text for a number, or a
string where a track belongs, would be accepted and fail later, in a method, with a raw numpy
error far from its cause. :func:`check_fields` refuses it where it is built, naming the field.

Only the kind of each field is checked, from its annotation (``np.ndarray``: numbers of any
shape, NaN allowed, as results hold them; ``float``/``int``/``bool``/``str``; ``dict`` and
``tuple``, and ``tuple[float, float]``, ``tuple[str, ...]``, ``tuple[Wheel, ...]``: entries of
that kind; a ``Literal`` alias such as ``Layout``: one of its values; a class of the package: an
instance of it; ``X | None``: None too); numbers given as a list are held as an array, a list for
a tuple as a tuple, as the record's methods read them. :func:`check_rows` adds the one rule of
shape that records share: one row per entry of a first array (per time, per band). Annotations this
reading does not know (callables, ``Any``) are not checked. The values' physics is the job of
the code that computed them.
"""

from __future__ import annotations

import dataclasses
import functools
import sys
from collections.abc import Mapping
from typing import Literal

import numpy as np

from .checks import brief, check_real
from .errors import InputError, InputTypeError

__all__ = ["check_fields", "check_rows"]


def _is_numbers(value: object) -> bool:
    if isinstance(value, (str, bytes)) or value is None:
        return False
    try:
        kind = np.asarray(value).dtype.kind
    except (TypeError, ValueError):  # a ragged sequence
        return False
    return kind in "biufc"


#: What each plain annotation admits, and how messages say it.
_PLAIN = {
    "np.ndarray": (_is_numbers, "numbers (an array)"),
    "float": (lambda v: isinstance(v, (int, float, np.integer, np.floating)) and not isinstance(v, bool),
              "a real number"),
    "int": (lambda v: isinstance(v, (int, np.integer)) and not isinstance(v, bool), "an integer"),
    "bool": (lambda v: isinstance(v, (bool, np.bool_)), "True or False"),
    "str": (lambda v: isinstance(v, str), "a string"),
    "dict": (lambda v: isinstance(v, Mapping), "a dict"),
    "tuple": (lambda v: isinstance(v, (tuple, list)), "a tuple"),
}


def _typed_tuple(inner: str, namespace: dict):
    """``(accepts, description)`` of ``tuple[float, float]``, ``tuple[str, ...]``, ``tuple[Wheel, ...]``:
    a tuple whose entries are all of one kind (and of that many, unless ``...``); None for others."""
    kinds = [k.strip() for k in inner.split(",")]
    size = None if kinds[-1] == "..." else len(kinds)
    kinds = {k for k in kinds if k != "..."}
    if len(kinds) != 1:
        return None
    (kind,) = kinds
    if kind in ("float", "int", "str"):
        entry, said = _PLAIN[kind]
    elif isinstance(namespace.get(kind), type):
        entry, said = (lambda v, cls=namespace[kind]: isinstance(v, cls)), f"a {kind}"
    else:
        return None

    def accepts(v) -> bool:
        return (isinstance(v, (tuple, list)) and (size is None or len(v) == size) and all(entry(x) for x in v))
    return accepts, f"a tuple of {size or 'any number of'} entries, each {said}"


def _rule(annotation: str, namespace: dict):
    """``(accepts, description)`` of one annotation string, or None when it is not checked."""
    parts = [p.strip() for p in annotation.split("|")]
    optional = "None" in parts
    parts = [p for p in parts if p != "None"]
    if len(parts) != 1:
        return None
    head, _, inner = parts[0].partition("[")
    kind = namespace.get(head)
    if head == "tuple" and inner and _typed_tuple(inner.rstrip("]"), namespace) is not None:
        accepts, said = _typed_tuple(inner.rstrip("]"), namespace)
    elif head in _PLAIN:
        accepts, said = _PLAIN[head]
    elif getattr(kind, "__origin__", None) is Literal:  # an alias such as Layout = Literal["slab", "ballasted"]
        choices = kind.__args__
        accepts, said = (lambda v, c=choices: isinstance(v, str) and v in c), f"one of {list(choices)}"
    else:
        if not isinstance(kind, type):
            return None
        accepts, said = (lambda v, kind=kind: isinstance(v, kind)), f"a {kind.__name__}"
    if optional:
        return (lambda v, accepts=accepts: v is None or accepts(v)), f"{said} or None"
    return accepts, said


@functools.cache
def _rules(cls: type) -> tuple:
    """The checked fields of a dataclass: ``((name, accepts, description), ...)``, read once per class."""
    namespace = vars(sys.modules[cls.__module__])
    out = []
    for spec in dataclasses.fields(cls):
        annotation = spec.type if isinstance(spec.type, str) else getattr(spec.type, "__name__", "")
        rule = _rule(annotation, namespace)
        if rule is not None:
            out.append((spec.name, *rule))
    return tuple(out)


def check_fields(record) -> None:
    """Refuse a result record whose fields are not of their annotated kinds, naming the first that is not.

    Parameters
    ----------
    record : dataclass instance
        The record, as built.

    Raises
    ------
    InputTypeError
        ``"<Record>.<field> must be <kind>, got <value>"``.
    """
    for name, accepts, said in _rules(type(record)):
        value = getattr(record, name)
        if not accepts(value):
            raise InputTypeError(f"{type(record).__name__}.{name} must be {said}, got {brief(value)} "
                                 f"({type(value).__name__})")
        if accepts is _is_numbers and not isinstance(value, np.ndarray):  # a list of numbers: held as an array
            object.__setattr__(record, name, np.asarray(value))
        elif said.startswith(("a tuple", _PLAIN["tuple"][1])) and isinstance(value, list):  # held as the tuple it is
            object.__setattr__(record, name, tuple(value))
        elif said.startswith(_PLAIN["float"][1]) and value is not None and not isinstance(value, float):
            object.__setattr__(record, name, check_real(f"{type(record).__name__}.{name}", value))  # held as float
        elif said.startswith(_PLAIN["int"][1]) and value is not None and not -2**63 <= value < 2**63:
            raise InputError(f"{type(record).__name__}.{name} must be an integer within 64 bits, got {brief(value)}")


def check_rows(record, names: tuple[str, ...], ndims: tuple[int, ...] = (1,)) -> None:
    """Refuse a record whose array fields ``names`` do not have one row each of the first one's rows.

    Parameters
    ----------
    record : dataclass instance
        The record, its fields already checked by :func:`check_fields`.
    names : tuple of str
        Array fields; the first sets the number of rows (its first dimension, at least one).
    ndims : tuple of int
        The dimensions each may have (1-D per row, or 2-D: a row per time and a column per wheel).

    Raises
    ------
    InputError
        ``"<Record>.<field> must have ... rows, got shape ..."``.
    """
    rows = None
    for name in names:
        shape = np.shape(getattr(record, name))
        if len(shape) not in ndims or (rows is not None and shape[0] != rows) or (rows is None and not shape[0]):
            want = f"one row per entry of {names[0]} ({rows})" if rows is not None else "at least one row"
            raise InputError(f"{type(record).__name__}.{name} must be {' or '.join(f'{d}-D' for d in ndims)} with "
                             f"{want}, got shape {shape}")
        rows = shape[0] if rows is None else rows
