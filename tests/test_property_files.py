"""Every file reader of the package fuzzed: damaged, hostile, huge and foreign files (issue 34, point 3).

A file the package reads may be hand-edited, written by another program, cut short by a full disk,
planted in a shared cache folder, or not a file at all. Whatever it is, a reader must end

* in a valid result (the reader's own checks passed: a passive boundary, symmetric positive
  semi-definite M, C, K, finite numbers, a cache entry equal to what it stands for), or
* in :class:`semitrack.BadInput` with ONE line that names the file (:class:`OSError`, which names
  it too, is accepted only for a path that is not a readable regular file); the command line
  exits 2 with such a line on stderr,

within 1 s (a cache: 1 s beyond recomputing the entry it could not use), and, for the huge files,
with a peak memory under 300 MB. It must never end in another exception (``JSONDecodeError``,
``RecursionError``, ``MemoryError``, zipfile's errors, ``KeyError``, ...), hang, or allocate in
proportion to what a file claims. A file that declares conventions other than the package's
(mm, ``exp(-i omega t)``, swapped ports, a left end, ...) is refused naming the field, or read
with a warning naming it where the conversion is well defined.

The readers (:data:`READERS`), each started from a valid file the package wrote itself:

=====================================  ============================================================
``load_track_toml``                    the shipped example ``slab.toml``
``load_frequency_table``               a pad table in the documented format (the package has no
                                       writer for it): the paper's pad, ``kv (1 + i eta)``
``load_boundary`` (.json, .mat)        :func:`semitrack.save_boundary` of ``tests/data``' slab fit
``load_system_json/_csv/_mat``         :func:`semitrack.export_system` of the paper's Table 4
``load_matrix_system`` (.json, .csv,   :func:`semitrack.export_boundary` with ``mck=True``: the
.mat)                                  same boundary's M, C, K
fit and sweep caches                   :func:`semitrack.cached_fit` and ``cached_central_response``
                                       (:mod:`semitrack.equivalent.cache`) with a cache folder
boundary cache (.json)                 :func:`semitrack.cached_boundary` of a viscous slab, 4 poles
kernel cache (.npz)                    ``cached_kernels`` (:mod:`semitrack.fe.kernelcache`), a
                                       coarse slab mesh: its file is what it read
study records (.json)                  :func:`semitrack.run_study` with a ``cache_dir``: one case's
                                       record, recomputed when it cannot be trusted
``semitrack receptance``               the track file, and the pad table a track file names
``semitrack export``                   each of the eight end files above
=====================================  ============================================================

The cases:

* **damage** (Hypothesis): one to four of truncation at a drawn offset, a bit flip, an insertion
  (random bytes or a token a parser trips on: ``[``, ``\\xff``, ``1e999``, ``NaN``, a pickle's
  opening bytes, ...) and a deletion;
* **not a regular file**: missing, empty, a directory, links to a directory and to ``/dev/null``,
  a dangling link, a loop of links, and a FIFO (run in a thread; if the read blocks, the test
  opens the FIFO's other end so that it returns, and fails); for a cache, a link planted in its
  folder, whose target must be left as it was (a cache is written without following links), and
  a cache folder that is a file or a loop;
* **huge**: a sparse file of 4 GB (``truncate``), a link to ``/dev/zero``, a ``.mat`` file of 3 MB
  whose compressed variable inflates to 3 GiB (:func:`inflating_mat`, built in 0.1 s), and a
  kernel file whose ``.npy`` member's header claims 8 TB or 2 GiB. Each is read in a process of
  its own whose peak RSS is measured as :mod:`peak_memory` documents (``VmHWM``): a fork of one
  measuring process per test worker that has imported the readers and read each one's valid file
  once (:func:`serve`), its address space allowed to grow by 3 GiB only, so that a reader that
  does grow ends in a ``MemoryError`` there instead of taking the machine's memory;
* **deep nesting**: 100 000 nested ``[`` (or ``{"a":``) as the whole JSON file, in a TOML value,
  in a ``.mat`` file's JSON variable and in the kernel file's key; 20 000 in a CSV file's JSON
  cell, and a CSV cell past the ``csv`` module's field limit;
* **foreign conventions**: each of the seven fields of the end files' ``conventions`` record
  changed in turn, and the ports' names swapped in an M, C, K file, in every end file format and
  through ``semitrack export``; a table in kHz, as magnitude and phase, or in ``exp(-i omega t)``;
  a track file in mm.

A failure here is a defect of the reader, not of the test: the tests state the rule and are not
adjusted to today's behaviour. Examples per Hypothesis test: :data:`EXAMPLES` (25, derandomized
under the suite's ``ci`` profile; the ``long`` profile's own number with
``--hypothesis-profile long``); no example database is written. The file's 452 tests run in about
15 s with ``-n 2`` when the readers hold (measured 13.5 s; 29 s on a package whose readers block on
FIFOs, each costing its 1 s bound).
"""

from __future__ import annotations

import contextlib
import csv
import dataclasses
import io
import json
import os
import resource
import select
import shutil
import signal
import struct
import subprocess
import sys
import tempfile
import textwrap
import threading
import time
import warnings
import zipfile
import zlib
from collections.abc import Callable
from functools import cache
from pathlib import Path

import numpy as np
import pytest
import scipy.io
import study_functions
from hypothesis import HealthCheck, given, note, settings
from hypothesis import strategies as hs
from peak_memory import PEAK_RSS
from refusals import refused

import semitrack as st
from semitrack.base.errors import BadInput
from semitrack.cli import main
from semitrack.equivalent.cache import CachedResponse, cached_central_response, clear_fit_memo
from semitrack.equivalent.exchange import mat_conventions
from semitrack.fe.kernelcache import cached_kernels, clear_kernel_memo
from semitrack.fe.kernels import grid_of
from semitrack.model.trackfile import example_path

TESTS = Path(__file__).resolve().parent
SRC = Path(st.__file__).resolve().parent.parent
BOUNDARY_DATA = TESTS / "data" / "boundary_slab_viscous_24.json"

