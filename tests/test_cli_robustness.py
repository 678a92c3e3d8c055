"""The command line against hostile and careless users: exit codes, one-line messages, files left behind.

The contract (``semitrack.cli``): exit 0 success, 2 bad input with ONE line on stderr naming the
problem and no traceback, 1 unexpected failure, 130 interrupted, 143 terminated. Every case checks
the exit code, the message and what is left on disk: the target of a symbolic link written and the
link still a link, a FIFO still a FIFO, an old file intact after a failed write, no hidden
temporary file, modes that honour the umask. Most cases run ``semitrack.cli.main`` in-process (fast);
signals, a closed stdout and a closed pipe need a subprocess.
"""

from __future__ import annotations

import errno
import io
import json
import os
import re
import signal
import socket
import stat
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import semitrack as st
from semitrack.base.files import atomic_write, check_output_path
from semitrack.cli import main
from semitrack.model.trackfile import example_path, track_to_toml

GRID = ["--fmin", "100", "--fmax", "200", "--df", "50"]  # three frequencies: fast
# As a reader's shell runs the program: stdout block-buffered (no PYTHONUNBUFFERED, which some CI
# environments set and which hid an exit-time flush failure on a full disk).
ENV = {**{k: v for k, v in os.environ.items() if k != "PYTHONUNBUFFERED"}, "OPENBLAS_NUM_THREADS": "1"}
OLD = "old content\n"


def cli(capsys, *args) -> tuple[int, str, str]:
    """Run the program in-process: (exit code, stdout, stderr)."""
    code = main([str(a) for a in args])
    out, err = capsys.readouterr()
    return code, out, err


def assert_refused(code: int, err: str, *words: str) -> None:
    """Exit code 2 and exactly one line on stderr, without traceback, naming each of ``words``."""
    assert code == 2, err
    assert len(err.splitlines()) == 1 and err.endswith("\n"), err
    assert "Traceback" not in err
    for word in words:
        assert word in err, err


def temporaries(folder: Path) -> list[str]:
    """Hidden temporary files of the atomic writer left in ``folder``."""
    return sorted(p.name for p in folder.iterdir() if p.name.startswith(".") and p.name.endswith(".tmp"))


@pytest.fixture
def track(tmp_path) -> Path:
    path = tmp_path / "slab.toml"
    path.write_text(example_path("slab").read_text())
    return path


@pytest.fixture
def system_file(tmp_path) -> Path:
    return st.export_system(st.paper_table4(), tmp_path / "system.json")


# --- what an output path names ---------------------------------------------------------------------
WRITERS = {  # option under test -> arguments, with OUT where the path goes
    "receptance -o": ["receptance", "TRACK", *GRID, "-o", "OUT"],
    "receptance --plot": ["receptance", "TRACK", *GRID, "-o", "other.csv", "--plot", "OUT"],
    "export -o": ["export", "SYSTEM", "-o", "OUT"],
    "fit -o": ["fit", "TRACK", "--bars", "2", "--band", "3", "300", "-o", "OUT"],
}
SUFFIX = {"receptance -o": ".csv", "receptance --plot": ".png", "export -o": ".csv", "fit -o": ".json"}


def arguments(writer: str, folder: Path, track: Path, system: Path, out: str | Path) -> list[str]:
    replace = {"TRACK": str(track), "SYSTEM": str(system), "OUT": str(out), "other.csv": str(folder / "other.csv")}
    return [replace.get(a, a) for a in WRITERS[writer]]


def make_socket(path: Path) -> None:
    sock = socket.socket(socket.AF_UNIX)
    try:
        sock.bind(str(path))
    except OSError as err:  # e.g. a path longer than sun_path
        pytest.skip(f"cannot create a socket here: {err}")
    finally:
        sock.close()


NOT_REGULAR = {  # kind -> (make it at path, the words of the message, test that it is still what it was)
    "directory": (lambda p: p.mkdir(), "is a directory", Path.is_dir),
    "fifo": (lambda p: os.mkfifo(p), "is a FIFO", Path.is_fifo),
    "socket": (make_socket, "is a socket", Path.is_socket),
    "link to a device": (lambda p: p.symlink_to(os.devnull), "is a character device", Path.is_symlink),
    "link to a directory": (lambda p: p.symlink_to(p.parent), "is a directory", Path.is_symlink),
    "link loop": (lambda p: (p.symlink_to(f"{p.name}.loop"), p.with_name(f"{p.name}.loop").symlink_to(p.name)),
                  "loop of symbolic links", Path.is_symlink),
}


