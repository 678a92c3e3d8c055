"""``semitrack`` and ``python -m semitrack``: the command-line program.

The console script enters here, not in :mod:`semitrack.cli`, so that an interrupt that arrives
while the program is still importing numpy, scipy and the package (the first second or so) ends
it with exit code 130 and one line, as it does later, instead of a traceback.
"""

import sys


def main() -> int:
    """Import the command line (deferred, so that Ctrl-C is caught from the start) and run it."""
    try:
        from .cli import main as cli_main
    except KeyboardInterrupt:
        print("semitrack: interrupted", file=sys.stderr)
        return 130
    return cli_main()


if __name__ == "__main__":
    sys.exit(main())
