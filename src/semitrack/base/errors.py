"""The package's exceptions for bad input: what the command line reports as a refusal (exit 2).

Every refusal of an input by the package (a value out of its rule, a wrong type, work beyond a
limit, an unreadable file's content) raises :class:`InputError` (a ``ValueError``) or
:class:`InputTypeError` (a ``TypeError``), both :class:`BadInput`: callers that catch
``ValueError``/``TypeError`` keep working, and the command line tells a refusal from an
unexpected failure by its class alone.
"""

from __future__ import annotations

__all__ = ["BadInput", "InputError", "InputTypeError"]


class BadInput(Exception):
    """Input the package refuses; the message names the parameter (or file and key), its value and the rule."""


class InputError(BadInput, ValueError):
    """A value the package refuses (out of its rule, beyond a work limit, inconsistent)."""


class InputTypeError(BadInput, TypeError):
    """An input of a type the package refuses."""
