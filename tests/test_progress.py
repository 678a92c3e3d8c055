"""The progress line: written to a terminal only, never when quiet or redirected."""

import io

from semitrack.base.progress import Progress


class FakeTerminal(io.StringIO):
    def isatty(self):
        return True


def test_progress_writes_to_a_terminal():
    term = FakeTerminal()
    p = Progress("fit", 4, stream=term)
    p.update(2, "start 2")
    p.close()
    out = term.getvalue()
    assert "fit: 2/4" in out and "50 %" in out and "start 2" in out and out.endswith("\n")


def test_progress_silent_when_quiet_or_redirected():
    term = FakeTerminal()
    Progress("fit", 4, quiet=True, stream=term).update(1)
    pipe = io.StringIO()  # not a terminal, like a file or a pipe
    p = Progress("fit", 4, stream=pipe)
    p.update(1)
    p.close()
    assert term.getvalue() == "" and pipe.getvalue() == ""