#: The longest a read may take (s), refusal or result: issue 34's bound (measured: under 0.25 s).
SECONDS = 1.0
#: The largest peak RSS of a subprocess reading a huge file (KiB): issue 34's 300 MB.
PEAK_KIB = 300_000_000 // 1024
#: How far such a subprocess may grow its address space (bytes): a reader that grows fails here, not the machine.
ADDRESS_SPACE = 3 << 30
#: Examples per Hypothesis test: 25 (the file in about a minute on 2 cores), or the ``long`` profile's.
EXAMPLES = settings().max_examples if settings.get_current_profile_name() == "long" else 25
FUZZ = settings(max_examples=EXAMPLES, deadline=None, database=None,
                suppress_health_check=[HealthCheck.too_slow])

# What the caches hold: a small fit, a three-frequency sweep, a coarse mesh's kernels (each ~0.1 s).
PAPER_SLAB = st.slab_track()
VISCOUS_SLAB = st.slab_track(damping="viscous")
KERNEL_GRID = grid_of(VISCOUS_SLAB, 50.0, 1e-4)
RECEPTANCE = ["--fmin", "100", "--fmax", "200", "--df", "50", "--quiet"]


# --- the readers -----------------------------------------------------------------------------------
class CliRefusal(Exception):
    """``semitrack`` exited 2: the message is what it printed on stderr."""


@dataclasses.dataclass(frozen=True)
class CliRun:
    """``semitrack`` exited 0: what it printed, and the file it wrote."""

    stdout: str
    stderr: str
    output: Path