@pytest.mark.parametrize("writer", [w for w in WRITERS if w != "fit -o"])
@pytest.mark.parametrize("dangling", [False, True], ids=["link", "dangling link"])
def test_a_symbolic_link_is_written_through(capsys, tmp_path, track, system_file, writer, dangling):
    target = tmp_path / ("new" if dangling else "target")
    target = target.with_suffix(SUFFIX[writer])
    if not dangling:
        target.write_text(OLD)
        target.chmod(0o640)
    link = tmp_path / f"link{SUFFIX[writer]}"
    link.symlink_to(target.name)
    code, _, err = cli(capsys, *arguments(writer, tmp_path, track, system_file, link))
    assert code == 0 and err == "", err
    assert link.is_symlink() and os.readlink(link) == target.name  # still the same link
    assert target.is_file() and target.read_bytes() != OLD.encode()
    if not dangling:
        assert stat.S_IMODE(target.stat().st_mode) == 0o640  # a replaced file keeps its mode
    assert temporaries(tmp_path) == []


@pytest.mark.parametrize("writer", WRITERS)
@pytest.mark.parametrize("kind", NOT_REGULAR)
def test_a_path_that_is_not_a_regular_file_is_refused_before_the_work(capsys, tmp_path, track, system_file,
                                                                      writer, kind):
    make, words, still = NOT_REGULAR[kind]
    out = tmp_path / f"out{SUFFIX[writer]}"
    make(out)
    start = time.perf_counter()
    code, _, err = cli(capsys, *arguments(writer, tmp_path, track, system_file, out))
    assert time.perf_counter() - start < 1.0  # refused before the work (a fit takes seconds)
    option = writer.split()[1]
    assert_refused(code, err, option, out.name, words)
    assert still(out)
    assert temporaries(tmp_path) == [] and not (tmp_path / "other.csv").exists()


@pytest.mark.parametrize("writer", WRITERS)
@pytest.mark.parametrize("case", ["empty", "no folder", "file as folder", "device", "read-only folder",
                                  "read-only file"])
def test_unwritable_output_paths_are_refused_before_the_work(capsys, tmp_path, track, system_file, monkeypatch,
                                                             writer, case):
    (tmp_path / "file.txt").write_text(OLD)
    read_only = tmp_path / f"ro-file{SUFFIX[writer]}"
    read_only.write_text(OLD)
    out, words = {"empty": ("", ["must name a file", "''"]),
                  "no folder": (tmp_path / "nope" / "x", ["does not exist", "nope"]),
                  "file as folder": (tmp_path / "file.txt" / "x", ["file.txt"]),
                  "device": (os.devnull, ["is a character device", os.devnull]),
                  "read-only folder": (tmp_path / "ro" / "x", ["is not writable", "ro"]),
                  "read-only file": (read_only, ["is read-only", read_only.name])}[case]
    if case == "read-only folder":
        (tmp_path / "ro").mkdir(mode=0o555)
    if case == "read-only file":
        read_only.chmod(0o444)
    if case.startswith("read-only") and os.geteuid() == 0:  # root may write anyway: simulate what others meet
        real_access = os.access
        monkeypatch.setattr(os, "access", lambda p, mode: False if Path(p).name.startswith("ro")
                            else real_access(p, mode))
    if out and writer == "receptance --plot" and case != "device":
        out = Path(out).with_suffix(".png")
    start = time.perf_counter()
    code, _, err = cli(capsys, *arguments(writer, tmp_path, track, system_file, out))
    assert time.perf_counter() - start < 1.0
    assert_refused(code, err, *words)
    assert (tmp_path / "file.txt").read_text() == OLD and read_only.read_text() == OLD
    assert temporaries(tmp_path) == []
    assert stat.S_ISCHR(os.stat(os.devnull).st_mode)


