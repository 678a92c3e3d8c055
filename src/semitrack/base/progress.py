"""A one-line progress report on stderr for long work (fits, long sweeps, a study's cases).

It writes only when stderr is a terminal and the user did not ask for quiet, so output redirected
to a file or a pipe, and CSV written to stdout, never contain progress text.
"""

from __future__ import annotations

import sys
import time
from typing import TextIO


class Progress:
    """Report ``done / total`` on one rewritten stderr line.

    Parameters
    ----------
    label : str
        What is being done, e.g. ``"receptance"``.
    total : int
        Number of steps.
    quiet : bool
        Never write.
    stream : file, optional
        Where to write (stderr by default); writing happens only if it is a terminal.
    """

    def __init__(self, label: str, total: int, quiet: bool = False, stream: TextIO | None = None):
        self.stream = stream if stream is not None else sys.stderr
        self.enabled = not quiet and hasattr(self.stream, "isatty") and self.stream.isatty()
        self.label, self.total, self.start = label, max(int(total), 1), time.perf_counter()

    def update(self, done: int, note: str = "") -> None:
        """Show that ``done`` of ``total`` steps are finished."""
        if not self.enabled:
            return
        pct = 100.0 * min(done, self.total) / self.total
        elapsed = time.perf_counter() - self.start
        extra = f"  {note}" if note else ""
        self.stream.write(f"\r{self.label}: {done}/{self.total} ({pct:3.0f} %), {elapsed:5.1f} s{extra}\x1b[K")
        self.stream.flush()

    def close(self) -> None:
        """End the progress line."""
        if self.enabled:
            self.stream.write("\n")
            self.stream.flush()
