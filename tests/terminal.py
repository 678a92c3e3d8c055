"""A stream that says it is a terminal, so that progress bars draw on it (tests of the bars)."""

import io


class FakeTerminal(io.StringIO):
    """Text written to it is kept (``getvalue()``); ``isatty()`` is True, as a terminal's is."""

    def isatty(self):
        return True