@pytest.mark.parametrize("kind", NOT_REGULAR)
def test_package_writers_refuse_what_is_not_a_regular_file(tmp_path, kind):
    """st.export_system and st.save_boundary share the CLI's checks: ValueError, nothing replaced."""
    make, words, still = NOT_REGULAR[kind]
    boundary = st.fit_boundary(st.slab_track(damping="viscous"), band=(3, 300), n_poles=4)
    for name, write in (("system.json", lambda p: st.export_system(st.paper_table4(), p)),
                        ("system.mat", lambda p: st.export_system(st.paper_table4(), p)),
                        ("boundary.json", lambda p: st.save_boundary(boundary, p)),
                        ("boundary.mat", lambda p: st.save_boundary(boundary, p))):
        out = tmp_path / name
        make(out)
        with pytest.raises(ValueError, match=words):
            write(out)
        assert still(out) and temporaries(tmp_path) == []


def test_package_writers_write_through_links_and_honour_the_umask(tmp_path):
    boundary = st.fit_boundary(st.slab_track(damping="viscous"), band=(3, 300), n_poles=4)
    old_mask = os.umask(0o027)
    try:
        for name, write, load in (("s.csv", lambda p: st.export_system(st.paper_table4(), p), st.load_system_csv),
                                  ("b.json", lambda p: st.save_boundary(boundary, p), st.load_boundary)):
            link = tmp_path / f"link-{name}"
            link.symlink_to(name)  # dangling: the target is created
            write(link)
            assert link.is_symlink() and stat.S_IMODE((tmp_path / name).stat().st_mode) == 0o640
            assert load(tmp_path / name) is not None
    finally:
        os.umask(old_mask)
    assert temporaries(tmp_path) == []


@pytest.mark.parametrize("mask", [0o022, 0o077, 0o002])
def test_new_files_honour_the_umask_and_replaced_files_keep_their_mode(capsys, tmp_path, track, mask):
    old_mask = os.umask(mask)
    try:
        code, _, err = cli(capsys, "receptance", track, *GRID, "-o", tmp_path / "new.csv")
        kept = tmp_path / "kept.csv"
        kept.write_text(OLD)
        kept.chmod(0o604)
        code2, _, _ = cli(capsys, "receptance", track, *GRID, "-o", kept)
    finally:
        os.umask(old_mask)
    assert code == code2 == 0, err
    assert stat.S_IMODE((tmp_path / "new.csv").stat().st_mode) == 0o666 & ~mask
    assert stat.S_IMODE(kept.stat().st_mode) == 0o604 and kept.read_text() != OLD


# --- the two outputs of receptance -------------------------------------------------------------------
@pytest.mark.parametrize("suffix,magic", [(".png", b"\x89PNG"), (".pdf", b"%PDF"), (".svg", b"<?xml"),
                                          (".PDF", b"%PDF")])
def test_plot_format_follows_the_suffix(capsys, tmp_path, track, suffix, magic):
    plot = tmp_path / f"alpha{suffix}"
    code, _, err = cli(capsys, "receptance", track, *GRID, "-o", tmp_path / "a.csv", "--plot", plot)
    assert code == 0, err
    assert plot.read_bytes().startswith(magic)


@pytest.mark.parametrize("name", ["alpha.jpg", "alpha", "alpha.csv"])
def test_plot_of_unknown_format_is_refused_before_the_work(capsys, tmp_path, track, name):
    code, _, err = cli(capsys, "receptance", track, *GRID, "-o", tmp_path / "a.csv", "--plot", tmp_path / name)
    assert_refused(code, err, "--plot", name, ".png, .pdf, .svg")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["slab.toml"]


@pytest.mark.parametrize("plot", ["same.png", "./same.png", "link.png"])
def test_the_same_file_twice_is_refused(capsys, tmp_path, track, plot, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "same.png").write_text(OLD)
    (tmp_path / "link.png").symlink_to("same.png")
    code, _, err = cli(capsys, "receptance", track, *GRID, "-o", "same.png", "--plot", plot)
    assert_refused(code, err, "--plot and -o name the same file", plot)
    assert (tmp_path / "same.png").read_text() == OLD


# --- bad input files and numbers -----------------------------------------------------------------------
def edited(folder: Path, key: str, value: str) -> Path:
    """The slab example with ``key = value``."""
    path = folder / "edited.toml"
    text, count = re.subn(rf"(?m)^{key}\s*=\s*\S+", f"{key} = {value}", example_path("slab").read_text(), count=1)
    assert count == 1
    path.write_text(text)
    return path


