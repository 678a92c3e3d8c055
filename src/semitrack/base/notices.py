"""Warnings that point at the user's line, whatever the depth of the package's calls beneath it.

A fixed ``stacklevel`` is right for one call path only: ``export_system`` and ``export_boundary``
reach the same writer at different depths, and a warning that names a line of the package tells
the user nothing. :func:`warn_user` walks out of the package first.
"""

from __future__ import annotations

import os
import sys
import warnings

__all__ = ["PACKAGE_DIR", "HystereticDampingWarning", "ImplausibleValueWarning", "user_stacklevel", "warn_user"]

#: The package's folder: frames of files under it are the package's own.
PACKAGE_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__))) + os.sep


class HystereticDampingWarning(UserWarning):
    """A hysteretic (loss-factor) track run in the time domain, on the viscous dampers that stand in
    for its loss factors: filter this class to silence it where that is meant."""


class ImplausibleValueWarning(UserWarning):
    """A value the package accepts but which is far outside what a track holds (a gap of metres,
    a pad without stiffness): most often a unit mistyped."""


def user_stacklevel() -> int:
    """The ``stacklevel`` (for a :func:`warnings.warn` called by the caller of this function) of the
    first frame outside the package."""
    frame, level = sys._getframe(1), 1  # the caller of this function is level 1 of its warnings.warn
    while frame is not None and os.path.abspath(frame.f_code.co_filename).startswith(PACKAGE_DIR):
        frame, level = frame.f_back, level + 1
    return level


def warn_user(message: str, category: type[Warning] = UserWarning) -> None:
    """:func:`warnings.warn` naming the user's line that led to it (the first frame outside the package).

    Parameters
    ----------
    message : str
        The warning, in words, with rounded numbers.
    category : type of Warning
        Its class (UserWarning by default).
    """
    warnings.warn(message, category, stacklevel=user_stacklevel())
