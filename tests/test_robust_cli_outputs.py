"""The command line never writes over one of its inputs, and refuses options that would be ignored.

An output that names an input by any name (the same path, a symbolic link to it, a hard link)
is refused before any work: exit 2, one line naming the option and the input, the input left
byte for byte as it was. Options of one kind of fit given to the other (``--poles`` without
``--boundary``; ``--bars``, ``--layout``, ``--unconstrained`` with it) are refused the same way,
as is a ``--boundary`` band whose fit would take hours.
"""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest

import semitrack as st
from semitrack.cli import main
from semitrack.model.trackfile import example_path

GRID = ["--fmin", "100", "--fmax", "200", "--df", "50"]
SECONDS = 10.0  # every refusal comes before the work (measured: < 0.3 s in-process)


def run(capsys, *args) -> tuple[int, str, float]:
    start = time.perf_counter()
    code = main([str(a) for a in args])
    elapsed = time.perf_counter() - start
    _, err = capsys.readouterr()
    return code, err, elapsed


def assert_refused(capsys, args, files: list[Path], *words: str) -> str:
    """Exit 2, one line naming ``words``, within :data:`SECONDS`, every file of ``files`` unchanged."""
    before = {path: path.read_bytes() for path in files}
    code, err, elapsed = run(capsys, *args)
    assert code == 2, err
    assert len(err.splitlines()) == 1 and "Traceback" not in err, err
    for word in words:
        assert word in err, err
    assert elapsed < SECONDS, elapsed
    for path, content in before.items():
        assert path.read_bytes() == content, path
    return err


@pytest.fixture
def track(tmp_path) -> Path:
    path = tmp_path / "t.toml"
    path.write_text(example_path("slab").read_text())
    return path


@pytest.fixture
def system(tmp_path) -> Path:
    return st.export_system(st.paper_table4(), tmp_path / "sys.json")


def _aliases(path: Path) -> dict[str, Path]:
    """The input by its own name, a symbolic link to it, a hard link to it, and a relative path."""
    symlink = path.with_name("alias-" + path.name)
    symlink.symlink_to(path.name)
    hardlink = path.with_name("hard-" + path.name)
    os.link(path, hardlink)
    return {"same": path, "symlink": symlink, "hardlink": hardlink, "dotted": path.parent / "." / path.name}


COMMANDS = {  # name -> arguments with OUT for the output, TRACK for the track
    "receptance -o": ["receptance", "TRACK", *GRID, "-o", "OUT"],
    "receptance --plot": ["receptance", "TRACK", *GRID, "-o", "other.csv", "--plot", "OUT"],
    "fit -o": ["fit", "TRACK", "--band", "3", "300", "-o", "OUT"],
    "fit --boundary -o": ["fit", "TRACK", "--boundary", "--band", "3", "300", "-o", "OUT"],
    "decay -o": ["decay", "TRACK", "-o", "OUT"],
}


@pytest.mark.parametrize("alias", ["same", "symlink", "hardlink", "dotted"])
@pytest.mark.parametrize("command", sorted(COMMANDS))
def test_an_output_naming_the_track_file_is_refused(capsys, track, tmp_path, command, alias):
    out = _aliases(track)[alias]
    args = [str(out) if a == "OUT" else str(track) if a == "TRACK" else str(tmp_path / a) if a.endswith(".csv")
            else a for a in COMMANDS[command]]
    option = "--plot" if "--plot" in command else "-o"
    assert_refused(capsys, args, [track], option, "track file", "replace")
    assert not (tmp_path / "other.csv").exists()


@pytest.mark.parametrize("alias", ["same", "symlink", "hardlink"])
def test_export_over_its_system_file_is_refused(capsys, system, alias):
    out = _aliases(system)[alias]
    assert_refused(capsys, ["export", system, "--format", "csv", "-o", out], [system], "-o", "system file")


