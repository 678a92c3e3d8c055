"""Boundary (and system) files under hostile input: bounded reads, complete checks, physics, the track.

Every case asserts the exception class, a one-line message naming the file and the key or check,
a time bound, and that the file was left as it was. The largest cases (``/dev/zero`` behind a
``.json`` name, a ``.mat`` whose compressed variable inflates to 1 GB) run in a subprocess whose
peak RSS is measured (``VmHWM``, :mod:`peak_memory`): under 1 GB and 30 s before the refusal.
"""

from __future__ import annotations

import copy
import json
import os
import struct
import subprocess
import sys
import textwrap
import time
import zlib
from pathlib import Path

import numpy as np
import pytest
import scipy.io
from peak_memory import PEAK_RSS

import semitrack as st
from semitrack.base.errors import BadInput, InputError
from semitrack.boundary.io import boundary_to_dict

DATA = Path(__file__).parent / "data"
SLAB_FILE = DATA / "boundary_slab_viscous_24.json"
BALLASTED_FILE = DATA / "boundary_ballasted_viscous_24.json"
SECONDS = 5.0  # each in-process refusal, with room for a busy machine (measured: < 0.1 s)


@pytest.fixture(scope="module")
def data() -> dict:
    return json.loads(SLAB_FILE.read_text())


def refused(path: Path, *words: str, cls=InputError, loader=st.load_boundary, **options) -> str:
    """Load ``path``, expect ``cls`` with one line naming the file and ``words``, fast, the file unchanged."""
    before = path.read_bytes() if path.is_file() else None
    start = time.perf_counter()
    with pytest.raises(cls) as info:
        loader(path, **options)
    elapsed = time.perf_counter() - start
    message = str(info.value)
    assert len(message.splitlines()) == 1, message
    assert str(path) in message, message
    for word in words:
        assert word in message, message
    assert elapsed < SECONDS, elapsed
    if before is not None:
        assert path.read_bytes() == before
    return message


def write(tmp_path: Path, content: dict | str | bytes, name: str = "b.json") -> Path:
    path = tmp_path / name
    if isinstance(content, dict):
        content = json.dumps(content)
    path.write_bytes(content if isinstance(content, bytes) else content.encode())
    return path


def test_a_good_file_still_loads(data):
    bnd = st.load_boundary(SLAB_FILE)
    assert bnd.rational.poles.size == len(data["poles"]) and bool(bnd.is_passive())


# --- sizes bounded before parsing ------------------------------------------------------------------
def test_dev_zero_behind_a_json_name(tmp_path):
    link = tmp_path / "zero.json"
    link.symlink_to("/dev/zero")
    refused(link, "larger than")


def test_json_nested_100000_deep(tmp_path):
    refused(write(tmp_path, "[" * 100_000 + "]" * 100_000), "nested too deeply")


@pytest.mark.parametrize("n", [2000, 6000])
def test_thousands_of_poles_are_refused_before_any_matrix(data, tmp_path, n):
    bad = dict(data, poles=[[-1.0 - i, 1.0 + i] for i in range(n)], coefficients=[[0.0, 0.0, 0.0]] * (2 * n))
    bad.pop("state_space")
    refused(write(tmp_path, bad), "'poles'", f"{n} poles", "more than")


