"""Tracks and slabs under hostile input: fields that may not be None, span indices, 200 fasteners.

Each case asserts the exception class or exit code, a one-line message naming the parameter, a
time bound, and that the track file is unchanged. A slab with the allowed 200 fasteners makes
every frequency ~1000 times dearer than one support: the exact method's work is weighed as
frequencies x supports before any evaluation, its memory bounded by evaluating in blocks (RSS
measured in a subprocess), and the paper's wavenumber method, whose arrays grow with the square
of the supports, refused.
"""

from __future__ import annotations

import dataclasses
import os
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np
import pytest
from peak_memory import PEAK_RSS
from refusals import SECONDS, refused

import semitrack as st
from semitrack.base.errors import InputError, InputTypeError
from semitrack.cli import main
from semitrack.model.trackfile import example_path
from semitrack.model.tracks import OPTIONAL_FIELDS

# --- Track fields: None only for sleeper_mass and kb ---------------------------------------------------
FIELDS = [f.name for f in dataclasses.fields(st.Track) if f.name not in OPTIONAL_FIELDS
          and f.name not in ("slab", "foundation")]  # slab and foundation: None is "none"


@pytest.mark.parametrize("name", FIELDS)
def test_no_track_field_but_the_sleeper_s_may_be_none(name):
    message = refused(lambda: dataclasses.replace(st.ballasted_track(), **{name: None}), (InputError, InputTypeError),
                      name, "None")
    assert message.startswith(name)


def test_damping_none_is_not_the_viscous_track():
    refused(lambda: st.slab_track(damping=None), InputError, "damping", "hysteretic", "viscous")
    refused(lambda: st.slab_track(kv=None), InputTypeError, "kv")


def test_sleeper_mass_and_kb_none_together_is_a_rigid_foundation():
    track = st.ballasted_track(sleeper_mass=None, kb=None)
    assert not track.is_ballasted
    refused(lambda: st.ballasted_track(kb=None), InputError, "sleeper_mass and kb")


# --- Slab span indices ---------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def slab() -> st.Slab:
    return st.load_track_toml(example_path("floating-slab")).slab


@pytest.mark.parametrize("from_span", [5.5, True, "1", None, np.float64(1.0)])
def test_a_span_index_must_be_an_integer(slab, from_span):
    refused(lambda: slab.receptance([100.0], 0.65, from_span=from_span), InputTypeError, "from_span", "integer")


@pytest.mark.parametrize("from_span", [-1, 10, 10**6])
def test_a_span_index_must_be_on_the_slab(slab, from_span):
    refused(lambda: slab.receptance([100.0], 0.65, from_span=from_span), InputError, "from_span")


def test_integer_span_indices_still_work(slab):
    assert slab.receptance([100.0], 0.65, from_span=np.int64(2)).shape == (1, 8, 8)


# --- 200 fasteners ---------------------------------------------------------------------------------------
def _many_fasteners(folder: Path, n: int = 200) -> Path:
    text = example_path("floating-slab").read_text()
    text = text.replace("length = 6.45 ", f"length = {0.65 * n:.2f} ").replace("fasteners = 10 ", f"fasteners = {n} ")
    path = folder / f"slab{n}.toml"
    path.write_text(text)
    assert st.load_track_toml(path).slab.fasteners == n
    return path


@pytest.fixture
def many(tmp_path) -> Path:
    return _many_fasteners(tmp_path)


COMMANDS = {  # what once ran for hours or allocated GiBs -> words of the refusal
    "receptance --df 0.015": (["receptance", "TRACK", "--df", "0.015", "-o", "OUT"], ("--df", "200 supports")),
    "receptance wavenumber": (["receptance", "TRACK", "--method", "wavenumber", "-o", "OUT"],
                              ("200 supports", "method='transfer'")),
    "features": (["features", "TRACK"], ("df=", "200 supports")),
    "fit --boundary": (["fit", "TRACK", "--boundary", "--band", "3", "3000", "-o", "OUT.json"], ("200 supports",)),
}


@pytest.mark.parametrize("command", sorted(COMMANDS))
def test_200_fasteners_are_refused_at_once_by_the_command_line(capsys, many, tmp_path, command):
    args, words = COMMANDS[command]
    out = tmp_path / "out"
    args = [str(many) if a == "TRACK" else str(out) + a[3:] if a.startswith("OUT") else a for a in args]
    before = many.read_bytes()
    start = time.perf_counter()
    code = main(args)
    elapsed = time.perf_counter() - start
    _, err = capsys.readouterr()
    assert code == 2 and len(err.splitlines()) == 1, err
    for word in words:
        assert word in err, err
    assert elapsed < SECONDS and many.read_bytes() == before
    assert not list(tmp_path.glob("out*"))


def test_200_fasteners_in_python(many):
    track = st.load_track_toml(many)
    refused(lambda: st.semi_infinite_receptance(track, np.linspace(3, 3000, 2000)), InputError, "2000 frequencies",
            "200 supports")
    refused(lambda: st.central_response(track, [100.0], method="wavenumber"), InputError, "200 supports",
            "transfer")
    refused(lambda: st.fit_boundary(track), InputError, "200 supports")


MEASURE = PEAK_RSS + textwrap.dedent("""
    import sys, time
    import numpy as np
    import semitrack as st
    track = st.load_track_toml(sys.argv[1])
    start = time.perf_counter()
    alpha = st.semi_infinite_receptance(track, np.linspace(3.0, 300.0, 38))
    print(bool(np.all(np.isfinite(alpha))), time.perf_counter() - start,
          peak_rss_kib())
""")


def test_many_frequencies_on_200_fasteners_are_evaluated_in_bounded_memory(many):
    # 38 frequencies in blocks of 12: in one block they held 845 MiB (and 200 frequencies 1.6 GiB)
    env = {**os.environ, "PYTHONPATH": str(Path(st.__file__).parent.parent)}
    out = subprocess.run([sys.executable, "-c", MEASURE, str(many)], env=env, capture_output=True, text=True,
                         timeout=120)
    finite, seconds, rss_kib = out.stdout.split()
    assert finite == "True", out.stderr
    assert float(seconds) < 30 and int(rss_kib) < 600_000, (seconds, rss_kib)


def test_blocks_give_the_same_numbers(tmp_path, monkeypatch):
    from semitrack.methods import receptance

    track = st.load_track_toml(_many_fasteners(tmp_path, 12))
    f = np.array([50.0, 120.0, 400.0])
    whole = st.semi_infinite_receptance(track, f)
    monkeypatch.setattr(receptance, "BLOCK_BYTES", 1)  # one frequency per block
    np.testing.assert_array_equal(st.semi_infinite_receptance(track, f), whole)
    assert len(receptance.frequency_blocks(track.cell(), f)) == 3
