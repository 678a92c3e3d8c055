"""End-to-end tests of the command-line program through a subprocess."""

import csv
import dataclasses
import io
import json
import os
import subprocess
import sys

import numpy as np
import pandas as pd
import pytest
import scipy.io

import semitrack as st
from semitrack.base.conventions import ALL_ELEMENTS, ELEMENT_UNITS
from semitrack.base.paper_values import TABLE3_SLAB_FREQUENCIES
from semitrack.cli import paper_mode_names, receptance_csv, receptance_figure
from semitrack.model.trackfile import EXAMPLES, example_path, example_track, load_track_toml, track_to_toml

ENV = {**os.environ, "OPENBLAS_NUM_THREADS": "1"}
# Line of "kv = ..." in the shipped ballasted example, where the located error must point.
KV_LINE = next(n for n, line in enumerate(example_path("ballasted").read_text().splitlines(), 1)
               if line.startswith("kv "))


def run(*args, cwd=None):
    return subprocess.run([sys.executable, "-m", "semitrack", *map(str, args)], capture_output=True,
                          text=True, cwd=cwd, env=ENV, timeout=300)


def assert_bad_input(result, *words):
    """Exit code 2, one line on stderr naming the problem, no traceback."""
    assert result.returncode == 2, result.stderr
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1, result.stderr
    assert "Traceback" not in result.stderr
    for w in words:
        assert w in lines[0], lines[0]


@pytest.fixture
def slab_file(tmp_path):
    path = tmp_path / "slab.toml"
    path.write_text(example_path("slab").read_text())
    return path


def edited(tmp_path, old, new, name="edited.toml"):
    path = tmp_path / name
    text = example_path("ballasted").read_text()
    assert old in text
    path.write_text(text.replace(old, new, 1))
    return path


@pytest.mark.parametrize("name", ["soft pads", "Nord's \"fast\" track \\ 2"])
def test_toml_round_trip(tmp_path, name):
    track = st.ballasted_track(kv=2e8, name=name)
    path = tmp_path / "t.toml"
    path.write_text(track_to_toml(track))
    assert load_track_toml(path) == track