def _inflating_mat(path: Path, inflated: int) -> Path:
    """A MAT-5 file (header and one miCOMPRESSED element) whose stream inflates to ``inflated`` zero bytes."""
    z, chunk, parts = zlib.compressobj(9), b"\0" * (1 << 24), []
    for _ in range(inflated // len(chunk)):
        parts.append(z.compress(chunk))
    parts.append(z.flush())
    stream = b"".join(parts)
    header = b"MATLAB 5.0 MAT-file, hostile".ljust(116, b" ") + b"\0" * 8 + struct.pack("<H", 0x0100) + b"IM"
    path.write_bytes(header + struct.pack("<II", 15, len(stream)) + stream)
    return path


def test_a_mat_whose_compressed_field_inflates(tmp_path):
    path = _inflating_mat(tmp_path / "bomb.mat", 1 << 27)  # 128 MiB of zeros in 130 kB
    assert path.stat().st_size < 200_000
    refused(path, "inflate to more than")


MEASURE = PEAK_RSS + textwrap.dedent("""
    import sys, time
    import semitrack as st
    start = time.perf_counter()
    try:
        st.{loader}(sys.argv[1])
    except Exception as err:
        print(type(err).__name__, "|", err)
    print(time.perf_counter() - start, peak_rss_kib())
""")


@pytest.mark.parametrize("case", ["dev-zero", "bomb"])
def test_hostile_files_stay_within_1_gb_and_30_s(tmp_path, case):
    if case == "dev-zero":
        path = tmp_path / "zero.json"
        path.symlink_to("/dev/zero")
    else:
        path = _inflating_mat(tmp_path / "bomb.mat", 1 << 30)  # 1 GiB inflated, ~1 MB on disk
    env = {**os.environ, "PYTHONPATH": str(Path(st.__file__).parent.parent)}
    for loader in ("load_boundary", "load_system_json" if case == "dev-zero" else "load_system_mat"):
        system_path = path if loader == "load_boundary" else path
        out = subprocess.run([sys.executable, "-c", MEASURE.format(loader=loader), str(system_path)], env=env,
                             capture_output=True, text=True, timeout=60)
        refusal, figures = out.stdout.strip().splitlines()
        seconds, rss_kib = figures.split()
        assert refusal.startswith("InputError"), out.stdout + out.stderr
        assert float(seconds) < 30 and int(rss_kib) < 1_000_000, (loader, seconds, rss_kib)


# --- every field's type and value ------------------------------------------------------------------
BAD_FIELDS = {  # name -> (change of the data, words of the message)
    "median_error text": ({"median_error": "abc"}, ("'median_error'", "number")),
    "median_error NaN": ({"median_error": float("nan")}, ("'median_error'", "finite")),
    "max_error negative": ({"max_error": -1.0}, ("'max_error'",)),
    "rounds 1e400": ({"enforcement_rounds": 1e400}, ("'enforcement_rounds'", "integer")),
    "rounds text": ({"enforcement_rounds": "2"}, ("'enforcement_rounds'",)),
    "empty band": ({"band_hz": []}, ("'band_hz'",)),
    "three-element band": ({"band_hz": [3.0, 30.0, 300.0]}, ("'band_hz'", "two frequencies")),
    "band reversed": ({"band_hz": [300.0, 3.0]}, ("'band_hz'",)),
    "unknown version": ({"version": 99}, ("'version'", "99")),
    "version text": ({"version": "1"}, ("'version'",)),
    "other format": ({"format": "something"}, ("'format'",)),
    "poles text": ({"poles": "abc"}, ("'poles'",)),
    "poles NaN": ({"poles": [[float("nan"), 1.0]]}, ("'poles'", "finite")),
    "poles triples": ({"poles": [[-1.0, 1.0, 0.0]]}, ("'poles'", "shape")),
    "K0 3x3": ({"K0": np.eye(3).tolist()}, ("'K0'", "shape")),
    "D text": ({"D": [["a", 0], [0, 1]]}, ("'D'", "numbers")),
    "coefficients ragged": ({"coefficients": [[1.0], [1.0, 2.0]]}, ("'coefficients'",)),
    "track number": ({"track": 5}, ("'track'", "text")),
    "state space text": ({"state_space": "abc"}, ("'state_space'",)),
}


@pytest.mark.parametrize("case", sorted(BAD_FIELDS))
def test_every_field_is_checked(data, tmp_path, case):
    change, words = BAD_FIELDS[case]
    bad = {**copy.deepcopy(data), **change}
    refused(write(tmp_path, bad), *words)


@pytest.mark.parametrize("key", ["poles", "coefficients", "K0", "D", "band_hz"])
def test_a_missing_key_is_named(data, tmp_path, key):
    bad = copy.deepcopy(data)
    del bad[key]
    refused(write(tmp_path, bad), f"{key!r}")


@pytest.mark.parametrize("content", ["[1, 2]", '"text"', "", "{", "\xff"])
def test_json_that_is_not_a_boundary(tmp_path, content):
    refused(write(tmp_path, content.encode("latin-1")), "")


# --- physics: stable, K0 positive definite, passive; the check=False opt-out ----------------------
def _without_state_space(data: dict, **change) -> dict:
    bad = {**copy.deepcopy(data), **change}
    bad.pop("state_space")  # the state space follows from the poles: consistent with the change
    return bad


def _unstable(data):
    poles = copy.deepcopy(data["poles"])
    poles[0][0] = abs(poles[0][0])
    return _without_state_space(data, poles=poles)


PHYSICS = {
    "unstable": (_unstable, "unstable"),
    "not passive": (lambda d: _without_state_space(d, coefficients=(-10 * np.array(d["coefficients"])).tolist()),
                    "not passive"),
    "negative K0": (lambda d: _without_state_space(d, K0=(-np.array(d["K0"])).tolist()), "K0"),
}


@pytest.mark.parametrize("case", sorted(PHYSICS))
def test_physics_is_checked_on_loading_and_on_attaching(data, tmp_path, case):
    make, word = PHYSICS[case]
    path = write(tmp_path, make(data))
    refused(path, word)
    inspected = st.load_boundary(path, check=False)  # the experts' opt-out: loaded, to be looked at
    assert not bool(inspected.is_passive())
    with pytest.raises(InputError, match=word) as info:  # but it never closes a model
        st.TruncatedTrack(st.slab_track(damping="viscous"), 4, ends="boundary", system=inspected)
    assert len(str(info.value).splitlines()) == 1


def test_a_mat_file_is_checked_the_same(data, tmp_path):
    good = st.load_boundary(SLAB_FILE)
    path = tmp_path / "b.mat"
    st.save_boundary(good, path)
    assert st.load_boundary(path).n_poles == good.n_poles
    m = scipy.io.loadmat(path)
    m["K0"] = -m["K0"]
    for key in "ABC":
        m.pop(key)
    scipy.io.savemat(path, {k: v for k, v in m.items() if not k.startswith("__")})
    refused(path, "K0", "positive definite")


# --- the track a boundary was fitted to ----------------------------------------------------------
def test_a_ballasted_boundary_on_the_slab_track_is_refused():
    ballasted = st.load_boundary(BALLASTED_FILE)
    start = time.perf_counter()
    with pytest.raises(InputError) as info:
        st.TruncatedTrack(st.slab_track(damping="viscous"), 10, ends="boundary", system=ballasted)
    message = str(info.value)
    assert len(message.splitlines()) == 1 and "another track" in message and "K0" in message, message
    assert "%" in message and "'ballasted'" in message
    assert time.perf_counter() - start < SECONDS
    # its own track takes it
    st.TruncatedTrack(st.ballasted_track(damping="viscous"), 2, ends="boundary", system=ballasted)


def test_a_near_variant_of_the_track_is_warned():
    slab = st.load_boundary(SLAB_FILE)
    track = st.slab_track(damping="viscous")
    with pytest.warns(UserWarning, match="another track.*used as it is"):
        st.TruncatedTrack(track.replace(kv=1.003 * track.kv), 2, ends="boundary", system=slab)


# --- .mat files that are not what they claim --------------------------------------------------------
def _mat_variants(tmp_path: Path) -> dict[str, Path]:
    good = tmp_path / "good.mat"
    st.save_boundary(st.load_boundary(SLAB_FILE), good)
    raw = good.read_bytes()
    m = {k: v for k, v in scipy.io.loadmat(good).items() if not k.startswith("__")}
    rng = np.random.default_rng(0)
    variants = {"json": json.dumps(boundary_to_dict(st.load_boundary(SLAB_FILE))).encode(), "empty": b"",
                "truncated": raw[: len(raw) // 2], "header only": raw[:128],
                "hdf5": b"\0" * 512 + b"\x89HDF\r\n\x1a\n" + b"\0" * 64,
                "v73 header": raw[:124] + b"\x00\x02IM" + raw[128:],
                "random": rng.bytes(4096)}
    paths = {}
    for name, content in variants.items():
        paths[name] = tmp_path / f"{name.replace(' ', '-')}.mat"
        paths[name].write_bytes(content)
    for key in ("poles", "coefficients", "K0", "band_hz", "format"):
        paths[f"missing {key}"] = tmp_path / f"missing-{key}.mat"
        scipy.io.savemat(paths[f"missing {key}"], {k: v for k, v in m.items() if k != key})
        paths[f"empty {key}"] = tmp_path / f"empty-{key}.mat"
        scipy.io.savemat(paths[f"empty {key}"], {**m, key: np.zeros((0, 0))})
    return paths


MAT_WORDS = {"json": "not a MATLAB 5", "empty": "not a MATLAB 5", "truncated": "", "header only": "",
             "hdf5": "v7.3", "v73 header": "v7.3", "random": "not a MATLAB 5"}


def test_mat_files_that_are_not_boundaries(tmp_path):
    for name, path in _mat_variants(tmp_path).items():
        key = name.split(" ", 1)[1] if name.startswith(("missing", "empty ")) else None
        words = (f"{key!r}",) if key else (MAT_WORDS[name],)
        refused(path, *words)


# --- system files: the same bounded reader ---------------------------------------------------------
def test_system_files_are_read_within_bounds(tmp_path):
    link = tmp_path / "zero.json"
    link.symlink_to("/dev/zero")
    refused(link, "larger than", loader=st.load_system_json)
    refused(write(tmp_path, "[" * 100_000, "deep.json"), "nested too deeply", loader=st.load_system_json)
    refused(_inflating_mat(tmp_path / "bomb.mat", 1 << 28), "inflate to more than", loader=st.load_system_mat)
    for name, path in _mat_variants(tmp_path).items():
        if not name.startswith(("missing", "empty ")):
            refused(path, MAT_WORDS[name], loader=st.load_system_mat)


def test_system_files_name_the_key_of_a_bad_value(tmp_path):
    good = st.export_system(st.paper_table4(), tmp_path / "s.json")
    data = json.loads(good.read_text())
    data["parameters"]["m"]["values"][0] = "abc"
    refused(write(tmp_path, data, "s2.json"), "'m'", loader=st.load_system_json)
    data["parameters"]["m"]["values"][0] = -1.0
    refused(write(tmp_path, data, "s3.json"), "m[0]", loader=st.load_system_json)
    csv = st.export_system(st.paper_table4(), tmp_path / "s.csv")
    text = csv.read_text().replace("\nm,kg,", "\nm,kg,abc", 1)
    refused(write(tmp_path, text, "s4.csv"), "[parameters] m", "'abc", loader=st.load_system_csv)
    mat = st.export_system(st.paper_table4(), tmp_path / "s.mat")
    m = {k: v for k, v in scipy.io.loadmat(mat).items() if not k.startswith("__")}
    scipy.io.savemat(tmp_path / "s5.mat", {k: v for k, v in m.items() if k != "parameters"})
    refused(tmp_path / "s5.mat", "'parameters'", loader=st.load_system_mat)
    assert issubclass(InputError, BadInput)
