"""Every public function, class and method of the flat ``st.*`` API documents all its parameters.

In the spirit of python-control's ``control/tests/docstrings_test.py``: for each name in
``semitrack.__all__`` that is callable (and each public method and property of a public class),
the docstring must exist and its numpydoc "Parameters" (or "Other Parameters", or for a
dataclass "Attributes") section must name every parameter of the signature (``self``/``cls``
excepted; ``*args``/``**kwargs`` under their own names, with or without the stars).
"""

from __future__ import annotations

import inspect
import re

import pytest

import semitrack as st

_SECTION = re.compile(r"^(Parameters|Other Parameters|Attributes)\n-+\n(.*?)(?=^\S[^\n]*\n-+\n|\Z)", re.M | re.S)
_ENTRY = re.compile(r"^(\*{0,2}[A-Za-z_][\w]*(?:\s*,\s*\*{0,2}[A-Za-z_]\w*)*)\s*(?::|$)", re.M)


def documented_parameters(doc: str) -> set[str]:
    """Names listed in the Parameters / Other Parameters / Attributes sections of a numpydoc docstring."""
    names: set[str] = set()
    for section in _SECTION.finditer(inspect.cleandoc(doc)):
        for entry in _ENTRY.finditer(section.group(2)):
            names.update(n.strip().lstrip("*") for n in entry.group(1).split(","))
    return names


def _public_callables():
    for name in sorted(st.__all__):
        obj = getattr(st, name)
        if inspect.isclass(obj):
            yield name, obj
            for attr, member in vars(obj).items():
                if attr.startswith("_"):
                    continue
                if isinstance(member, (staticmethod, classmethod)):
                    member = member.__func__
                if inspect.isfunction(member):
                    yield f"{name}.{attr}", member
        elif callable(obj):
            yield name, obj


CALLABLES = list(_public_callables())


def _parameters(obj) -> list[str]:
    target = obj.__init__ if inspect.isclass(obj) else obj
    try:
        sig = inspect.signature(target)
    except (TypeError, ValueError):  # builtins without a signature
        return []
    return [p for p in sig.parameters if p not in ("self", "cls")]


@pytest.mark.parametrize("name, obj", CALLABLES, ids=[n for n, _ in CALLABLES])
def test_every_parameter_is_documented(name, obj):
    doc = inspect.getdoc(obj)
    assert doc, f"{name} has no docstring"
    params = _parameters(obj)
    if inspect.isclass(obj) and (obj.__init__ is object.__init__ or issubclass(obj, Exception)):
        params = []  # no constructor of its own, or an exception's (*args)
    if not params:
        return
    missing = [p for p in params if p not in documented_parameters(doc)]
    assert not missing, f"{name}: parameters {missing} are not in its Parameters section"


def test_parser_finds_combined_and_starred_entries():
    doc = """Summary.

    Parameters
    ----------
    a, b : float
        Two.
    **options
        More.

    Returns
    -------
    c : float
    """
    assert documented_parameters(doc) == {"a", "b", "options"}
