"""``semitrack`` and ``python -m semitrack``: the command-line program.

The console script enters here, not in :mod:`semitrack.cli`, so that an interrupt that arrives
while the program is still importing numpy, scipy and the package (the first second or so) ends
it with exit code 130 and one line, as it does later, instead of a traceback; an ImportError
raised from that interrupt (numpy reports a Ctrl-C during its import as a "bad install") too.
"""

import sys

try:  # the C module: ``signal`` imports enum, which was a third of the console script's start before this
    import _signal as signal
except ImportError:  # not CPython
    import signal


def main() -> int:
    """Import the command line (deferred, so that Ctrl-C is caught from the start) and run it."""
    interrupted = []

    def note_interrupt(signum, frame):  # the default's KeyboardInterrupt, remembered: a C-level import
        interrupted.append(signum)      # (numpy's datetime capsule) can turn it into an unrelated ImportError
        raise KeyboardInterrupt

    previous = signal.signal(signal.SIGINT, note_interrupt)
    try:
        from .cli import main as cli_main
    except KeyboardInterrupt:
        print("semitrack: interrupted", file=sys.stderr)
        return 130
    except ImportError as err:  # numpy's "bad install" text for a Ctrl-C while it loads
        from .base.errors import caused_by_interrupt

        if not (interrupted or caused_by_interrupt(err)):
            raise
        print("semitrack: interrupted", file=sys.stderr)
        return 130
    finally:
        signal.signal(signal.SIGINT, previous)
    return cli_main()


if __name__ == "__main__":
    sys.exit(main())