TRACK_FILES = {  # case -> (bytes of the file, words of the message)
    "binary": (b"\xff\xfe\x00\x01", ["not a UTF-8 text track file", "0xff"]),
    "latin-1": ('type = "slab"\nname = "café"\n'.encode("latin-1"), ["not a UTF-8", "0xe9", "offset 25"]),
    "nested TOML": (("a = " + "[" * 5000 + "]" * 5000 + "\n").encode(), ["nested too deeply"]),
    "nested tables": (("a = " + "{b = " * 3000 + "1" + "}" * 3000 + "\n").encode(), ["nested too deeply"]),
    "empty": (b"", ['missing key "type"']),
}


@pytest.mark.parametrize("case", TRACK_FILES)
def test_bad_track_files(capsys, tmp_path, case):
    content, words = TRACK_FILES[case]
    path = tmp_path / "bad.toml"
    path.write_bytes(content)
    code, _, err = cli(capsys, "receptance", path, *GRID, "-o", tmp_path / "out.csv")
    assert_refused(code, err, "bad.toml", *words)
    assert not (tmp_path / "out.csv").exists()


def test_an_endless_track_file_is_refused(capsys):
    code, _, err = cli(capsys, "receptance", "/dev/zero", *GRID)
    assert_refused(code, err, "/dev/zero", "larger than 1000000 bytes")


def test_spacing_beyond_any_track_is_refused_with_its_line(capsys, tmp_path):
    path = edited(tmp_path, "spacing", "1e300")
    line = next(n for n, text in enumerate(path.read_text().splitlines(), 1) if text.startswith("spacing"))
    code, _, err = cli(capsys, "receptance", path, *GRID)
    assert_refused(code, err, "edited.toml", f"line {line}", "spacing must be at most 1000 m", "1e+300")


def test_a_track_the_fit_cannot_use_is_bad_input(capsys, tmp_path):
    """E = 1 kPa, the lowest a track takes: the receptance is computed, the fit finds no dip to pin itself on."""
    path = edited(tmp_path, "E", "1000")
    code, out, err = cli(capsys, "receptance", path, *GRID)
    assert code == 0 and np.isfinite(pd.read_csv(io.StringIO(out), comment="#").to_numpy()).all()
    code, _, err = cli(capsys, "fit", path, "--bars", 2, "--band", 3, 300, "-o", tmp_path / "s.json")
    assert_refused(code, err, "no dip", "Hz")
    assert not (tmp_path / "s.json").exists()


@pytest.mark.parametrize("args,words", [
    (["--fmax", "1e308"], ["--fmax must be from 0.001 to 1e+06 Hz", "got 1e308"]),
    (["--fmax", "1e309"], ["--fmax must be positive and finite", "got 1e309"]),
    (["--fmin", "-0"], ["--fmin must be positive", "got -0"]),
    (["--fmin", "nan"], ["--fmin", "got nan"]),
    (["--df", "1e-320"], ["the grid would hold inf frequencies", "--df"]),
    (["--df", "1e-3"], ["the grid would hold 3e+06 frequencies", "--df"]),
])
def test_numbers_are_quoted_as_typed(capsys, track, args, words):
    code, _, err = cli(capsys, "receptance", track, *args)
    assert_refused(code, err, *words)
    assert "inf" not in err.replace("inf frequencies", "")


@pytest.mark.parametrize("band,words", [(["3", "1e308"], ["--band must be from 0.001 to 1e+06 Hz", "1e308"]),
                                        (["3", "1e309"], ["--band", "1e309"])])
def test_fit_band_is_checked_before_the_work(capsys, tmp_path, track, band, words):
    start = time.perf_counter()
    code, _, err = cli(capsys, "fit", track, "--band", *band, "-o", tmp_path / "s.json")
    assert time.perf_counter() - start < 1.0
    assert_refused(code, err, *words)


