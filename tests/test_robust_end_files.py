"""End files on the M, C, K path under hostile input: bounded reads and conventions read back.

The boundary files' readers were bounded a round earlier; the M, C, K files of
:func:`semitrack.load_matrix_system` (and the command line's look at a file's header before
``export``) read whole files with :func:`json.load` and :func:`scipy.io.loadmat`, and five of the
seven conventions fields an end file declares were never read. Here every end file kind is held to
the same rules: ``/dev/zero`` behind the name, deep nesting, a ``.mat`` bomb and truncation are
refused at once, one line naming the file; the largest cases run in a subprocess whose peak memory
(``VmHWM``, :mod:`peak_memory`) and CPU time before the refusal are bounded (300 MB, 1 s); and a
file that declares other conventions than the package's is refused, naming the field.
"""

from __future__ import annotations

import copy
import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest
import scipy.io
from peak_memory import PEAK_RSS
from refusals import refused
from test_robust_boundary_files import BALLASTED_FILE, _inflating_mat

import semitrack as st
from semitrack.base.errors import BadInput, InputError
from semitrack.cli import main
from semitrack.equivalent.exchange import CHECKED_CONVENTIONS, end_conventions

#: Conventions another code may follow, one field at a time: what the package used to load silently.
OTHER_CONVENTIONS = {
    "side": "left",
    "load_convention": "applied_by_end",
    "port_dofs": ["psi", "w"],
    "port_indices": [1, 0],
    "left_end_mirror": [[1.0, 0.0], [0.0, 1.0]],
    "units": dict(end_conventions()["units"], length="mm"),
    "time_factor": "exp(-i omega t)",
}


@pytest.fixture(scope="module")
def boundary():
    return st.load_boundary(BALLASTED_FILE)


@pytest.fixture(scope="module")
def files(boundary, tmp_path_factory) -> dict[str, Path]:
    """One good end file of every kind the package reads back, written by the package."""
    folder = tmp_path_factory.mktemp("ends")
    system = boundary.matrix_system()
    paper = st.paper_table4()
    out = {}
    for suffix in (".json", ".csv", ".mat"):
        out[f"mck{suffix}"] = st.export_system(system, folder / f"mck{suffix}")
    out["boundary.json"] = st.save_boundary(boundary, folder / "boundary.json")
    out["boundary.mat"] = st.save_boundary(boundary, folder / "boundary.mat")
    for suffix in (".json", ".csv", ".mat"):
        out[f"system{suffix}"] = st.export_system(paper, folder / f"system{suffix}")
    return out


LOADERS = {"mck": st.load_matrix_system, "boundary": st.load_boundary,
           "system.json": st.load_system_json, "system.csv": st.load_system_csv, "system.mat": st.load_system_mat}


def _loader(kind: str):
    return LOADERS.get(kind) or LOADERS[kind.split(".")[0]]


def test_the_convention_fields_checked_are_every_field_a_program_acts_on():
    assert set(OTHER_CONVENTIONS) == set(CHECKED_CONVENTIONS)
    assert set(CHECKED_CONVENTIONS) < set(end_conventions())


def test_good_files_load_and_keep_their_matrices(files, boundary):
    system = boundary.matrix_system()
    for suffix in (".json", ".csv", ".mat"):
        back = st.load_matrix_system(files[f"mck{suffix}"])
        for ours, theirs in zip(system.matrices(), back.matrices()):
            np.testing.assert_array_equal(ours, theirs)


# --- sizes and damage, refused at once --------------------------------------------------------------
def test_dev_zero_behind_a_json_or_csv_name(tmp_path):
    for name in ("zero.json", "zero.csv"):
        link = tmp_path / name
        link.symlink_to("/dev/zero")
        refused(lambda link=link: st.load_matrix_system(link), InputError, str(link), "larger than")


def test_json_nested_100000_deep(tmp_path):
    path = tmp_path / "deep.json"
    path.write_text("[" * 100_000 + "]" * 100_000)
    refused(lambda: st.load_matrix_system(path), InputError, str(path), "nested too deeply")


def test_a_mat_bomb_is_refused_before_it_inflates(tmp_path):
    path = _inflating_mat(tmp_path / "bomb.mat", 1 << 28)  # 256 MiB of zeros in ~260 kB
    refused(lambda: st.load_matrix_system(path), InputError, str(path), "inflate to more than")


@pytest.mark.parametrize("suffix", [".json", ".csv", ".mat"])
@pytest.mark.parametrize("keep", [0.0, 0.3, 0.97])
def test_a_truncated_file_names_itself(files, tmp_path, suffix, keep):
    data = files[f"mck{suffix}"].read_bytes()
    path = tmp_path / f"cut{suffix}"
    path.write_bytes(data[:int(keep * len(data))])
    with pytest.raises(BadInput) as info:
        st.load_matrix_system(path)
    assert str(path) in str(info.value) and len(str(info.value).splitlines()) == 1


MEASURE = PEAK_RSS + textwrap.dedent("""
    import sys, time
    from semitrack.cli import main
    import semitrack as st
    cpu, wall = time.process_time(), time.perf_counter()
    try:
        if sys.argv[1] == "cli":
            code = main(["export", sys.argv[2], "-o", sys.argv[3]])
            print("exit", code)
        else:
            st.load_matrix_system(sys.argv[2])
            print("loaded")
    except Exception as err:
        print(type(err).__name__, "|", err)
    print(time.process_time() - cpu, time.perf_counter() - wall, peak_rss_kib())
""")