def cli(output: Path, *args) -> CliRun:
    """Run ``semitrack`` in-process; exit 2 raises :class:`CliRefusal`, any code but 0 and 2 fails."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main([str(a) for a in args])
    if code == 2:
        raise CliRefusal(err.getvalue().removesuffix("\n"))
    assert code == 0, f"semitrack {' '.join(map(str, args))}: exit {code}\n{err.getvalue()}"
    return CliRun(out.getvalue(), err.getvalue(), output)


def fit_in(folder: Path):
    clear_fit_memo()
    return st.cached_fit(PAPER_SLAB, "slab", n_bars=2, band=(3.0, 300.0), n_starts=1, cache_dir=folder)


def sweep_in(folder: Path):
    clear_fit_memo()
    return cached_central_response(PAPER_SLAB, [100.0, 150.0, 200.0], "transfer", cache_dir=folder)


def kernels_in(folder: Path):
    clear_kernel_memo()
    return cached_kernels(VISCOUS_SLAB, 8, None, KERNEL_GRID, 100, None, folder)


def study_in(folder: Path):
    return st.run_study(study_functions.eigen, [{"x": 3, "n": 8}], cache_dir=folder, progress=False)


def boundary_in(folder: Path):
    clear_fit_memo()
    return st.cached_boundary(VISCOUS_SLAB, band=(3.0, 300.0), n_poles=4, df=30.0, n_iter=3, cache_dir=folder)


COMPUTE = {"fit": fit_in, "sweep": sweep_in, "kernels": kernels_in, "study": study_in, "boundary": boundary_in}


@cache
def computed(kind: str):
    """The cache entry ``kind`` computed afresh (no folder), and the seconds that took."""
    clear_fit_memo()
    clear_kernel_memo()
    start = time.perf_counter()
    with tempfile.TemporaryDirectory() as folder:
        value = COMPUTE[kind](Path(folder))
    return value, time.perf_counter() - start


@cache
def cache_file_name(kind: str) -> str:
    """The name of the one file a cache writes for its entry in an empty folder (the key's digest)."""
    with tempfile.TemporaryDirectory() as folder:
        COMPUTE[kind](Path(folder))
        (name,) = [p.name for p in Path(folder).iterdir() if not p.name.endswith(".lock")]
    return name


def pad_track_file(table: Path) -> Path:
    """A track file beside ``table`` whose pad stiffness is that table (the slab example otherwise)."""
    text = example_path("slab").read_text().replace("kv = 5.44e7", f'kv = {{table = "{table.name}"}}')
    assert text != example_path("slab").read_text()
    track = table.with_name("with-pad-table.toml")
    track.write_text(text)
    return track


# What a result must be.
def is_track(result):
    assert isinstance(result, st.Track), result


def is_table(result):
    assert isinstance(result, st.FrequencyTable), result


def is_boundary(result):
    assert isinstance(result, st.BroadbandBoundary) and bool(result.passivity), result


def _finite_symmetric(matrices, psd: bool):
    for X in matrices:
        assert np.all(np.isfinite(X)) and np.allclose(X, X.T, rtol=0, atol=1e-12 * np.abs(X).max()), X
        if psd:
            assert np.linalg.eigvalsh(X).min() >= -1e-10 * max(np.abs(X).max(), 1e-300), X


def is_system(result):
    assert isinstance(result, st.EquivalentSystem), result
    _finite_symmetric(result.matrices(), psd=False)


def is_matrix_system(result):
    assert isinstance(result, st.MatrixSystem), result
    _finite_symmetric(result.matrices(), psd=True)


def is_fit(result):
    assert isinstance(result, st.FitResult) and isinstance(result.system, st.EquivalentSystem), result


def is_sweep(result):
    assert isinstance(result, CachedResponse) and np.all(np.isfinite(result.response.w1)), result


def is_an_end(result):
    assert isinstance(result, st.BroadbandBoundary) and np.all(np.isfinite(result.receptance([10.0, 100.0]))), result


def are_the_kernels(result):
    """A damaged kernel file is never read as other kernels: the zip's CRCs catch it, the entry is recomputed."""
    fresh, _ = computed("kernels")
    assert np.array_equal(result.loop, fresh.loop) and np.array_equal(result.flexibility, fresh.flexibility)


def is_the_study(result):
    """A damaged study record is never read as another result: it is recomputed, equal to the fresh one."""
    fresh, _ = computed("study")
    assert result.equals(fresh) and result.error[0] == "", result


def wrote_output(result: CliRun):
    assert result.output.is_file() and result.output.stat().st_size > 0, result


@dataclasses.dataclass(frozen=True)
class Reader:
    """One reader: where it looks in a folder, how it is called, what a result must be.

    ``source`` names the valid file it starts from (:func:`write_valid_files`); ``cache`` is the
    kind of a cache entry (its file is named by its key; a file it cannot use is recomputed, so a
    damaged one is never refused); ``cli``: the command line, whose refusal is exit 2.
    """

    name: str
    source: str
    read: Callable[[Path], object]
    valid: Callable[[object], None]
    cache: str = ""
    cli: bool = False

    def place(self, folder: Path) -> Path:
        """The path this reader reads in ``folder``."""
        return folder / (cache_file_name(self.cache) if self.cache else self.source)

    def refusals(self, regular: bool) -> tuple[type, ...]:
        """The exceptions that count as a refusal: of a damaged regular file, or of a path that is not one."""
        if self.cli:
            return (CliRefusal,)
        if self.cache:
            return () if regular else (BadInput,)
        return (BadInput,) if regular else (BadInput, OSError)

    @property
    def seconds(self) -> float:
        """The time bound: :data:`SECONDS`, and for a cache also twice the time of recomputing its entry."""
        return SECONDS + (2 * computed(self.cache)[1] if self.cache else 0.0)


def _export(path: Path) -> CliRun:
    out = path.with_name("exported.csv")
    return cli(out, "export", path, "-o", out)


def _receptance(track: Path) -> CliRun:
    out = track.with_name("alpha.csv")
    return cli(out, "receptance", track, *RECEPTANCE, "-o", out)


END_FILES = ("boundary.json", "boundary.mat", "system.json", "system.csv", "system.mat",
             "matrices.json", "matrices.csv", "matrices.mat")
READERS = {reader.name: reader for reader in [
    Reader("load_track_toml", "track.toml", st.load_track_toml, is_track),
    Reader("load_frequency_table", "pad.csv", st.load_frequency_table, is_table),
    Reader("load_boundary-json", "boundary.json", st.load_boundary, is_boundary),
    Reader("load_boundary-mat", "boundary.mat", st.load_boundary, is_boundary),
    Reader("load_system_json", "system.json", st.load_system_json, is_system),
    Reader("load_system_csv", "system.csv", st.load_system_csv, is_system),
    Reader("load_system_mat", "system.mat", st.load_system_mat, is_system),
    Reader("load_matrix_system-json", "matrices.json", st.load_matrix_system, is_matrix_system),
    Reader("load_matrix_system-csv", "matrices.csv", st.load_matrix_system, is_matrix_system),
    Reader("load_matrix_system-mat", "matrices.mat", st.load_matrix_system, is_matrix_system),
    Reader("fit-cache", "fit", lambda p: fit_in(p.parent), is_fit, cache="fit"),
    Reader("sweep-cache", "sweep", lambda p: sweep_in(p.parent), is_sweep, cache="sweep"),
    Reader("kernel-cache", "kernels", lambda p: kernels_in(p.parent), are_the_kernels, cache="kernels"),
    Reader("study-cache", "study", lambda p: study_in(p.parent), is_the_study, cache="study"),
    Reader("boundary-cache", "boundary", lambda p: boundary_in(p.parent), is_an_end, cache="boundary"),
    Reader("cli-receptance-track", "track.toml", _receptance, wrote_output, cli=True),
    Reader("cli-receptance-pad-table", "pad.csv", lambda p: _receptance(pad_track_file(p)), wrote_output, cli=True),
    *[Reader(f"cli-export-{name}", name, _export, wrote_output, cli=True) for name in END_FILES],
]}


def write_valid_files(folder: Path) -> dict[str, bytes]:
    """The valid file of every reader's ``source``, as the package writes it: ``{source: bytes}``."""
    track = PAPER_SLAB
    rows = "".join(f"{f!r}, {track.kv!r}, {track.kv * track.eta_pad!r}\n" for f in map(float, range(0, 3001, 100)))
    (folder / "pad.csv").write_text("# the paper's slab track's pad, kv (1 + i eta_pad)\nf_Hz, re, im\n" + rows)
    shutil.copyfile(example_path("slab"), folder / "track.toml")
    boundary = st.load_boundary(BOUNDARY_DATA)
    for suffix in ("json", "mat"):
        st.save_boundary(boundary, folder / f"boundary.{suffix}")
    for suffix in ("json", "csv", "mat"):
        st.export_system(st.paper_table4(), folder / f"system.{suffix}")
        st.export_boundary(boundary, folder / f"matrices.{suffix}", mck=True)
    files = {p.name: p.read_bytes() for p in folder.iterdir()}
    for kind in COMPUTE:
        entry = folder / kind
        entry.mkdir()
        COMPUTE[kind](entry)
        files[kind] = (entry / cache_file_name(kind)).read_bytes()
    return files


@pytest.fixture(scope="module")
def valid_files(tmp_path_factory) -> dict[str, bytes]:
    return write_valid_files(tmp_path_factory.mktemp("valid"))


@pytest.fixture(scope="module")
def workdir(tmp_path_factory) -> Path:
    return tmp_path_factory.mktemp("fuzz")


@contextlib.contextmanager
def new_folder(workdir: Path):
    """An empty folder for one example, removed afterwards."""
    folder = Path(tempfile.mkdtemp(dir=workdir))
    try:
        yield folder
    finally:
        shutil.rmtree(folder, ignore_errors=True)


# --- one read and its verdict ----------------------------------------------------------------------
@dataclasses.dataclass
class Outcome:
    result: object = None
    error: Exception | None = None
    seconds: float = 0.0
    warnings: tuple[str, ...] = ()


def attempt(reader: Reader, path: Path, record_warnings: bool = True) -> Outcome:
    """Call the reader on ``path``: its result or exception, the time, the warnings it issued."""
    with warnings.catch_warnings(record=True) if record_warnings else contextlib.nullcontext() as seen:
        if record_warnings:
            warnings.simplefilter("always")
        start = time.perf_counter()
        try:
            outcome = Outcome(result=reader.read(path))
        except Exception as err:  # noqa: BLE001 - every exception is judged by judge()
            outcome = Outcome(error=err)
        outcome.seconds = time.perf_counter() - start
    outcome.warnings = tuple(str(w.message) for w in seen or ())
    return outcome


def judge(reader: Reader, path: Path, outcome: Outcome, regular: bool = True) -> None:
    """A valid result, or a refusal of the reader's kind in one line naming ``path``; in time."""
    error = outcome.error
    if error is not None:
        message = str(error)
        allowed = reader.refusals(regular)
        assert isinstance(error, allowed), (
            f"{reader.name} on {path}: {type(error).__module__}.{type(error).__name__}: {message[:300]} "
            f"(expected a valid result{' or ' + '/'.join(c.__name__ for c in allowed) if allowed else ''})")
        assert len(message.splitlines()) == 1, f"{reader.name}: not one line: {message!r}"
        assert str(path) in message, f"{reader.name}: the message does not name {path}: {message!r}"
    else:
        reader.valid(outcome.result)
    assert outcome.seconds < reader.seconds, f"{reader.name} on {path}: {outcome.seconds:.2f} s"


# --- the valid files read back ---------------------------------------------------------------------
@pytest.mark.parametrize("name", READERS)
def test_the_packages_own_file_reads_back(valid_files, workdir, name):
    """The starting point of every case: the file the package wrote reads back, valid, in time."""
    reader = READERS[name]
    with new_folder(workdir) as folder:
        path = reader.place(folder)
        path.write_bytes(valid_files[reader.source])
        outcome = attempt(reader, path)
        assert outcome.error is None, f"{type(outcome.error).__name__}: {outcome.error}"
        judge(reader, path, outcome)


# --- damage ---------------------------------------------------------------------------------------
#: Bytes that parsers trip on: brackets, quotes, separators, invalid UTF-8, overflowing numbers, a
#: pickle's opening, a section header of the CSV files, a MAT file's compressed-element tag.
TOKENS = [b"[", b"{", b"]", b"}", b'"', b",", b"\n", b"\r", b"#", b"=", b"-", b"\x00", b"\xff", b"\xc3",
          b"1e999", b"NaN", b"-Infinity", b"\x80\x04", b"[meta]", b"[K]", b"\x0f\x00\x00\x00"]
OFFSET = hs.integers(min_value=0, max_value=1 << 24)  # taken modulo the length of the file at the time
DAMAGE = hs.lists(hs.one_of(
    hs.tuples(hs.just("truncate"), OFFSET),
    hs.tuples(hs.just("flip"), OFFSET, hs.integers(0, 7)),
    hs.tuples(hs.just("insert"), OFFSET, hs.one_of(hs.sampled_from(TOKENS), hs.binary(min_size=1, max_size=16))),
    hs.tuples(hs.just("delete"), OFFSET, hs.integers(1, 64)),
), min_size=1, max_size=4)


def damaged(data: bytes, damage: list[tuple]) -> bytes:
    """``data`` with each of ``damage`` applied in turn."""
    out = bytearray(data)
    for kind, offset, *arg in damage:
        at = offset % (len(out) + 1)
        if kind == "truncate":
            del out[at:]
        elif kind == "flip" and at < len(out):
            out[at] ^= 1 << arg[0]
        elif kind == "insert":
            out[at:at] = arg[0]
        elif kind == "delete":
            del out[at:at + arg[0]]
    return bytes(out)


@pytest.mark.parametrize("name", READERS)
@FUZZ
@given(damage=DAMAGE)
def test_a_damaged_file_is_read_or_refused(valid_files, workdir, name, damage):
    reader = READERS[name]
    data = damaged(valid_files[reader.source], damage)
    with new_folder(workdir) as folder:
        path = reader.place(folder)
        path.write_bytes(data)
        note(f"{len(data)} bytes at {path}")
        judge(reader, path, attempt(reader, path))


# --- paths that are not a readable regular file ----------------------------------------------------
def _loop(path: Path) -> None:
    other = path.with_name(path.name + ".other")
    other.symlink_to(path)
    path.symlink_to(other)


SPECIAL = {  # what the path is -> how to make it
    "missing": lambda path: None,
    "empty": lambda path: path.write_bytes(b""),
    "a directory": lambda path: path.mkdir(),
    "a link to a directory": lambda path: path.symlink_to(path.parent),
    "a dangling link": lambda path: path.symlink_to(path.parent / "target-of-the-link"),
    "a loop of links": _loop,
    "a link to /dev/null": lambda path: path.symlink_to("/dev/null"),
}


@pytest.mark.parametrize("kind", SPECIAL)
@pytest.mark.parametrize("name", READERS)
def test_a_path_that_is_not_a_regular_file(workdir, name, kind):
    reader = READERS[name]
    with new_folder(workdir) as folder:
        path = reader.place(folder)
        SPECIAL[kind](path)
        judge(reader, path, attempt(reader, path), regular=kind == "empty")
        if reader.cache and kind == "a dangling link":
            assert not (folder / "target-of-the-link").exists(), "the cache wrote through a link planted in its folder"


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no FIFOs here")
@pytest.mark.parametrize("name", READERS)
def test_a_fifo_is_refused_without_blocking(workdir, name):
    """A FIFO in the reader's place: the read must end within the time bound without a writer.

    The read runs in a thread. If it is still running after the bound, the test opens the FIFO's
    writing end and closes it, over and over, until the read returns (a reader blocked in
    ``open`` then reads an empty file), and then fails: the suite itself never hangs.
    """
    reader = READERS[name]
    with new_folder(workdir) as folder:
        path = reader.place(folder)
        os.mkfifo(path)
        box = {}
        thread = threading.Thread(target=lambda: box.update(outcome=attempt(reader, path, record_warnings=False)),
                                  daemon=True)
        thread.start()
        thread.join(reader.seconds)
        blocked = thread.is_alive()
        deadline = time.monotonic() + 20
        while thread.is_alive() and time.monotonic() < deadline:
            with contextlib.suppress(OSError):  # ENXIO: no reader has the FIFO open at this moment
                os.close(os.open(path, os.O_WRONLY | os.O_NONBLOCK))
            thread.join(0.05)
        assert not blocked, f"{reader.name} blocked on the FIFO {path} (released by the test)"
        judge(reader, path, box["outcome"], regular=False)


CACHES = [name for name, reader in READERS.items() if reader.cache]


@pytest.mark.parametrize("name", CACHES)
def test_a_link_planted_in_a_cache_folder_is_not_written_through(workdir, name):
    """The cache reads what a planted link points to (not its entry) and recomputes it; the file outside
    the folder must be left as it was (the entry is written without following links, or refused)."""
    reader = READERS[name]
    with new_folder(workdir) as folder:
        outside = folder / "outside.txt"
        outside.write_bytes(b"a file outside the cache folder\n")
        (folder / "cache").mkdir()
        path = reader.place(folder / "cache")
        path.symlink_to(outside)
        judge(reader, path, attempt(reader, path), regular=False)
        assert outside.read_bytes() == b"a file outside the cache folder\n", "written through the planted link"


@pytest.mark.parametrize("folder_is", ["a file", "a loop of links"])
@pytest.mark.parametrize("name", CACHES)
def test_a_cache_folder_that_is_not_a_folder_is_refused(workdir, name, folder_is):
    reader = READERS[name]
    with new_folder(workdir) as folder:
        cache_dir = folder / "cache"
        if folder_is == "a file":
            cache_dir.write_text("not a folder\n")
        else:
            _loop(cache_dir)
        path = reader.place(cache_dir)
        refused(lambda: reader.read(path), BadInput, str(cache_dir), seconds=reader.seconds)


# --- huge files, measured in a subprocess ----------------------------------------------------------
#: The measuring process: it imports the readers once, then reads each case it is sent in a fork of itself.
MEASURING = PEAK_RSS + textwrap.dedent("""
    import json, sys
    import test_property_files as fuzz

    for line in sys.stdin:
        print(json.dumps(fuzz.serve(json.loads(line), peak_rss_kib)), flush=True)
""")
_WARM: set[str] = set()


def _vm_size() -> int:
    """This process's address space (bytes)."""
    with open("/proc/self/status") as fh:
        return next(int(line.split()[1]) * 1024 for line in fh if line.startswith("VmSize:"))


def measured_read(reader: Reader, path: Path, regular: bool, peak_rss_kib) -> dict:
    """Read ``path`` here: the verdict, the seconds and the peak RSS (KiB), the address space capped."""
    cap = _vm_size() + ADDRESS_SPACE
    resource.setrlimit(resource.RLIMIT_AS, (cap, cap))
    start = time.perf_counter()
    try:
        result = reader.read(path)
    except Exception as err:  # noqa: BLE001 - reported, judged by the test
        report = {"error": f"{type(err).__module__}.{type(err).__name__}", "message": str(err),
                  "refusal": isinstance(err, reader.refusals(regular))}
    else:
        try:
            reader.valid(result)
            report = {"result": type(result).__name__}
        except AssertionError as err:
            report = {"error": "an invalid result", "message": str(err)[:300], "refusal": False}
    report.update(seconds=time.perf_counter() - start, peak_kib=peak_rss_kib())
    return report


def serve(request: dict, peak_rss_kib) -> dict:
    """In the measuring process: warm the reader up on its valid file (once), then read the case in a fork.

    The fork is the process measured. Linux starts a fork's ``VmHWM`` at its own resident size, not
    at its parent's peak (measured: a fork of a process that had peaked at 513 MB reported 17 MB),
    so each case's peak is its own, on top of the imports every reading process pays.
    """
    reader, path = READERS[request["reader"]], Path(request["path"])
    failed = {"refusal": False, "message": "", "seconds": 0.0, "peak_kib": 0}
    try:
        if reader.name not in _WARM:
            reader.read(Path(request["pristine"]))  # imports and first-call set-up: not part of a case
            _WARM.add(reader.name)
        if reader.place(path.parent) != path:
            return {**failed, "error": "the package's cache key changed under the test"}
    except Exception as err:  # noqa: BLE001 - reported
        return {**failed, "error": f"the warm-up failed: {type(err).__name__}: {err}"}
    read_end, write_end = os.pipe()
    pid = os.fork()
    if pid == 0:  # the measured process
        os.close(read_end)
        try:
            report = measured_read(reader, path, request["regular"], peak_rss_kib)
        except BaseException as err:  # noqa: BLE001 - e.g. a MemoryError while reporting
            report = {**failed, "error": f"{type(err).__name__} in the measuring fork"}
        with os.fdopen(write_end, "w") as fh:
            fh.write(json.dumps(report))
        os._exit(0)
    os.close(write_end)
    with os.fdopen(read_end) as fh:
        text = fh.read()
    _, status = os.waitpid(pid, 0)
    return json.loads(text) if text else {**failed, "error": f"the measuring fork died (wait status {status})"}


class MeasuringProcess:
    """The client of :data:`MEASURING`: one per test worker, restarted after a case that timed out."""

    def __init__(self, folder: Path):
        self.folder, self.process, self.log = folder, None, folder / "measuring-process.log"

    def measure(self, request: dict, timeout: float = 60.0) -> dict:
        if self.process is None or self.process.poll() is not None:
            env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(SRC), str(TESTS)]), "OPENBLAS_NUM_THREADS": "1"}
            with open(self.log, "ab") as log:
                self.process = subprocess.Popen([sys.executable, "-c", MEASURING], stdin=subprocess.PIPE,
                                                stdout=subprocess.PIPE, stderr=log, env=env, cwd=self.folder,
                                                text=True, start_new_session=True)
        self.process.stdin.write(json.dumps(request) + "\n")
        self.process.stdin.flush()
        ready, _, _ = select.select([self.process.stdout], [], [], timeout)
        line = self.process.stdout.readline() if ready else ""
        if not line:
            self.stop()
            what = f"still running after {timeout:g} s (killed)" if not ready else "the measuring process died"
            log = self.log.read_text()[-1500:]
            pytest.fail(f"{request['reader']} on {request['path']}: {what}; its log ends: {log}")
        return json.loads(line)

    def stop(self) -> None:
        if self.process is not None:
            if self.process.poll() is None:
                os.killpg(self.process.pid, signal.SIGKILL)  # the process and a fork still reading
            self.process.wait()
            self.process.stdin.close()
            self.process.stdout.close()
            self.process = None