def test_receptance_csv_matches_package(slab_file, tmp_path):
    out = tmp_path / "alpha.csv"
    result = run("receptance", slab_file, "--fmin", 3, "--fmax", 303, "--df", 6, "-o", out,
                 "--plot", tmp_path / "a.png")
    assert result.returncode == 0, result.stderr
    header = [line for line in out.read_text().splitlines() if line.startswith("#")]
    # The package's one element naming and unit table: alpha12 and alpha21 in 1/N.
    assert any(all(f"{name} in {ELEMENT_UNITS[name]}" in h for name in ALL_ELEMENTS) for h in header)
    assert any("downward" in h for h in header)
    data = pd.read_csv(out, comment="#")
    f = data["f_Hz"].to_numpy()
    np.testing.assert_allclose(f, np.arange(3.0, 304.0, 6.0))
    alpha = st.semi_infinite_receptance(st.slab_track(), f)
    assert list(data.columns[1:5]) == ["alpha11_re", "alpha11_im", "alpha11_abs", "alpha11_phase"]
    for name, (i, k) in ALL_ELEMENTS.items():
        # 13 significant digits are printed: agreement to 1e-11 relative is "to the printed precision".
        np.testing.assert_allclose(data[f"{name}_re"] + 1j * data[f"{name}_im"], alpha[:, i, k], rtol=1e-11)
        np.testing.assert_allclose(data[f"{name}_abs"], np.abs(alpha[:, i, k]), rtol=1e-11)
    assert (tmp_path / "a.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_receptance_units_are_those_of_the_conventions():
    """CSV header and plot axes write each element's one unit: alpha12 in 1/N, never m/(N m)."""
    f = np.array([10.0, 100.0])
    alpha = st.semi_infinite_receptance(st.slab_track(), f)
    text = receptance_csv(st.slab_track(), f, alpha, "transfer")
    assert "m/(N m)" not in text and "alpha12 in 1/N, alpha21 in 1/N" in text
    labels = [ax.get_ylabel() for ax in receptance_figure(st.slab_track(), f, alpha).axes]
    assert labels == [r"$|\alpha_{11}|$ (m/N)", r"$|\alpha_{12}|$ (1/N)", r"$|\alpha_{22}|$ (rad/(N m))"]


@pytest.mark.parametrize("name", ["slab", "ballasted"])
def test_example_prints_a_track_file_that_loads(tmp_path, name):
    result = run("example", name)
    assert result.returncode == 0, result.stderr
    assert result.stdout == example_path(name).read_text()
    path = tmp_path / f"{name}.toml"
    path.write_text(result.stdout)
    assert load_track_toml(path).replace(name="x") == getattr(st, f"{name}_track")(name="x")


def test_example_list_and_bad_names():
    listed = run("example", "--list")
    assert listed.returncode == 0 and [line.split()[0] for line in listed.stdout.splitlines()] == [*EXAMPLES, "bogie",
                                                                                                   "wheel"]
    kinds = dict(line.split(maxsplit=1) for line in listed.stdout.splitlines())
    assert kinds["bogie"] == "vehicle: Bogie with 2 wheel(s)"
    assert kinds["slab"].endswith("(rigid slab)") and kinds["ballasted"].endswith("(sleepers on ballast)")
    for name in ("mortar-slab", "floating-slab"):
        assert kinds[name].endswith("(flexible slab, 10 fasteners per 6.45 m slab, cut at a slab joint)")
    assert_bad_input(run("example", "tram"), "unknown example 'tram'", "slab, ballasted")
    assert_bad_input(run("example"), "name an example", "slab, ballasted")


def test_bare_command_prints_usage_and_commands():
    result = run()
    assert result.returncode == 2 and result.stdout == ""
    assert result.stderr.startswith("usage: semitrack")
    for sub in ("example", "receptance", "fit", "export", "features"):
        assert f"\n    {sub} " in result.stderr or f"\n    {sub}\n" in result.stderr


def test_receptance_to_stdout_has_no_progress_text(slab_file):
    result = run("receptance", slab_file, "--fmax", 100, "--method", "wavenumber")
    assert result.returncode == 0, result.stderr
    assert result.stderr == ""  # not a terminal: no progress line
    rows = [line for line in result.stdout.splitlines() if not line.startswith("#")]
    assert rows[0].startswith("f_Hz,") and len(rows) == 1 + 17


def test_features(slab_file):
    result = run("features", slab_file, "--fmax", 1200, "--csv")
    assert result.returncode == 0, result.stderr
    data = pd.read_csv(io.StringIO(result.stdout), keep_default_na=False)
    assert list(data.columns) == ["f_Hz", "f_grid_Hz", "quantity", "kind", "magnitude", "unit", "mode"]
    assert np.all(np.diff(data["f_Hz"]) >= 0)  # rows by frequency
    # Each quantity's magnitude carries its own unit; alpha12 in 1/N as everywhere.
    units = dict(zip(data["quantity"], data["unit"]))
    assert units == {"w1": "m/N", "psi2": "rad/(N m)", "Q2": "N/(N m)", "M1": "N m/N", "det": "N^2",
                     "alpha11": "m/N", "alpha12": "1/N", "alpha22": "rad/(N m)"}
    # The same peaks as the package computes in-process, to the 6 significant digits printed.
    w1_peaks = data[(data.quantity == "w1") & (data.kind == "peak")]
    ref = st.characteristic_frequencies(st.slab_track(), band=(3.0, 1200.0))
    ref = ref[(ref.quantity == "w1") & (ref.kind == "peak")]
    np.testing.assert_allclose(w1_peaks["f_Hz"], ref["f"], rtol=1e-5)
    np.testing.assert_allclose(w1_peaks["magnitude"], ref["magnitude"], rtol=1e-5)
    # The paper's names (Table 3) on the extrema nearest its values, and on no other row.
    named = dict(zip(w1_peaks["f_Hz"].round(), w1_peaks["mode"]))
    assert named == {186.0: "rail bouncing on the fastener stiffness (Table 3)",
                     942.0: "first pinned-pinned mode (Table 3)", 1046.0: ""}
    assert (data["mode"] != "").sum() == sum(f < 1200 for f, *_ in TABLE3_SLAB_FREQUENCIES)  # one row each


def test_features_names_modes_only_for_the_papers_tracks(tmp_path):
    """One parameter changed: the modes may have moved, so the paper's names are not given."""
    changed = edited(tmp_path, "kv = 3.5e8", "kv = 3.6e8")
    result = run("features", changed, "--fmax", 600)
    assert result.returncode == 0, result.stderr
    assert "named for the paper's two tracks only" in result.stdout
    assert result.stdout.splitlines()[2].split() == ["f", "(Hz)", "grid", "f", "(Hz)", "quantity", "kind",
                                                     "magnitude", "unit"]
    paper = run("features", example_path("ballasted"), "--fmax", 600)
    assert "rail and sleeper bouncing together on the ballast (Table 6)" in paper.stdout


def test_fit_then_export_in_every_format(tmp_path):
    track_file = tmp_path / "slab.toml"
    track_file.write_text(track_to_toml(st.slab_track()))
    system_file = tmp_path / "system.json"
    result = run("fit", track_file, "--bars", 2, "--band", 3, 300, "--seed", 1, "-o", system_file)
    assert result.returncode == 0, result.stderr
    assert "median relative error" in result.stdout
    system = st.load_system_json(system_file)
    f = np.linspace(3.0, 300.0, 40)
    reference = system.receptance(f)
    for fmt in ("json", "csv", "mat"):
        out = tmp_path / f"export.{fmt}"
        result = run("export", system_file, "--format", fmt, "-o", out)
        assert result.returncode == 0, result.stderr
        loader = {"json": st.load_system_json, "csv": st.load_system_csv, "mat": st.load_system_mat}[fmt]
        np.testing.assert_allclose(loader(out).receptance(f), reference, rtol=1e-10)
    # Every file names the track and band it was fitted on, carried on by each export.
    assert json.loads(system_file.read_text())["conventions"]["band_hz"] == [3.0, 300.0]
    csv_conventions = {row[0]: row[1] for row in csv.reader((tmp_path / "export.csv").read_text().splitlines())
                       if len(row) == 2}
    assert json.loads(csv_conventions["track"]) == st.slab_track().name
    assert json.loads(csv_conventions["band_hz"]) == [3.0, 300.0]
    # ... and the damping of that (hysteretic) track: the csv and mat carry it on, a .bdf warns on stderr
    assert json.loads(csv_conventions["track_damping"]) == "hysteretic"
    assert json.loads(system_file.read_text())["conventions"]["track_damping"] == "hysteretic"
    bdf = run("export", tmp_path / "export.mat", "-o", tmp_path / "end.bdf")
    assert bdf.returncode == 0 and "fitted to the hysteretic track" in bdf.stderr
    assert '"track_damping":"hysteretic"' in "".join(
        line[2:] for line in (tmp_path / "end.bdf").read_text().splitlines() if line.startswith("$|")).replace(" ", "")
    # The .mat matrices themselves, as a MATLAB user sees them, reproduce the receptance.
    mat = scipy.io.loadmat(tmp_path / "export.mat")
    m, c, k = (np.asarray(mat[n], dtype=float) for n in ("M", "C", "K"))
    omega = 2 * np.pi * f
    z = k[None] + 1j * omega[:, None, None] * c[None] - omega[:, None, None] ** 2 * m[None]
    rhs = np.zeros((f.size, k.shape[0], 2))
    rhs[:, 0, 0] = rhs[:, 1, 1] = 1.0
    np.testing.assert_allclose(np.linalg.solve(z, rhs)[:, :2, :], reference, rtol=1e-10)


def test_fit_boundary_writes_a_passive_model_that_loads_back(tmp_path):
    """``semitrack fit --boundary``: the file reproduces the in-process fit and its state space."""
    track = st.slab_track(damping="viscous")
    track_file = tmp_path / "slab.toml"
    track_file.write_text(track_to_toml(track))
    for suffix in ("json", "mat"):
        out = tmp_path / f"boundary.{suffix}"
        band = ("--band", 3, 3000) if suffix == "json" else ()  # the default band is the API's, 3-3000 Hz
        result = run("fit", track_file, "--boundary", *band, "--poles", 24, "-o", out)
        assert result.returncode == 0, result.stderr
        assert "proven passive" in result.stdout
        loaded = st.load_boundary(out)
        reference = st.fit_boundary(track, band=(3, 3000), n_poles=24)
        f = np.geomspace(1.0, 1e4, 30)
        np.testing.assert_allclose(loaded.receptance(f), reference.receptance(f), rtol=1e-10)
    bad = run("fit", track_file, "--boundary", "--band", 3, 3000, "-o", tmp_path / "b.txt")
    assert bad.returncode == 2 and ".json/.mat/.csv/.bdf/.inp" in bad.stderr
    system = run("fit", track_file, "-o", tmp_path / "s.json")  # an equivalent system holds only in its band
    assert system.returncode == 2 and "--band is needed for an equivalent system's fit" in system.stderr
    assert len(system.stderr.strip().splitlines()) == 1 and not (tmp_path / "s.json").exists()


def test_boundary_files_export_to_every_format(tmp_path):
    """``semitrack export`` takes boundary files: state space to state space and to every M, C, K format."""
    track_file = tmp_path / "slab.toml"
    track_file.write_text(track_to_toml(st.slab_track(damping="viscous")))
    boundary_file = tmp_path / "boundary.json"
    assert run("fit", track_file, "--boundary", "--band", 3, 3000, "--poles", 24, "-o", boundary_file).returncode == 0
    reference = st.load_boundary(boundary_file)
    f = np.geomspace(1.0, 1e4, 30)
    result = run("export", boundary_file, "--format", "mat")  # as the README types it: boundary.mat beside it
    assert result.returncode == 0, result.stderr
    np.testing.assert_allclose(st.load_boundary(tmp_path / "boundary.mat").receptance(f), reference.receptance(f),
                               rtol=1e-12)
    for name, extra in (("end.csv", []), ("end_mck.json", ["--mck"]), ("end_mck.mat", ["--mck"]),
                        ("end.bdf", []), ("end.inp", [])):
        result = run("export", tmp_path / "boundary.mat", "-o", tmp_path / name, *extra)
        assert result.returncode == 0, result.stderr
        assert "M, C, K" in result.stdout
    for name in ("end.csv", "end_mck.json", "end_mck.mat"):
        np.testing.assert_allclose(st.load_matrix_system(tmp_path / name).receptance(f), reference.receptance(f),
                                   rtol=1e-8)
    # M, C, K files export on to the codes' formats; fit --boundary writes them directly
    assert run("export", tmp_path / "end.csv", "-o", tmp_path / "again.inp").returncode == 0
    assert (tmp_path / "again.inp").read_text() == (tmp_path / "end.inp").read_text()
    assert run("fit", track_file, "--boundary", "--band", 3, 3000, "--poles", 24, "-o", tmp_path / "fit.bdf"
               ).returncode == 0
    assert (tmp_path / "fit.bdf").read_text() == (tmp_path / "end.bdf").read_text()
    mck = run("fit", track_file, "--band", 3, 300, "--bars", 1, "--mck", "-o", tmp_path / "s.json")
    assert mck.returncode == 2 and "--mck applies with --boundary" in mck.stderr
    same = run("export", boundary_file, "--format", "json")
    assert same.returncode == 2 and "would replace the input" in same.stderr
    # the labels of a code's file: the API's, refused where a file names its DOFs
    labelled = run("export", boundary_file, "-o", tmp_path / "n101.bdf", "--node", 101, "--first-label", 501)
    assert labelled.returncode == 0, labelled.stderr
    st.export_boundary(reference, tmp_path / "api.bdf", node=101, first_label=501)
    assert (tmp_path / "n101.bdf").read_text() == (tmp_path / "api.bdf").read_text()
    fitted = run("fit", track_file, "--boundary", "--poles", 24, "--node", 101, "--first-label", 501,
                 "-o", tmp_path / "fit101.bdf")
    assert fitted.returncode == 0 and (tmp_path / "fit101.bdf").read_text() == (tmp_path / "api.bdf").read_text()
    assert_bad_input(run("export", boundary_file, "-o", tmp_path / "n.mat", "--node", 101), "--node", ".mat file")
    assert_bad_input(run("export", boundary_file, "-o", tmp_path / "n.bdf", "--node", 0), "--node")
    assert_bad_input(run("fit", track_file, "--boundary", "--node", 5, "-o", tmp_path / "b.json"), "--node")
    assert_bad_input(run("fit", track_file, "--band", 3, 300, "--node", 5, "-o", tmp_path / "s.json"),
                     "--node and --first-label label a --boundary fit's")
    assert not any((tmp_path / name).exists() for name in ("n.mat", "n.bdf", "b.json", "s.json"))


@pytest.mark.parametrize("sub", ["example", "receptance", "fit", "export", "features"])
def test_help_has_an_example(sub):
    result = run(sub, "--help")
    assert result.returncode == 0 and ("example:" in result.stdout or "examples:" in result.stdout)


def test_bad_toml(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text("type = slab\n[rail\n")
    out = tmp_path / "out.csv"
    assert_bad_input(run("receptance", bad, "-o", out), "not a valid TOML")
    assert not out.exists()


@pytest.mark.parametrize("old,new,words", [
    ("kb = 100e6", "kb = 100e6\nkbb = 1.0", ["unknown key 'kbb'", "[ballast]", "line"]),
    ("kv = 3.5e8", "kv = -3.5e8", ["kv must be positive and finite", "-350000000.0", f"line {KV_LINE}"]),
    ("spacing = 0.6", "spacing = 0.0", ["spacing must be positive and finite", "0.0", "line"]),
    ("kv = 3.5e8", 'kv = "stiff"', ["kv must be a real number", "'stiff'"]),
    ("kphi = 1.82e6", "kphi = -1.0", ["kphi must be non-negative and finite", "-1.0"]),
    ('name = "paper ballasted track"', "name = 7", ["name must be a string", "7", "line 6"]),
    ("eta_pad = 0.1            # loss factor, -\n", "", ["missing key 'eta_pad' in [pad]"]),
])
def test_bad_track_values(tmp_path, old, new, words):
    path = edited(tmp_path, old, new)
    out = tmp_path / "out.csv"
    result = run("receptance", path, "--fmax", 30, "-o", out)
    assert_bad_input(result, *words, path.name)
    assert not out.exists() and [p.name for p in tmp_path.iterdir()] == [path.name]  # no temp file left


@pytest.mark.parametrize("args,words", [
    (["--fmin", 50, "--fmax", 10], ["--fmin must not exceed --fmax"]),
    (["--fmin", "abc"], ["--fmin", "invalid number value", "abc"]),
    (["--df", 0], ["--df must be positive"]),
])
def test_bad_frequency_arguments(slab_file, tmp_path, args, words):
    out = tmp_path / "out.csv"
    assert_bad_input(run("receptance", slab_file, *args, "-o", out), *words)
    assert not out.exists()


def test_bad_fit_and_export_inputs(slab_file, tmp_path):
    assert_bad_input(run("fit", slab_file, "--band", 500, 100, "-o", tmp_path / "s.json"), "--band", "[500, 100]")
    assert_bad_input(run("fit", slab_file, "--band", 3, 100, "--bars", 0, "-o", tmp_path / "s.json"), "--bars")
    assert_bad_input(run("fit", slab_file, "--band", 100, 100, "-o", tmp_path / "s.json"), "--band")
    assert_bad_input(run("fit", slab_file, "--band", 3, 100, "--seed", -1, "-o", tmp_path / "s.json"), "--seed")
    junk = tmp_path / "junk.json"
    junk.write_text(json.dumps({"layout": "tram"}))
    assert_bad_input(run("export", junk, "-o", tmp_path / "x.mat"), "cannot load the system")
    assert_bad_input(run("receptance", tmp_path / "missing.toml"), "cannot read the track file")
    assert not (tmp_path / "s.json").exists() and not (tmp_path / "x.mat").exists()


# ---------------------------------------------------------------------------------------------
# A flexible slab (a [slab] table): the floating-slab example through every command that reads a track.

@pytest.fixture(scope="module")
def slab_files(tmp_path_factory):
    """``semitrack example floating-slab`` as written by the program, and the same with the cut at the centre."""
    folder = tmp_path_factory.mktemp("floating")
    result = run("example", "floating-slab")
    assert result.returncode == 0, result.stderr
    assert result.stdout == example_path("floating-slab").read_text()
    joint, centre = folder / "floating.toml", folder / "centre.toml"
    joint.write_text(result.stdout)
    assert result.stdout.count('cut = "joint"') == 1
    centre.write_text(result.stdout.replace('cut = "joint"', 'cut = "centre"'))
    return joint, centre


def test_slab_examples_print_the_shipped_designs(tmp_path):
    result = run("example", "mortar-slab")
    assert result.returncode == 0, result.stderr
    path = tmp_path / "mortar.toml"
    path.write_text(result.stdout)
    track = load_track_toml(path)
    assert track == example_track("mortar-slab") and track.has_flexible_slab


def test_receptance_of_a_flexible_slab(slab_files, tmp_path):
    """The CSV is the package's alpha of the slab track at its cut; the [slab] table did reach it."""
    f = np.array([25.0, 50.0])
    floating = example_track("floating-slab")
    centre = floating.replace(slab=dataclasses.replace(floating.slab, cut="centre"))
    alphas = {}
    for path, track, where in zip(slab_files, (floating, centre), ("a slab joint", "the slab centre")):
        out = tmp_path / f"{path.stem}.csv"
        result = run("receptance", path, "--fmin", 25, "--fmax", 50, "--df", 25, "-o", out)
        assert result.returncode == 0, result.stderr
        assert f"(flexible slab, 10 fasteners per 6.45 m slab, cut at {where}; method=transfer)" in out.read_text()
        data = pd.read_csv(out, comment="#")
        np.testing.assert_allclose(data["f_Hz"], f)
        alphas[where] = data["alpha11_re"] + 1j * data["alpha11_im"]
        # 13 significant digits printed: agreement to 1e-11 relative
        np.testing.assert_allclose(alphas[where], st.semi_infinite_receptance(track, f)[:, 0, 0], rtol=1e-11)
    rigid = st.semi_infinite_receptance(st.slab_track(), f)[:, 0, 0]
    assert abs(alphas["a slab joint"][0] / rigid[0]) > 3  # measured 4.77 at 25 Hz: the slab bounces on its mat
    assert abs(alphas["the slab centre"][1] / alphas["a slab joint"][1]) > 1.2  # measured 1.31 at 50 Hz
    # The paper's method cannot cut inside a slab: refused in one line, in the CLI's words.
    refused = run("receptance", slab_files[1], "--fmax", 30, "--method", "wavenumber")
    assert_bad_input(refused, "Eq. (14)")
    assert "--method transfer" in refused.stderr and "method='transfer'" not in refused.stderr


def test_features_of_a_flexible_slab(slab_files):
    """Peaks and dips of the floating slab, none named with the paper's modes (its rail and pads are the
    paper's, its slab is not rigid); at a cut inside a slab, alpha and det are those of the track with
    its slab cut there (not Eq. 14, which holds at a joint only)."""
    result = run("features", slab_files[0], "--fmax", 45, "--csv")
    assert result.returncode == 0, result.stderr
    data = pd.read_csv(io.StringIO(result.stdout), keep_default_na=False)
    assert (data["mode"] == "").all()
    w1_peaks = data[(data.quantity == "w1") & (data.kind == "peak")]["f_Hz"]
    bounce = example_track("floating-slab").slab.natural_frequencies(1)[0]  # 26.0 Hz, free slab on its mat
    assert np.any(np.abs(w1_peaks - bounce) < 2.0)  # measured 24.9 Hz: the rail and pads load the slab
    inside = run("features", slab_files[1], "--fmax", 60, "--csv")
    assert inside.returncode == 0, inside.stderr
    data = pd.read_csv(io.StringIO(inside.stdout), keep_default_na=False)
    centre = example_track("floating-slab").replace(
        slab=dataclasses.replace(example_track("floating-slab").slab, cut="centre"))
    expected = st.characteristic_frequencies(centre, band=(3, 60))
    a11 = expected[(expected.quantity == "alpha11") & (expected.kind == "peak")]["f"].to_numpy()
    got = data[(data.quantity == "alpha11") & (data.kind == "peak")]["f_Hz"].to_numpy()
    np.testing.assert_allclose(got, a11, rtol=1e-5)  # the CSV prints 6 significant digits


def test_paper_mode_names_skip_a_flexible_slab():
    """The paper's slab track with a slab under it: same rail and pads, no names (in process, exact table)."""
    table = pd.DataFrame({"quantity": ["w1", "w1"], "kind": ["peak", "peak"], "f": [186.0, 942.0]})
    assert all(paper_mode_names(st.slab_track(), table))
    assert paper_mode_names(example_track("mortar-slab"), table) == ["", ""]


def test_fit_to_a_flexible_slab(slab_files, tmp_path):
    """The slab layout fitted to the floating slab: the file's system has the errors the program printed."""
    out = tmp_path / "system.json"
    result = run("fit", slab_files[0], "--bars", 2, "--band", 3, 300, "-o", out)
    assert result.returncode == 0, result.stderr
    assert ("fitted a slab equivalent system with 2 bars to 'floating slab on an elastomer mat' (flexible slab, "
            "10 fasteners per 6.45 m slab, cut at a slab joint) over 3-300 Hz") in result.stdout
    grid = st.error_band_grid((3.0, 300.0))
    errors = st.error_summary(st.load_system_json(out).receptance(grid),
                              st.semi_infinite_receptance(example_track("floating-slab"), grid))
    assert f"median relative error {errors.median:.4f}, maximum {errors.max:.4f}" in result.stdout


def test_decay_writes_the_rates_and_a_plot(tmp_path):
    track = tmp_path / "ballasted.toml"
    track.write_text(example_path("ballasted").read_text())
    result = run("decay", track, "--band", "500", "1000", "--df", "5", "-o", tmp_path / "tdr.csv",
                 "--plot", tmp_path / "tdr.png")
    assert result.returncode == 0, result.stderr
    table = pd.read_csv(tmp_path / "tdr.csv", comment="#")
    expected = st.track_decay_rate(st.ballasted_track(), band=(500, 1000), df=5.0)
    np.testing.assert_allclose(table["decay_rate_dB_per_m"], expected.decay_rate, rtol=1e-5)
    assert table["band_Hz"].tolist() == [500, 630, 800, 1000]  # nominal names, the exact centres beside them
    np.testing.assert_allclose(table["centre_Hz"], expected.centres, rtol=1e-5)
    np.testing.assert_array_equal(table["iso3095_limit_dB_per_m"], [6.0, 6.0, 2.19, 0.8])
    assert dict(zip(table["band_Hz"].astype(float), table["meets_iso3095"].astype(bool))) == expected.meets()
    failing = [f"{b:g}" for b, ok in expected.meets().items() if not ok]
    assert f"{len(failing)} of 4 judged bands fail: {' '.join(failing)} Hz" in (tmp_path / "tdr.csv").read_text()
    assert (tmp_path / "tdr.png").stat().st_size > 1000
    slab = tmp_path / "floating.toml"
    slab.write_text(example_path("floating-slab").read_text())
    refused = run("decay", slab)
    assert refused.returncode == 2 and "without a flexible slab" in refused.stderr
