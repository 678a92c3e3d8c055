"""Warnings that point at the user's line, whatever the depth of the package's calls beneath it.

A fixed ``stacklevel`` is right for one call path only: ``export_system`` and ``export_boundary``
reach the same writer at different depths, and a warning that names a line of the package tells
the user nothing. :func:`warn_user` walks out of the package first. On a thread of
:func:`semitrack.base.parallel.thread_map` the walk ends in the thread pool's machinery, not at the
user's line: there the warning names the line that called the map (:func:`warnings_from`).
"""

from __future__ import annotations

import concurrent.futures
import contextvars
import os
import sys
import threading
import warnings
from collections.abc import Iterator
from contextlib import contextmanager
from types import FrameType

__all__ = ["PACKAGE_DIR", "HystereticDampingWarning", "ImplausibleValueWarning", "user_line", "user_stacklevel",
           "warn_user", "warnings_from"]

#: The package's folder: frames of files under it are the package's own.
PACKAGE_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__))) + os.sep
#: Files of the threads' machinery: a walk out of the package that ends in one is on a worker thread.
_THREAD_FILES = (os.path.dirname(os.path.abspath(concurrent.futures.__file__)) + os.sep,
                 os.path.abspath(threading.__file__))
#: The user's line that started this thread's work (file, line, module globals), set by :func:`warnings_from`.
_CALLER: contextvars.ContextVar[tuple[str, int, dict] | None] = contextvars.ContextVar("semitrack_caller",
                                                                                       default=None)


class HystereticDampingWarning(UserWarning):
    """A hysteretic (loss-factor) track run in the time domain, on the viscous dampers that stand in
    for its loss factors: filter this class to silence it where that is meant."""


class ImplausibleValueWarning(UserWarning):
    """A value the package accepts but which is far outside what a track holds (a gap of metres,
    a pad without stiffness): most often a unit mistyped."""


def _outside(frame: FrameType | None) -> tuple[FrameType | None, int]:
    """The first frame from ``frame`` outwards that is not the package's, and how many frames out it is."""
    level = 0
    while frame is not None and os.path.abspath(frame.f_code.co_filename).startswith(PACKAGE_DIR):
        frame, level = frame.f_back, level + 1
    return frame, level


def user_stacklevel() -> int:
    """The ``stacklevel`` (for a :func:`warnings.warn` called by the caller of this function) of the
    first frame outside the package."""
    return 1 + _outside(sys._getframe(1))[1]  # the caller of this function is level 1 of its warnings.warn


def user_line() -> tuple[str, int, dict] | None:
    """The first line outside the package on this thread's stack, as (file, line number, its module's
    globals), or the one that started this thread's work where the stack leaves the package into a
    thread pool's machinery (None if neither)."""
    frame = _outside(sys._getframe(1))[0]
    if frame is None or os.path.abspath(frame.f_code.co_filename).startswith(_THREAD_FILES):
        return _CALLER.get()
    return frame.f_code.co_filename, frame.f_lineno, frame.f_globals


@contextmanager
def warnings_from(line: tuple[str, int, dict] | None) -> Iterator[None]:
    """Within, a warning of the package on this thread names ``line`` (from :func:`user_line` on the
    thread that handed over the work) where its own stack leaves the package into a thread pool."""
    token = _CALLER.set(line)
    try:
        yield
    finally:
        _CALLER.reset(token)


def warn_user(message: str, category: type[Warning] = UserWarning) -> None:
    """:func:`warnings.warn` naming the user's line that led to it (the first frame outside the package).

    Parameters
    ----------
    message : str
        The warning, in words, with rounded numbers.
    category : type of Warning
        Its class (UserWarning by default).
    """
    frame, level = _outside(sys._getframe(0))  # this frame is level 1 of warnings.warn: 1 + level is the first outside
    if frame is not None and not os.path.abspath(frame.f_code.co_filename).startswith(_THREAD_FILES):
        warnings.warn(message, category, stacklevel=1 + level)
        return
    line = _CALLER.get()
    if line is None:  # a thread the package did not start: its own first frame
        warnings.warn(message, category, stacklevel=1 + level)
        return
    filename, lineno, module_globals = line
    warnings.warn_explicit(message, category, filename, lineno, module=module_globals.get("__name__"),
                           registry=module_globals.setdefault("__warningregistry__", {}),
                           module_globals=module_globals)