@pytest.fixture(scope="module")
def measuring(tmp_path_factory):
    process = MeasuringProcess(tmp_path_factory.mktemp("measuring"))
    yield process
    process.stop()


def read_measured(measuring: MeasuringProcess, reader: Reader, path: Path, pristine: Path, regular: bool) -> None:
    """Read ``path`` in a measured process; assert its verdict (as :func:`judge`), time and peak RSS."""
    report = measuring.measure({"reader": reader.name, "path": str(path), "pristine": str(pristine),
                                "regular": regular})
    where = f"{reader.name} on {path}: {report} ({report['seconds']:.2f} s, peak {report['peak_kib'] / 1024:.0f} MiB)"
    if "error" in report:
        assert report["refusal"], where
        assert len(report["message"].splitlines()) == 1 and str(path) in report["message"], where
    assert report["seconds"] < reader.seconds, where
    assert report["peak_kib"] < PEAK_KIB, where


def _sparse(path: Path, data: bytes) -> None:
    with open(path, "wb") as fh:
        fh.write(data)
        fh.truncate(4 << 30)  # 4 GiB, a hole after the valid content: no disk used


HUGE = {"a sparse file of 4 GB": _sparse, "a link to /dev/zero": lambda path, data: path.symlink_to("/dev/zero")}


