"""The package's exceptions for bad input: what the command line reports as a refusal (exit 2).

Every refusal of an input by the package (a value out of its rule, a wrong type, work beyond a
limit, an unreadable file's content) raises :class:`InputError` (a ``ValueError``) or
:class:`InputTypeError` (a ``TypeError``), both :class:`BadInput`: callers that catch
``ValueError``/``TypeError`` keep working, and the command line tells a refusal from an
unexpected failure by its class alone.
"""

from __future__ import annotations

__all__ = ["BadInput", "InputError", "InputTypeError", "caused_by_interrupt"]


class BadInput(Exception):
    """Input the package refuses; the message names the parameter (or file and key), its value and the rule."""


class InputError(BadInput, ValueError):
    """A value the package refuses (out of its rule, beyond a work limit, inconsistent)."""


class InputTypeError(BadInput, TypeError):
    """An input of a type the package refuses."""


def caused_by_interrupt(error: BaseException) -> bool:
    """Whether ``error`` is, or was raised while handling, a ``KeyboardInterrupt`` (Ctrl-C).

    A Ctrl-C that arrives while numpy loads its compiled core turns into numpy's ImportError about
    a "bad install", raised from the interrupt; the command line reports it as the interrupt it is.

    Parameters
    ----------
    error : BaseException
        The exception caught.

    Returns
    -------
    bool
    """
    seen = set()
    while error is not None and id(error) not in seen:
        if isinstance(error, KeyboardInterrupt):
            return True
        seen.add(id(error))
        error = error.__cause__ or error.__context__
    return False
