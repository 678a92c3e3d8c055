"""The package's exceptions for bad input: what the command line reports as a refusal (exit 2).

Every refusal of an input by the package (a value out of its rule, a wrong type, work beyond a
limit, an unreadable file's content) raises :class:`InputError` (a ``ValueError``) or
:class:`InputTypeError` (a ``TypeError``), both :class:`BadInput`: callers that catch
``ValueError``/``TypeError`` keep working, and the command line tells a refusal from an
unexpected failure by its class alone.
"""

from __future__ import annotations

import re

__all__ = ["BadInput", "InputError", "InputTypeError", "UnreadableFile", "unreadable_file", "caused_by_interrupt"]


class BadInput(Exception):
    """Input the package refuses; the message names the parameter (or file and key), its value and the rule.

    The message is one line whatever it quotes: a line break followed by indentation (a 2-D array
    shown with ``repr``) is folded into one space, any other (in a path, in the user's text) is
    written ``\\n``, so that the command line's refusals and a caller's log stay one line and
    keep what they quote.
    """

    def __init__(self, *args):
        if len(args) == 1 and isinstance(args[0], str) and ("\n" in args[0] or "\r" in args[0]):
            text = re.sub(r"\r?\n[ \t]+", " ", args[0])
            args = (text.replace("\r", "\\r").replace("\n", "\\n"),)
        super().__init__(*args)


class InputError(BadInput, ValueError):
    """A value the package refuses (out of its rule, beyond a work limit, inconsistent)."""


class InputTypeError(BadInput, TypeError):
    """An input of a type the package refuses."""


class UnreadableFile(OSError, BadInput):
    """An input file that cannot be opened or read (absent, a directory, no permission).

    An :class:`OSError` (with ``errno`` and ``filename``), as callers that catch it expect, and a
    :class:`BadInput`: the path is the user's input, and the package refuses it like any other.
    :func:`unreadable_file` gives the subclass that is also the built-in error of its errno
    (``FileNotFoundError``, ``PermissionError``, ...), so ``except FileNotFoundError`` keeps working.
    """


_BY_ERRNO: dict[int, type] = {}


def unreadable_file(err: OSError, path: str, why: str | None = None) -> UnreadableFile:
    """The :class:`UnreadableFile` of ``err`` for ``path``: also ``type(err)`` (e.g. ``FileNotFoundError``).

    Parameters
    ----------
    err : OSError
        The error the operating system gave.
    path : str
        The file, as the user named it.
    why : str, optional
        The reason in words (default: ``err.strerror``).
    """
    base = type(err) if type(err) is not OSError and not isinstance(err, BadInput) else None
    cls = UnreadableFile
    if base is not None:
        cls = _BY_ERRNO.get(err.errno) or _BY_ERRNO.setdefault(err.errno, type(f"Unreadable{base.__name__}",
                                                                              (UnreadableFile, base), {}))
    return cls(err.errno, why or err.strerror, path)


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