@pytest.mark.parametrize("kind", HUGE)
@pytest.mark.parametrize("name", READERS)
def test_a_huge_file_is_refused_within_bounds(valid_files, workdir, measuring, name, kind):
    reader = READERS[name]
    with new_folder(workdir) as folder:
        pristine = reader.place(folder / "pristine") if reader.cache else folder / "pristine" / reader.source
        pristine.parent.mkdir()
        pristine.write_bytes(valid_files[reader.source])
        (folder / "case").mkdir()
        path = reader.place(folder / "case")
        HUGE[kind](path, valid_files[reader.source])
        read_measured(measuring, reader, path, pristine, regular=kind.startswith("a sparse"))


def zeros_deflated(prefix: bytes, n_zeros: int) -> bytes:
    """A zlib stream of ``prefix`` and ``n_zeros`` zero bytes, built in a tenth of a second for gigabytes.

    After a full flush the compressor starts afresh, so every 16 MiB chunk of zeros compresses to the
    same bytes: the stream is the prefix's deflate blocks, one chunk's blocks repeated, an empty final
    block and the Adler-32 of the whole (zeros leave its sum ``a`` as it is and add ``a`` to ``b`` each).
    """
    chunk = 1 << 24
    assert n_zeros % chunk == 0
    z = zlib.compressobj(9)
    head = z.compress(prefix) + z.flush(zlib.Z_FULL_FLUSH)
    body = z.compress(b"\0" * chunk) + z.flush(zlib.Z_FULL_FLUSH)
    assert z.compress(b"\0" * chunk) + z.flush(zlib.Z_FULL_FLUSH) == body
    adler = zlib.adler32(prefix)
    a, b = adler & 0xFFFF, adler >> 16
    b = (b + n_zeros % 65521 * a) % 65521
    return head + body * (n_zeros // chunk) + b"\x01\x00\x00\xff\xff" + struct.pack(">I", b << 16 | a)


def inflating_mat(name: str, shape: tuple[int, int]) -> bytes:
    """A MAT-5 file of one compressed double matrix ``name`` of ``shape``, all zeros (3 MB for 3 GiB)."""
    n_bytes = shape[0] * shape[1] * 8
    named = name.encode()
    name_element = struct.pack("<II", 1, len(named)) + named.ljust(-(-len(named) // 8) * 8, b"\0")
    subelements = (struct.pack("<II", 6, 8) + struct.pack("<II", 6, 0)  # array flags: mxDOUBLE_CLASS
                   + struct.pack("<II", 5, 8) + struct.pack("<ii", *shape)  # dimensions
                   + name_element + struct.pack("<II", 9, n_bytes))  # the name; miDOUBLE, its zeros follow
    stream = zeros_deflated(struct.pack("<II", 14, len(subelements) + n_bytes) + subelements, n_bytes)
    header = b"MATLAB 5.0 MAT-file, a compressed variable of 3 GiB".ljust(116, b" ") + b"\0" * 8
    return header + struct.pack("<H", 0x0100) + b"IM" + struct.pack("<II", 15, len(stream)) + stream


def test_the_inflating_mat_inflates():
    """The bomb is what it claims: a small version inflates to its zeros and is a matrix scipy reads."""
    data = inflating_mat("M", (4096, 512))  # 16 MiB
    content = scipy.io.loadmat(io.BytesIO(data))
    assert content["M"].shape == (4096, 512) and not content["M"].any()
    assert len(inflating_mat("M", (1 << 14, 24576))) < 4_000_000  # 3 GiB of zeros


MAT_READERS = [name for name, reader in READERS.items() if reader.source.endswith(".mat")]


@pytest.mark.parametrize("name", MAT_READERS)
def test_a_mat_whose_variable_inflates_to_3_gib(valid_files, workdir, measuring, name):
    reader = READERS[name]
    with new_folder(workdir) as folder:
        pristine = folder / "pristine" / reader.source
        pristine.parent.mkdir()
        pristine.write_bytes(valid_files[reader.source])
        path = reader.place(folder)
        path.write_bytes(inflating_mat("M", (1 << 14, 24576)))  # 16384 x 24576 doubles: 3 GiB
        read_measured(measuring, reader, path, pristine, regular=True)


def lying_npz(data: bytes, member: str, shape: tuple[int, ...]) -> bytes:
    """The npz ``data`` with ``member``'s ``.npy`` header claiming ``shape``, its bytes as they were."""
    out = io.BytesIO()
    with zipfile.ZipFile(io.BytesIO(data)) as src, zipfile.ZipFile(out, "w", zipfile.ZIP_STORED) as dst:
        for info in src.infolist():
            content = src.read(info)
            if info.filename == member:
                fh = io.BytesIO(content)
                version = np.lib.format.read_magic(fh)
                header = (np.lib.format.read_array_header_1_0 if version == (1, 0)
                          else np.lib.format.read_array_header_2_0)(fh)
                new = io.BytesIO()
                np.lib.format.write_array_header_2_0(new, {"descr": header[2].str, "fortran_order": header[1],
                                                           "shape": shape})
                content = new.getvalue() + content[fh.tell():]
            dst.writestr(info.filename, content)
    return out.getvalue()


@pytest.mark.parametrize("shape", [(10**6, 10**6, 1), (1 << 28,)], ids=["8-TB", "2-GiB"])
def test_a_kernel_file_whose_member_lies_about_its_shape(valid_files, workdir, measuring, shape):
    """The members' stored sizes pass the size bound; the header's shape must not be allocated: recomputed."""
    reader = READERS["kernel-cache"]
    with new_folder(workdir) as folder:
        pristine = reader.place(folder / "pristine")
        pristine.parent.mkdir()
        pristine.write_bytes(valid_files["kernels"])
        (folder / "case").mkdir()
        path = reader.place(folder / "case")
        path.write_bytes(lying_npz(valid_files["kernels"], "loop.npy", shape))
        read_measured(measuring, reader, path, pristine, regular=True)


# --- deep nesting ---------------------------------------------------------------------------------
DEPTH = 100_000
#: A CSV cell holds at most 131 072 characters (the csv module's field limit: a case of its own below).
CELL_DEPTH = 20_000


def nesting(shape: str, depth: int = DEPTH) -> str:
    return "[" * depth + "]" * depth if shape == "arrays" else '{"a":' * depth + "1" + "}" * depth


NESTED = ("arrays", "objects")


def _mat_variables(data: bytes) -> dict:
    raw = scipy.io.loadmat(io.BytesIO(data))
    return {k: v for k, v in raw.items() if not k.startswith("__")}


def _savemat(variables: dict) -> bytes:
    out = io.BytesIO()
    scipy.io.savemat(out, variables)
    return out.getvalue()


def _csv_rows(data: bytes) -> list[list[str]]:
    return list(csv.reader(io.StringIO(data.decode(), newline="")))


def _csv_bytes(rows: list[list[str]]) -> bytes:
    out = io.StringIO()
    csv.writer(out, lineterminator="\n").writerows(rows)
    return out.getvalue().encode()


def with_conventions(source: str, data: bytes, change: dict, raw: str | None = None) -> bytes:
    """An end file with its ``conventions`` record changed: ``change`` as values, or the field of
    ``change`` set to the JSON text ``raw`` (which need not be valid)."""
    suffix = source.rsplit(".", 1)[1]
    if suffix == "json":
        content = json.loads(data)
        content["conventions"].update(change)
        text = json.dumps(content, indent=1)
        if raw is not None:
            (field,) = change
            text = text.replace(f'"{field}": {json.dumps(change[field])}', f'"{field}": {raw}', 1)
        return text.encode()
    if suffix == "csv":
        rows, section = _csv_rows(data), None
        for row in rows:
            if row and row[0].startswith("["):
                section = row[0]
            elif section == "[conventions]" and row and row[0] in change:
                row[1] = raw if raw is not None else json.dumps(change[row[0]])
        return _csv_bytes(rows)
    variables = _mat_variables(data)
    conventions = json.loads(str(np.squeeze(variables["conventions_json"])))
    conventions.update(change)
    variables["conventions"] = mat_conventions(conventions)
    text = json.dumps(conventions)
    if raw is not None:
        (field,) = change
        text = text.replace(f'"{field}": {json.dumps(change[field])}', f'"{field}": {raw}', 1)
    variables["conventions_json"] = text
    return _savemat(variables)


def nested(reader: Reader, data: bytes, shape: str) -> bytes:
    """The reader's valid file with data nested ``DEPTH`` deep where its format holds nested data."""
    payload = nesting(shape)
    if reader.source == "kernels":  # the key, a JSON text in the npz
        with np.load(io.BytesIO(data), allow_pickle=False) as content:
            arrays = {k: content[k] for k in content.files}
        arrays["key"] = np.array(payload)
        out = io.BytesIO()
        np.savez(out, **arrays)
        return out.getvalue()
    if reader.source.endswith(".toml"):
        return data + f"\nnested = {payload if shape == 'arrays' else payload.replace(':', '=')}\n".encode()
    if reader.source.endswith(".json") or reader.cache:
        return payload.encode()
    if reader.source.endswith(".csv"):  # a JSON cell
        return with_conventions(reader.source, data, {"side": "right"}, raw=nesting(shape, CELL_DEPTH))
    return with_conventions(reader.source, data, {"side": "right"}, raw=payload)  # .mat: a JSON variable


@pytest.mark.parametrize("shape", NESTED)
@pytest.mark.parametrize("name", [name for name, reader in READERS.items() if reader.source != "pad.csv"])
def test_deeply_nested_data(valid_files, workdir, name, shape):
    reader = READERS[name]
    with new_folder(workdir) as folder:
        path = reader.place(folder)
        path.write_bytes(nested(reader, valid_files[reader.source], shape))
        judge(reader, path, attempt(reader, path))


CSV_READERS = [name for name, reader in READERS.items() if reader.source.endswith(".csv")]


@pytest.mark.parametrize("name", CSV_READERS)
def test_a_csv_cell_longer_than_the_csv_modules_limit(valid_files, workdir, name):
    """A cell of 200 000 characters: past :func:`csv.field_size_limit`, whose ``_csv.Error`` must not escape."""
    reader = READERS[name]
    rows = _csv_rows(valid_files[reader.source])
    rows[len(rows) // 2] = ["x" * 200_000, *rows[len(rows) // 2][1:]]
    with new_folder(workdir) as folder:
        path = reader.place(folder)
        path.write_bytes(_csv_bytes(rows))
        judge(reader, path, attempt(reader, path))


# --- foreign conventions --------------------------------------------------------------------------
PACKAGE_UNITS = {"length": "m", "rotation": "rad", "force": "N", "moment": "N m", "time": "s", "mass": "kg",
                 "frequency": "Hz"}
FOREIGN = {  # the field of the conventions record -> a value another code or convention would write
    "side": "left",
    "units": {**PACKAGE_UNITS, "length": "mm"},
    "time_factor": "exp(-i omega t)",
    "port_dofs": ["psi", "w"],
    "port_indices": [1, 0],
    "load_convention": "applied_by_end",
    "left_end_mirror": [[1.0, 0.0], [0.0, 1.0]],
}
IN_PROCESS_END_READERS = [name for name, reader in READERS.items() if reader.source in END_FILES and not reader.cli]
CLI_END_READERS = [name for name, reader in READERS.items() if reader.source in END_FILES and reader.cli]


def refused_or_warned(reader: Reader, path: Path, field: str) -> None:
    """Refused naming ``field`` (one line, the file), or read with a warning naming it; in time."""
    outcome = attempt(reader, path)
    if outcome.error is None:
        said = " ".join(outcome.warnings) + (outcome.result.stderr if reader.cli else "")
        assert field in said, f"{reader.name}: {path} declares another {field!r} and was read without a word"
    else:
        judge(reader, path, outcome)
        assert field in str(outcome.error), f"{reader.name}: the refusal does not name {field!r}: {outcome.error}"
    assert outcome.seconds < reader.seconds


#: Every field in every format; through the command line, whose reading is the loaders', three of them.
CONVENTION_CASES = [(name, field) for name in IN_PROCESS_END_READERS for field in ("(none)", *FOREIGN)] + \
                   [(name, field) for name in CLI_END_READERS for field in ("(none)", "side", "time_factor", "units")]


@pytest.mark.parametrize(("name", "field"), CONVENTION_CASES, ids=[f"{n}-{f}" for n, f in CONVENTION_CASES])
def test_foreign_conventions_are_refused_or_converted_naming_the_field(valid_files, workdir, name, field):
    """Each field of the conventions record changed alone; ``(none)``: the same file rewritten unchanged, read."""
    reader = READERS[name]
    with new_folder(workdir) as folder:
        path = reader.place(folder)
        change = {} if field == "(none)" else {field: FOREIGN[field]}
        path.write_bytes(with_conventions(reader.source, valid_files[reader.source], change))
        if field == "(none)":
            outcome = attempt(reader, path)
            assert outcome.error is None, outcome.error
            judge(reader, path, outcome)
        else:
            refused_or_warned(reader, path, field)


@pytest.mark.parametrize("name", [n for n in IN_PROCESS_END_READERS + CLI_END_READERS
                                  if READERS[n].source.startswith("matrices")])
def test_an_m_c_k_file_with_its_ports_named_in_another_order_is_refused(valid_files, workdir, name):
    """``dof_names`` says the first DOF is psi and the second w: the matrices are not in the package's order."""
    reader = READERS[name]
    suffix = reader.source.rsplit(".", 1)[1]
    data = valid_files[reader.source]
    if suffix == "json":
        content = json.loads(data)
        content["dof_names"][:2] = content["dof_names"][1::-1]  # psi, w
        data = json.dumps(content, indent=1).encode()
    elif suffix == "csv":
        rows = _csv_rows(data)
        for row in rows:
            if row[:1] == ["dof_names"]:
                names = json.loads(row[1])
                row[1] = json.dumps([names[1], names[0], *names[2:]])
        data = _csv_bytes(rows)
    else:
        variables = _mat_variables(data)
        names = [str(np.squeeze(n)) for n in np.ravel(variables["dof_names"])]
        variables["dof_names"] = np.array([names[1], names[0], *names[2:]], dtype=object)
        data = _savemat(variables)
    with new_folder(workdir) as folder:
        path = reader.place(folder)
        path.write_bytes(data)
        refused_or_warned(reader, path, "dof_names")


TABLES = {  # a pad table in conventions the package does not use -> the words of its refusal
    "kHz": (lambda rows: rows.replace("f_Hz, re, im", "f_kHz, re, im"), ("line 2",)),
    "magnitude and phase": (lambda rows: rows.replace("f_Hz, re, im", "f_Hz, magnitude, phase"), ("line 2",)),
    "exp(-i omega t)": (lambda rows: "\n".join(line.rsplit(", ", 1)[0] + ", -" + line.rsplit(", ", 1)[1]
                                               if line[:1].isdigit() else line for line in rows.splitlines()),
                        ("passive",)),
}


@pytest.mark.parametrize("case", TABLES)
@pytest.mark.parametrize("name", ["load_frequency_table", "cli-receptance-pad-table"])
def test_a_table_in_other_conventions_is_refused(valid_files, workdir, name, case):
    reader = READERS[name]
    change, words = TABLES[case]
    with new_folder(workdir) as folder:
        path = reader.place(folder)
        path.write_text(change(valid_files["pad.csv"].decode()))
        outcome = attempt(reader, path)
        assert outcome.error is not None, f"{reader.name}: a table in {case} was read"
        judge(reader, path, outcome)
        for word in words:
            assert word in str(outcome.error), outcome.error


@pytest.mark.parametrize("name", ["load_track_toml", "cli-receptance-track"])
def test_a_track_file_in_millimetres_is_refused(valid_files, workdir, name):
    reader = READERS[name]
    with new_folder(workdir) as folder:
        path = reader.place(folder)
        path.write_bytes(b'units = "mm"\n' + valid_files["track.toml"])
        outcome = attempt(reader, path)
        assert outcome.error is not None, f"{reader.name}: a track file in mm was read"
        judge(reader, path, outcome)
        assert "'units'" in str(outcome.error), outcome.error
