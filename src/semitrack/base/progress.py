"""Progress bars for long work (kernel set-up, long runs, fits, studies), drawn by tqdm.

A bar is drawn only where someone watches:

- on a terminal (the stream's ``isatty()``), or in a Jupyter kernel's output stream, so output
  redirected to a file or a pipe, and CSV written to stdout, never holds progress text;
- never when the caller asks for quiet (the command line's ``--quiet``), inside :func:`silenced`
  (the command line's ``--quiet`` for the package's own bars; a study's cases, whose study draws
  one bar for them all), when the environment variable ``CI`` is set (as CI services set it), or
  when ``SEMITRACK_PROGRESS=0``. The book's build sets ``SEMITRACK_PROGRESS=0`` in its kernels,
  and a study's dask workers in theirs, so the rendered pages hold no bars.
  ``SEMITRACK_PROGRESS=1`` draws bars even where the stream is not a terminal.

Work inside the package opens its bars with a :data:`LIBRARY_DELAY` of a second: a call that ends
sooner draws nothing, so short calls and tests stay silent and only long work reports. Its bars
are kept on the screen when they finish only when no other bar is open (a bar inside the command
line's stage bar goes when it is done).
"""

from __future__ import annotations

import contextvars
import os
import sys
from collections.abc import Iterator
from contextlib import contextmanager
from typing import TextIO

from tqdm import tqdm

from .notices import warn_user

#: Seconds before a bar of the package's own long work first shows: shorter work draws nothing.
LIBRARY_DELAY = 1.0

_ON, _OFF = ("1", "on", "true", "yes"), ("0", "off", "false", "no")
_warned_values: set[str] = set()
#: Depth of the open :func:`silenced` blocks, per thread (a context variable: a worker's threads run cases apart).
_SILENCED = contextvars.ContextVar("semitrack_progress_silenced", default=0)


class _Bar(tqdm):
    """tqdm without its monitor thread: the package updates its bars often enough itself, and a
    thread per process would outlive the work in dask's workers."""

    monitor_interval = 0


def _forced() -> bool | None:
    """``SEMITRACK_PROGRESS``: True (on), False (off) or None (unset, or a value it does not name)."""
    value = os.environ.get("SEMITRACK_PROGRESS")
    if value is None or value.strip() == "":
        return None
    word = value.strip().lower()
    if word in _ON:
        return True
    if word in _OFF:
        return False
    if value not in _warned_values:  # said once, not at every bar
        _warned_values.add(value)
        warn_user(f"SEMITRACK_PROGRESS={value!r} is not one of 0/off/false/no or 1/on/true/yes: progress bars "
                  "follow the terminal")
    return None


def _in_ci() -> bool:
    return os.environ.get("CI", "").strip().lower() not in ("", *_OFF)


@contextmanager
def silenced() -> Iterator[None]:
    """No progress bar opens inside this block (bars already open go on)."""
    token = _SILENCED.set(_SILENCED.get() + 1)
    try:
        yield
    finally:
        _SILENCED.reset(token)


def _watched(stream) -> bool:
    """Whether ``stream`` is a terminal or a Jupyter kernel's output (where a person reads it)."""
    if type(stream).__module__.split(".")[0] == "ipykernel":
        return True
    try:
        return bool(stream.isatty())
    except (AttributeError, ValueError, OSError):  # no isatty, or a closed stream
        return False


def progress_shown(stream: TextIO | None = None, quiet: bool = False) -> bool:
    """Whether a progress bar on ``stream`` (stderr by default) is drawn, by the rules of this module.

    Parameters
    ----------
    stream : file, optional
        Where the bar would be written.
    quiet : bool
        The caller asks for no bar.

    Returns
    -------
    bool
    """
    if quiet or _SILENCED.get():
        return False
    forced = _forced()
    if forced is not None:
        return forced
    if _in_ci():
        return False
    return _watched(sys.stderr if stream is None else stream)


class Progress:
    """A tqdm bar of ``done / total`` steps, drawn only where :func:`progress_shown` says so.

    Parameters
    ----------
    label : str
        What is being done, e.g. ``"receptance"``.
    total : int
        Number of steps (none: no bar).
    quiet : bool
        Never draw.
    stream : file, optional
        Where to write (stderr, as it is when the bar opens, by default).
    unit : str
        The name of a step, e.g. ``"block"``.
    delay : float
        Seconds before the bar first shows (:data:`LIBRARY_DELAY` for the package's own work).
    every : bool
        Redraw at every update (for slow steps such as a study's cases); else at most ten times a second.

    Notes
    -----
    Use it as a context manager (or call :meth:`close`) so an interrupted computation ends its
    line. An update costs a comparison unless tqdm redraws (at most ten times a second).
    """

    def __init__(self, label: str, total: int, quiet: bool = False, stream: TextIO | None = None,
                 unit: str = "step", delay: float = 0.0, every: bool = False):
        self.stream = sys.stderr if stream is None else stream
        self.label, self.total = label, max(int(total), 0)
        self.enabled = self.total > 0 and progress_shown(self.stream, quiet)
        redraw = {"mininterval": 0, "miniters": 1} if every else {}
        # leave=None: a finished bar stays only when it was the outermost (not inside a stage bar)
        self._bar = (_Bar(total=self.total, desc=label, unit=unit, file=self.stream, delay=float(delay),
                          leave=None, dynamic_ncols=True, **redraw) if self.enabled else None)

    def update(self, done: int, note: str = "") -> None:
        """Show that ``done`` of ``total`` steps are finished, with an optional note after the bar."""
        if self._bar is None:
            return
        if note:
            self._bar.set_postfix_str(note, refresh=False)
        step = min(int(done), self.total) - self._bar.n
        if step:
            self._bar.update(step)
        elif note and self._bar.format_dict["elapsed"] >= self._bar.delay:  # a new stage: shown at once
            self._bar.refresh()

    def advance(self, steps: int = 1, note: str = "") -> None:
        """Show that ``steps`` more steps are finished.

        Parameters
        ----------
        steps : int
            Steps finished since the last update.
        note : str
            Shown after the bar.
        """
        if self._bar is not None:
            self.update(self._bar.n + int(steps), note)

    def finish(self) -> None:
        """The work ended, maybe before ``total`` (a search that stopped early): what was done is the whole."""
        if self._bar is not None:
            self._bar.total = max(self._bar.n, 1)
            if self._bar.format_dict["elapsed"] >= self._bar.delay:  # short work stays silent
                self._bar.refresh()

    def close(self) -> None:
        """End the bar's line."""
        if self._bar is not None:
            self._bar.close()
            self._bar = None

    def __enter__(self) -> Progress:
        return self

    def __exit__(self, *exc) -> None:
        self.close()