SYSTEMS = {  # case -> (edit of the JSON object or raw text, words of the message)
    "parameters a list": (lambda d: {**d, "parameters": [1, 2]}, ["'parameters' must be an object", "[1, 2]"]),
    "matrices a number": (lambda d: {**d, "matrices": 3}, ["'matrices' must be an object", "3"]),
    "entry without values": (lambda d: {**d, "parameters": {**d["parameters"], "m": {"unit": "kg"}}},
                             ["parameters['m'] has no key 'values'"]),
    "values not numbers": (lambda d: {**d, "parameters": {**d["parameters"], "m": {"values": ["x"]}}},
                           ["cannot load the system"]),
    "missing parameter": (lambda d: {**d, "parameters": {"m": d["parameters"]["m"]}},
                          ["cannot load the system", "missing parameter"]),
    "a JSON array": (lambda d: [d], ["must hold a JSON object", "list"]),
    "not JSON": ("{'single': quotes}", ["not a JSON file"]),
    "nested": ("[" * 100000, ["nested too deeply"]),
    "binary": (b"\xff\xfe", ["not a UTF-8 text system file"]),
}


@pytest.mark.parametrize("case", SYSTEMS)
def test_bad_system_files(capsys, tmp_path, system_file, case):
    edit, words = SYSTEMS[case]
    if callable(edit):
        system_file.write_text(json.dumps(edit(json.loads(system_file.read_text()))))
    elif isinstance(edit, bytes):
        system_file.write_bytes(edit)
    else:
        system_file.write_text(edit)
    code, _, err = cli(capsys, "export", system_file, "-o", tmp_path / "x.mat")
    assert_refused(code, err, "system.json", *words)
    assert not (tmp_path / "x.mat").exists()


def test_a_warning_is_one_line_and_not_a_failure(capsys, tmp_path, system_file):
    data = json.loads(system_file.read_text())
    data["matrices"]["K"]["values"][0][0] *= 2
    system_file.write_text(json.dumps(data))
    code, _, err = cli(capsys, "export", system_file, "-o", tmp_path / "x.csv")
    assert code == 0 and len(err.splitlines()) == 1
    assert err.startswith("semitrack export: warning: ") and "stored K differs" in err


# --- names and messages stay on one line -------------------------------------------------------------
def test_a_track_name_with_line_breaks_stays_on_its_header_line(capsys, tmp_path):
    path = tmp_path / "t.toml"
    path.write_text(track_to_toml(st.slab_track(name="evil\nf_Hz,1,2\r\x1b[31m\u2028name")))
    code, out, err = cli(capsys, "receptance", path, *GRID, "-o", tmp_path / "a.csv")
    assert code == 0, err
    text = (tmp_path / "a.csv").read_text()
    assert [line[:1] for line in text.splitlines()[:4]] == ["#", "#", "#", "f"]  # three comments, the header
    assert r"evil\nf_Hz,1,2\r\x1b[31m\u2028name" in text.splitlines()[0]
    assert len(pd.read_csv(tmp_path / "a.csv", comment="#")) == 3
    code, out, err = cli(capsys, "features", path, "--fmin", 100, "--fmax", 300, "--df", 20)
    assert code == 0 and out.splitlines()[0].startswith(r"peaks and dips of 'evil\nf_Hz")


def test_a_path_with_a_line_break_gives_a_one_line_message(capsys, tmp_path):
    code, _, err = cli(capsys, "receptance", tmp_path / "a\nb.toml")
    assert_refused(code, err, r"a\nb.toml", "cannot read the track file")


# --- writing: full disks, concurrent writers, unicode --------------------------------------------------
@pytest.mark.parametrize("failing", ["fsync", "replace"])
def test_a_full_disk_leaves_the_old_file_and_no_temporary(capsys, tmp_path, track, monkeypatch, failing):
    out = tmp_path / "out.csv"
    out.write_text(OLD)

    def full(*args):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(os, failing, full)
    code, _, err = cli(capsys, "receptance", track, *GRID, "-o", out)
    assert_refused(code, err, str(out), "No space left on device")
    assert out.read_text() == OLD and temporaries(tmp_path) == []


def test_an_interrupted_write_leaves_no_temporary(tmp_path):
    out = tmp_path / "out.csv"
    out.write_text(OLD)

    def interrupted(fh):
        fh.write("half")
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        atomic_write(out, interrupted)
    assert out.read_text() == OLD and temporaries(tmp_path) == []


