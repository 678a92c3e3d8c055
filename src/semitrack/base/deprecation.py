"""Old names kept working for one release: renamed keyword arguments and renamed attributes.

The package's naming rule (``CONTRIBUTING.md``) gives one name to each quantity. A name it
replaces keeps working until :data:`REMOVED_IN` with a :class:`DeprecationWarning` that names the
new one: :func:`renamed_keywords` maps old keyword arguments onto the new ones (the signature
shows the new names only), :func:`deprecated_alias` keeps an old attribute or method name.
"""

from __future__ import annotations

import functools
import warnings
from collections.abc import Callable, Mapping
from typing import Any

from .errors import InputTypeError

__all__ = ["REMOVED_IN", "renamed_keywords", "deprecated_alias", "warn_renamed"]

#: The release in which the old names go.
REMOVED_IN = "0.3"


def warn_renamed(old: str, new: str, where: str, stacklevel: int = 3) -> None:
    """Warn that ``old`` is now ``new`` in ``where`` (a :class:`DeprecationWarning` naming both).

    Parameters
    ----------
    old, new : str
        The old and the new name.
    where : str
        The function or class they belong to.
    stacklevel : int
        As :func:`warnings.warn` takes it: the caller of ``where`` by default.
    """
    warnings.warn(f"{where}: {old!r} is renamed {new!r} (the package's naming rule); {old!r} goes in "
                  f"semitrack {REMOVED_IN}", DeprecationWarning, stacklevel=stacklevel)


def renamed_keywords(renames: Mapping[str, str]) -> Callable:
    """Decorate a function whose keyword arguments ``renames`` (old -> new) were renamed.

    A call with an old keyword warns (:func:`warn_renamed`) and runs with the new one; a call that
    gives both is refused by name. :func:`inspect.signature` of the result is the function's own,
    the new names only.

    Parameters
    ----------
    renames : mapping of str to str
        Old keyword -> new keyword.

    Returns
    -------
    callable
        The decorator.
    """
    def decorate(func: Callable) -> Callable:
        where = func.__qualname__.replace(".__init__", "")

        @functools.wraps(func)
        def wrapper(*args: Any, **kwargs: Any) -> Any:
            for old, new in renames.items():
                if old in kwargs:
                    if new in kwargs:
                        raise InputTypeError(f"{where} got both {old!r} and {new!r}, which is its new name: "
                                             f"give {new!r} only")
                    warn_renamed(old, new, where)
                    kwargs[new] = kwargs.pop(old)
            return func(*args, **kwargs)

        return wrapper

    return decorate


def deprecated_alias(new: str, old: str) -> property:
    """A read-only property ``old`` that warns and returns attribute (or method) ``new``.

    Parameters
    ----------
    new : str
        The attribute's name now.
    old : str
        Its old name (the property's name in the class, for the message).

    Returns
    -------
    property
    """
    def get(self: Any) -> Any:
        warn_renamed(old, new, type(self).__name__)
        return getattr(self, new)

    get.__doc__ = f"Deprecated: the old name of :attr:`{new}` (goes in {REMOVED_IN})."
    return property(get)