def test_an_output_naming_a_table_the_track_reads_is_refused(capsys, tmp_path):
    table = tmp_path / "pad.csv"
    table.write_text("f_Hz, re, im\n0, 1.0e8, 2.5e7\n10000, 1.0e8, 2.5e7\n")
    text = example_path("slab").read_text()
    lines = [('kv = {table = "pad.csv"}' if line.strip().startswith("kv ") else line) for line in text.splitlines()]
    track = tmp_path / "t.toml"
    track.write_text("\n".join(lines) + "\n")
    assert main(["receptance", str(track), *GRID, "-o", str(tmp_path / "alpha.csv")]) == 0  # the track is valid
    capsys.readouterr()
    assert_refused(capsys, ["receptance", track, *GRID, "-o", table], [table, track], "-o", "table")


def test_other_outputs_still_work(capsys, track, system, tmp_path):
    code, err, _ = run(capsys, "export", system, "--format", "csv", "-o", tmp_path / "sys.csv")
    assert code == 0, err
    assert st.load_system_csv(tmp_path / "sys.csv") == st.paper_table4()


# --- options of the other kind of fit ----------------------------------------------------------------
@pytest.mark.parametrize("options, words", [
    (["--poles", "12"], ("--poles", "--boundary")),
    (["--boundary", "--bars", "3"], ("--bars", "--boundary")),
    (["--boundary", "--unconstrained"], ("--unconstrained",)),
    (["--boundary", "--layout", "slab"], ("--layout",)),
    (["--boundary", "--bars", "5", "--unconstrained"], ("--bars and --unconstrained",)),
])
def test_options_that_would_be_ignored_are_refused(capsys, track, tmp_path, options, words):
    out = tmp_path / "out.json"
    assert_refused(capsys, ["fit", track, "--band", "3", "300", *options, "-o", out], [track], *words)
    assert not out.exists()


def test_a_boundary_band_of_hours_is_refused(capsys, track, tmp_path):
    out = tmp_path / "b.json"
    assert_refused(capsys, ["fit", track, "--boundary", "--band", "3", "299000", "-o", out], [track], "band",
                   "samples", "limit")
    assert not out.exists()


# --- Ctrl-C while numpy or scipy loads ---------------------------------------------------------------
INTERRUPTED_IMPORT = textwrap.dedent("""
    import sys

    class Interrupted:  # a Ctrl-C during the import of {module}, reported as numpy reports it
        def find_spec(self, name, path=None, target=None):
            if name == "{module}":
                try:
                    raise KeyboardInterrupt
                except KeyboardInterrupt as err:
                    raise ImportError("Importing the numpy C-extensions failed: check your install") from err
            return None

    sys.meta_path.insert(0, Interrupted())
    from semitrack.__main__ import main
    sys.argv = ["semitrack", *sys.argv[1:]]
    sys.exit(main())
""")


@pytest.mark.parametrize("module", ["numpy", "scipy"])
def test_an_import_interrupted_by_ctrl_c_exits_130(track, tmp_path, module):
    # numpy: while the command line itself loads; scipy: in the fit's deferred imports
    env = {**os.environ, "PYTHONPATH": str(Path(st.__file__).parent.parent)}
    start = time.perf_counter()
    out = subprocess.run([sys.executable, "-c", INTERRUPTED_IMPORT.format(module=module), "fit", str(track),
                          "--band", "3", "300", "-o", str(tmp_path / "s.json")], env=env, capture_output=True,
                         text=True, timeout=60)
    assert out.returncode == 130, out.stderr
    assert out.stderr.splitlines() == [out.stderr.strip()] and "interrupted" in out.stderr, out.stderr
    assert "Traceback" not in out.stderr and "install" not in out.stderr
    assert time.perf_counter() - start < 30
    assert not (tmp_path / "s.json").exists()


def test_a_real_import_error_is_still_reported(track, tmp_path):
    env = {**os.environ, "PYTHONPATH": str(Path(st.__file__).parent.parent)}
    script = INTERRUPTED_IMPORT.format(module="scipy").replace("raise KeyboardInterrupt", "raise OSError")
    script = script.replace("except KeyboardInterrupt", "except OSError")
    out = subprocess.run([sys.executable, "-c", script, "fit", str(track), "--band", "3", "300", "-o",
                          str(tmp_path / "s.json")], env=env, capture_output=True, text=True, timeout=60)
    assert out.returncode == 1 and "unexpected failure" in out.stderr and "Traceback" in out.stderr