def test_interrupted_during_the_work(capsys, tmp_path, track, monkeypatch):
    import semitrack.methods.receptance as receptance

    def interrupt(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(receptance, "semi_infinite_receptance", interrupt)
    code, _, err = cli(capsys, "receptance", track, *GRID, "-o", tmp_path / "out.csv")
    assert code == 130 and err == "semitrack receptance: interrupted\n"
    assert not (tmp_path / "out.csv").exists() and temporaries(tmp_path) == []


def test_unicode_paths(capsys, tmp_path):
    folder = tmp_path / "données-ü"
    folder.mkdir()
    track = folder / "voie-ß.toml"
    track.write_text(example_path("slab").read_text())
    code, _, err = cli(capsys, "receptance", track, *GRID, "-o", folder / "α.csv", "--plot", folder / "α.png")
    assert code == 0, err
    assert len(pd.read_csv(folder / "α.csv", comment="#")) == 3 and (folder / "α.png").stat().st_size > 0
    code, _, err = cli(capsys, "receptance", folder / "absente.toml")
    assert_refused(code, err, "données-ü", "absente.toml")


def test_check_output_path_returns_the_target_of_a_link(tmp_path):
    (tmp_path / "a").symlink_to("b")
    (tmp_path / "b").symlink_to("c.csv")
    assert check_output_path(tmp_path / "a") == tmp_path / "c.csv"
    with pytest.raises(TypeError, match="str or os.PathLike"):
        check_output_path(3)


def test_a_name_too_long_for_its_folder_is_refused_before_any_write(tmp_path, capsys):
    """A file name that fits only without the temporary file's 14 characters, a folder name past the
    system's 255 bytes and a path past 4096 are refused by name (they raised OSError ENAMETOOLONG)."""
    boundary = st.load_boundary(Path(__file__).parent / "data" / "boundary_slab_viscous_24.json")
    fits = tmp_path / ("x" * 236 + ".json")  # 241 bytes: with ".", ".<8 hex>.tmp" the 255 its folder holds
    st.save_boundary(boundary, fits)
    for path, words in ((tmp_path / ("x" * 237 + ".json"), "name a shorter file"),
                        (tmp_path / ("y" * 300) / "b.json", "name a shorter path"),
                        (tmp_path.joinpath(*["z" * 200] * 25, "b.json"), "name a shorter path")):
        with pytest.raises(st.BadInput, match=words):
            st.save_boundary(boundary, path)
        with pytest.raises(st.BadInput, match=words):
            check_output_path(path, "-o")
    assert sorted(p.name for p in tmp_path.iterdir()) == [fits.name]  # nothing else written
    code, _, err = cli(capsys, "receptance", example_path("slab"), "-o", tmp_path / ("x" * 300 + ".csv"))
    assert_refused(code, err, "name a shorter file")


# --- subprocesses: concurrency, pipes, closed stdout, signals -----------------------------------------
def _interruptible() -> None:
    """In the child: Ctrl-C as a terminal delivers it. A shell that starts a job in the background
    without job control (e.g. `cmd &` in a script) makes its children ignore SIGINT, and a
    program rightly keeps an ignored SIGINT ignored, which is not what these tests are about."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def spawn(*args, **kwargs) -> subprocess.Popen:
    return subprocess.Popen([sys.executable, "-m", "semitrack", *map(str, args)], env=ENV, text=True,
                            preexec_fn=_interruptible, **kwargs)


def test_two_writers_of_the_same_file_leave_one_whole_file(tmp_path, track):
    out = tmp_path / "out.csv"
    grids = (["--fmin", 3, "--fmax", 3000, "--df", 3], ["--fmin", 3, "--fmax", 300, "--df", 1])
    runs = [spawn("receptance", track, *grid, "-o", out, stderr=subprocess.PIPE) for grid in grids]
    assert all(p.wait(timeout=120) == 0 for p in runs), [p.stderr.read() for p in runs]
    data = pd.read_csv(out, comment="#")
    f = data["f_Hz"].to_numpy()
    assert np.array_equal(f, np.arange(3.0, 3001.0, 3.0)) or np.array_equal(f, np.arange(3.0, 301.0, 1.0))
    assert data.notna().all().all() and temporaries(tmp_path) == []


def test_a_reader_that_goes_away_is_not_a_failure(track):
    """``semitrack receptance ... | head -1``: exit 0, nothing on stderr."""
    p = spawn("receptance", track, "--fmin", 3, "--fmax", 3000, "--df", 3, stdout=subprocess.PIPE,
              stderr=subprocess.PIPE)
    assert p.stdout.readline().startswith("# semitrack")
    p.stdout.close()
    assert p.wait(timeout=120) == 0
    assert p.stderr.read() == ""


@pytest.mark.parametrize("command", [["features", "TRACK"], ["receptance", "TRACK", *GRID], ["example", "slab"]])
def test_closed_stdout_is_bad_input(track, command):
    args = " ".join(f"'{track}'" if a == "TRACK" else a for a in command)
    result = subprocess.run(["sh", "-c", f"exec '{sys.executable}' -m semitrack {args} >&-"], env=ENV,
                            capture_output=True, text=True, timeout=120)
    assert_refused(result.returncode, result.stderr, "stdout is closed")


def test_a_full_stdout_is_bad_input(track):
    if not os.path.exists("/dev/full"):
        pytest.skip("no /dev/full")
    with open("/dev/full", "w") as full:
        p = spawn("receptance", track, *GRID, stdout=full, stderr=subprocess.PIPE)
        err = p.communicate(timeout=120)[1]
    assert_refused(p.returncode, err, "cannot write to stdout", "No space left on device")


SLOW_WRITE = textwrap.dedent("""
    import os, sys, time
    from semitrack.cli import main
    def slow_fsync(fd):  # the temporary file exists: the test signals now
        time.sleep(60)
    os.fsync = slow_fsync
    sys.exit(main(sys.argv[1:]))
""")


@pytest.mark.parametrize("signum,code,word", [(signal.SIGTERM, 143, "terminated"), (signal.SIGINT, 130, "interrupted")])
def test_a_signal_during_the_write_leaves_the_old_file_and_no_temporary(tmp_path, track, signum, code, word):
    out = tmp_path / "out.csv"
    out.write_text(OLD)
    p = subprocess.Popen([sys.executable, "-c", SLOW_WRITE, "receptance", str(track), *GRID, "-o", str(out)],
                         env=ENV, text=True, stderr=subprocess.PIPE, preexec_fn=_interruptible)
    deadline = time.monotonic() + 60
    while not temporaries(tmp_path) and time.monotonic() < deadline and p.poll() is None:
        time.sleep(0.02)
    assert temporaries(tmp_path), "the write never started"
    p.send_signal(signum)
    err = p.communicate(timeout=60)[1]
    assert p.returncode == code and err == f"semitrack receptance: {word}\n", err
    assert out.read_text() == OLD and temporaries(tmp_path) == []


def test_sigint_during_start_up_exits_without_traceback(track):
    """Ctrl-C while the program imports numpy, scipy and the package (the first ~0.1-1 s): exit
    130 (or killed by SIGINT before Python runs, which a shell reports as 130 too), never a
    traceback. The first ~30 ms are the interpreter's own start-up (its site module), which no
    program can intercept: the delays start after it."""
    interrupted = 0
    for delay in (0.1, 0.15, 0.3, 0.5, 1.0):
        p = spawn("features", track, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
        time.sleep(delay)
        if p.poll() is not None:  # done already (an idle machine runs `features` in under 1 s)
            assert p.returncode == 0 and "Traceback" not in p.communicate()[1], delay
            continue
        p.send_signal(signal.SIGINT)
        err = p.communicate(timeout=60)[1]
        # 0: the run finished between poll() and the signal (a race the test cannot close), cleanly
        assert p.returncode in (0, 130, -signal.SIGINT) and "Traceback" not in err, (delay, err)
        interrupted += p.returncode != 0
    assert interrupted >= 2  # the start-up itself was interrupted, not only finished runs


def test_an_unrecognised_argument_with_a_newline_is_refused_on_one_line(capsys):
    """argparse quotes what it did not recognise as typed: ``--band '\\n' 400`` once split the refusal
    over two lines (found by the property suite, seed 31)."""
    assert main(["decay", "--", "--band", "\n", "400", "--df", "20"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.endswith("\n") and "unrecognized arguments: \\n 400" in err