@pytest.mark.parametrize("case", ["dev-zero", "bomb"])
@pytest.mark.parametrize("route", ["load", "cli"])
def test_hostile_files_within_300_mb_and_1_s(tmp_path, case, route):
    if case == "dev-zero":
        path = tmp_path / "zero.json"
        path.symlink_to("/dev/zero")
    else:
        path = _inflating_mat(tmp_path / "bomb.mat", 3 << 30)  # 3 GiB inflated from ~3 MB: the case
    env = {**os.environ, "PYTHONPATH": str(Path(st.__file__).parent.parent)}
    out = subprocess.run([sys.executable, "-c", MEASURE, route, str(path), str(tmp_path / "out.bdf")], env=env,
                         capture_output=True, text=True, timeout=120)
    verdict, figures = out.stdout.strip().splitlines()[-2:]
    cpu, wall, rss_kib = figures.split()
    assert verdict == "exit 2" if route == "cli" else verdict.startswith("InputError"), out.stdout + out.stderr
    # CPU time, not wall time: the bound is the work done, whatever else the machine runs
    assert float(cpu) < 1.0 and int(rss_kib) < 300_000, (cpu, wall, rss_kib)
    assert not (tmp_path / "out.bdf").exists()


# --- conventions read back --------------------------------------------------------------------------
def _with_conventions(path: Path, tmp_path: Path, field: str, value) -> Path:
    """A copy of the end file ``path`` whose conventions declare ``value`` for ``field``."""
    out = tmp_path / f"other-{field}{path.suffix}"
    if path.suffix == ".json":
        data = json.loads(path.read_text())
        data["conventions"][field] = value
        out.write_text(json.dumps(data))
    elif path.suffix == ".csv":
        rows = path.read_text().splitlines()
        at = next(i for i, row in enumerate(rows) if row.startswith(f"{field},"))
        import csv
        import io

        buf = io.StringIO()
        csv.writer(buf, lineterminator="").writerow([field, json.dumps(value)])
        rows[at] = buf.getvalue()
        out.write_text("\n".join(rows) + "\n")
    else:
        raw = scipy.io.loadmat(path)
        conventions = json.loads(str(raw["conventions_json"][0]))
        conventions[field] = value
        raw["conventions_json"] = json.dumps(conventions)
        scipy.io.savemat(out, {k: v for k, v in raw.items() if not k.startswith("__")})
    return out


# every field in every M, C, K form and in a boundary's JSON; the .mat twin once (same check after the read)
CONVENTION_CASES = [(kind, field) for kind in ("mck.json", "mck.csv", "mck.mat", "boundary.json")
                    for field in OTHER_CONVENTIONS] + [("boundary.mat", "units")]


@pytest.mark.parametrize(("kind", "field"), CONVENTION_CASES)
def test_other_conventions_are_refused_naming_the_field(files, tmp_path, kind, field):
    path = _with_conventions(files[kind], tmp_path, field, OTHER_CONVENTIONS[field])
    refused(lambda: _loader(kind)(path), InputError, str(path), f"conventions[{field!r}]")


@pytest.mark.parametrize("kind", ["system.json", "system.csv", "system.mat"])
def test_paper_style_system_files_check_them_too(files, tmp_path, kind):
    path = _with_conventions(files[kind], tmp_path, "units", OTHER_CONVENTIONS["units"])
    refused(lambda: _loader(kind)(path), InputError, str(path), "conventions['units']")


def test_a_left_boundary_file_does_not_export(files, tmp_path, capsys):
    path = _with_conventions(files["boundary.json"], tmp_path, "side", "left")
    assert main(["export", str(path), "-o", str(tmp_path / "end.bdf")]) == 2
    assert "conventions['side']" in capsys.readouterr().err
    assert not (tmp_path / "end.bdf").exists()


def test_a_file_that_declares_no_conventions_is_read_as_the_packages(files, tmp_path):
    data = json.loads(files["mck.json"].read_text())
    del data["conventions"]
    path = tmp_path / "plain.json"
    path.write_text(json.dumps(data))
    assert st.load_matrix_system(path).n_dof == st.load_matrix_system(files["mck.json"]).n_dof
    data["conventions"] = "right"
    path.write_text(json.dumps(data))
    refused(lambda: st.load_matrix_system(path), InputError, "'conventions' must be a record")


def test_the_packages_own_conventions_pass_in_every_form(files):
    for kind, path in files.items():
        _loader(kind)(path)  # the round trip of every kind, conventions included
    assert copy.deepcopy(end_conventions()) == end_conventions()


def test_a_system_with_plain_dof_names_reads_back(tmp_path):
    """Names without units are the user's; only names whose units contradict the ports are refused."""
    system = st.MatrixSystem(np.eye(3), np.zeros((3, 3)), np.eye(3) * 1e6, dofs=("w", "psi", "q1"))
    for suffix in (".json", ".csv", ".mat"):
        assert st.load_matrix_system(st.export_system(system, tmp_path / f"plain{suffix}")).dofs == system.dofs


def test_units_the_file_leaves_out_or_adds_are_not_a_contradiction(files, tmp_path):
    units = {"length": "m", "force": "N", "temperature": "K"}
    path = _with_conventions(files["mck.json"], tmp_path, "units", units)
    assert st.load_matrix_system(path).n_dof > 2
