"""A property-based check of every command of the command line: hostile values end in exit 0 or a named exit 2.

Each command of ``semitrack`` (:func:`semitrack.cli.build_parser`) is a surface of
:mod:`api_strategies` (:data:`api_strategies.CLI_SURFACES`): a cheap valid argv (three
frequencies, a four-pole boundary) whose option values and file arguments Hypothesis replaces,
one or two at a time, by hostile text (``nan``, ``1e309``, ``-1``, ``0x10``, ``''``, a NUL byte,
...) or hostile paths (missing, a folder, ``/dev/null``, empty, garbage, a FIFO, a link loop).
The program runs in-process (:func:`semitrack.cli.main`, bounded by an alarm) and must end in:

- exit 0, its result file (where it writes one) holding no ``nan`` unless a warning was printed;
- exit 2 within :data:`test_property_api.REFUSAL_SECONDS`, with one line on stderr, no traceback,
  naming the option (or the file) that was replaced.

Any other exit code (1 is an unexpected failure, with a traceback), a hang or a late refusal fails.
The profiles (``ci`` by default, ``long`` on demand) are those of ``tests/test_property_api.py``.
"""

from __future__ import annotations

import contextlib
import io
import re

import pytest
from api_strategies import CLI_SURFACES, CLI_WORDS, cli_examples, names_in
from hypothesis import given, settings
from test_property_api import CALL_SECONDS, REFUSAL_SECONDS, bounded

from semitrack.cli import build_parser, main, printable

#: The positional arguments that name a file: a refusal quoting the file names the argument.
FILE_ARGUMENTS = ("track", "system", "vehicle")


@pytest.fixture(scope="module", autouse=True)
def in_a_scratch_folder(tmp_path_factory):
    """Run in a folder of the run: a hostile relative path (``'nan'``, ``''``) writes there, not in the repository."""
    with contextlib.chdir(tmp_path_factory.mktemp("cwd")):
        yield


def commands() -> set[str]:
    """The commands the program offers (its sub-parsers)."""
    parser = build_parser()
    (sub,) = [a for a in parser._actions if a.__class__.__name__ == "_SubParsersAction"]
    return set(sub.choices)


def test_every_command_has_a_strategy():
    """A command lands only with a surface in :data:`api_strategies.CLI_SURFACES`."""
    missing = commands() - {s.command for s in CLI_SURFACES.values()}
    assert not missing, f"commands without a strategy in tests/api_strategies.py: {sorted(missing)}"


def run(argv: list[str]):
    """``(outcome, stdout, stderr)`` of the program run in-process on ``argv``, bounded in time."""
    out, err = io.StringIO(), io.StringIO()

    def call():
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            return main(argv)
    return bounded(call), out.getvalue(), err.getvalue()


@pytest.mark.parametrize("name", sorted(CLI_SURFACES))
def test_every_base_command_line_runs(name):
    argv = [t for _, t in CLI_SURFACES[name].argv()]
    outcome, _, err = run(argv)
    assert outcome.error is None and outcome.result == 0, (outcome, err)


@pytest.mark.parametrize("name", sorted(CLI_SURFACES))
def test_hostile_command_lines_end_in_success_or_a_named_refusal(name):
    surface = CLI_SURFACES[name]

    @settings(max_examples=max(2, round(settings.default.max_examples * surface.weight)))
    @given(example=cli_examples(surface))
    def check(example):
        argv, replaced = example
        outcome, out, err = run(argv)
        call = "semitrack " + " ".join(repr(a) if not re.fullmatch(r"[\w./+-]+", a) else a for a in argv)
        assert not outcome.hang, f"{call} still ran after {CALL_SECONDS} s"
        assert outcome.error is None, f"{call} raised {type(outcome.error).__name__}: {outcome.error}"
        code = outcome.result
        assert code in (0, 2), f"{call} exited {code}: {err[-600:]}"
        assert "Traceback" not in err, f"{call} printed a traceback: {err[-600:]}"
        if code == 2:
            assert len(err.splitlines()) == 1, f"{call}: the refusal is not one line: {err!r}"
            words = [w for k, _ in replaced for w in (k, *CLI_WORDS.get(k, ()))]
            # the option's name, or the file itself when the replaced argument names one (not a "1" found anywhere)
            # a path is named as printed, its control characters escaped (a file called "\n" shows as \n)
            named = names_in(err, words) or any(
                printable(v).strip() and printable(v) in err and (k in FILE_ARGUMENTS or len(v.strip()) >= 4)
                for k, v in replaced)
            # "--" where a file belongs is the end-of-options marker, which argparse takes before any value;
            # a blank file name is named where the error quotes it ("error:  : not a valid TOML file")
            named = named or any((v == "--" or (v.isspace() and f"error: {v}: " in err)) and k in FILE_ARGUMENTS
                                 for k, v in replaced)
            assert named, f"{call}: the refusal does not name {' or '.join(k for k, _ in replaced)}: {err.strip()}"
            assert outcome.cpu < REFUSAL_SECONDS, f"{call} was refused only after {outcome.cpu:.2f} s of CPU"
        else:
            warned = "warning" in err
            text = out
            if surface.output:
                path = argv[argv.index(surface.output) + 1]
                text = ""
                if path.endswith((".csv", ".json")):  # text results (a .mat is binary)
                    with contextlib.suppress(OSError, UnicodeDecodeError), open(path) as fh:
                        text = fh.read()
            assert warned or not re.search(r"(?i)\bnan\b", text), f"{call} wrote NaN without a warning"

    check()
